//! Diffuse transfer vectors per vertex (Sloan, Kautz & Snyder 2002, §5).
//!
//! For a vertex at `p` with unit normal `n` and albedo `rho`, under distant
//! radiance `L(s) = sum_i L_i Y_i(s)`, the exit radiance is one dot product
//! `L_o = sum_i T_i L_i` with
//!
//! ```text
//! unshadowed      T_i = rho/pi int max(n.s, 0)          Y_i(s) ds
//! shadowed        T_i = rho/pi int max(n.s, 0) V(p, s)  Y_i(s) ds
//! interreflected  T   = T^0 + T^1 + ... + T^B,  T^0 the shadowed transfer,
//!                 T^b_i(p) = rho/pi int max(n.s, 0) (1 - V(p, s)) T^{b-1}_i(q(p, s)) ds
//! ```
//!
//! where `V` is 1 when the ray from `p` along `s` escapes the mesh, and
//! `q(p, s)` is the point it hits, whose transfer `T^{b-1}(q)` is the
//! barycentric interpolation of its triangle's vertex transfers (the
//! radiance a diffuse point leaves in every direction, so bounce `b` gathers
//! bounce `b-1` as in the paper's iteration). Albedo over pi is folded into
//! `T`, so a renderer computes `T . L` and nothing else.
//!
//! # Estimator
//!
//! One jittered equal-area grid of directions `s_j`
//! ([`shlight_core::map::montecarlo::stratified_directions`], seeded) serves
//! every vertex. Per vertex, only directions above the tangent plane are
//! cast, and each gets the weight `w_j = (n.s_j) / sum_k max(n.s_k, 0)`, so
//! `int max(n.s, 0) f(s) ds ~ pi sum_j w_j f(s_j)`: a ratio estimator whose
//! weights sum to exactly 1 (bias O(1/N)), so a white surface (albedo 1)
//! under constant light never gains or loses energy in the estimate, and the
//! interreflected limit of the white furnace is exact.
//!
//! Rays start at `p + eps (n + c)`, `eps` = [`OFFSET`] times the mesh's
//! bounding box diagonal, so a vertex does not shadow itself; `c` is the
//! unit tangent from the vertex towards the mean centroid of its triangles,
//! so a vertex on a concave edge (where a wall meets a ceiling) starts off
//! the other surface's plane instead of on it, where its rays would slip
//! out between the two ([`ray_origins`]). A ray that hits the back
//! of a triangle (an open mesh seen from behind) is blocked and brings no
//! bounce light: surfaces are one-sided.
//!
//! Directions are cast in parallel (rayon), each as packets of eight
//! parallel rays from neighbouring vertices ([`crate::packet`]), and each
//! vertex's sum runs over the directions in order, so the result is the
//! same bit for bit at any thread count.
//!
//! The bounces are gathered in `f32`, vertices a chunk at a time in Morton
//! order: a chunk goes through the directions in order and reads its
//! vertices' front hits along each (a direction's hits are kept in the
//! order its rays were cast, so a chunk's are one run, and there is no
//! per-vertex copy of them to make), each hit adding its triangle's three
//! corner records, the transfer and the emitters' light of the last bounce
//! together (with AVX2 and FMA eight floats at a time, detected at run
//! time; portable loops elsewhere). Neighbouring vertices' hits along one
//! direction land near one another, so the records they read are mostly in
//! cache.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_core::sh::{ShBasis, ShCoeffs, sh_count};
use shlight_format::ShprtFile;
use shlight_mesh::{Mesh, Subdivision};

use crate::bvh::Bvh;
use crate::packet::{Direction, LANES, Packet, PacketBvh};
use crate::records::{self, Kernels, LINE, Line, flat, flat_mut};

/// Ray origins are offset along the normal by this times the bounding box
/// diagonal.
pub const OFFSET: f32 = 1e-4;

/// Which light transport the transfer holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Cosine-weighted, no visibility: the SH irradiance transfer.
    Unshadowed,
    /// Cosine-weighted with binary visibility (self-shadowing).
    Shadowed,
    /// Shadowed plus `bounces` bounces of diffuse interreflection.
    Interreflected {
        /// Number of bounces gathered after the shadowed term.
        bounces: u32,
    },
}

impl Mode {
    /// `unshadowed`, `shadowed` or `interreflected`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Mode::Unshadowed => "unshadowed",
            Mode::Shadowed => "shadowed",
            Mode::Interreflected { .. } => "interreflected",
        }
    }

    /// Bounces gathered (0 unless interreflected).
    #[must_use]
    pub fn bounces(self) -> u32 {
        match self {
            Mode::Interreflected { bounces } => bounces,
            _ => 0,
        }
    }
}

/// The surface's diffuse albedo.
#[derive(Clone, Debug, PartialEq)]
pub enum Albedo {
    /// The same linear RGB albedo everywhere; one channel when the three are
    /// equal.
    Constant([f32; 3]),
    /// One linear RGB albedo per vertex (e.g. the mesh's vertex colours).
    PerVertex(Vec<Vec3>),
}

impl Albedo {
    /// 1 for a grey constant albedo, 3 otherwise.
    #[must_use]
    pub fn channels(&self) -> usize {
        match self {
            Albedo::Constant([r, g, b]) if r == g && g == b => 1,
            _ => 3,
        }
    }

    /// Albedo of vertex `v` in channel `c` (`channels()` of them).
    fn get(&self, v: usize, c: usize) -> f32 {
        match self {
            Albedo::Constant(rgb) => rgb[c],
            Albedo::PerVertex(all) => all[v][c],
        }
    }
}

/// What to bake.
#[derive(Clone, Debug)]
pub struct BakeOptions {
    /// Highest SH degree (`(lmax+1)^2` coefficients per channel).
    pub lmax: usize,
    /// Directions wanted over the whole sphere (rounded to a whole grid,
    /// see [`stratified_directions`]); about half are cast per vertex.
    pub samples: usize,
    /// Transport.
    pub mode: Mode,
    /// Albedo.
    pub albedo: Albedo,
    /// Seed of the direction set.
    pub seed: u64,
    /// Emitted radiance per vertex (linear RGB, one per vertex, e.g.
    /// [`Mesh::emission`]); with it the bake also gathers the light the
    /// emitters send around the mesh ([`Transfer::emitted`]).
    pub emission: Option<Vec<Vec3>>,
}

