//! Baking a probe volume through a scene.
//!
//! # What a probe holds
//! The SH projection of the radiance arriving at its position `x` from
//! every direction `s`:
//!
//! ```text
//! L(x, s) = L_env(s)                 where the ray from x along s escapes,
//!         = T(q) . L_env + E(q)      where it first hits the front of a surface at q,
//!         = 0                        where it hits the back of one,
//! ```
//!
//! `T(q)` being the surface's interreflected diffuse transfer (shadowed
//! direct light plus `bounces` bounces, [`shlight_prt::transfer`]) and
//! `E(q)` its exit radiance due to emitters (their emission plus the same
//! bounces). Both are linear in the environment's coefficients, so per
//! probe and channel `c`
//!
//! ```text
//! L_probe,c = M_c L_env,c + L_emitted,c
//! M_c[i][k] = delta_ik - int_blocked Y_i(s) Y_k(s) ds + int_front Y_i(s) T_c,k(q(s)) ds
//! L_emitted,c[i] = int_front Y_i(s) E_c(q(s)) ds
//! ```
//!
//! # Estimator
//! One jittered equal-area set of `N` directions
//! ([`shlight_core::montecarlo::stratified_directions`], seeded) serves
//! every probe, each with weight `4 pi / N`. The sky's part, `delta_ik -
//! int_blocked Y_i Y_k`, is estimated from whichever of the escaping and the
//! blocked rays are fewer: `w sum_escaped Y_i Y_k` when most rays are
//! blocked, `delta_ik - w sum_blocked Y_i Y_k` (a control variate) when
//! most escape. So a probe that sees no geometry equals the environment
//! exactly, one in a closed room gets no sky light at all, and the variance
//! comes from the smaller set. Surfaces are one-sided: a ray that meets the back of a
//! triangle brings no light, and a probe for which more than
//! [`VolumeOptions::invalid_backfaces`] of the rays do so is inside
//! geometry and marked invalid. `T(q)` and `E(q)` are the barycentric
//! interpolation of the surface's vertex values; long edges are first split
//! ([`shlight_mesh::Mesh::subdivided`]) so that vertices hold shadows.
//!
//! Probes are baked in parallel, each summing its directions in order, so
//! the result is the same bit for bit at any thread count for a seed.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use shlight_core::montecarlo::stratified_directions;
use shlight_core::{ShBasis, sh_count};
use shlight_mesh::Mesh;
use shlight_prt::bvh::{Bvh, Ray};
use shlight_prt::transfer::{self, Albedo, BakeOptions, Mode};

use crate::{Grid, ProbeVolume, VolumeError};

/// Highest lmax a volume bakes.
pub const MAX_LMAX: usize = shlight_format::shvol::MAX_LMAX;

/// What to bake.
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeOptions {
    /// Highest SH degree of the probes and of the environment they take.
    pub lmax: usize,
    /// Rays per probe (rounded to a whole stratified grid).
    pub samples: usize,
    /// Interreflection bounces of the surfaces' light (0: direct light
    /// through shadows only).
    pub bounces: u32,
    /// Directions per surface vertex for the surfaces' transfer.
    pub surface_samples: usize,
    /// Longest surface edge before the surface is subdivided, in scene
    /// units; `None`: the scene's bounding-box diagonal over
    /// [`SURFACE_DIVISIONS`].
    pub max_edge: Option<f32>,
    /// Diffuse albedo of surfaces without vertex colours (linear RGB).
    pub albedo: [f32; 3],
    /// A probe is invalid when more than this fraction of its rays hit back
    /// faces.
    pub invalid_backfaces: f32,
    /// Seed of the direction sets.
    pub seed: u64,
}

/// Default subdivision: edges no longer than the scene's diagonal over this.
pub const SURFACE_DIVISIONS: f32 = 32.0;

impl Default for VolumeOptions {
    fn default() -> Self {
        Self {
            lmax: 2,
            samples: 1024,
            bounces: 2,
            surface_samples: 512,
            max_edge: None,
            albedo: [0.8; 3],
            invalid_backfaces: 0.5,
            seed: 0,
        }
    }
}

/// Where a bake is, for progress bars.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The surfaces' transfer (the PRT bake's stages).
    Surface(transfer::Stage),
    /// Casting the probes' rays.
    Probes,
}

