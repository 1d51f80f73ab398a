//! Brute-force irradiance of an environment map: the ground truth that SH
//! irradiance is compared against.

use glam::DVec3;

use crate::map::layout::env_map::EnvMap;

/// Normals per unit of parallel work (and per progress report).
const NORMALS_PER_TASK: usize = 64;

/// The texels of a map that hold a direction, as structure-of-arrays:
/// directions, and radiance times solid angle `L_k Ω_k` per channel.
#[derive(Clone, Debug, Default)]
pub struct TexelSet {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    /// `L_k Ω_k`, red, green, blue.
    weighted: [Vec<f64>; 3],
}

impl TexelSet {
    /// Every texel of `map` with a direction and a positive solid angle
    /// ([`EnvMap::texel_direction`], [`EnvMap::texel_solid_angles`]).
    #[must_use]
    pub fn from_map(map: &EnvMap<'_>) -> Self {
        let omega = map.texel_solid_angles();
        let mut set = Self::default();
        for y in 0..map.height {
            for x in 0..map.width {
                let w = omega[y * map.width + x];
                let Some(d) = map.texel_direction(x, y) else {
                    continue;
                };
                if w <= 0.0 {
                    continue;
                }
                let l = map.pixels[y * map.width + x];
                set.push(d, DVec3::from(l.map(f64::from)) * w);
            }
        }
        set
    }

    /// Adds one texel: unit direction `d` and radiance times solid angle.
    pub fn push(&mut self, d: DVec3, weighted: DVec3) {
        self.x.push(d.x);
        self.y.push(d.y);
        self.z.push(d.z);
        for (c, v) in self.weighted.iter_mut().zip(weighted.to_array()) {
            c.push(v);
        }
    }

    /// Texels held.
    #[must_use]
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when no texel is held.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// `E(n) = Σ_k (L_k Ω_k) max(n · d_k, 0)` for one normal `n` (unit).
    #[must_use]
    pub fn irradiance(&self, n: DVec3) -> DVec3 {
        const LANES: usize = 8;
        let [r, g, b] = &self.weighted;
        let mut acc = [[0.0f64; LANES]; 3];
        let chunks = self
            .x
            .chunks_exact(LANES)
            .zip(self.y.chunks_exact(LANES))
            .zip(self.z.chunks_exact(LANES))
            .zip(r.chunks_exact(LANES))
            .zip(g.chunks_exact(LANES))
            .zip(b.chunks_exact(LANES));
        for (((((x, y), z), r), g), b) in chunks {
            for i in 0..LANES {
                let c = (n.x * x[i] + n.y * y[i] + n.z * z[i]).max(0.0);
                acc[0][i] += c * r[i];
                acc[1][i] += c * g[i];
                acc[2][i] += c * b[i];
            }
        }
        let mut e = acc.map(|lanes| lanes.iter().sum::<f64>());
        for j in self.len() - self.len() % LANES..self.len() {
            let c = (n.x * self.x[j] + n.y * self.y[j] + n.z * self.z[j]).max(0.0);
            e[0] += c * r[j];
            e[1] += c * g[j];
            e[2] += c * b[j];
        }
        DVec3::from(e)
    }

    /// [`TexelSet::irradiance`] at every normal, in parallel with the
    /// `rayon` feature. `progress` is called with the number of normals
    /// finished since its last call (from any thread), so a progress bar
    /// can advance by it.
    #[must_use]
    pub fn irradiance_at(
        &self,
        normals: &[DVec3],
        progress: &(dyn Fn(usize) + Sync),
    ) -> Vec<DVec3> {
        let mut out = vec![DVec3::ZERO; normals.len()];
        let task = |(dst, src): (&mut [DVec3], &[DVec3])| {
            for (e, n) in dst.iter_mut().zip(src) {
                *e = self.irradiance(*n);
            }
            progress(src.len());
        };
        #[cfg(feature = "rayon")]
        {
            use rayon::prelude::*;
            out.par_chunks_mut(NORMALS_PER_TASK)
                .zip(normals.par_chunks(NORMALS_PER_TASK))
                .for_each(task);
        }
        #[cfg(not(feature = "rayon"))]
        out.chunks_mut(NORMALS_PER_TASK)
            .zip(normals.chunks(NORMALS_PER_TASK))
            .for_each(task);
        out
    }
}