impl Default for BakeOptions {
    fn default() -> Self {
        Self {
            lmax: 4,
            samples: 1024,
            mode: Mode::Shadowed,
            albedo: Albedo::Constant([0.8; 3]),
            seed: 0,
            emission: None,
        }
    }
}

/// Where a bake is, for progress bars.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Casting rays from the vertices.
    Rays,
    /// Gathering bounce `k` (1-based).
    Bounce(u32),
    /// Summing glossy transfer matrices, in vertices.
    Matrices,
}

/// Per-vertex transfer vectors and what produced them.
#[derive(Clone, Debug)]
pub struct Transfer {
    /// Highest SH degree.
    pub lmax: usize,
    /// 1 (grey albedo) or 3 (linear RGB).
    pub channels: usize,
    /// Vertices, in the mesh's order.
    pub vertex_count: usize,
    /// `vertex_count * channels * (lmax+1)^2` coefficients: vertex-major,
    /// then channel, then SH index `l(l+1)+m`.
    pub coeffs: Vec<f32>,
    /// Directions in the shared set (the grid's size).
    pub samples: usize,
    /// Rays cast (directions above each vertex's tangent plane).
    pub rays: u64,
    /// With [`BakeOptions::emission`]: each vertex's exit radiance due to
    /// the emitters alone (linear RGB), `E = E^0 + ... + E^B` with
    /// `E^0 = Le` and `E^b(p) = rho/pi int max(n.s, 0) (1 - V(p, s))
    /// E^{b-1}(q(p, s)) ds`, the transfer's own iteration with the emission
    /// as the source, so the exit radiance of a vertex under light `L` is
    /// `T . L + E`.
    pub emitted: Option<Vec<Vec3>>,
}

impl Transfer {
    /// The transfer vectors borrowed, as the renderer and every reader of a
    /// bake take them.
    #[must_use]
    pub fn view(&self) -> shlight_baked::TransferView<'_> {
        shlight_baked::TransferView {
            lmax: self.lmax,
            channels: self.channels,
            vertex_count: self.vertex_count,
            data: &self.coeffs,
        }
    }

    /// The `.shprt` file of this bake and what produced it.
    #[must_use]
    pub fn to_shprt(
        &self,
        mode: Mode,
        seed: u64,
        albedo: Option<[f32; 3]>,
        mesh_hash: u64,
        mesh: &str,
    ) -> ShprtFile {
        ShprtFile {
            lmax: self.lmax,
            channels: self.channels,
            vertex_count: self.vertex_count,
            transfer: self.coeffs.clone(),
            mode: mode.name().to_string(),
            samples: self.samples as u64,
            bounces: mode.bounces(),
            seed,
            albedo,
            mesh_hash,
            mesh: mesh.to_string(),
            glossy: None,
        }
    }

    /// Exit radiance per vertex under the radiance coefficients `light`:
    /// `sum_i T_i L_i` per channel, over the coefficients both have (a grey
    /// transfer is applied to each colour channel of the light).
    #[must_use]
    pub fn exit_radiance(&self, light: &ShCoeffs<DVec3>) -> Vec<Vec3> {
        exit_radiance(&self.coeffs, self.lmax, self.channels, light)
    }
}

/// `sum_i T_i L_i` per vertex and channel for transfer `coeffs` laid out as
/// in [`Transfer::coeffs`].
#[must_use]
pub fn exit_radiance(
    coeffs: &[f32],
    lmax: usize,
    channels: usize,
    light: &ShCoeffs<DVec3>,
) -> Vec<Vec3> {
    let nc = sh_count(lmax);
    let used = nc.min(light.len());
    coeffs
        .chunks_exact(nc * channels)
        .map(|t| {
            let mut out = DVec3::ZERO;
            for c in 0..3 {
                let row = &t[(c % channels) * nc..][..used];
                out[c] = row
                    .iter()
                    .zip(light.as_slice())
                    .map(|(&ti, li)| f64::from(ti) * li[c])
                    .sum();
            }
            out.as_vec3()
        })
        .collect()
}

/// A ray along one direction that met the front of a triangle: its
/// vertex's rank (Morton order), the triangle and the barycentric weights
/// of corners 1 and 2.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FrontHit {
    pub(crate) rank: u32,
    pub(crate) triangle: u32,
    pub(crate) b1: f32,
    pub(crate) b2: f32,
}

const CHUNK: usize = 64;

/// Vertices per task of the bounces' gathering ([`Gather`]): their
/// records of a bounce, 64 KB at lmax 2 with emitters, stay in cache
/// while the chunk goes through the directions.
const BOUNCE_CHUNK: usize = 1024;

