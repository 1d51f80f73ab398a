//! Light gathered at points on a scene's surfaces, facing their normals:
//! what a lightmap's texel holds ([`gather_at_surface_points`]).

use std::f64::consts::PI;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use shlight_core::sh::{ShBasis, ShCoeffs, sh_count};
use shlight_mesh::{PunctualLight, Surfaces};
use shlight_rays::{OFFSET, Ray, SHORTER_OFFSETS};

use super::{Stage, Surface, VolumeOptions, check_options, relocate};
use crate::error::VolumeError;

/// A point on a scene's surface where light is gathered, and the side it
/// is gathered on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// Position in world space, on the surface.
    pub position: Vec3,
    /// Unit normal of the side the light arrives on.
    pub normal: Vec3,
    /// The point's own number (a texel's index in its lightmap): it alone,
    /// with the bake's seed, jitters the point's rays, so that a point
    /// gets the same light in whatever call and company it is gathered.
    pub id: u64,
}

/// The light arriving at a [`SurfacePoint`] from the hemisphere its normal
/// faces (nothing from below the surface).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceLight {
    /// Irradiance for the point's normal `n`, per channel:
    /// `E = int_{n.s > 0} L(s) (n . s) ds`.
    pub irradiance: DVec3,
    /// The radiance arriving from the hemisphere projected to lmax 1,
    /// `c_lm = int_{n.s > 0} L(s) Y_lm(s) ds`, at index `l(l+1)+m` (real
    /// orthonormal SH with the Condon-Shortley phase, shlight's basis).
    pub sh: [DVec3; 4],
    /// The fraction of the point's rays that met the back of a one-sided
    /// surface: a point inside geometry sees mostly back faces.
    pub backfaces: f32,
}

/// What [`gather_at_surface_points`] gathered.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfacePointsBake {
    /// Per point, in the order given.
    pub light: Vec<SurfaceLight>,
    /// Rays per point (a whole stratified grid: the nearest square to
    /// [`VolumeOptions::samples`]).
    pub samples: usize,
    /// Rays cast in all: the surfaces' and the points'.
    pub rays: u64,
}

