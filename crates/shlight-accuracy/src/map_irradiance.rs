//! [`MapIrradiance`]: a map's exact irradiance on a grid of normals, and
//! an encoding's error against it (`shlight irradiance`).
//!
//! The normals are the texel centres `n` of a `W x H` equirect grid in the
//! map's own orientation, weighted by their texels' solid angles. The
//! exact irradiance is the brute-force sum over **every** texel `k` of the
//! map, `E(n) = Σ_k L_k max(n · d_k, 0) Ω_k`
//! ([`shlight_core::map`]). An estimate `Ê` (an encoding's
//! irradiance, [`shlight_core::encoding::Encoded::irradiance_at`]) is judged by the
//! luminance `Y` of both ([`shlight_core::map::luminance`]), with
//! area-weighted means:
//!
//! - pointwise, `|Ŷ(n) - Y(n)| / max(Y(n), f Y_peak)` with the floor
//!   `f =` [`POINTWISE_FLOOR`] where the map is nearly dark
//!   ([`crate::error::pointwise_errors`]);
//! - relative to the peak, `|Ŷ(n) - Y(n)| / Y_peak`, as Ramamoorthi &
//!   Hanrahan measure it ([`crate::error::peak_relative_errors`]).

use glam::DVec3;
use shlight_core::encoding::Encoded;
use shlight_core::map::{
    EnvMap, Layout, LayoutSizeError, MapOrientation, TexelGrid, irradiance_brute_force, luminance,
};

use crate::error::{self, ErrorStats};

/// Irradiance below this fraction of its peak counts as this fraction of
/// the peak in the pointwise error (module docs).
pub const POINTWISE_FLOOR: f64 = 1e-3;

/// The exact irradiance of a map on an equirect grid of normals (module
/// docs).
#[derive(Clone, Debug, PartialEq)]
pub struct MapIrradiance {
    /// The normals: texel centres of the grid, row-major.
    pub normals: Vec<DVec3>,
    /// The solid angle of each normal's texel.
    pub weights: Vec<f64>,
    /// `E(n)` at each normal.
    pub exact: Vec<DVec3>,
}

/// An estimate's errors against [`MapIrradiance::exact`] (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IrradianceErrors {
    /// Relative to `E(n)` (floored at [`POINTWISE_FLOOR`] of the peak).
    pub pointwise: ErrorStats,
    /// Relative to the peak of `E`.
    pub peak_relative: ErrorStats,
}