/// Vertex indices sorted along a Morton (Z-order) curve through the
/// bounding box `(lo, hi)`, 10 bits per axis ([`shlight_baked::morton_code`]):
/// neighbours in the list are neighbours in space, so consecutive vertices
/// make coherent ray packets.
#[must_use]
pub fn vertex_order(positions: &[Vec3], (lo, hi): (Vec3, Vec3)) -> Vec<u32> {
    let scale = Vec3::splat(1023.0) / (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    shlight_baked::morton_order(positions.iter().map(|p| {
        let q = ((*p - lo) * scale).clamp(Vec3::ZERO, Vec3::splat(1023.0));
        shlight_baked::morton_code(q.x as u32, q.y as u32, q.z as u32)
    }))
}

/// The inverse of the permutation `order`: `ranks(order)[order[s]] = s`.
fn ranks(order: &[u32]) -> Vec<u32> {
    let mut rank = vec![0u32; order.len()];
    for (s, &v) in order.iter().enumerate() {
        rank[v as usize] = s as u32;
    }
    rank
}

/// `mesh`'s triangles with their corners by rank (`rank[v]`, [`ranks`]).
fn ranked_triangles(mesh: &Mesh, rank: &[u32]) -> Vec<[u32; 3]> {
    mesh.triangles
        .iter()
        .map(|t| t.map(|i| rank[i as usize]))
        .collect()
}

/// The rays [`bake`] casts along each of `dirs`: the direction, and the
/// origins (`p + eps n`) of the vertices facing it (`n.d > 0`) in Morton
/// order. For benchmarks and comparisons with other ray casters; `bake`
/// makes the same rays as it goes.
#[must_use]
pub fn cast_rays(mesh: &Mesh, dirs: &[Vec3]) -> Vec<(Vec3, Vec<Vec3>)> {
    let bounds = mesh.bounds();
    let start = ray_origins(mesh);
    let order = vertex_order(&mesh.positions, bounds);
    dirs.iter()
        .map(|d| {
            let origins = order
                .iter()
                .filter(|&&v| mesh.normals[v as usize].dot(*d) > 0.0)
                .map(|&v| start[v as usize])
                .collect();
            (*d, origins)
        })
        .collect()
}

/// Where each vertex's rays start: `p + eps (n + c)`, `eps` = [`OFFSET`]
/// times the bounding-box diagonal, `c` the unit vector in the tangent plane
/// from `p` towards the mean centroid of the triangles that use it (zero
/// for a vertex no triangle uses, or one whose mean lies along its normal,
/// like a sphere's pole) — unless the segment from `p` to that point
/// crosses the mesh, which an origin must never do: a vertex just inside
/// another part of a self-intersecting mesh would have its rays start on
/// the far side of the surface it is inside, and be lit where every ray from
/// it meets a back face. Then the first of `p + eps n`, `p + eps n / 4`,
/// `p + eps n / 16`, ... ([`SHORTER_OFFSETS`] of them) whose segment from
/// `p` crosses nothing is taken, and the shortest when every one crosses.
#[must_use]
pub fn ray_origins(mesh: &Mesh) -> Vec<Vec3> {
    ray_origins_against(mesh, &Bvh::new(&mesh.positions, &mesh.triangles))
}

/// Normal-only offsets tried, each a quarter of the last, when the
/// concave-edge offset of [`ray_origins`] would cross the mesh.
pub const SHORTER_OFFSETS: usize = 8;

/// Hits on a segment from `p` nearer than this fraction of its length are
/// the triangles through `p` itself (its own), which it leaves, not crosses.
const OWN_TRIANGLES: f32 = 1e-3;

/// [`ray_origins`], the segments from each `p` tested against `bvh` (the
/// mesh's surface, or the surface it was subdivided from).
fn ray_origins_against(mesh: &Mesh, bvh: &Bvh) -> Vec<Vec3> {
    let bounds = mesh.bounds();
    let eps = OFFSET * (bounds.1 - bounds.0).length();
    let mut centroids = vec![(DVec3::ZERO, 0u32); mesh.vertex_count()];
    for t in &mesh.triangles {
        let c = t
            .iter()
            .map(|&i| mesh.positions[i as usize].as_dvec3())
            .sum::<DVec3>()
            / 3.0;
        for &i in t {
            let e = &mut centroids[i as usize];
            e.0 += c;
            e.1 += 1;
        }
    }
    // Whether the segment from `p` to `p + offset` crosses a triangle
    // other than those through `p`.
    let crosses = |p: Vec3, offset: Vec3| {
        let start = p + OWN_TRIANGLES * offset;
        bvh.occluded(&crate::bvh::Ray::new(start, offset, 1.0 - OWN_TRIANGLES))
    };
    mesh.positions
        .par_iter()
        .zip(&mesh.normals)
        .zip(&centroids)
        .map(|((p, n), &(sum, count))| {
            let inward = if count == 0 {
                Vec3::ZERO
            } else {
                let c = sum / f64::from(count) - p.as_dvec3();
                let n = n.as_dvec3();
                (c - c.dot(n) * n)
                    .try_normalize()
                    .map_or(Vec3::ZERO, |c| c.as_vec3())
            };
            let offset = eps * (*n + inward);
            if !crosses(*p, offset) {
                return *p + offset;
            }
            let mut offset = eps * *n;
            for _ in 1..SHORTER_OFFSETS {
                if !crosses(*p, offset) {
                    break;
                }
                offset *= 0.25;
            }
            *p + offset
        })
        .collect()
}

/// `(b - a) x (c - a)` of each triangle `(a, b, c)`: its front side.
fn face_normals(mesh: &Mesh) -> Vec<Vec3> {
    mesh.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
            (b - a).cross(c - a)
        })
        .collect()
}

/// The bounces' gathering. A vertex's record holds its transfer of the
/// last bounce (`channels x nc`) and, when the mesh emits, its exit
/// radiance due to emitters, in `f32`, padded to whole 64-byte lines; the
/// records are in rank (Morton) order.
///
/// The vertices are taken [`BOUNCE_CHUNK`] ranks at a time, and each chunk goes
/// through the directions in order, reading the hits its vertices have
/// along each (every direction's front hits are in rank order, so a
/// chunk's are one run): each vertex sums its hits in direction order, in
/// `f32`, whatever the threads, and the hits of neighbouring vertices along
/// one direction land near one another, so their records are read from
/// cache.
struct Gather<'a> {
    order: &'a [u32],
    /// Normals and `sum_j max(n.s_j, 0)` by rank.
    normals: &'a [Vec3],
    totals: &'a [f64],
    dirs: &'a [Vec3],
    hits: &'a [Vec<FrontHit>],
    /// Per direction, the first hit of each chunk (and the end).
    starts: Vec<u32>,
    /// Entries of `starts` per direction: the chunks, and one more.
    row: usize,
    /// The mesh's triangles, corners by rank.
    triangles: &'a [[u32; 3]],
    albedo: &'a Albedo,
    nc: usize,
    channels: usize,
    /// Floats used per record (`channels nc`, 3 more when the mesh emits).
    len: usize,
    /// Lines per record.
    lines: usize,
}

