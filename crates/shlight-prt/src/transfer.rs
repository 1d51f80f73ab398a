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
//! ([`shlight_core::montecarlo::stratified_directions`], seeded) serves
//! every vertex. Per vertex, only directions above the tangent plane are
//! cast, and each gets the weight `w_j = (n.s_j) / sum_k max(n.s_k, 0)`, so
//! `int max(n.s, 0) f(s) ds ~ pi sum_j w_j f(s_j)`: a ratio estimator whose
//! weights sum to exactly 1 (bias O(1/N)), so a white surface (albedo 1)
//! under constant light never gains or loses energy in the estimate, and the
//! interreflected limit of the white furnace is exact.
//!
//! Rays start at `p + eps n`, `eps` = [`OFFSET`] times the mesh's bounding
//! box diagonal, so a vertex does not shadow itself. A ray that hits the back
//! of a triangle (an open mesh seen from behind) is blocked and brings no
//! bounce light: surfaces are one-sided.
//!
//! Vertices are baked in parallel (rayon), each from the shared directions
//! alone, so the result is the same bit for bit at any thread count.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use shlight_core::montecarlo::stratified_directions;
use shlight_core::{ShBasis, ShCoeffs, sh_count};
use shlight_mesh::Mesh;

use crate::bvh::{Bvh, Ray};

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
}