/// The exact (brute-force) irradiance of `map` at each unit normal:
/// `E(n) = Σ_k L_k max(n · d_k, 0) Ω_k` over every texel (below).
/// `progress` receives the number of normals done, in steps.
///
/// ```
/// use glam::DVec3;
/// use shlight_core::map::{EnvMap, Layout, MapOrientation, irradiance_brute_force, render_map};
///
/// let o = MapOrientation::default();
/// let px = render_map(Layout::Equirect, o, 64, 32, |_| DVec3::ONE).unwrap();
/// let map = EnvMap::new(Layout::Equirect, o, 64, 32, &px).unwrap();
/// let e = irradiance_brute_force(&map, &[DVec3::Y], &|_| {});
/// // A uniform sky of radiance 1 gives E = π everywhere, to the rule's O(h²)
/// // (9e-4 relative on 32 rows).
/// assert!((e[0].x / std::f64::consts::PI - 1.0).abs() < 2e-3);
/// ```
///
/// For a map of texels with radiance `L_k`, centre direction `d_k` and exact
/// solid angle `Ω_k` (any [`Layout`](crate::map::Layout), through
/// [`EnvMap`]), the irradiance on a surface with unit normal `n` is the
/// cosine-weighted sum over **every** texel
///
/// ```text
/// E(n) = Σ_k L_k max(n · d_k, 0) Ω_k
/// ```
///
/// accumulated in `f64`: `O(texels)` per normal, with no truncation in
/// angular frequency. It is the same texel-centre quadrature that
/// [`crate::map::project_map`] uses, applied to the clamped cosine
/// instead of `Y_l^m`, so its only error is that rule's: `O(h²)` in the
/// texel size where the map is smooth, and the cosine's kink at the horizon
/// of `n`, which moves the result by at most one ring of texels' worth
/// (`O(h)`, tiny next to the kink's own small weight there).
///
/// Normals are processed in parallel with the `rayon` feature, each summed
/// over the texels in eight `f64` lanes (which the compiler vectorises).
#[must_use]
pub fn irradiance_brute_force(
    map: &EnvMap<'_>,
    normals: &[DVec3],
    progress: &(dyn Fn(usize) + Sync),
) -> Vec<DVec3> {
    TexelSet::from_map(map).irradiance_at(normals, progress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::layout::kind::Layout;
    use crate::map::orientation::MapOrientation;
    use crate::map::render::render_map;
    use crate::sh::quadrature::fibonacci_sphere;
    use core::f64::consts::PI;

    /// A uniform upper hemisphere about the map's up axis (+Y), whose edge
    /// lies on a row boundary of an even-height equirect map, so every
    /// texel is exactly lit or dark: `E(n) = π (1 + n_y) / 2`
    /// (sh-reference 4b), computed independently of the sum.
    #[test]
    fn hemisphere_matches_the_closed_form_and_converges_as_h_squared() {
        let o = MapOrientation::default();
        let normals: Vec<DVec3> = fibonacci_sphere(500).into_iter().collect();
        let mut errors = Vec::new();
        for (w, h) in [(64, 32), (128, 64), (256, 128)] {
            let px = render_map(Layout::Equirect, o, w, h, |d| {
                DVec3::splat(if d.y > 0.0 { 1.0 } else { 0.0 })
            })
            .unwrap();
            let map = EnvMap::new(Layout::Equirect, o, w, h, &px).unwrap();
            let done = std::sync::atomic::AtomicUsize::new(0);
            let e = irradiance_brute_force(&map, &normals, &|k| {
                done.fetch_add(k, std::sync::atomic::Ordering::Relaxed);
            });
            assert_eq!(
                done.into_inner(),
                normals.len(),
                "progress counts every normal"
            );
            let worst = normals
                .iter()
                .zip(&e)
                .map(|(n, e)| (e.x - PI * (1.0 + n.y) / 2.0).abs() / PI)
                .fold(0.0f64, f64::max);
            errors.push(worst);
        }
        // Measured 8.8e-4, 2.2e-4, 5.5e-5: the midpoint rule's h².
        assert!(errors[0] < 2e-3, "{errors:?}");
        for k in 1..errors.len() {
            let ratio = errors[k - 1] / errors[k];
            assert!((3.0..5.0).contains(&ratio), "not O(h²): {errors:?}");
        }
    }

    #[test]
    fn every_layout_sums_a_constant_sky_to_pi() {
        let o = MapOrientation::default();
        for layout in [Layout::CrossHorizontal, Layout::Angular, Layout::MirrorBall] {
            let (w, h) = layout.dimensions(if layout.is_cube() { 32 } else { 128 });
            let px = render_map(layout, o, w, h, |_| DVec3::new(1.0, 2.0, 0.5)).unwrap();
            let map = EnvMap::new(layout, o, w, h, &px).unwrap();
            let n = DVec3::new(0.3, -0.5, 0.8).normalize();
            let e = irradiance_brute_force(&map, &[n], &|_| {});
            let want = DVec3::new(1.0, 2.0, 0.5) * PI;
            assert!((e[0] - want).abs().max_element() < 1e-2, "{layout}: {e:?}");
        }
    }
}
