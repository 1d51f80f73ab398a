//! Closed-form SH projections of analytic light sources.
//!
//! Each function returns the exact coefficients (up to rounding) of a radiance
//! distribution over the sphere of directions, in shlight's basis; `value` is
//! the colour (or scalar) that scales it. Directions are unit vectors in world
//! axes. These are the oracles the projection of maps is tested against.

use core::f64::consts::PI;

use glam::DVec3;

use crate::sh::real::Real;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;
use crate::sh::zonal::{cap_zonal, clamped_cosine_zonal, zonal_to_sh};

/// Constant radiance `value` in every direction: only `f_0^0 = 2 sqrt(pi) value`.
#[must_use]
pub fn constant<C: ShValue>(lmax: usize, value: C) -> ShCoeffs<C> {
    let mut f = ShCoeffs::zeros(lmax);
    f[0] = value.scale(C::Scalar::from_f64(2.0 * PI.sqrt()));
    f
}

/// A directional light (a delta distribution) from unit direction `d` whose
/// irradiance on a surface facing it is `value`: `f_l^m = value Y_l^m(d)`.
///
/// Its irradiance is `value * max(n . d, 0)`; truncated at lmax 2 it is
/// `value (1/4 + cos/2 + (5/32)(3 cos^2 - 1))` (17/16 at 0 degrees).
#[must_use]
pub fn directional<C: ShValue>(lmax: usize, d: DVec3, value: C) -> ShCoeffs<C> {
    ShCoeffs::from_vec(crate::sh::basis::sh_eval(lmax, d))
        .expect("basis count is a square")
        .map(|y| value.scale(C::Scalar::from_f64(y)))
}

/// Radiance `value * max(axis . d, 0)`: a clamped-cosine lobe about `axis`.
#[must_use]
pub fn cosine_lobe<C: ShValue>(lmax: usize, axis: DVec3, value: C) -> ShCoeffs<C> {
    zonal_to_sh(&clamped_cosine_zonal(lmax), axis).map(|c| value.scale(C::Scalar::from_f64(c)))
}

/// Uniform radiance `value` inside the spherical cap of half-angle
/// `half_angle` (radians, `0..=pi`) about `axis`, zero outside.
/// `half_angle = pi/2` is the uniform hemisphere.
#[must_use]
pub fn cap<C: ShValue>(lmax: usize, axis: DVec3, half_angle: f64, value: C) -> ShCoeffs<C> {
    zonal_to_sh(&cap_zonal(lmax, half_angle), axis).map(|c| value.scale(C::Scalar::from_f64(c)))
}

/// Radiance varying linearly with the direction, `a + b (axis . d)` (a sky
/// gradient when `axis` is up). Band-limited to degree 1:
/// `f_0^0 = 2 sqrt(pi) a`, and band 1 is `b` times the directional
/// coefficients of `axis` scaled by `4 pi / 3`.
#[must_use]
pub fn linear_gradient<C: ShValue>(lmax: usize, axis: DVec3, a: C, b: C) -> ShCoeffs<C> {
    let mut f = constant(lmax, a);
    if lmax >= 1 {
        let y = crate::sh::basis::sh_eval(1, axis);
        for i in 1..4 {
            // int (axis . d) Y_1^m(d) dd = (4 pi / 3) Y_1^m(axis)
            f[i] = b.scale(C::Scalar::from_f64(4.0 * PI / 3.0 * y[i]));
        }
    }
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(v: [f64; 3]) -> DVec3 {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        DVec3::new(v[0] / n, v[1] / n, v[2] / n)
    }

    #[test]
    fn closed_forms_match_numerical_projection() {
        let axis = unit([0.3, -0.5, 0.8]);
        let dot = |d: DVec3| d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
        // Band-limited sources are reproduced exactly by a product rule.
        let c = constant(4, 1.5f64);
        let g = linear_gradient(4, axis, 0.7f64, 0.2);
        let cp = ShCoeffs::project_fn(4, 8, |_| 1.5);
        let gp = ShCoeffs::project_fn(4, 8, |d| 0.7 + 0.2 * dot(d));
        for i in 0..25 {
            assert!((c[i] - cp[i]).abs() < 1e-13);
            assert!((g[i] - gp[i]).abs() < 1e-13);
        }
        // Discontinuous ones converge slowly; a fine rule gets within 1e-3.
        let lobe = cosine_lobe(4, axis, 1.0f64);
        let lp = ShCoeffs::project_fn(4, 800, |d| dot(d).max(0.0));
        let cap_ = cap(4, axis, 0.6, 1.0f64);
        let capp = ShCoeffs::project_fn(4, 800, |d| if dot(d) >= 0.6f64.cos() { 1.0 } else { 0.0 });
        for i in 0..25 {
            assert!((lobe[i] - lp[i]).abs() < 1e-4, "lobe {i}");
            assert!(
                (cap_[i] - capp[i]).abs() < 2e-3,
                "cap {i}: {} {}",
                cap_[i],
                capp[i]
            );
        }
    }

    #[test]
    fn directional_light_irradiance_is_the_cosine_at_high_lmax() {
        let d = unit([1.0, 2.0, -0.5]);
        let e = crate::sh::zonal::irradiance(&directional(60, d, 1.0f64));
        for n in [d, unit([1.0, 0.0, 0.0]), unit([0.2, 0.9, 0.1])] {
            let want = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).max(0.0);
            assert!((e.eval(n) - want).abs() < 2e-3, "{n:?}");
        }
    }

    #[test]
    fn directional_light_nine_term_irradiance_matches_the_published_figures() {
        // L_lm = Y_lm(d) (unit irradiance E_perp = 1 from +Z); E2(n) at 0, 90, 180 degrees.
        let d = [0.0, 0.0, 1.0];
        let l: ShCoeffs<f64> = directional(2, glam::DVec3::from(d), 1.0);
        let e = crate::sh::zonal::irradiance(&l);
        let at = |deg: f64| {
            let t = deg.to_radians();
            e.eval(DVec3::new(t.sin(), 0.0, t.cos()))
        };
        assert!((at(0.0) - 17.0 / 16.0).abs() < 1e-14);
        assert!((at(90.0) - 3.0 / 32.0).abs() < 1e-14);
        assert!((at(180.0) - 1.0 / 16.0).abs() < 1e-14);
    }
}