impl<'a> Gather<'a> {
    fn new(
        order: &'a [u32],
        normals: &'a [Vec3],
        totals: &'a [f64],
        triangles: &'a [[u32; 3]],
        dirs: &'a [Vec3],
        hits: &'a [Vec<FrontHit>],
        options: &'a BakeOptions,
    ) -> Self {
        let n = order.len();
        let chunks = n.div_ceil(BOUNCE_CHUNK);
        let mut starts = Vec::with_capacity(dirs.len() * (chunks + 1));
        for h in hits {
            debug_assert!(
                h.is_sorted_by_key(|x| x.rank),
                "a direction's hits are in rank order"
            );
            for c in 0..=chunks {
                let first = (c * BOUNCE_CHUNK) as u32;
                starts.push(h.partition_point(|x| x.rank < first) as u32);
            }
        }
        let nc = sh_count(options.lmax);
        let channels = options.albedo.channels();
        let len = channels * nc + if options.emission.is_some() { 3 } else { 0 };
        Self {
            order,
            normals,
            totals,
            dirs,
            hits,
            starts,
            row: chunks + 1,
            triangles,
            albedo: &options.albedo,
            nc,
            channels,
            len,
            lines: records::lines(len),
        }
    }

    /// The next bounce's records from the last one's, `progress(vertices)`
    /// as chunks finish.
    fn bounce(
        &self,
        kernels: Kernels,
        previous: &[Line],
        progress: &(dyn Fn(usize) + Sync),
    ) -> Vec<Line> {
        let mut next = vec![Line::ZERO; previous.len()];
        let prev = flat(previous);
        let stride = self.channels * self.nc;
        next.par_chunks_mut(BOUNCE_CHUNK * self.lines)
            .enumerate()
            .for_each(|(c, out)| {
                let acc = flat_mut(out);
                #[cfg(target_arch = "x86_64")]
                if kernels == Kernels::Avx2 {
                    // SAFETY: AVX2 and FMA were detected.
                    unsafe { self.chunk_avx2(c, prev, acc) };
                } else {
                    self.chunk(c, prev, acc);
                }
                #[cfg(not(target_arch = "x86_64"))]
                {
                    let _ = kernels;
                    self.chunk(c, prev, acc);
                }
                let rec = self.lines * LINE;
                for (k, r) in acc.chunks_exact_mut(rec).enumerate() {
                    let v = self.order[c * BOUNCE_CHUNK + k] as usize;
                    for ch in 0..self.channels {
                        let rho = self.albedo.get(v, ch);
                        for x in &mut r[ch * self.nc..][..self.nc] {
                            *x *= rho;
                        }
                    }
                    if self.len > stride {
                        // Every albedo has three channels (a grey one three
                        // equal).
                        for ch in 0..3 {
                            r[stride + ch] *= self.albedo.get(v, ch);
                        }
                    }
                }
                progress(acc.len() / rec);
            });
        next
    }

    /// The hits of chunk `c`'s vertices, direction by direction in order:
    /// `f(k, [w_j w_a, w_j w_b, w_j w_c], [a, b, c])` for each, `k` the
    /// vertex's place in the chunk, `w_j` its weight of the direction,
    /// `w_a`, `w_b`, `w_c` the hit's barycentric weights of the triangle's
    /// corners and `a`, `b`, `c` their ranks. Inlined into both kernels,
    /// the AVX2 one's `f` included.
    #[inline(always)]
    fn each_hit(&self, c: usize, mut f: impl FnMut(usize, [f32; 3], [usize; 3])) {
        let first = c * BOUNCE_CHUNK;
        for (j, d) in self.dirs.iter().enumerate() {
            let starts = &self.starts[j * self.row + c..];
            for h in &self.hits[j][starts[0] as usize..starts[1] as usize] {
                let s = h.rank as usize;
                let w = (f64::from(self.normals[s].dot(*d)) / self.totals[s]) as f32;
                let [a, b, cc] = self.triangles[h.triangle as usize];
                f(
                    s - first,
                    [w * (1.0 - h.b1 - h.b2), w * h.b1, w * h.b2],
                    [a as usize, b as usize, cc as usize],
                );
            }
        }
    }

    /// The hits of chunk `c`'s vertices: `w_j (w_a R_a + w_b R_b + w_c R_c)`
    /// summed into their rows of `acc` (zeros), `R` the corners' records in
    /// `prev`.
    fn chunk(&self, c: usize, prev: &[f32], acc: &mut [f32]) {
        let (rec, len) = (self.lines * LINE, self.len);
        self.each_hit(c, |v, [wa, wb, wc], [a, b, cc]| {
            let ra = &prev[a * rec..][..len];
            let rb = &prev[b * rec..][..len];
            let rc = &prev[cc * rec..][..len];
            let out = &mut acc[v * rec..][..len];
            for k in 0..len {
                out[k] += wa * ra[k] + wb * rb[k] + wc * rc[k];
            }
        });
    }

    /// [`chunk`](Self::chunk) with AVX2, eight floats of a record at a
    /// time.
    ///
    /// # Safety
    /// AVX2 and FMA must be available.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn chunk_avx2(&self, c: usize, prev: &[f32], acc: &mut [f32]) {
        use std::arch::x86_64::*;
        let rec = self.lines * LINE;
        let vectors = self.len.div_ceil(8);
        self.each_hit(c, |v, [wa, wb, wc], [a, b, cc]| {
            let ra = &prev[a * rec..][..rec];
            let rb = &prev[b * rec..][..rec];
            let rc = &prev[cc * rec..][..rec];
            let out = &mut acc[v * rec..][..rec];
            // SAFETY: vector k covers floats 8k..8k+8 <= rec of each record
            // and of `out`.
            unsafe {
                let (wa, wb, wc) = (_mm256_set1_ps(wa), _mm256_set1_ps(wb), _mm256_set1_ps(wc));
                for k in 0..vectors {
                    let x = _mm256_mul_ps(wa, _mm256_loadu_ps(ra.as_ptr().add(8 * k)));
                    let x = _mm256_fmadd_ps(wb, _mm256_loadu_ps(rb.as_ptr().add(8 * k)), x);
                    let x = _mm256_fmadd_ps(wc, _mm256_loadu_ps(rc.as_ptr().add(8 * k)), x);
                    let o = out.as_mut_ptr().add(8 * k);
                    _mm256_storeu_ps(o, _mm256_add_ps(_mm256_loadu_ps(o), x));
                }
            }
        });
    }

    /// Adds bounce records `next` to the transfer `total` and the exit
    /// radiance `emitted` (by rank).
    fn add(&self, next: &[Line], total: &mut [f32], emitted: Option<&mut [Vec3]>) {
        let stride = self.channels * self.nc;
        for (r, t) in next
            .chunks_exact(self.lines)
            .zip(total.chunks_exact_mut(stride))
        {
            for (t, b) in t.iter_mut().zip(flat(r)) {
                *t += b;
            }
        }
        if let Some(e) = emitted {
            for (r, e) in next.chunks_exact(self.lines).zip(e) {
                let r = flat(r);
                *e += Vec3::new(r[stride], r[stride + 1], r[stride + 2]);
            }
        }
    }
}