/// Gathers the light arriving at each of `points` on `surfaces`, lit by
/// the environment `env` (radiance SH; its coefficients to
/// [`VolumeOptions::lmax`] are read) and the punctual `lights`, as a
/// lightmap holds it: the irradiance for the point's normal and the lmax-1
/// SH of the radiance from its hemisphere ([`SurfaceLight`]).
///
/// The surfaces are baked as [`bake_surfaces`](super::bake_surfaces)
/// bakes them (their interreflected light from the environment, emitters
/// and lights, with [`VolumeOptions::bounces`] and
/// [`VolumeOptions::surface_samples`]) and lit by `env`; then each point
/// casts `N = k^2` rays over its hemisphere, stratified in `(cos theta,
/// phi)` (equal-area cells, one jittered direction in each), each of
/// weight `w = 2 pi / N`, with the mean radiance of its rays `Lbar` as a
/// control variate: `E ~ w sum L(s) cos theta + Lbar (pi - w sum cos
/// theta)` and `c_lm ~ w sum L(s) Y_lm(s) + Lbar (int Y_lm - w sum
/// Y_lm(s))`, the hemisphere's integrals being `2 pi Y_00` and `pi
/// Y_1m(n)`, so that light of one radiance over the hemisphere is
/// gathered exactly and the noise comes from its variation alone. A ray that escapes brings `env` in its direction; one
/// that meets the front of a surface (or either face of a double-sided
/// one) at `q` brings `Le(q) + rho(q) F(q)`, the emission there plus the
/// albedo of the texel there times the light arriving, interpolated from
/// the subdivided surfaces' vertices; one that meets the back of a
/// one-sided surface brings nothing and counts in
/// [`SurfaceLight::backfaces`]. Each punctual light adds its delta exactly:
/// where its shadow ray reaches it and it is in front of the surface,
/// `E_perp (n . toward)` to the irradiance and `E_perp Y_lm(toward)` to the
/// SH.
///
/// Rays start at `p + eps n`, `eps` being [`shlight_rays::OFFSET`] times
/// the scene's diagonal, shortened (by quarters, up to
/// [`shlight_rays::SHORTER_OFFSETS`] times) while the step from the
/// surface would cross another one: a point at a wall's foot starts on
/// its own side of the wall. A point's jitter comes from
/// [`VolumeOptions::seed`] and its [`SurfacePoint::id`] alone, and its sums
/// run in a fixed order in `f64`: the same bits at any thread count and
/// for any split of the points into calls.
///
/// `progress(stage, done, total)`: the surfaces' stages, then
/// [`Stage::Points`] in points.
///
/// # Errors
/// The options [`bake()`](super::bake) refuses, and a point or normal that
/// is not finite (naming it).
pub fn gather_at_surface_points(
    surfaces: &Arc<Surfaces>,
    lights: &[PunctualLight],
    env: &ShCoeffs<DVec3>,
    points: &[SurfacePoint],
    options: &VolumeOptions,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<SurfacePointsBake, VolumeError> {
    check_options(options)?;
    super::check_max_edge(&surfaces.mesh, options.max_edge)?;
    if let Some((i, p)) = points
        .iter()
        .enumerate()
        .find(|(_, p)| !p.position.is_finite() || !p.normal.is_finite())
    {
        return Err(VolumeError::Options(format!(
            "surface point {i} is not finite ({:?} facing {:?})",
            p.position, p.normal
        )));
    }
    let (surface, _) = Surface::bake(
        &surfaces.mesh,
        Some(surfaces),
        lights,
        options,
        None,
        progress,
    );
    let nc = sh_count(options.lmax);
    let light: Vec<DVec3> = (0..nc)
        .map(|i| env.as_slice().get(i).copied().unwrap_or(DVec3::ZERO))
        .collect();
    let env_basis = ShBasis::<f64>::new(options.lmax);
    let exit = surface.exit_light(&light);
    let side = (options.samples as f64).sqrt().round().max(1.0) as usize;
    let samples = side * side;
    let (lo, hi) = surface.mesh.bounds();
    let eps = OFFSET * (hi - lo).length();
    let gather = Gather {
        surface: &surface,
        surfaces,
        exit: &exit,
        lights,
        options,
        light: &light,
        env_basis: &env_basis,
        side,
        eps,
    };
    let done = AtomicUsize::new(0);
    let total = points.len();
    progress(Stage::Points, 0, total);
    let mut out = vec![
        SurfaceLight {
            irradiance: DVec3::ZERO,
            sh: [DVec3::ZERO; 4],
            backfaces: 0.0,
        };
        points.len()
    ];
    const CHUNK: usize = 64;
    out.par_chunks_mut(CHUNK)
        .zip(points.par_chunks(CHUNK))
        .for_each_init(
            || (ShBasis::<f64>::new(1), vec![0.0f64; nc]),
            |(l1, ylm), (out, points)| {
                for (o, p) in out.iter_mut().zip(points) {
                    *o = gather.point(p, l1, ylm);
                }
                let len = points.len();
                progress(
                    Stage::Points,
                    done.fetch_add(len, Ordering::Relaxed) + len,
                    total,
                );
            },
        );
    Ok(SurfacePointsBake {
        light: out,
        samples,
        rays: surface.rays + (samples * points.len()) as u64,
    })
}

/// What every point's gather reads.
struct Gather<'a> {
    surface: &'a Surface,
    surfaces: &'a Surfaces,
    /// Per vertex of the two-sided subdivided mesh: the light arriving over
    /// pi (before the albedo at a hit), and the emitted radiance.
    exit: &'a [[Vec3; 2]],
    lights: &'a [PunctualLight],
    options: &'a VolumeOptions,
    /// The environment's coefficients to the bake's lmax.
    light: &'a [DVec3],
    env_basis: &'a ShBasis<f64>,
    side: usize,
    eps: f32,
}