impl Default for BakeOptions {
    fn default() -> Self {
        Self {
            lmax: 4,
            samples: 1024,
            mode: Mode::Shadowed,
            albedo: Albedo::Constant([0.8; 3]),
            seed: 0,
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
}

impl Transfer {
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

/// One blocked direction of a vertex, for the bounces: the triangle hit,
/// the barycentric weights of its corners 1 and 2, and the direction's
/// weight `w_j`.
#[derive(Clone, Copy, Debug)]
struct Blocked {
    triangle: u32,
    w: f32,
    b1: f32,
    b2: f32,
}

const CHUNK: usize = 64;

/// Bakes the transfer of every vertex of `mesh`.
///
/// `progress(stage, done, total)` is called from worker threads as vertices
/// finish (in no fixed order; `done` only grows within a stage).
///
/// # Panics
/// If a per-vertex albedo has another length than the mesh's vertices.
#[must_use]
pub fn bake(
    mesh: &Mesh,
    options: &BakeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Transfer {
    let n_vertices = mesh.vertex_count();
    if let Albedo::PerVertex(a) = &options.albedo {
        assert_eq!(a.len(), n_vertices, "one albedo per vertex");
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
        basis.eval(d.as_dvec3().to_array(), row);
    }

    let bvh =
        (options.mode != Mode::Unshadowed).then(|| Bvh::new(&mesh.positions, &mesh.triangles));
    let (lo, hi) = mesh.bounds();
    let eps = OFFSET * (hi - lo).length();
    let keep_hits = matches!(options.mode, Mode::Interreflected { bounces } if bounces > 0);
    let rays = AtomicU64::new(0);
    let done = AtomicUsize::new(0);

    // Geometric transfer (no albedo) per vertex, and the blocked directions.
    let mut geometric = vec![0.0f32; n_vertices * nc];
    let mut blocked: Vec<Vec<Blocked>> = vec![Vec::new(); if keep_hits { n_vertices } else { 0 }];
    let mut blocked_chunks: Vec<&mut [Vec<Blocked>]> = if keep_hits {
        blocked.chunks_mut(CHUNK).collect()
    } else {
        (0..n_vertices.div_ceil(CHUNK))
            .map(|_| &mut [][..])
            .collect()
    };
    geometric
        .par_chunks_mut(CHUNK * nc)
        .zip(blocked_chunks.par_iter_mut())
        .enumerate()
        .for_each(|(chunk, (out, hits_out))| {
            let mut acc = vec![0.0f64; nc];
            let mut cast = 0u64;
            for (k, t) in out.chunks_exact_mut(nc).enumerate() {
                let v = chunk * CHUNK + k;
                let (p, n) = (mesh.positions[v], mesh.normals[v]);
                let origin = p + eps * n;
                let total: f64 = dirs.iter().map(|d| f64::from(n.dot(*d).max(0.0))).sum();
                acc.fill(0.0);
                if total > 0.0 {
                    for (j, d) in dirs.iter().enumerate() {
                        let cos = n.dot(*d);
                        if cos <= 0.0 {
                            continue;
                        }
                        let w = f64::from(cos) / total;
                        let visible = match (&bvh, options.mode) {
                            (None, _) => true,
                            (Some(bvh), Mode::Interreflected { bounces }) if bounces > 0 => {
                                cast += 1;
                                match bvh.closest_hit(&Ray::new(origin, *d, f32::INFINITY)) {
                                    None => true,
                                    Some(hit) => {
                                        let tri = mesh.triangles[hit.triangle as usize]
                                            .map(|i| mesh.positions[i as usize]);
                                        let face = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
                                        if face.dot(*d) < 0.0 {
                                            hits_out[k].push(Blocked {
                                                triangle: hit.triangle,
                                                w: w as f32,
                                                b1: hit.barycentrics[1],
                                                b2: hit.barycentrics[2],
                                            });
                                        }
                                        false
                                    }
                                }
                            }
                            (Some(bvh), _) => {
                                cast += 1;
                                !bvh.occluded(&Ray::new(origin, *d, f32::INFINITY))
                            }
                        };
                        if visible {
                            let y = &ylm[j * nc..][..nc];
                            for (a, yi) in acc.iter_mut().zip(y) {
                                *a += w * yi;
                            }
                        }
                    }
                }
                for (ti, a) in t.iter_mut().zip(&acc) {
                    *ti = *a as f32;
                }
            }
            rays.fetch_add(cast, Ordering::Relaxed);
            let now = done.fetch_add(out.len() / nc, Ordering::Relaxed) + out.len() / nc;
            progress(Stage::Rays, now, n_vertices);
        });
    drop(blocked_chunks);

    // T^0 = albedo x geometric transfer, per channel.
    let stride = channels * nc;
    let mut total = vec![0.0f32; n_vertices * stride];
    for (v, (t, g)) in total
        .chunks_exact_mut(stride)
        .zip(geometric.chunks_exact(nc))
        .enumerate()
    {
        for c in 0..channels {
            let rho = options.albedo.get(v, c);
            for (o, gi) in t[c * nc..][..nc].iter_mut().zip(g) {
                *o = rho * gi;
            }
        }
    }
    drop(geometric);

    // Bounces: T^b(v) = rho(v) sum_blocked w_j interp(T^{b-1}, hit).
    let mut previous = total.clone();
    for bounce in 1..=options.mode.bounces() {
        let done = AtomicUsize::new(0);
        let mut next = vec![0.0f32; n_vertices * stride];
        next.par_chunks_mut(CHUNK * stride)
            .enumerate()
            .for_each(|(chunk, out)| {
                let mut acc = vec![0.0f64; stride];
                for (k, t) in out.chunks_exact_mut(stride).enumerate() {
                    let v = chunk * CHUNK + k;
                    acc.fill(0.0);
                    for h in &blocked[v] {
                        let [a, b, c] = mesh.triangles[h.triangle as usize];
                        let wa = f64::from(h.w * (1.0 - h.b1 - h.b2));
                        let (wb, wc) = (f64::from(h.w * h.b1), f64::from(h.w * h.b2));
                        let (ta, tb, tc) = (
                            &previous[a as usize * stride..][..stride],
                            &previous[b as usize * stride..][..stride],
                            &previous[c as usize * stride..][..stride],
                        );
                        for i in 0..stride {
                            acc[i] += wa * f64::from(ta[i])
                                + wb * f64::from(tb[i])
                                + wc * f64::from(tc[i]);
                        }
                    }
                    for c in 0..channels {
                        let rho = f64::from(options.albedo.get(v, c));
                        for i in c * nc..(c + 1) * nc {
                            t[i] = (rho * acc[i]) as f32;
                        }
                    }
                }
                let now =
                    done.fetch_add(out.len() / stride, Ordering::Relaxed) + out.len() / stride;
                progress(Stage::Bounce(bounce), now, n_vertices);
            });
        for (t, b) in total.iter_mut().zip(&next) {
            *t += b;
        }
        previous = next;
    }

    Transfer {
        lmax,
        channels,
        vertex_count: n_vertices,
        coeffs: total,
        samples: dirs.len(),
        rays: rays.into_inner(),
    }
}