/// Bakes the transfer of every vertex of `mesh`.
///
/// Rays are cast direction by direction: for each shared direction, the
/// vertices facing it are taken in Morton order eight at a time, and each
/// eight is traced as one [`Packet`] of parallel rays. The transfer is then
/// summed per vertex in direction order, so the result does not depend on
/// the number of threads.
///
/// `progress(stage, done, total)` is called from worker threads as work
/// finishes (in no fixed order; `done` only grows within a stage): for
/// [`Stage::Rays`] in directions, for the bounces in vertices.
///
/// # Panics
/// If a per-vertex albedo has another length than the mesh's vertices.
#[must_use]
pub fn bake(
    mesh: &Mesh,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    bake_with_occluder(mesh, None, options, progress)
}

/// [`bake`] for a `mesh` made by [`Mesh::subdivided_with_map`] from
/// `occluder.0` (`occluder.1` its map): the rays are cast against the
/// original triangles (the same surface, fewer triangles) and their hits
/// found in `mesh` by [`Subdivision::locate_each`], a direction's hits
/// together. `None`: cast against `mesh`.
///
/// # Panics
/// As [`bake`].
#[must_use]
pub fn bake_with_occluder(
    mesh: &Mesh,
    occluder: Option<(&Mesh, &Subdivision)>,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    let built = occluder.map(|(coarse, map)| (Occluder::new(coarse), map));
    let occluder = built.as_ref().map(|(o, map)| (o, *map));
    bake_with(mesh, occluder, options, progress, Kernels::detect())
}

/// [`bake_with_occluder`] with the occluder made ready already
/// ([`Occluder::new`] of the mesh `mesh` was subdivided from), for callers
/// that cast rays of their own against it too.
///
/// # Panics
/// As [`bake`].
#[must_use]
pub fn bake_against(
    mesh: &Mesh,
    occluder: Option<(&Occluder, &Subdivision)>,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    bake_with(mesh, occluder, options, progress, Kernels::detect())
}

/// A mesh made ready to cast rays against: its vertices in Morton order
/// (a direction's ray-space copies of them are then read near one
/// another), the packet hierarchy over its triangles, and their face
/// normals (a hit on a triangle's back is blocked).
#[derive(Clone, Debug)]
pub struct Occluder {
    positions: Vec<Vec3>,
    bvh: PacketBvh,
    faces: Vec<Vec3>,
}

impl Occluder {
    /// `mesh` made ready.
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        let order = vertex_order(&mesh.positions, mesh.bounds());
        let triangles = ranked_triangles(mesh, &ranks(&order));
        Self::from_ranked(mesh, &order, &triangles)
    }

    /// `mesh` made ready, its vertices' Morton order `order` and its
    /// triangles with corners by rank (`triangles`) already known.
    fn from_ranked(mesh: &Mesh, order: &[u32], triangles: &[[u32; 3]]) -> Self {
        let positions: Vec<Vec3> = order.iter().map(|&v| mesh.positions[v as usize]).collect();
        Self {
            bvh: PacketBvh::new(Bvh::new(&positions, triangles)),
            positions,
            faces: face_normals(mesh),
        }
    }

    /// The vertices in Morton order: the positions the hierarchy's corner
    /// indices refer to (what [`PacketBvh::closest`] takes in ray space).
    #[must_use]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// The packet hierarchy; its hits name the mesh's triangles.
    #[must_use]
    pub fn bvh(&self) -> &PacketBvh {
        &self.bvh
    }

    /// Whether a ray along `dir` meets triangle `triangle` (the mesh's
    /// index) on its front.
    #[inline]
    #[must_use]
    pub fn is_front(&self, triangle: u32, dir: Vec3) -> bool {
        self.faces[triangle as usize].dot(dir) < 0.0
    }
}

/// [`bake_with_occluder`], the bounces gathered with `kernels`.
fn bake_with(
    mesh: &Mesh,
    occluder: Option<(&Occluder, &Subdivision)>,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
    kernels: Kernels,
) -> Transfer {
    let shadowed = options.mode != Mode::Unshadowed;
    let bounces = options.mode.bounces();
    let cast = Cast::new(mesh, occluder, options, shadowed, bounces > 0, progress);
    let (total, emitted) = cast.diffuse(options, bounces, kernels, progress);
    let stride = cast.channels * cast.nc;
    Transfer {
        lmax: options.lmax,
        channels: cast.channels,
        vertex_count: cast.order.len(),
        coeffs: by_vertex(&total, stride, &cast.order),
        samples: cast.dirs.len(),
        rays: cast.rays,
        emitted: emitted.map(|e| by_vertex(&e, 1, &cast.order)),
    }
}

