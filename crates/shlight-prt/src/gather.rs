//! The diffuse transfer gathered from a bake's cast rays: the shadowed
//! sums per vertex, then the bounces ([`Gather`]).
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
//!
//! Without surfaces a record is a vertex's exit transfer (its albedo
//! folded in) and a hit reads the interpolation of its corners' records.
//! With surfaces ([`crate::BakeOptions::surfaces`]) a record is the light
//! arriving at the vertex before any albedo, and each hit's sum is
//! multiplied, per channel, by the albedo of the texel it met (with AVX2,
//! one permutation spreads the hit's three albedos over a vector of the
//! record); emission is not multiplied by it, the direct light of lights
//! the bake does not trace (arriving light) is.

use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec3;
use rayon::prelude::*;
use shlight_core::sh::sh_count;

use crate::cast::{Cast, FrontHit};
use crate::options::{Albedo, BakeOptions, Stage};
use crate::records::{self, Kernels, LINE, Line, flat, flat_mut};
use crate::transfer::IncidentTransfer;

const CHUNK: usize = 64;

/// Vertices per task of the bounces' gathering ([`Gather`]): their
/// records of a bounce, 64 KB at lmax 2 with emitters, stay in cache
/// while the chunk goes through the directions.
const BOUNCE_CHUNK: usize = 1024;

