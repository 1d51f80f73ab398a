//! The ambient cube: six colours, one per axis direction, blended by the
//! squared normal (J. Mitchell, G. McTaggart, C. Green, *Shading in Valve's
//! Source Engine*, SIGGRAPH 2006 course, slide 28 "Ambient Cube Basis";
//! what Bevy's irradiance volumes store and look up in
//! `bevy_pbr/src/light_probe/irradiance_volume.wgsl`).

use glam::DVec3;

use crate::encoding::channel_values::{from_f64, to_f64};
use crate::sh::real::Real;
use crate::sh::real::dir_f64;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// The axis directions in the order the colours are kept: `+x, -x, +y, -y, +z, -z`.
pub const AMBIENT_CUBE_AXES: [DVec3; 6] = [
    DVec3::X,
    DVec3::NEG_X,
    DVec3::Y,
    DVec3::NEG_Y,
    DVec3::Z,
    DVec3::NEG_Z,
];

/// Six irradiance colours, in [`AMBIENT_CUBE_AXES`] order.
///
/// ```text
/// E(n) = n_x² C[x] + n_y² C[y] + n_z² C[z],
/// C[x] = C_{+x} if n_x >= 0 else C_{-x}  (likewise y, z)
/// ```
///
/// The weights `n_i²` sum to 1, so the six colours are exactly the
/// irradiance at the six axes; shlight fits them that way, from the exact
/// irradiance of a map or from SH irradiance ([`AmbientCube::from_irradiance`]).
#[derive(Clone, Debug, PartialEq)]
pub struct AmbientCube<C> {
    /// `C_{+x}, C_{-x}, C_{+y}, C_{-y}, C_{+z}, C_{-z}`.
    pub colours: [C; 6],
}

impl<C: ShValue> AmbientCube<C> {
    /// The cube whose colours are `irradiance` at the six [`AMBIENT_CUBE_AXES`]: it then
    /// reproduces the irradiance there exactly.
    #[must_use]
    pub fn from_irradiance(irradiance: impl Fn(DVec3) -> C) -> Self {
        Self {
            colours: AMBIENT_CUBE_AXES.map(irradiance),
        }
    }

    /// The cube of radiance coefficients `f`: the SH irradiance
    /// `Σ A_l f_l^m Y_l^m` at the six axes.
    #[must_use]
    pub fn from_sh(f: &ShCoeffs<C>) -> Self {
        let e = crate::sh::zonal::irradiance(f);
        Self::from_irradiance(|d| {
            let y = crate::sh::basis::sh_eval(e.lmax(), d);
            let mut acc = [0.0; 3];
            for (c, yi) in e.as_slice().iter().zip(y) {
                for (a, v) in acc.iter_mut().zip(to_f64(*c)) {
                    *a += v * yi;
                }
            }
            from_f64(acc)
        })
    }

    /// `E(n)` at unit normal `n` ([`AmbientCube`]).
    #[must_use]
    pub fn irradiance(&self, n: <C::Scalar as Real>::Vec3) -> C {
        let n = dir_f64::<C::Scalar>(n);
        let pick = |v: f64, pos: usize| to_f64(self.colours[if v < 0.0 { pos + 1 } else { pos }]);
        let (cx, cy, cz) = (pick(n.x, 0), pick(n.y, 2), pick(n.z, 4));
        let nn = n * n;
        from_f64([0, 1, 2].map(|k| nn.x * cx[k] + nn.y * cy[k] + nn.z * cz[k]))
    }

    /// Floats stored: 6 per channel.
    #[must_use]
    pub fn floats(&self) -> usize {
        6 * C::CHANNELS
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::closed_form;
    use crate::sh::quadrature::fibonacci_sphere;
    use crate::sh::zonal::irradiance;

    /// Bevy's lookup (irradiance_volume.wgsl) with the six texels as an
    /// array: the negative half of each slice where `N < 0`, then
    /// `rgb_x * NN.x + rgb_y * NN.y + rgb_z * NN.z`.
    fn bevy_lookup(c: &[DVec3; 6], n: DVec3) -> DVec3 {
        let neg = |v: f64| if v < 0.0 { 1 } else { 0 };
        let rgb_x = c[neg(n.x)];
        let rgb_y = c[2 + neg(n.y)];
        let rgb_z = c[4 + neg(n.z)];
        let nn = n * n;
        rgb_x * nn.x + rgb_y * nn.y + rgb_z * nn.z
    }

    #[test]
    fn reproduces_the_irradiance_at_the_axes_and_bevys_lookup() {
        let f = &closed_form::cap(
            2,
            DVec3::new(0.3, 0.8, 0.5).normalize(),
            0.4,
            DVec3::new(3.0, 2.0, 1.0),
        ) + &closed_form::constant(2, DVec3::new(0.1, 0.2, 0.4));
        let cube = AmbientCube::from_sh(&f);
        let e = irradiance(&f);
        for axis in AMBIENT_CUBE_AXES {
            assert!(
                (cube.irradiance(axis) - e.eval(axis)).abs().max_element() < 1e-12,
                "{axis}"
            );
        }
        for n in fibonacci_sphere(200) {
            let d = cube.irradiance(n) - bevy_lookup(&cube.colours, n);
            assert!(d.abs().max_element() < 1e-12, "{n}");
        }
        // Between the axes it is a blend, not the SH: a light off the axes
        // is not reproduced everywhere.
        let worst = fibonacci_sphere(200)
            .into_iter()
            .map(|n| (cube.irradiance(n) - e.eval(n)).abs().max_element())
            .fold(0.0, f64::max);
        assert!(worst > 1e-2, "{worst}");
    }

    #[test]
    fn a_constant_sky_is_constant() {
        let cube: AmbientCube<f64> = AmbientCube::from_irradiance(|_| core::f64::consts::PI);
        for n in fibonacci_sphere(50) {
            assert!((cube.irradiance(n) - core::f64::consts::PI).abs() < 1e-12);
        }
    }
}
