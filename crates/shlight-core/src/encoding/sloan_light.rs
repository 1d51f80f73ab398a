//! A directional light from SH coefficients alone (no map), after P.-P.
//! Sloan, *Stupid Spherical Harmonics (SH) Tricks*, GDC 2008, §"Extracting
//! Conventional Lights from SH":

use core::f64::consts::PI;

use glam::DVec3;

use crate::encoding::cap_light::CapLight;
use crate::encoding::channel_values::{band1_vector, from_f64, luminance_weights, to_f64};
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// Sloan's directional light of `f` (lmax >= 1, else `None`) and the
/// residual (below). `None` also when the degree-1 vector is zero.
///
/// - **direction**: the optimal linear direction, the unit vector along
///   the luminance's degree-1 vector `Σ_c w_c (-f_1^1, -f_1^-1, f_1^0)`
///   (Condon-Shortley phase; `w` the Rec.709 weights);
/// - **intensity**: per channel the least-squares fit of the light's own
///   coefficients `c Y_l^m(d)` to degrees `1..=lmax` (the directional
///   energy; degree 0 is left to the ambient):
///   `c = Σ_{l>=1} Σ_m f_l^m Y_l^m(d) / Σ_{l=1}^{lmax} (2l+1)/(4π)`,
///   clamped at 0;
/// - **residual**: `f - c Y(d)` in every degree, so light plus residual is
///   the input.
///
/// `c` is the light's power (the irradiance it gives a surface facing it).
#[must_use]
pub fn sloan_directional<C: ShValue>(f: &ShCoeffs<C>) -> Option<(CapLight<C>, ShCoeffs<C>)> {
    if f.lmax() < 1 {
        return None;
    }
    let s = f.as_slice();
    let w = luminance_weights::<C>();
    let mut v = DVec3::ZERO;
    for (c, wc) in w.iter().enumerate().take(C::CHANNELS) {
        v += band1_vector(s, c) * *wc;
    }
    let direction = v.try_normalize()?;
    let y = crate::sh::basis::sh_eval(f.lmax(), direction);
    let norm: f64 = (1..=f.lmax())
        .map(|l| (2 * l + 1) as f64 / (4.0 * PI))
        .sum();
    let mut c = [0.0; 3];
    for (fi, yi) in s.iter().zip(&y).skip(1) {
        for (ck, v) in c.iter_mut().zip(to_f64(*fi)) {
            *ck += v * yi;
        }
    }
    let c = c.map(|x| (x / norm).max(0.0));
    let mut residual = f.clone();
    for (r, yi) in residual.as_mut_slice().iter_mut().zip(&y) {
        *r = *r - from_f64::<C>(c.map(|ck| ck * yi));
    }
    let light = CapLight {
        direction,
        half_angle: 0.0,
        power: from_f64(c),
    };
    Some((light, residual))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::closed_form;

    #[test]
    fn recovers_a_directional_light_over_a_constant_sky() {
        let d = DVec3::new(-0.3, 0.6, 0.74).normalize();
        let colour = DVec3::new(3.0, 2.0, 1.0);
        let f =
            &closed_form::directional(2, d, colour) + &closed_form::constant(2, DVec3::splat(0.2));
        let (light, residual) = sloan_directional(&f).unwrap();
        assert!(light.direction.angle_between(d) < 1e-12);
        assert!((light.power - colour).abs().max_element() < 1e-12);
        // The residual is the constant sky alone.
        let sky = closed_form::constant(2, DVec3::splat(0.2));
        for (a, b) in residual.as_slice().iter().zip(sky.as_slice()) {
            assert!((*a - *b).abs().max_element() < 1e-12);
        }
    }

    #[test]
    fn two_opposite_lamps_give_no_direction_to_trust() {
        // Equal lamps on opposite sides: the degree-1 vector vanishes.
        let f = &closed_form::directional(2, DVec3::X, 1.0f64)
            + &closed_form::directional(2, DVec3::NEG_X, 1.0f64);
        assert!(sloan_directional(&f).is_none_or(|(l, _)| l.power < 1e-9));
    }
}