impl Gather<'_> {
    /// The light at `p`.
    fn point(&self, p: &SurfacePoint, l1: &ShBasis<f64>, ylm: &mut [f64]) -> SurfaceLight {
        let n = p.normal.normalize_or(Vec3::Y);
        let origin = self.origin(p.position, n);
        let (t1, t2) = n.any_orthonormal_pair();
        let mut rng = SplitMix::new(self.options.seed, p.id);
        let k = self.side;
        let w = 2.0 * PI / (k * k) as f64;
        // Sums over every ray: of L cos and L Y (the estimates), of L (its
        // mean is the control variate's constant), of cos and Y (whose
        // integrals over the hemisphere are known).
        let (mut l_cos, mut l_y, mut l_sum) = (DVec3::ZERO, [DVec3::ZERO; 4], DVec3::ZERO);
        let (mut cos_sum, mut y_sum, mut backs) = (0.0f64, [0.0f64; 4], 0usize);
        let mut y1 = [0.0f64; 4];
        for i in 0..k {
            for j in 0..k {
                let cos = (i as f64 + rng.next_f64()) / k as f64;
                let phi = 2.0 * PI * (j as f64 + rng.next_f64()) / k as f64;
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let s = (t1.as_dvec3() * (sin * phi.cos())
                    + t2.as_dvec3() * (sin * phi.sin())
                    + n.as_dvec3() * cos)
                    .normalize();
                l1.eval(s, &mut y1);
                cos_sum += cos;
                for (a, y) in y_sum.iter_mut().zip(&y1) {
                    *a += *y;
                }
                let radiance = self.radiance(origin, s, ylm).unwrap_or_else(|| {
                    backs += 1;
                    DVec3::ZERO
                });
                l_sum += radiance;
                l_cos += radiance * cos;
                for (a, y) in l_y.iter_mut().zip(&y1) {
                    *a += radiance * *y;
                }
            }
        }
        // The control variate: the mean radiance times the error of the
        // same rays' estimate of int cos = pi and int Y_lm (2 pi Y_00, and
        // pi Y_1m(n) for l = 1), so that light of one radiance over the
        // hemisphere is gathered exactly.
        let mean = l_sum / (k * k) as f64;
        l1.eval(n.as_dvec3(), &mut y1);
        let exact_y = [2.0 * PI * y1[0], PI * y1[1], PI * y1[2], PI * y1[3]];
        let mut e = l_cos * w + mean * (PI - w * cos_sum);
        let mut sh = [DVec3::ZERO; 4];
        for m in 0..4 {
            sh[m] = l_y[m] * w + mean * (exact_y[m] - w * y_sum[m]);
        }
        for light in self.lights {
            let Some(a) = light.arriving(p.position, self.options.light_units) else {
                continue;
            };
            let cos = f64::from(n.dot(a.toward));
            if cos <= 0.0
                || !shlight_prt::light_reaches(Some(&self.surface.occluder), p.position, origin, &a)
            {
                continue;
            }
            let perp = a.irradiance.as_dvec3();
            e += perp * cos;
            l1.eval(a.toward.as_dvec3(), &mut y1);
            for (c, y) in sh.iter_mut().zip(&y1) {
                *c += perp * *y;
            }
        }
        SurfaceLight {
            irradiance: e,
            sh,
            backfaces: backs as f32 / (k * k) as f32,
        }
    }

    /// Where the rays of a point at `p` facing `n` start: `p + eps n`,
    /// shortened while the step would cross a surface.
    fn origin(&self, p: Vec3, n: Vec3) -> Vec3 {
        const OWN_TRIANGLES: f32 = 1e-3;
        let mut offset = self.eps * n;
        for _ in 0..SHORTER_OFFSETS {
            let start = p + OWN_TRIANGLES * offset;
            if !self
                .surface
                .occluder
                .occluded(&Ray::new(start, offset, 1.0 - OWN_TRIANGLES))
            {
                break;
            }
            offset *= 0.25;
        }
        p + offset
    }

    /// The radiance arriving at `origin` from direction `s`; `None` when
    /// the ray meets the back of a one-sided surface.
    fn radiance(&self, origin: Vec3, s: DVec3, ylm: &mut [f64]) -> Option<DVec3> {
        let dir = s.as_vec3();
        let surface = self.surface;
        let Some(hit) = surface
            .occluder
            .closest_hit(&Ray::new(origin, dir, f32::INFINITY))
        else {
            self.env_basis.eval(s, ylm);
            return Some(
                self.light
                    .iter()
                    .zip(ylm.iter())
                    .map(|(c, y)| *c * *y)
                    .sum(),
            );
        };
        let back = !surface.occluder.is_front(hit.triangle, dir);
        if back && !relocate::double_sided(&surface.double, hit.triangle) {
            return None;
        }
        let (triangle, [_, b1, b2]) = surface.map.locate(hit.triangle, hit.barycentrics)?;
        let (triangle, b1, b2) = match &surface.sides {
            Some(sides) if back => sides
                .back_hit(triangle, b1, b2)
                .unwrap_or((triangle, b1, b2)),
            _ => (triangle, b1, b2),
        };
        let corners = surface.mesh.triangles[triangle as usize];
        let weights = [1.0 - b1 - b2, b1, b2];
        let (mut arriving, mut emitted) = (DVec3::ZERO, DVec3::ZERO);
        for (&v, &w) in corners.iter().zip(&weights) {
            let [a, le] = self.exit[v as usize];
            arriving += a.as_dvec3() * f64::from(w);
            emitted += le.as_dvec3() * f64::from(w);
        }
        let rho = self
            .surfaces
            .reflectance(hit.triangle, hit.barycentrics)
            .as_dvec3();
        Some(emitted + rho * arriving)
    }
}