/// The rays of a bake, cast: the shared directions and their basis
/// values, the vertices in Morton order, which rays escape and where the
/// others met the front of a triangle.
pub(crate) struct Cast {
    /// `order[s]`: the vertex at rank `s`.
    pub(crate) order: Vec<u32>,
    /// The mesh's triangles with their corners by rank (empty when no
    /// bounce or cast needed them).
    pub(crate) triangles: Vec<[u32; 3]>,
    /// Normals by rank.
    pub(crate) normals: Vec<Vec3>,
    /// `sum_j max(n.s_j, 0)` per vertex, by rank.
    totals: Vec<f64>,
    /// The shared directions.
    pub(crate) dirs: Vec<Vec3>,
    /// `Y_i(s_j)`, `nc` per direction.
    pub(crate) ylm: Vec<f64>,
    /// `(lmax+1)^2`.
    pub(crate) nc: usize,
    /// The albedo's channels.
    pub(crate) channels: usize,
    /// Bit `s` of row `j` (`words` per row): the ray from the vertex of
    /// rank `s` along direction `j` escapes (empty when unshadowed).
    pub(crate) visible: Vec<u64>,
    pub(crate) words: usize,
    /// Per direction, its rays' front hits in rank order (empty unless
    /// kept).
    pub(crate) front_hits: Vec<Vec<FrontHit>>,
    /// Rays cast.
    pub(crate) rays: u64,
}

impl Cast {
    /// Casts the rays of `options` (its lmax, samples, seed and albedo)
    /// when `shadowed`, keeping the front hits when `keep_hits`.
    ///
    /// # Panics
    /// If a per-vertex albedo or the emission has another length than the
    /// mesh's vertices.
    pub(crate) fn new(
        mesh: &Mesh,
        occluder: Option<(&Occluder, &Subdivision)>,
        options: &BakeOptions,
        shadowed: bool,
        keep_hits: bool,
        progress: &(dyn Fn(Stage, usize, usize) + Sync),
    ) -> Self {
        let n_vertices = mesh.vertex_count();
        if let Albedo::PerVertex(a) = &options.albedo {
            assert_eq!(a.len(), n_vertices, "one albedo per vertex");
        }
        if let Some(e) = &options.emission {
            assert_eq!(e.len(), n_vertices, "one emission per vertex");
        }
        let lmax = options.lmax;
        let nc = sh_count(lmax);
        let channels = options.albedo.channels();
        let dirs: Vec<Vec3> = stratified_directions(options.samples.max(1), options.seed)
            .iter()
            .map(|d| d.as_vec3())
            .collect();
        let basis = ShBasis::<f64>::new(lmax);
        let mut ylm = vec![0.0f64; dirs.len() * nc];
        for (d, row) in dirs.iter().zip(ylm.chunks_exact_mut(nc)) {
            basis.eval(d.as_dvec3(), row);
        }

        // The mesh with its vertices in Morton order: `order[s]` is the vertex
        // at rank `s`, so the vertices facing a direction, taken in rank order,
        // make coherent packets and every pass reads memory in sequence.
        let bounds = mesh.bounds();
        let order = vertex_order(&mesh.positions, bounds);
        // The triangles with their corners by rank: what the bounces read, and
        // what the rays are cast against when there is no occluder.
        let triangles = if keep_hits || shadowed && occluder.is_none() {
            ranked_triangles(mesh, &ranks(&order))
        } else {
            Vec::new()
        };
        let normals: Vec<Vec3> = order.iter().map(|&v| mesh.normals[v as usize]).collect();
        // sum_j max(n.s_j, 0) per vertex, by rank: the weights' denominators.
        let totals: Vec<f64> = normals
            .par_iter()
            .map(|n| dirs.iter().map(|d| f64::from(n.dot(*d).max(0.0))).sum())
            .collect();
        let words = n_vertices.div_ceil(64);
        // Bit s of row j: the ray from the vertex of rank s along direction j
        // escapes.
        let mut visible = vec![0u64; if shadowed { dirs.len() * words } else { 0 }];
        let mut front_hits: Vec<Vec<FrontHit>> = vec![Vec::new(); dirs.len()];
        let rays = AtomicU64::new(0);
        if shadowed {
            // What the rays are cast against: `mesh`, or the occluder.
            let own;
            let (occluder, map) = match occluder {
                Some((o, m)) => (o, Some(m)),
                None => {
                    own = Occluder::from_ranked(mesh, &order, &triangles);
                    (&own, None)
                }
            };
            let (cast_positions, bvh) = (occluder.positions(), occluder.bvh());
            // Where the rays start, by rank.
            let origins = ray_origins_against(mesh, bvh.bvh());
            let start: Vec<Vec3> = order.iter().map(|&v| origins[v as usize]).collect();
            let done = AtomicUsize::new(0);
            visible
                .par_chunks_mut(words.max(1))
                .zip(front_hits.par_iter_mut())
                .enumerate()
                .for_each_init(
                    || (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new()),
                    |(local, facing, pending, coarse, located), (j, (row, hits))| {
                        let d = dirs[j];
                        let dir = Direction::new(d);
                        local.clear();
                        local.extend(cast_positions.iter().map(|p| dir.to_ray_space(*p)));
                        facing.clear();
                        facing.extend(
                            normals
                                .iter()
                                .enumerate()
                                .filter(|(_, n)| n.dot(d) > 0.0)
                                .map(|(s, _)| s as u32),
                        );
                        for eight in facing.chunks(LANES) {
                            let mut origins = [Vec3::ZERO; LANES];
                            for (o, &s) in origins.iter_mut().zip(eight) {
                                *o = start[s as usize];
                            }
                            let packet = Packet::new(&dir, &origins[..eight.len()]);
                            let escaped = if keep_hits {
                                let found = bvh.closest(&dir, local, &packet);
                                for (k, &s) in eight.iter().enumerate() {
                                    if found.mask >> k & 1 == 0 {
                                        continue;
                                    }
                                    let triangle = found.triangle[k];
                                    if !occluder.is_front(triangle, d) {
                                        continue;
                                    }
                                    match map {
                                        None => {
                                            let [_, b1, b2] = found.barycentrics[k];
                                            hits.push(FrontHit {
                                                rank: s,
                                                triangle,
                                                b1,
                                                b2,
                                            });
                                        }
                                        Some(_) => {
                                            pending.push(s);
                                            coarse.push((triangle, found.barycentrics[k]));
                                        }
                                    }
                                }
                                !found.mask
                            } else {
                                !bvh.occluded(&dir, local, &packet)
                            };
                            for (k, &s) in eight.iter().enumerate() {
                                if escaped >> k & 1 == 1 {
                                    row[s as usize / 64] |= 1 << (s % 64);
                                }
                            }
                        }
                        // The direction's hits on the occluder, found in `mesh`
                        // together (their memory reads overlap).
                        if let Some(m) = map {
                            m.locate_each(coarse, located);
                            for (&s, l) in pending.iter().zip(located.iter()) {
                                if let Some((triangle, [_, b1, b2])) = *l {
                                    hits.push(FrontHit {
                                        rank: s,
                                        triangle,
                                        b1,
                                        b2,
                                    });
                                }
                            }
                            pending.clear();
                            coarse.clear();
                        }
                        rays.fetch_add(facing.len() as u64, Ordering::Relaxed);
                        progress(
                            Stage::Rays,
                            done.fetch_add(1, Ordering::Relaxed) + 1,
                            dirs.len(),
                        );
                    },
                );
        }

        Self {
            order,
            triangles,
            normals,
            totals,
            dirs,
            ylm,
            nc,
            channels,
            visible,
            words,
            front_hits,
            rays: rays.into_inner(),
        }
    }