/// Bakes the probes of `grid` through `scene` (`None`: nothing in the
/// way). The result is relightable: [`ProbeVolume::relight`] gives the
/// probes for any environment.
///
/// `progress(stage, done, total)` is called from worker threads as work
/// finishes.
///
/// # Errors
/// An lmax beyond [`MAX_LMAX`], no samples, or an albedo or
/// `invalid_backfaces` outside 0..=1.
pub fn bake(
    scene: Option<&Mesh>,
    grid: &Grid,
    options: &VolumeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<ProbeVolume, VolumeError> {
    let lmax = options.lmax;
    if lmax > MAX_LMAX {
        return Err(VolumeError::Options(format!(
            "lmax {lmax} is beyond {MAX_LMAX}, the most a volume holds"
        )));
    }
    if options.samples == 0 || options.surface_samples == 0 {
        return Err(VolumeError::Options("samples must be at least 1".into()));
    }
    if !options.albedo.iter().all(|a| (0.0..=1.0).contains(a)) {
        return Err(VolumeError::Options(format!(
            "albedo {:?} is not within 0..=1",
            options.albedo
        )));
    }
    if !(0.0..=1.0).contains(&options.invalid_backfaces) {
        return Err(VolumeError::Options(format!(
            "invalid_backfaces {} is not within 0..=1",
            options.invalid_backfaces
        )));
    }
    let nc = sh_count(lmax);
    let probes = grid.positions();
    let dirs: Vec<Vec3> = stratified_directions(options.samples, options.seed)
        .iter()
        .map(|d| d.as_vec3())
        .collect();
    let basis = ShBasis::<f64>::new(lmax);
    let mut ylm = vec![0.0f64; dirs.len() * nc];
    for (d, row) in dirs.iter().zip(ylm.chunks_exact_mut(nc)) {
        basis.eval(d.as_dvec3(), row);
    }
    let weight = 4.0 * std::f64::consts::PI / dirs.len() as f64;

    let surface = scene.map(|mesh| Surface::bake(mesh, options, progress));
    let eye = identity(nc);
    let mut transfer = vec![0.0f32; probes.len() * 3 * nc * nc];
    let mut emitted = vec![0.0f32; probes.len() * 3 * nc];
    let mut backfaces = vec![0.0f32; probes.len()];
    let done = AtomicUsize::new(0);
    let rays = AtomicU64::new(0);
    transfer
        .par_chunks_mut(3 * nc * nc)
        .zip(emitted.par_chunks_mut(3 * nc))
        .zip(backfaces.par_iter_mut())
        .zip(probes.par_iter())
        .for_each(|(((m, e), back), &x)| {
            let mut blocked = vec![0.0f64; nc * nc];
            let mut escaped = vec![0.0f64; nc * nc];
            let mut escaped_count = 0usize;
            let mut front = vec![0.0f64; 3 * nc * nc];
            let mut light = vec![0.0f64; 3 * nc];
            let mut t = vec![0.0f64; 3 * nc];
            let mut back_count = 0usize;
            if let Some(s) = &surface {
                for (j, d) in dirs.iter().enumerate() {
                    let y = &ylm[j * nc..][..nc];
                    let hit = s.bvh.closest_hit(&Ray::new(x, *d, f32::INFINITY));
                    let sum = if hit.is_some() {
                        &mut blocked
                    } else {
                        escaped_count += 1;
                        &mut escaped
                    };
                    for (row, yi) in sum.chunks_exact_mut(nc).zip(y) {
                        for (b, yk) in row.iter_mut().zip(y) {
                            *b += yi * yk;
                        }
                    }
                    let Some(hit) = hit else {
                        continue;
                    };
                    let tri = s.mesh.triangles[hit.triangle as usize];
                    let [a, b, c] = tri.map(|i| s.mesh.positions[i as usize]);
                    if (b - a).cross(c - a).dot(*d) >= 0.0 {
                        back_count += 1;
                        continue;
                    }
                    let exit = s.interpolate(tri, hit.barycentrics, &mut t);
                    for ch in 0..3 {
                        let tc = &t[ch * nc..][..nc];
                        let fc = &mut front[ch * nc * nc..][..nc * nc];
                        for (row, yi) in fc.chunks_exact_mut(nc).zip(y) {
                            for (f, tk) in row.iter_mut().zip(tc) {
                                *f += yi * tk;
                            }
                        }
                    }
                    for (l, yi) in light.chunks_exact_mut(3).zip(y) {
                        for ch in 0..3 {
                            l[ch] += yi * exit[ch];
                        }
                    }
                }
                rays.fetch_add(dirs.len() as u64, Ordering::Relaxed);
            }
            // The sky's part from the smaller of the two sets of rays.
            let sky: Vec<f64> = if surface.is_none() {
                eye.clone()
            } else if escaped_count <= dirs.len() - escaped_count {
                escaped.iter().map(|e| weight * e).collect()
            } else {
                eye.iter()
                    .zip(&blocked)
                    .map(|(i, b)| i - weight * b)
                    .collect()
            };
            for ch in 0..3 {
                let mc = &mut m[ch * nc * nc..][..nc * nc];
                for (k, o) in mc.iter_mut().enumerate() {
                    *o = (sky[k] + weight * front[ch * nc * nc + k]) as f32;
                }
            }
            for (o, l) in e.iter_mut().zip(&light) {
                *o = (weight * l) as f32;
            }
            *back = back_count as f32 / dirs.len() as f32;
            progress(
                Stage::Probes,
                done.fetch_add(1, Ordering::Relaxed) + 1,
                probes.len(),
            );
        });
    let valid = backfaces
        .iter()
        .map(|&f| f <= options.invalid_backfaces)
        .collect();
    Ok(ProbeVolume {
        grid: *grid,
        lmax,
        valid,
        backfaces,
        transfer,
        emitted,
        samples: dirs.len(),
        bounces: options.bounces,
        seed: options.seed,
        rays: rays.into_inner() + surface.as_ref().map_or(0, |s| s.rays),
        scene_hash: scene.map_or(0, Mesh::content_hash),
    })
}

/// The `n x n` identity, row-major.
fn identity(n: usize) -> Vec<f64> {
    (0..n * n)
        .map(|k| if k / n == k % n { 1.0 } else { 0.0 })
        .collect()
}

/// The scene's surfaces, subdivided, with their transfer and emitted light
/// per vertex.
struct Surface {
    mesh: Mesh,
    bvh: Bvh,
    /// Per vertex `channels x nc` transfer.
    transfer: Vec<f32>,
    channels: usize,
    nc: usize,
    /// Per vertex exit radiance due to emitters.
    emitted: Option<Vec<Vec3>>,
    rays: u64,
}

impl Surface {
    fn bake(
        mesh: &Mesh,
        options: &VolumeOptions,
        progress: &(dyn Fn(Stage, usize, usize) + Sync),
    ) -> Self {
        let (lo, hi) = mesh.bounds();
        let max_edge = options
            .max_edge
            .unwrap_or((hi - lo).length() / SURFACE_DIVISIONS);
        let mesh = mesh.subdivided(max_edge);
        let albedo = match &mesh.colors {
            Some(c) => {
                Albedo::PerVertex(c.iter().map(|c| c.clamp(Vec3::ZERO, Vec3::ONE)).collect())
            }
            None => Albedo::Constant(options.albedo),
        };
        let mode = if options.bounces == 0 {
            Mode::Shadowed
        } else {
            Mode::Interreflected {
                bounces: options.bounces,
            }
        };
        let bake_options = BakeOptions {
            lmax: options.lmax,
            samples: options.surface_samples,
            mode,
            albedo,
            seed: options.seed ^ 0x5eed_5eed_5eed_5eed,
            emission: mesh.emission.clone(),
        };
        let t = transfer::bake(&mesh, &bake_options, &|stage, done, total| {
            progress(Stage::Surface(stage), done, total);
        });
        let bvh = Bvh::new(&mesh.positions, &mesh.triangles);
        Self {
            bvh,
            channels: t.channels,
            nc: sh_count(t.lmax),
            transfer: t.coeffs,
            emitted: t.emitted,
            rays: t.rays,
            mesh,
        }
    }

    /// The transfer at a hit (into `out`, 3 channels x nc, a grey transfer
    /// repeated) and its emitted light.
    fn interpolate(&self, tri: [u32; 3], w: [f32; 3], out: &mut [f64]) -> DVec3 {
        out.fill(0.0);
        let mut exit = DVec3::ZERO;
        for (&v, &wv) in tri.iter().zip(&w) {
            let wv = f64::from(wv);
            let t =
                &self.transfer[v as usize * self.channels * self.nc..][..self.channels * self.nc];
            for ch in 0..3 {
                let src = &t[ch.min(self.channels - 1) * self.nc..][..self.nc];
                for (o, s) in out[ch * self.nc..][..self.nc].iter_mut().zip(src) {
                    *o += wv * f64::from(*s);
                }
            }
            if let Some(e) = &self.emitted {
                exit += wv * e[v as usize].as_dvec3();
            }
        }
        exit
    }
}