/// SplitMix64 (Steele, Lea & Flood 2014): a point's own stream of
/// uniform numbers, from the bake's seed and the point's index.
struct SplitMix(u64);

impl SplitMix {
    fn new(seed: u64, index: u64) -> Self {
        let mut s = SplitMix(seed ^ 0x243f_6a88_85a3_08d3);
        let mixed = s.next_u64() ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15);
        SplitMix(mixed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`, 53 bits.
    fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

impl Surface {
    /// Per vertex of the two-sided subdivided mesh, under the environment
    /// `light` (coefficients to the bake's lmax): `[G . L + F, Le]`, the
    /// light arriving over pi and the emitted radiance, so that a hit of
    /// albedo `rho` leaves `Le + rho (G . L + F)`.
    fn exit_light(&self, light: &[DVec3]) -> Vec<[Vec3; 2]> {
        let floats = self.records.floats();
        let (rec, used) = (self.records.stride(), self.records.used());
        let (channels, nc) = (self.channels, self.nc);
        let stride = channels * nc;
        (0..self.mesh.vertex_count())
            .into_par_iter()
            .map(|v| {
                let r = &floats[v * rec..][..used];
                let mut arriving = DVec3::ZERO;
                for c in 0..3 {
                    let g = &r[if channels == 1 { 0 } else { c * nc }..][..nc];
                    arriving[c] = g.iter().zip(light).map(|(g, l)| f64::from(*g) * l[c]).sum();
                }
                if used >= stride + 6 {
                    let le = Vec3::from_slice(&r[stride..stride + 3]);
                    let f = Vec3::from_slice(&r[stride + 3..stride + 6]);
                    [(arriving + f.as_dvec3()).as_vec3(), le]
                } else {
                    [arriving.as_vec3(), Vec3::ZERO]
                }
            })
            .collect()
    }
}