    /// The diffuse transfer of `options` with `bounces` bounces gathered
    /// (its rays cast by [`Cast::new`], shadowed unless `visible` is empty,
    /// front hits kept when `bounces > 0`), and the emitters' light: both
    /// by rank.
    pub(crate) fn diffuse(
        &self,
        options: &BakeOptions,
        bounces: u32,
        kernels: Kernels,
        progress: &(dyn Fn(Stage, usize, usize) + Sync),
    ) -> (Vec<f32>, Option<Vec<Vec3>>) {
        let Self {
            order,
            triangles,
            normals,
            totals,
            dirs,
            ylm,
            nc,
            channels,
            visible,
            words,
            front_hits,
            ..
        } = self;
        let (nc, channels, words) = (*nc, *channels, *words);
        let n_vertices = order.len();
        let shadowed = !visible.is_empty();
        // Geometric transfer (no albedo) per vertex, in rank order: the sum over
        // the escaping directions above the tangent plane of w_j Y(s_j),
        // w_j = n.s_j / total.
        let mut ranked = vec![0.0f32; n_vertices * nc];
        ranked
            .par_chunks_mut(CHUNK * nc)
            .enumerate()
            .for_each(|(chunk, out)| {
                let mut acc = vec![0.0f64; nc];
                for (k, t) in out.chunks_exact_mut(nc).enumerate() {
                    let s = chunk * CHUNK + k;
                    let (n, total) = (normals[s], totals[s]);
                    acc.fill(0.0);
                    if total > 0.0 {
                        for (j, d) in dirs.iter().enumerate() {
                            let cos = n.dot(*d);
                            if cos <= 0.0
                                || shadowed && visible[j * words + s / 64] >> (s % 64) & 1 == 0
                            {
                                continue;
                            }
                            let w = f64::from(cos) / total;
                            let y = &ylm[j * nc..][..nc];
                            for (a, yi) in acc.iter_mut().zip(y) {
                                *a += w * yi;
                            }
                        }
                    }
                    for (ti, a) in t.iter_mut().zip(&acc) {
                        *ti = *a as f32;
                    }
                }
            });

        // T^0 = albedo x geometric transfer, per channel, by rank.
        let stride = channels * nc;
        let mut total = vec![0.0f32; n_vertices * stride];
        for ((t, g), &v) in total
            .chunks_exact_mut(stride)
            .zip(ranked.chunks_exact(nc))
            .zip(order.iter())
        {
            for c in 0..channels {
                let rho = options.albedo.get(v as usize, c);
                for (o, gi) in t[c * nc..][..nc].iter_mut().zip(g) {
                    *o = rho * gi;
                }
            }
        }

        // Bounces: T^b(v) = rho(v) sum_blocked w_j interp(T^{b-1}, hit), and
        // the same for the emitters' light E (E^0 = Le, by rank), both in one
        // pass over the hits.
        let mut emitted: Option<Vec<Vec3>> = options
            .emission
            .as_ref()
            .map(|e| order.iter().map(|&v| e[v as usize]).collect());
        if bounces > 0 {
            let gather = Gather::new(order, normals, totals, triangles, dirs, front_hits, options);
            let mut previous = records::build(&total, stride, emitted.as_deref());
            for bounce in 1..=bounces {
                let done = AtomicUsize::new(0);
                let next = gather.bounce(kernels, &previous, &|n| {
                    progress(
                        Stage::Bounce(bounce),
                        done.fetch_add(n, Ordering::Relaxed) + n,
                        n_vertices,
                    );
                });
                gather.add(&next, &mut total, emitted.as_deref_mut());
                previous = next;
            }
        }

        (total, emitted)
    }
}