impl Cast {
    /// The diffuse transfer of `options` with `bounces` bounces gathered
    /// (its rays cast by [`Cast::new`], shadowed unless `visible` is empty,
    /// front hits kept when `bounces > 0`), the emitters' light, and with
    /// surfaces the light arriving before albedo: all by rank.
    pub(crate) fn diffuse(
        &self,
        options: &BakeOptions,
        bounces: u32,
        kernels: Kernels,
        progress: &(dyn Fn(Stage, usize, usize) + Sync),
    ) -> Diffuse {
        let Self {
            order,
            normals,
            totals,
            dirs,
            ylm,
            nc,
            channels,
            visible,
            words,
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

        if self.texel {
            return self.diffuse_texel(options, bounces, kernels, progress, &ranked);
        }
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
        // the same for the emitters' light E, both in one pass over the hits.
        // E^0, by rank: the emission, plus albedo / pi times the direct
        // irradiance of lights the bake does not trace (BakeOptions::
        // exit_source).
        let mut emitted: Option<Vec<Vec3>> = options
            .exit_source()
            .map(|e| order.iter().map(|&v| e[v as usize]).collect());
        if bounces > 0 {
            let gather = Gather::new(self, options);
            let mut previous = records::build(&total, stride, emitted.as_deref());
            for bounce in 1..=bounces {
                let done = AtomicUsize::new(0);
                let next = gather.bounce(kernels, Scale::Vertex, &previous, &|n| {
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

        Diffuse {
            total,
            emitted,
            incident: None,
        }
    }

    /// [`diffuse`](Self::diffuse) with surfaces: the light arriving at
    /// each vertex before albedo, `G^b` and `F^b` ([`crate::Transfer`]),
    /// gathered with each hit's texel albedo, then the vertices' own albedo
    /// applied; `geometric` is `G^0` by rank (`nc` per vertex).
    fn diffuse_texel(
        &self,
        options: &BakeOptions,
        bounces: u32,
        kernels: Kernels,
        progress: &(dyn Fn(Stage, usize, usize) + Sync),
        geometric: &[f32],
    ) -> Diffuse {
        let (nc, channels, order) = (self.nc, self.channels, &self.order);
        let n_vertices = order.len();
        let stride = channels * nc;
        // G^0, the same in every channel.
        let mut incident = vec![0.0f32; n_vertices * stride];
        for (t, g) in incident
            .chunks_exact_mut(stride)
            .zip(geometric.chunks_exact(nc))
        {
            for c in 0..channels {
                t[c * nc..][..nc].copy_from_slice(g);
            }
        }
        let emission: Option<Vec<Vec3>> = options
            .emission
            .as_ref()
            .map(|e| order.iter().map(|&v| e[v as usize]).collect());
        // The lights' direct light arriving over pi, F^0 (BakeOptions::
        // direct_irradiance): read times the albedo wherever it is read, as
        // the environment's light is; bounce 1 takes it times the texel's
        // and the emission as it is, in a pass each when there are both.
        let direct: Option<Vec<Vec3>> = options.direct_irradiance.as_ref().map(|e| {
            order
                .iter()
                .map(|&v| e[v as usize] * std::f32::consts::FRAC_1_PI)
                .collect()
        });
        let mut arriving = (emission.is_some() || direct.is_some()).then(|| {
            direct
                .clone()
                .unwrap_or_else(|| vec![Vec3::ZERO; n_vertices])
        });
        if bounces > 0 {
            let gather = Gather::new(self, options);
            let first = emission.as_deref().or(direct.as_deref());
            let mut previous = records::build(&incident, stride, first);
            for bounce in 1..=bounces {
                let done = AtomicUsize::new(0);
                let scale = Scale::Texel {
                    emission: bounce > 1 || emission.is_none(),
                };
                let mut next = gather.bounce(kernels, scale, &previous, &|n| {
                    progress(
                        Stage::Bounce(bounce),
                        done.fetch_add(n, Ordering::Relaxed) + n,
                        n_vertices,
                    );
                });
                if let (1, Some(_), Some(d)) = (bounce, &emission, &direct) {
                    let none = vec![0.0f32; incident.len()];
                    let lit = records::build(&none, stride, Some(d));
                    let lit =
                        gather.bounce(kernels, Scale::Texel { emission: true }, &lit, &|_| {});
                    for (n, l) in flat_mut(&mut next).iter_mut().zip(flat(&lit)) {
                        *n += l;
                    }
                }
                gather.add(&next, &mut incident, arriving.as_deref_mut());
                previous = next;
            }
        }
        // The vertices' exit transfer and light: their albedo times what
        // arrives (emission as it is).
        let mut total = incident.clone();
        for (t, &v) in total.chunks_exact_mut(stride).zip(order.iter()) {
            for c in 0..channels {
                let rho = options.albedo.get(v as usize, c);
                for x in &mut t[c * nc..][..nc] {
                    *x *= rho;
                }
            }
        }
        let le = |s: usize| emission.as_ref().map_or(Vec3::ZERO, |e| e[s]);
        let emitted = arriving.as_ref().map(|f| {
            f.iter()
                .zip(order.iter())
                .enumerate()
                .map(|(s, (f, &v))| {
                    let rho =
                        Vec3::from_array([0, 1, 2].map(|c| options.albedo.get(v as usize, c)));
                    le(s) + rho * *f
                })
                .collect()
        });
        let kept = arriving.map(|f| f.into_iter().enumerate().map(|(s, f)| [le(s), f]).collect());
        Diffuse {
            total,
            emitted,
            incident: Some(IncidentTransfer {
                coeffs: incident,
                emitted: kept,
            }),
        }
    }
}

/// A diffuse bake's sums, by rank: the exit transfer (`channels x nc` per
/// vertex), the exit radiance due to emitters, and, with surfaces, the
/// light arriving before albedo.
pub(crate) struct Diffuse {
    pub(crate) total: Vec<f32>,
    pub(crate) emitted: Option<Vec<Vec3>>,
    pub(crate) incident: Option<IncidentTransfer>,
}

/// How a bounce's sums are scaled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scale {
    /// Each vertex's sum by its own albedo: the records are exit radiance.
    Vertex,
    /// Each hit's interpolated record by the albedo of the texel hit, the
    /// emitters' part too when `emission` (after the first bounce, whose
    /// source is the emitted radiance itself).
    Texel { emission: bool },
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
    /// With surfaces: per direction, each front hit's albedo.
    hit_albedo: &'a [Vec<Vec3>],
    /// With surfaces: per float of a record (whole vectors of 8), which
    /// entry of `[rho_r, rho_g, rho_b, e_r, e_g, e_b, 0, 0]` scales it
    /// (`rho` the hit's albedo, `e` the scale of the emitters' part).
    scale_index: Vec<[i32; 8]>,
    nc: usize,
    channels: usize,
    /// Floats used per record (`channels nc`, 3 more when the mesh emits).
    len: usize,
    /// Lines per record.
    lines: usize,
}

impl<'a> Gather<'a> {
    fn new(cast: &'a Cast, options: &'a BakeOptions) -> Self {
        let Cast {
            order,
            normals,
            totals,
            triangles,
            dirs,
            front_hits: hits,
            hit_albedo,
            ..
        } = cast;
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
        let channels = cast.channels;
        let len = channels * nc + if options.has_exit_source() { 3 } else { 0 };
        let lines = records::lines(len);
        let scale_index = if cast.texel {
            (0..lines * LINE / 8)
                .map(|k| {
                    std::array::from_fn(|l| {
                        let i = 8 * k + l;
                        if i < channels * nc {
                            (i / nc) as i32
                        } else if i < len {
                            (3 + i - channels * nc) as i32
                        } else {
                            6
                        }
                    })
                })
                .collect()
        } else {
            Vec::new()
        };
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
            hit_albedo,
            scale_index,
            nc,
            channels,
            len,
            lines,
        }
    }

    /// The next bounce's records from the last one's, scaled as `scale`
    /// says, `progress(vertices)` as chunks finish.
    fn bounce(
        &self,
        kernels: Kernels,
        scale: Scale,
        previous: &[Line],
        progress: &(dyn Fn(usize) + Sync),
    ) -> Vec<Line> {
        // Zeroed in parallel: the system zeroes a fresh allocation's pages
        // at their first touch, on whichever thread touches them.
        let mut next = Vec::with_capacity(previous.len());
        next.par_extend(rayon::iter::repeat_n(Line::ZERO, previous.len()));
        let prev = flat(previous);
        let stride = self.channels * self.nc;
        next.par_chunks_mut(BOUNCE_CHUNK * self.lines)
            .enumerate()
            .for_each(|(c, out)| {
                let acc = flat_mut(out);
                let rec = self.lines * LINE;
                if let Scale::Texel { emission } = scale {
                    #[cfg(target_arch = "x86_64")]
                    if kernels == Kernels::Avx2 {
                        // SAFETY: AVX2 and FMA were detected.
                        unsafe { self.chunk_texel_avx2(c, prev, acc, emission) };
                    } else {
                        self.chunk_texel(c, prev, acc, emission);
                    }
                    #[cfg(not(target_arch = "x86_64"))]
                    self.chunk_texel(c, prev, acc, emission);
                    progress(acc.len() / rec);
                    return;
                }
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
    /// `f(k, [w_j w_a, w_j w_b, w_j w_c], [a, b, c], rho)` for each, `k` the
    /// vertex's place in the chunk, `w_j` its weight of the direction,
    /// `w_a`, `w_b`, `w_c` the hit's barycentric weights of the triangle's
    /// corners, `a`, `b`, `c` their ranks and `rho` the hit's albedo when
    /// `TEXEL` (zero otherwise). Inlined into the kernels, the AVX2 ones'
    /// `f` included.
    #[inline(always)]
    fn each_hit<const TEXEL: bool>(
        &self,
        c: usize,
        mut f: impl FnMut(usize, [f32; 3], [usize; 3], Vec3),
    ) {
        let first = c * BOUNCE_CHUNK;
        for (j, d) in self.dirs.iter().enumerate() {
            let starts = &self.starts[j * self.row + c..];
            let range = starts[0] as usize..starts[1] as usize;
            let albedo = if TEXEL {
                &self.hit_albedo[j][range.clone()]
            } else {
                &[]
            };
            for (i, h) in self.hits[j][range].iter().enumerate() {
                let s = h.rank as usize;
                let w = (f64::from(self.normals[s].dot(*d)) / self.totals[s]) as f32;
                let [a, b, cc] = self.triangles[h.triangle as usize];
                f(
                    s - first,
                    [w * (1.0 - h.b1 - h.b2), w * h.b1, w * h.b2],
                    [a as usize, b as usize, cc as usize],
                    if TEXEL { albedo[i] } else { Vec3::ZERO },
                );
            }
        }
    }

    /// The hits of chunk `c`'s vertices: `w_j (w_a R_a + w_b R_b + w_c R_c)`
    /// summed into their rows of `acc` (zeros), `R` the corners' records in
    /// `prev`.
    fn chunk(&self, c: usize, prev: &[f32], acc: &mut [f32]) {
        let (rec, len) = (self.lines * LINE, self.len);
        self.each_hit::<false>(c, |v, [wa, wb, wc], [a, b, cc], _| {
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
        self.each_hit::<false>(c, |v, [wa, wb, wc], [a, b, cc], _| {
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

    /// [`chunk`](Self::chunk) with surfaces: each hit's interpolated
    /// record scaled by its albedo, per channel (`scale_index`), the
    /// emitters' part too when `emission`.
    fn chunk_texel(&self, c: usize, prev: &[f32], acc: &mut [f32], emission: bool) {
        let (rec, len) = (self.lines * LINE, self.len);
        self.each_hit::<true>(c, |v, [wa, wb, wc], [a, b, cc], rho| {
            let e = if emission { rho } else { Vec3::ONE };
            let table = [rho.x, rho.y, rho.z, e.x, e.y, e.z, 0.0, 0.0];
            let ra = &prev[a * rec..][..len];
            let rb = &prev[b * rec..][..len];
            let rc = &prev[cc * rec..][..len];
            let out = &mut acc[v * rec..][..len];
            for k in 0..len {
                let s = table[self.scale_index[k / 8][k % 8] as usize];
                out[k] += s * (wa * ra[k] + wb * rb[k] + wc * rc[k]);
            }
        });
    }

    /// [`chunk_texel`](Self::chunk_texel) with AVX2: per vector of a
    /// record, the hit's scales put in place by one permutation.
    ///
    /// # Safety
    /// AVX2 and FMA must be available.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn chunk_texel_avx2(&self, c: usize, prev: &[f32], acc: &mut [f32], emission: bool) {
        use std::arch::x86_64::*;
        let rec = self.lines * LINE;
        let vectors = self.len.div_ceil(8);
        let index = &self.scale_index[..vectors];
        self.each_hit::<true>(c, |v, [wa, wb, wc], [a, b, cc], rho| {
            let e = if emission { rho } else { Vec3::ONE };
            let ra = &prev[a * rec..][..rec];
            let rb = &prev[b * rec..][..rec];
            let rc = &prev[cc * rec..][..rec];
            let out = &mut acc[v * rec..][..rec];
            // SAFETY: vector k covers floats 8k..8k+8 <= rec of each record
            // and of `out`, and `index` holds `vectors` entries.
            unsafe {
                let table = _mm256_setr_ps(rho.x, rho.y, rho.z, e.x, e.y, e.z, 0.0, 0.0);
                let (wa, wb, wc) = (_mm256_set1_ps(wa), _mm256_set1_ps(wb), _mm256_set1_ps(wc));
                for (k, idx) in index.iter().enumerate() {
                    let x = _mm256_mul_ps(wa, _mm256_loadu_ps(ra.as_ptr().add(8 * k)));
                    let x = _mm256_fmadd_ps(wb, _mm256_loadu_ps(rb.as_ptr().add(8 * k)), x);
                    let x = _mm256_fmadd_ps(wc, _mm256_loadu_ps(rc.as_ptr().add(8 * k)), x);
                    let s =
                        _mm256_permutevar8x32_ps(table, _mm256_loadu_si256(idx.as_ptr().cast()));
                    let o = out.as_mut_ptr().add(8 * k);
                    _mm256_storeu_ps(o, _mm256_fmadd_ps(s, x, _mm256_loadu_ps(o)));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::Mode;
    use rand::{Rng, SeedableRng, rngs::StdRng};
    use shlight_mesh::generate;
    use shlight_rays::ranked_triangles;

    /// A seeded stream of random numbers in `0..1`.
    fn numbers(seed: u64) -> impl FnMut() -> f32 {
        let mut rng = StdRng::seed_from_u64(seed);
        move || rng.random::<f32>()
    }

    /// One bounce of random front hits of random directions on a mesh
    /// whose vertices hold random transfer (3 channels of lmax 2) and
    /// emitted light, gathered in f32 by either kernel, against the same
    /// sums in f64 here: scaled by each vertex's albedo (`scale` vertex),
    /// or each hit's sum by the hit's albedo, the emitted part too or not
    /// (texel).
    fn bounce_against_f64(scale: Scale) {
        let mesh = generate::uv_sphere(1.0, 12, 6);
        let n = mesh.vertex_count();
        let mut next = numbers(9);
        let albedo: Vec<Vec3> = (0..n).map(|_| Vec3::new(next(), next(), next())).collect();
        let texel = scale != Scale::Vertex;
        let options = BakeOptions {
            lmax: 2,
            samples: 64,
            mode: Mode::Interreflected { bounces: 1 },
            albedo: Albedo::PerVertex(albedo.clone()),
            seed: 0,
            emission: Some(vec![Vec3::ONE; n]),
            surfaces: None,
            direct_irradiance: None,
        };
        let order: Vec<u32> = (0..n as u32).rev().collect();
        let triangles = ranked_triangles(&mesh.triangles, &order);
        let normals: Vec<Vec3> = order.iter().map(|&v| mesh.normals[v as usize]).collect();
        let dirs: Vec<Vec3> = (0..40)
            .map(|_| Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize())
            .collect();
        let totals: Vec<f64> = (0..n).map(|_| 1.0 + f64::from(next()) * 10.0).collect();
        let ranked_totals: Vec<f64> = order.iter().map(|&v| totals[v as usize]).collect();
        let mut hits: Vec<Vec<FrontHit>> = vec![Vec::new(); dirs.len()];
        let mut hit_albedo: Vec<Vec<Vec3>> = vec![Vec::new(); dirs.len()];
        for (along, rho) in hits.iter_mut().zip(&mut hit_albedo) {
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
                if texel {
                    rho.push(Vec3::new(next(), next(), next()));
                }
            }
        }
        let cast = Cast {
            order: order.clone(),
            triangles,
            normals: normals.clone(),
            totals: ranked_totals,
            dirs: dirs.clone(),
            ylm: Vec::new(),
            nc: 9,
            channels: 3,
            visible: Vec::new(),
            words: 0,
            front_hits: hits.clone(),
            hit_albedo: hit_albedo.clone(),
            texel,
            rays: 0,
        };
        let gather = Gather::new(&cast, &options);
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
        // The channel of entry k.
        let channel = |k: usize| if k < stride { k / 9 } else { k - stride };
        let mut want = vec![0.0f64; n * 30];
        let mut size = vec![0.0f64; n * 30];
        for (j, d) in dirs.iter().enumerate() {
            for (i, h) in hits[j].iter().enumerate() {
                let s = h.rank as usize;
                let w = f64::from(normals[s].dot(*d)) / totals[order[s] as usize];
                let ws = [1.0 - h.b1 - h.b2, h.b1, h.b2].map(|b| w * f64::from(b));
                let corners = mesh.triangles[h.triangle as usize];
                for k in 0..30 {
                    let rho = match scale {
                        Scale::Texel { emission } if k < stride || emission => {
                            f64::from(hit_albedo[j][i][channel(k)])
                        }
                        _ => 1.0,
                    };
                    let x: f64 = (0..3).map(|i| ws[i] * value(corners[i] as usize, k)).sum();
                    want[s * 30 + k] += rho * x;
                    size[s * 30 + k] += (rho * x).abs();
                }
            }
        }
        let hits_per_vertex = hits.iter().map(Vec::len).sum::<usize>() as f64 / n as f64;
        if Kernels::detect() == Kernels::Portable {
            shlight_rays::skip_test(
                "f32_bounces_match_f64_sums_with_both_kernels",
                "no AVX2 and FMA here: only the portable kernel is held to the f64 sums",
            );
        }
        // Without AVX2 and FMA both passes are the portable kernel.
        for kernels in [Kernels::Portable, Kernels::detect()] {
            let got = gather.bounce(kernels, scale, &previous, &|_| {});
            for s in 0..n {
                let r = flat(&got[s * gather.lines..][..gather.lines]);
                let v = order[s] as usize;
                for k in 0..30 {
                    let rho = if texel {
                        1.0
                    } else {
                        f64::from(albedo[v][channel(k)])
                    };
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
                        "{kernels:?} {scale:?} rank {s} entry {k}: {} vs {want}",
                        r[k]
                    );
                }
                assert!(r[30..].iter().all(|&x| x == 0.0), "padding stays zero");
            }
        }
    }

    #[test]
    fn f32_bounces_match_f64_sums_with_both_kernels() {
        bounce_against_f64(Scale::Vertex);
    }

    #[test]
    fn texel_bounces_match_f64_sums_with_both_kernels() {
        bounce_against_f64(Scale::Texel { emission: false });
        bounce_against_f64(Scale::Texel { emission: true });
    }
}
