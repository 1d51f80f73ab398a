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
    use core::f64::consts::PI;

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

    /// A constant sky `c`, a gradient `a + b (u . w)` and a directional
    /// light of irradiance `e` from `d`, as radiance SH to lmax 2 (closed
    /// forms), and their irradiance written out by hand, not through the
    /// zonal convolution [`AmbientCube::from_sh`] uses: `π c` everywhere,
    /// `π a + (2π/3) b (u . n)` for the gradient (its radiance is degree 1,
    /// so its SH is exact), and for the light truncated at lmax 2
    /// `e (1/4 + k/2 + (5/32)(3 k² - 1))`, `k = d . n` (Ramamoorthi &
    /// Hanrahan: `A_l (2l+1)/(4π) P_l(k)` for l = 0, 1, 2).
    struct Sky {
        c: DVec3,
        u: DVec3,
        a: DVec3,
        b: DVec3,
        d: DVec3,
        e: DVec3,
    }

    impl Sky {
        fn new() -> Self {
            Self {
                c: DVec3::new(0.1, 0.2, 0.4),
                u: DVec3::new(0.2, 0.9, -0.3).normalize(),
                a: DVec3::new(0.5, 0.6, 0.8),
                b: DVec3::new(0.3, 0.25, 0.1),
                d: DVec3::new(0.3, 0.8, 0.5).normalize(),
                e: DVec3::new(3.0, 2.0, 1.0),
            }
        }

        fn sh(&self) -> ShCoeffs<DVec3> {
            let f = &closed_form::constant(2, self.c)
                + &closed_form::linear_gradient(2, self.u, self.a, self.b);
            &f + &closed_form::directional(2, self.d, self.e)
        }

        fn irradiance(&self, n: DVec3) -> DVec3 {
            let k = self.d.dot(n);
            PI * self.c
                + PI * self.a
                + 2.0 * PI / 3.0 * self.b * self.u.dot(n)
                + self.e * (0.25 + k / 2.0 + 5.0 / 32.0 * (3.0 * k * k - 1.0))
        }
    }

    #[test]
    fn reproduces_the_irradiance_at_the_axes_and_bevys_lookup() {
        let sky = Sky::new();
        let cube = AmbientCube::from_sh(&sky.sh());
        for (axis, colour) in AMBIENT_CUBE_AXES.into_iter().zip(&cube.colours) {
            let want = sky.irradiance(axis);
            assert!(
                (*colour - want).abs().max_element() < 1e-12,
                "{axis}: {colour} {want}"
            );
            assert!(
                (cube.irradiance(axis) - want).abs().max_element() < 1e-12,
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
            .map(|n| (cube.irradiance(n) - sky.irradiance(n)).abs().max_element())
            .fold(0.0, f64::max);
        assert!(worst > 1e-2, "{worst}");
    }

    /// The cube of a map's exact irradiance ([`crate::encoding::encode_map`])
    /// against closed forms: a one-texel sun of irradiance `E` gives
    /// `E max(0, axis . d)` at each axis (`d` the texel's centre, its
    /// radiance `E / Ω` with the row's solid angle written out here), and a
    /// constant sky `c` gives `π c` to the map's quadrature error.
    #[test]
    fn a_maps_cube_is_a_suns_and_a_constant_skys_closed_form() {
        use crate::encoding::dominant_lights::DominantLightOptions;
        use crate::encoding::encoded::{Encoded, Encoding, encode_map};
        use crate::map::layout::env_map::EnvMap;
        use crate::map::layout::kind::Layout;
        use crate::map::orientation::MapOrientation;
        let (w, h) = (128, 64);
        let o = MapOrientation::default();
        let cube_of = |px: &[[f32; 3]]| {
            let map = EnvMap::new(Layout::Equirect, o, w, h, px).unwrap();
            match encode_map(
                &map,
                Encoding::AmbientCube,
                0,
                &DominantLightOptions::default(),
            ) {
                Encoded::AmbientCube(c) => c,
                other => panic!("{other:?}"),
            }
        };
        // The sun texel's centre and solid angle: a 2π/w slice between the
        // row's polar angles.
        let (x0, y0) = (37, 11);
        let mut px = vec![[0.0f32; 3]; w * h];
        let d = EnvMap::new(Layout::Equirect, o, w, h, &px)
            .unwrap()
            .texel_direction(x0, y0)
            .unwrap();
        let polar = |y: usize| PI * y as f64 / h as f64;
        let omega = 2.0 * PI / w as f64 * (polar(y0).cos() - polar(y0 + 1).cos());
        let e = DVec3::new(2.0, 1.5, 0.5);
        px[y0 * w + x0] = (e / omega).as_vec3().to_array();
        let cube = cube_of(&px);
        for (axis, colour) in AMBIENT_CUBE_AXES.into_iter().zip(&cube.colours) {
            let want = e * axis.dot(d).max(0.0);
            // The radiance is stored as f32.
            assert!(
                (*colour - want).abs().max_element() <= 1e-7 * e.max_element(),
                "{axis}: {colour} {want}"
            );
        }
        // At least three axes see the sun, and three do not.
        assert_eq!(cube.colours.iter().filter(|c| c.x > 0.0).count(), 3);

        // A constant sky: the texel sum is the midpoint rule in θ and φ,
        // whose error on `max(0, n . w)` has a closed form on a w = 2h map
        // (w a multiple of 4). About ±y each row gives `cos θ_c Ω_row`,
        // `1 / cos(Δ/2)` times its exact integral (`Δ = π/h`), so `π c /
        // cos(Δ/2)`; about a horizontal axis the sum over φ is
        // `1 / sin(π/w)` and over θ `Σ sin² θ_c = h/2`, which with `Ω_row`
        // give `π c` exactly.
        let c = DVec3::new(0.25, 0.5, 1.0);
        let cube = cube_of(&vec![c.as_vec3().to_array(); w * h]);
        for (axis, colour) in AMBIENT_CUBE_AXES.into_iter().zip(&cube.colours) {
            let want = if axis.y == 0.0 {
                PI * c
            } else {
                PI * c / (PI / (2 * h) as f64).cos()
            };
            let rel = ((*colour - want) / want).abs().max_element();
            assert!(rel < 1e-12, "{axis}: {colour} against {want}");
            // Against the integral, the poles are off by the midpoint
            // rule's `Δ² / 8` (3.0e-4 at 128x64).
            assert!(((*colour - PI * c) / (PI * c)).abs().max_element() < 4e-4);
        }
    }

    #[test]
    fn a_constant_sky_is_constant() {
        let cube: AmbientCube<f64> = AmbientCube::from_irradiance(|_| core::f64::consts::PI);
        for n in fibonacci_sphere(50) {
            assert!((cube.irradiance(n) - core::f64::consts::PI).abs() < 1e-12);
        }
    }
}
