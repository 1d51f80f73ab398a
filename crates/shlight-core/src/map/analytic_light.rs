//! [`AnalyticLight`]: the radiance of the simple lights whose SH
//! coefficients are known in closed form ([`crate::sh::closed_form`]): the lights
//! `shlight synth` draws as maps to test projections against.

use glam::DVec3;

use crate::sh::closed_form;
use crate::sh::sh_coeffs::ShCoeffs;

/// A light of closed-form radiance and coefficients (below).
///
/// - constant: `L(d) = c`;
/// - cap: `L(d) = c` where `d · axis >= cos α`, else 0 (`α = π/2` is the
///   hemisphere about `axis`); the edge belongs to the cap;
/// - gradient: `L(d) = a + b (d · axis)`, band-limited to degree 1.
///
/// Colours are linear RGB; `axis` is a unit world direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnalyticLight {
    /// The same radiance in every direction.
    Constant(DVec3),
    /// `radiance` inside the cap `d · axis >= cos_half` about unit `axis`,
    /// 0 outside; `cos_half = 0` is the hemisphere.
    Cap {
        /// The cap's unit axis.
        axis: DVec3,
        /// Cosine of the half-angle.
        cos_half: f64,
        /// Radiance inside.
        radiance: DVec3,
    },
    /// `a + b (d · axis)` about unit `axis`.
    Gradient {
        /// Unit axis (a sky gradient when it is up).
        axis: DVec3,
        /// The mean.
        a: DVec3,
        /// The slope along `axis`.
        b: DVec3,
    },
}

impl AnalyticLight {
    /// The radiance arriving from unit direction `d`.
    #[must_use]
    pub fn radiance(&self, d: DVec3) -> DVec3 {
        match *self {
            AnalyticLight::Constant(v) => v,
            AnalyticLight::Cap {
                axis,
                cos_half,
                radiance,
            } => {
                if d.dot(axis) >= cos_half {
                    radiance
                } else {
                    DVec3::ZERO
                }
            }
            AnalyticLight::Gradient { axis, a, b } => a + b * d.dot(axis),
        }
    }

    /// Its exact radiance coefficients to `lmax`: [`closed_form::constant`],
    /// [`closed_form::cap`] (half-angle `acos(cos_half)`) or
    /// [`closed_form::linear_gradient`].
    #[must_use]
    pub fn coefficients(&self, lmax: usize) -> ShCoeffs<DVec3> {
        match *self {
            AnalyticLight::Constant(v) => closed_form::constant(lmax, v),
            AnalyticLight::Cap {
                axis,
                cos_half,
                radiance,
            } => closed_form::cap(lmax, axis, cos_half.clamp(-1.0, 1.0).acos(), radiance),
            AnalyticLight::Gradient { axis, a, b } => {
                closed_form::linear_gradient(lmax, axis, a, b)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::layout::env_map::EnvMap;
    use crate::map::layout::kind::Layout;
    use crate::map::layout::texel_grid::TexelGrid;
    use crate::map::orientation::MapOrientation;
    use crate::map::projection::project_map;
    use crate::map::texel_means::texel_means;
    use crate::test_util::max_diff;

    #[test]
    fn radiance_is_the_definition() {
        let axis = DVec3::new(0.0, 0.6, 0.8);
        let c = DVec3::new(1.0, 2.0, 3.0);
        let cap = AnalyticLight::Cap {
            axis,
            cos_half: 0.5,
            radiance: c,
        };
        assert_eq!(cap.radiance(axis), c);
        // Half-angle 60°: lit at 59.9° from the axis, dark at 60.1°.
        let turn = |deg: f64| glam::DQuat::from_rotation_x(deg.to_radians()) * axis;
        assert_eq!(cap.radiance(turn(59.9)), c);
        assert_eq!(cap.radiance(turn(60.1)), DVec3::ZERO);
        assert_eq!(cap.radiance(-axis), DVec3::ZERO);
        let g = AnalyticLight::Gradient {
            axis,
            a: c,
            b: DVec3::ONE,
        };
        assert_eq!(g.radiance(axis), c + 1.0);
        assert_eq!(g.radiance(-axis), c - 1.0);
        assert_eq!(AnalyticLight::Constant(c).radiance(-axis), c);
    }

    /// Drawn as texel means on an equirect map and projected by
    /// quadrature, each light gives its closed-form coefficients. `L_0^0`
    /// is the light's power, `Σ mean_k Ω_k`: exact (to `f32`) for the
    /// constant, the gradient about the pole (`Σ_rows (z_0² - z_1²)`
    /// telescopes to 0) and the hemisphere about the pole (its edge on a
    /// row boundary); for a tilted cap only its edge texels err. The
    /// higher coefficients carry the quadrature's own `O(h²)` error
    /// (measured 7e-4 for every light here at 128x64).
    #[test]
    fn texel_means_project_to_the_closed_forms() {
        let (w, h) = (128, 64);
        let o = MapOrientation::default();
        let grid = TexelGrid::new(Layout::Equirect, (w, h), o).unwrap();
        let tilted = DVec3::new(0.3, 0.8, -0.5).normalize();
        let c = DVec3::new(1.0, 0.5, 0.25);
        let cases = [
            (AnalyticLight::Constant(c), 1e-6),
            (
                AnalyticLight::Gradient {
                    axis: grid.up(),
                    a: c,
                    b: 0.5 * c,
                },
                1e-6,
            ),
            (
                AnalyticLight::Cap {
                    axis: grid.up(),
                    cos_half: 0.0,
                    radiance: c,
                },
                1e-6,
            ),
            (
                AnalyticLight::Cap {
                    axis: tilted,
                    cos_half: 40f64.to_radians().cos(),
                    radiance: c,
                },
                // Edge texels, 4x4 points each.
                1e-3,
            ),
        ];
        for (light, power_tolerance) in cases {
            let px = texel_means(&grid, 4, |d| light.radiance(d), &|_| {});
            let map = EnvMap::new(Layout::Equirect, o, w, h, &px).unwrap();
            let got = project_map(&map, 3);
            let want = light.coefficients(3);
            let power = ((got[0] - want[0]) / want[0]).abs().max_element();
            assert!(power < power_tolerance, "{light:?}: L00 {power}");
            let err = max_diff(got.as_slice(), want.as_slice());
            assert!(err < 2e-3, "{light:?}: {err}");
        }
    }
}