/// Rows of `width` values by rank (`order[s]` the vertex of rank `s`) in
/// vertex order.
fn by_vertex<T: Copy + Default>(ranked: &[T], width: usize, order: &[u32]) -> Vec<T> {
    let mut out = vec![T::default(); ranked.len()];
    for (row, &v) in ranked.chunks_exact(width).zip(order) {
        out[v as usize * width..][..width].copy_from_slice(row);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};
    use shlight_mesh::generate;

    /// A seeded stream of random numbers in `0..1`.
    fn numbers(seed: u64) -> impl FnMut() -> f32 {
        let mut rng = StdRng::seed_from_u64(seed);
        move || rng.random::<f32>()
    }

    #[test]
    fn f32_bounces_match_f64_sums_with_both_kernels() {
        // Random front hits of random directions on a mesh whose vertices
        // hold random transfer (3 channels of lmax 2) and emitted light:
        // one bounce gathered in f32 by either kernel against the same sums
        // in f64 here.
        let mesh = generate::uv_sphere(1.0, 12, 6);
        let n = mesh.vertex_count();
        let mut next = numbers(9);
        let albedo: Vec<Vec3> = (0..n).map(|_| Vec3::new(next(), next(), next())).collect();
        let options = BakeOptions {
            lmax: 2,
            samples: 64,
            mode: Mode::Interreflected { bounces: 1 },
            albedo: Albedo::PerVertex(albedo.clone()),
            seed: 0,
            emission: Some(vec![Vec3::ONE; n]),
        };
        let order: Vec<u32> = (0..n as u32).rev().collect();
        let triangles = ranked_triangles(&mesh, &ranks(&order));
        let normals: Vec<Vec3> = order.iter().map(|&v| mesh.normals[v as usize]).collect();
        let dirs: Vec<Vec3> = (0..40)
            .map(|_| Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize())
            .collect();
        let totals: Vec<f64> = (0..n).map(|_| 1.0 + f64::from(next()) * 10.0).collect();
        let ranked_totals: Vec<f64> = order.iter().map(|&v| totals[v as usize]).collect();
        let mut hits: Vec<Vec<FrontHit>> = vec![Vec::new(); dirs.len()];
        for along in &mut hits {
            for s in 0..n as u32 {
                if next() < 0.4 {
                    continue;
                }
                let (b1, b2) = (next(), next());
                let (b1, b2) = if b1 + b2 > 1.0 {
                    (1.0 - b1, 1.0 - b2)
                } else {
                    (b1, b2)
                };
                along.push(FrontHit {
                    rank: s,
                    triangle: (next() * mesh.triangle_count() as f32) as u32,
                    b1,
                    b2,
                });
            }
        }
        let gather = Gather::new(
            &order,
            &normals,
            &ranked_totals,
            &triangles,
            &dirs,
            &hits,
            &options,
        );
        let stride = 27;
        let total: Vec<f32> = (0..n * stride).map(|_| next() * 2.0 - 1.0).collect();
        let emission: Vec<Vec3> = (0..n).map(|_| Vec3::new(next(), next(), next())).collect();
        // The records by rank.
        let ranked_total: Vec<f32> = order
            .iter()
            .flat_map(|&v| &total[v as usize * stride..][..stride])
            .copied()
            .collect();
        let ranked_emission: Vec<Vec3> = order.iter().map(|&v| emission[v as usize]).collect();
        let previous = records::build(&ranked_total, stride, Some(&ranked_emission));
        // The f64 sums, by rank, and their sums of magnitudes.
        let value = |v: usize, k: usize| {
            if k < stride {
                f64::from(total[v * stride + k])
            } else {
                f64::from(emission[v][k - stride])
            }
        };
        let mut want = vec![0.0f64; n * 30];
        let mut size = vec![0.0f64; n * 30];
        for (j, d) in dirs.iter().enumerate() {
            for h in &hits[j] {
                let s = h.rank as usize;
                let w = f64::from(normals[s].dot(*d)) / totals[order[s] as usize];
                let ws = [1.0 - h.b1 - h.b2, h.b1, h.b2].map(|b| w * f64::from(b));
                let corners = mesh.triangles[h.triangle as usize];
                for k in 0..30 {
                    let x: f64 = (0..3).map(|i| ws[i] * value(corners[i] as usize, k)).sum();
                    want[s * 30 + k] += x;
                    size[s * 30 + k] += x.abs();
                }
            }
        }
        let hits_per_vertex = hits.iter().map(Vec::len).sum::<usize>() as f64 / n as f64;
        if Kernels::detect() == Kernels::Portable {
            crate::skip_test(
                "f32_bounces_match_f64_sums_with_both_kernels",
                "no AVX2 and FMA here: only the portable kernel is held to the f64 sums",
            );
        }
        // Without AVX2 and FMA both passes are the portable kernel.
        for kernels in [Kernels::Portable, Kernels::detect()] {
            let got = gather.bounce(kernels, &previous, &|_| {});
            for s in 0..n {
                let r = flat(&got[s * gather.lines..][..gather.lines]);
                let v = order[s] as usize;
                for k in 0..30 {
                    let rho = f64::from(albedo[v][if k < stride { k / 9 } else { k - stride }]);
                    let want = rho * want[s * 30 + k];
                    // f32 sums of about `hits_per_vertex` terms: each
                    // addition rounds by at most half an ulp of a running
                    // sum, bounded by the sum of magnitudes.
                    let tol = 4.0
                        * (hits_per_vertex + 8.0)
                        * f64::from(f32::EPSILON)
                        * rho
                        * size[s * 30 + k];
                    assert!(
                        (f64::from(r[k]) - want).abs() <= tol + 1e-12,
                        "{kernels:?} rank {s} entry {k}: {} vs {want}",
                        r[k]
                    );
                }
                assert!(r[30..].iter().all(|&x| x == 0.0), "padding stays zero");
            }
        }
    }

    #[test]
    fn bakes_with_either_kernel_agree() {
        if Kernels::detect() == Kernels::Portable {
            crate::skip_test(
                "bakes_with_either_kernel_agree",
                "no AVX2 and FMA here: both bakes gather with the portable kernel",
            );
        }
        let room = generate::cornell_box();
        let (fine, map) = room.subdivided_with_map(0.05);
        let options = BakeOptions {
            lmax: 2,
            samples: 128,
            mode: Mode::Interreflected { bounces: 2 },
            albedo: Albedo::PerVertex(fine.colors.clone().unwrap()),
            seed: 5,
            emission: fine.emission.clone(),
        };
        let occluder = Occluder::new(&room);
        let run = |kernels| {
            bake_with(
                &fine,
                Some((&occluder, &map)),
                &options,
                &|_, _, _| {},
                kernels,
            )
        };
        // Without AVX2 and FMA this compares the portable bake with itself.
        let (portable, simd) = (run(Kernels::Portable), run(Kernels::detect()));
        let max = portable.coeffs.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        for (a, b) in portable.coeffs.iter().zip(&simd.coeffs) {
            assert!((a - b).abs() <= 1e-5 * max, "{a} vs {b}");
        }
        for (a, b) in portable.emitted.unwrap().iter().zip(&simd.emitted.unwrap()) {
            assert!((*a - *b).abs().max_element() <= 1e-5 * a.abs().max_element().max(1.0));
        }
    }
}