impl MapIrradiance {
    /// The exact irradiance of `map` at the texel centres of a `size`
    /// equirect grid read in `orientation` (normally the map's), in
    /// parallel; `progress(n)` is called as `n` more normals are done.
    ///
    /// # Errors
    /// An empty grid.
    pub fn on_equirect(
        map: &EnvMap<'_>,
        size: (usize, usize),
        orientation: MapOrientation,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, LayoutSizeError> {
        let grid = TexelGrid::new(Layout::Equirect, size, orientation)?;
        let w = grid.width();
        let n = w * grid.height();
        let normals: Vec<DVec3> = (0..n)
            .map(|k| {
                grid.direction(k % w, k / w)
                    .expect("equirect texels all look somewhere")
            })
            .collect();
        let weights = grid.solid_angles();
        let exact = irradiance_brute_force(map, &normals, progress);
        Ok(Self {
            normals,
            weights,
            exact,
        })
    }

    /// `encoded`'s irradiance at the normals.
    #[must_use]
    pub fn estimate(&self, encoded: &Encoded) -> Vec<DVec3> {
        encoded.irradiance_at(&self.normals)
    }

    /// `estimate - exact` at each normal.
    #[must_use]
    pub fn difference(&self, estimate: &[DVec3]) -> Vec<DVec3> {
        estimate
            .iter()
            .zip(&self.exact)
            .map(|(s, e)| *s - *e)
            .collect()
    }

    /// `|Ŷ(n) - Y(n)| / Y_peak` at each normal (the values
    /// [`IrradianceErrors::peak_relative`] summarises, for an error map);
    /// `None` when the map has no light.
    #[must_use]
    pub fn peak_relative_map(&self, estimate: &[DVec3]) -> Option<Vec<f64>> {
        let reference: Vec<f64> = self.exact.iter().map(|e| luminance(*e)).collect();
        let estimate: Vec<f64> = estimate.iter().map(|e| luminance(*e)).collect();
        (error::peak(&reference) > 0.0).then(|| error::peak_relative_errors(&estimate, &reference))
    }

    /// The errors of `estimate` (one value per normal); `None` when the map
    /// has no light (the exact luminance is nowhere positive), where no
    /// relative error exists.
    #[must_use]
    pub fn errors(&self, estimate: &[DVec3]) -> Option<IrradianceErrors> {
        let reference: Vec<f64> = self.exact.iter().map(|e| luminance(*e)).collect();
        let estimate: Vec<f64> = estimate.iter().map(|e| luminance(*e)).collect();
        if error::peak(&reference) <= 0.0 {
            return None;
        }
        Some(IrradianceErrors {
            pointwise: ErrorStats::weighted(
                &error::pointwise_errors(&estimate, &reference, POINTWISE_FLOOR),
                &self.weights,
            ),
            peak_relative: ErrorStats::weighted(
                &error::peak_relative_errors(&estimate, &reference),
                &self.weights,
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use shlight_core::encoding::{DominantLightOptions, Encoding, encode_map};
    use shlight_core::sh::Frame;

    fn uniform(w: usize, h: usize) -> Vec<[f32; 3]> {
        vec![[1.0, 0.5, 0.25]; w * h]
    }

    /// A uniform sky of radiance `c` gives `E = π c` at every normal (to
    /// the texel sum's O(h²)); the weights cover the sphere; SH of any
    /// lmax holds it exactly, so its errors are the brute force's own.
    #[test]
    fn a_uniform_sky_gives_pi_everywhere() {
        let o = MapOrientation {
            frame: Frame::ZUp,
            mirror: true,
        };
        let (w, h) = (64, 32);
        let px = uniform(w, h);
        let map = EnvMap::new(Layout::Equirect, o, w, h, &px).unwrap();
        let done = std::sync::atomic::AtomicUsize::new(0);
        let m = MapIrradiance::on_equirect(&map, (16, 8), o, &|n| {
            done.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        })
        .unwrap();
        assert_eq!(done.into_inner(), 16 * 8);
        assert_eq!(m.normals.len(), 16 * 8);
        assert!((m.weights.iter().sum::<f64>() - 4.0 * PI).abs() < 1e-12);
        let want = DVec3::new(1.0, 0.5, 0.25) * PI;
        for e in &m.exact {
            // Measured 9e-4 relative at 32 rows.
            assert!(((*e - want) / want).abs().max_element() < 2e-3, "{e}");
        }
        let encoded = encode_map(&map, Encoding::Sh, 2, &DominantLightOptions::default());
        let estimate = m.estimate(&encoded);
        let errors = m.errors(&estimate).unwrap();
        assert!(errors.pointwise.max < 2e-3, "{errors:?}");
        assert!(errors.peak_relative.max <= errors.pointwise.max + 1e-15);
        let diff = m.difference(&estimate);
        for k in 0..diff.len() {
            assert_eq!(diff[k], estimate[k] - m.exact[k]);
        }
    }

    /// An estimate 1% too bright everywhere errs by exactly 1% pointwise,
    /// and by at most 1% of the peak; a dark map has no relative error.
    #[test]
    fn errors_are_relative_and_a_dark_map_has_none() {
        let o = MapOrientation::default();
        let (w, h) = (32, 16);
        let px: Vec<[f32; 3]> = (0..w * h)
            .map(|k| [1.0 + (k / w) as f32, 1.0, 1.0])
            .collect();
        let map = EnvMap::new(Layout::Equirect, o, w, h, &px).unwrap();
        let m = MapIrradiance::on_equirect(&map, (8, 4), o, &|_| {}).unwrap();
        let brighter: Vec<DVec3> = m.exact.iter().map(|e| *e * 1.01).collect();
        let errors = m.errors(&brighter).unwrap();
        assert!((errors.pointwise.mean - 0.01).abs() < 1e-12, "{errors:?}");
        assert!((errors.pointwise.max - 0.01).abs() < 1e-12, "{errors:?}");
        assert!(errors.peak_relative.max <= 0.01 + 1e-12 && errors.peak_relative.max > 0.005);
        // The error map holds the values the statistics summarise: 1% of
        // each normal's luminance over the peak's.
        let map_values = m.peak_relative_map(&brighter).unwrap();
        let lum: Vec<f64> = m.exact.iter().map(|e| luminance(*e)).collect();
        let peak = lum.iter().copied().fold(0.0, f64::max);
        for (v, l) in map_values.iter().zip(&lum) {
            assert!((v - 0.01 * l / peak).abs() < 1e-12);
        }
        let max = map_values.iter().copied().fold(0.0, f64::max);
        assert!((max - errors.peak_relative.max).abs() < 1e-15);
        let dark = vec![[0.0f32; 3]; w * h];
        let map = EnvMap::new(Layout::Equirect, o, w, h, &dark).unwrap();
        let m = MapIrradiance::on_equirect(&map, (8, 4), o, &|_| {}).unwrap();
        assert_eq!(m.errors(&m.exact.clone()), None);
        assert_eq!(m.peak_relative_map(&m.exact.clone()), None);
        assert!(MapIrradiance::on_equirect(&map, (0, 4), o, &|_| {}).is_err());
    }
}
