//! [`CapLight`]: a small uniform disc of light (a spherical cap of
//! directions) with its exact irradiance, the form dominant lights are kept
//! in ([`crate::encoding::DominantLights`]).

use glam::DVec3;

use crate::encoding::channel_values::{from_f64, to_f64};
use crate::sh::real::Real;
use crate::sh::real::dir_f64;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;
use crate::sh::zonal::cap_solid_angle;

/// A uniform cap of light: direction, angular radius and power.
///
/// A cap of half-angle `α` about unit `d` with uniform radiance `L` holds
/// the power `P = ∫ L dω = 2π (1 - cos α) L` (the irradiance a delta of the
/// same power gives facing it). Its irradiance on a surface whose normal is
/// at angle `t` from `d` is Snyder's formula (J. Snyder, *Area light sources
/// for real-time graphics*, Microsoft Research MSR-TR-96-11, 1996; the form
/// of Lagarde & de Rousiers, *Moving Frostbite to PBR*, 2014, §4.7.2):
///
/// ```text
/// cos² t >= sin² α:  E = π L sin² α max(cos t, 0)
/// otherwise, x = cot α, y = -x cot t, s = sin t sqrt(1 - y²):
///     E = L ((cos t acos(y) - x s) sin² α + atan(s / x))
/// ```
///
/// In terms of the power, facing the light `E = P (1 + cos α) / 2`, and a
/// cap of half-angle 0 is a directional light, `E = P max(cos t, 0)`.
#[derive(Clone, Debug, PartialEq)]
pub struct CapLight<C> {
    /// Unit direction towards the cap's centre (world axes).
    pub direction: DVec3,
    /// Half-angle `α` in radians, `0 <= α < π/2`.
    pub half_angle: f64,
    /// Power `P = ∫ L dω` per channel.
    pub power: C,
}

impl<C: ShValue> CapLight<C> {
    /// Solid angle of the cap, `2π (1 - cos α) = 4π sin²(α/2)`.
    #[must_use]
    pub fn solid_angle(&self) -> f64 {
        cap_solid_angle(self.half_angle)
    }

    /// The cap's exact irradiance at unit normal `n` ([`CapLight`]).
    #[must_use]
    pub fn irradiance(&self, n: <C::Scalar as Real>::Vec3) -> C {
        let n = dir_f64::<C::Scalar>(n);
        let k = cap_irradiance_per_power(self.half_angle, n.dot(self.direction));
        from_f64(to_f64(self.power).map(|p| p * k))
    }

    /// The cap's radiance coefficients to `lmax` (the zonal coefficients of
    /// [`crate::sh::closed_form::cap`] scaled to the power).
    #[must_use]
    pub fn to_sh(&self, lmax: usize) -> ShCoeffs<C> {
        if self.half_angle <= 0.0 {
            return crate::sh::closed_form::directional(lmax, self.direction, self.power);
        }
        let radiance = 1.0 / self.solid_angle();
        let unit = crate::sh::closed_form::cap(lmax, self.direction, self.half_angle, radiance);
        let p = to_f64(self.power);
        unit.map(|u: f64| from_f64::<C>(p.map(|pc| pc * u)))
    }
}

/// Irradiance per unit power of a uniform cap of half-angle `alpha` whose
/// centre makes cosine `cos_t` with the normal (Snyder's formula divided by
/// the power `2π (1 - cos α) L`, [`CapLight`]); `max(cos t, 0)` at `α = 0`.
#[must_use]
pub fn cap_irradiance_per_power(alpha: f64, cos_t: f64) -> f64 {
    let cos_t = cos_t.clamp(-1.0, 1.0);
    let sin_a = alpha.sin();
    let sin2 = sin_a * sin_a;
    if alpha <= 0.0 || cos_t * cos_t >= sin2 {
        // π sin²α / (2π (1 - cos α)) = (1 + cos α) / 2.
        return (1.0 + alpha.cos()) / 2.0 * cos_t.max(0.0);
    }
    let sin_t = (1.0 - cos_t * cos_t).sqrt();
    let x = alpha.cos() / sin_a;
    let y = -x * cos_t / sin_t;
    let s = sin_t * (1.0 - y * y).max(0.0).sqrt();
    let e = (cos_t * y.clamp(-1.0, 1.0).acos() - x * s) * sin2 + (s / x).atan();
    e / cap_solid_angle(alpha)
}

#[cfg(test)]
mod tests {
    use core::f64::consts::PI;

    use super::*;
    use crate::sh::quadrature::fibonacci_sphere;

    /// Brute-force irradiance of a unit-power cap: the cosine integrated over
    /// a fine polar grid of the cap (midpoint rule in `cos` and azimuth).
    fn brute(alpha: f64, d: DVec3, n: DVec3) -> f64 {
        let (rings, segs) = (400, 800);
        let (u, v) = d.any_orthonormal_pair();
        let z0 = alpha.cos();
        let mut e = 0.0;
        for i in 0..rings {
            let z = 1.0 - (1.0 - z0) * (i as f64 + 0.5) / rings as f64;
            let r = (1.0 - z * z).sqrt();
            for j in 0..segs {
                let p = 2.0 * PI * (j as f64 + 0.5) / segs as f64;
                let w = d * z + (u * p.cos() + v * p.sin()) * r;
                e += w.dot(n).max(0.0);
            }
        }
        e / (rings * segs) as f64
    }

    #[test]
    fn snyder_matches_brute_force_including_the_horizon() {
        let d = DVec3::new(0.2, 0.3, 0.9).normalize();
        for alpha in [0.05f64, 0.3, 0.8] {
            for n in fibonacci_sphere(60) {
                let got = cap_irradiance_per_power(alpha, n.dot(d));
                let want = brute(alpha, d, n);
                // The grid's midpoint error, measured below 2e-5.
                assert!((got - want).abs() < 1e-4, "α {alpha} n {n}: {got} {want}");
            }
        }
    }

    #[test]
    fn to_sh_is_the_same_light() {
        let light = CapLight {
            direction: DVec3::Y,
            half_angle: 0.3,
            power: DVec3::new(1.0, 2.0, 3.0),
        };
        // Irradiance of the SH at a high lmax against the closed form.
        let e = crate::sh::zonal::irradiance(&light.to_sh(40));
        for n in fibonacci_sphere(40) {
            let d = e.eval(n) - light.irradiance(n);
            assert!(d.abs().max_element() < 3e-3, "{n}: {d}");
        }
    }
}
