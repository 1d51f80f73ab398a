//! Non-linear reconstruction of irradiance from lmax-1 radiance: the
//! Geomerics (Enlighten) model of G. Hazel and C. Doran, *Converting SH
//! Radiance to Irradiance* (2017,
//! <https://grahamhazel.com/blog/2017/12/22/converting-sh-radiance-to-irradiance/>),
//! the curve Frostbite, Godot's lightmaps, Blender's EEVEE and MJP's
//! SH.hlsli evaluate.

use core::f64::consts::PI;

use crate::encoding::channel_values::{band1_vector, from_f64, to_f64};
use crate::sh::real::Real;
use crate::sh::real::dir_f64;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// Hazel's `(R_0, R_1)` per channel from lmax-1 radiance (below).
///
/// In Hazel's normalisation the radiance is `R_0 + 3 R_1 · ω` with
/// `R_0 = (1/4π) ∫ L` (the mean) and `R_1 = (1/4π) ∫ L ω dω`, so
/// `0 <= |R_1| <= R_0` for any non-negative radiance. In shlight's basis
/// `R_0 = f_0^0 / (2 sqrt(π))` and `R_1 = (-f_1^1, -f_1^-1, f_1^0) / (2 sqrt(3π))`.
/// The linear irradiance is `π (R_0 + 2 R_1 · n)`, negative away from a
/// strong light; the non-linear one is, per channel,
///
/// ```text
/// r = |R_1| / R_0,  p = 1 + 2r,  a = (1 - r) / (1 + r),  q = (1 + R̂_1 · n) / 2
/// E(n) = π R_0 (a + (1 - a) (p + 1) q^p)
/// ```
///
/// non-negative for `r <= 1` (here `r` is clamped to `[0, 1]`), with the
/// linear model's mean over the sphere (`π R_0`: energy is conserved,
/// since the mean of `(p + 1) q^p` is 1) and its slope as `r -> 0`.
///
/// The engines' shaders pass `R_0 = f_0^0` and `R_1 = v / 2`, whose ratio is
/// `sqrt(3)/2` of Hazel's (a delta reaches `r = 0.87`, not 1): shlight keeps
/// Hazel's normalisation, under which a single direction gives `p = 3`.
#[derive(Clone, Debug, PartialEq)]
pub struct L1NonLinear<C> {
    /// The four lmax-1 radiance coefficients, flat index order.
    pub l1: [C; 4],
}

impl<C: ShValue> L1NonLinear<C> {
    /// From radiance coefficients `f` (lmax >= 1, else `None`; higher
    /// degrees are ignored).
    #[must_use]
    pub fn new(f: &ShCoeffs<C>) -> Option<Self> {
        let s = f.as_slice();
        (f.lmax() >= 1).then(|| Self {
            l1: [s[0], s[1], s[2], s[3]],
        })
    }

    /// The non-linear irradiance at unit normal `n` ([`L1NonLinear`]); 0 where a
    /// channel's mean radiance is not positive.
    #[must_use]
    pub fn irradiance(&self, n: <C::Scalar as Real>::Vec3) -> C {
        let n = dir_f64::<C::Scalar>(n);
        let f0 = to_f64(self.l1[0]);
        let mut e = [0.0; 3];
        for (c, ec) in e.iter_mut().enumerate().take(C::CHANNELS) {
            let r0 = f0[c] / (2.0 * PI.sqrt());
            if r0 <= 0.0 {
                continue;
            }
            let r1 = band1_vector(&self.l1, c) / (2.0 * (3.0 * PI).sqrt());
            let len = r1.length();
            if len == 0.0 {
                *ec = PI * r0;
                continue;
            }
            let r = (len / r0).min(1.0);
            let p = 1.0 + 2.0 * r;
            let a = (1.0 - r) / (1.0 + r);
            let q = (0.5 * (1.0 + r1.dot(n) / len)).max(0.0);
            *ec = PI * r0 * (a + (1.0 - a) * (p + 1.0) * q.powf(p));
        }
        from_f64(e)
    }

    /// Floats stored: 4 per channel.
    #[must_use]
    pub fn floats(&self) -> usize {
        4 * C::CHANNELS
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::closed_form;
    use crate::sh::quadrature::{SphereQuadrature, fibonacci_sphere};
    use crate::sh::zonal::irradiance;
    use glam::DVec3;

    #[test]
    fn never_negative_where_linear_l1_is() {
        // A sun over a dim sky: linear L1 irradiance goes negative.
        let sun = DVec3::new(0.4, 0.8, -0.2).normalize();
        let f = &closed_form::directional(1, sun, DVec3::new(5.0, 4.0, 3.0))
            + &closed_form::constant(1, DVec3::splat(0.05));
        let linear = irradiance(&f);
        let nl = L1NonLinear::new(&f).unwrap();
        let dense = fibonacci_sphere(20_000);
        let lin_min = dense
            .iter()
            .map(|n| linear.eval(*n).min_element())
            .fold(f64::MAX, f64::min);
        assert!(lin_min < 0.0, "the test needs a light linear L1 rings on");
        for n in &dense {
            assert!(nl.irradiance(*n).min_element() >= 0.0, "{n}");
        }
    }

    #[test]
    fn equals_linear_for_constant_light_and_keeps_its_mean() {
        let c = closed_form::constant(1, DVec3::new(0.5, 1.0, 2.0));
        let nl = L1NonLinear::new(&c).unwrap();
        for n in fibonacci_sphere(50) {
            let want = DVec3::new(0.5, 1.0, 2.0) * PI;
            assert!((nl.irradiance(n) - want).abs().max_element() < 1e-12);
        }
        // Any light: the mean over the sphere is the linear model's π R_0,
        // integrated by a product rule independent of the formula.
        let f = &closed_form::cap(1, DVec3::X, 0.5, DVec3::new(3.0, 2.0, 1.0))
            + &closed_form::constant(1, DVec3::splat(0.2));
        let nl = L1NonLinear::new(&f).unwrap();
        let q = SphereQuadrature::exact_to_degree(200);
        let mut mean = DVec3::ZERO;
        for (d, w) in q.directions.iter().zip(&q.weights) {
            mean += nl.irradiance(*d) * *w / (4.0 * PI);
        }
        let want = f[0] * PI / (2.0 * PI.sqrt());
        assert!(
            (mean - want).abs().max_element() < 1e-6 * want.max_element(),
            "{mean} {want}"
        );
    }

    #[test]
    fn weak_directionality_approaches_the_linear_model() {
        // r = 1e-3: the difference is second order in r.
        let f = &closed_form::constant(1, 1.0f64)
            + &closed_form::linear_gradient(1, DVec3::Y, 0.0, 3e-3);
        let nl = L1NonLinear::new(&f).unwrap();
        let lin = irradiance(&f);
        for n in fibonacci_sphere(50) {
            let d = (nl.irradiance(n) - lin.eval(n)).abs();
            assert!(d < 1e-5, "{n}: {d}");
        }
    }

    #[test]
    fn a_single_direction_gives_the_cubic_lobe() {
        // r = 1: a = 0, p = 3, E = π R_0 4 q³ with π R_0 = 1/4 for unit power.
        let d = DVec3::new(0.0, 0.6, 0.8);
        let nl = L1NonLinear::new(&closed_form::directional(1, d, 1.0f64)).unwrap();
        for n in fibonacci_sphere(30) {
            let q = 0.5 * (1.0 + n.dot(d));
            assert!((nl.irradiance(n) - q.powi(3)).abs() < 1e-12);
        }
    }
}
