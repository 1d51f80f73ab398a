//! Channel plumbing shared by the encodings: a value's channels as `f64`,
//! back again, and the luminance weights of its channels.

use glam::DVec3;

use crate::sh::real::Real;
use crate::sh::sh_value::ShValue;

/// Rec.709 luminance weights for RGB values, `[1, 0, 0]` for scalars.
pub(crate) fn luminance_weights<C: ShValue>() -> [f64; 3] {
    if C::CHANNELS == 3 {
        [0.2126, 0.7152, 0.0722]
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// The channels of `c` as `f64` (unused ones 0).
pub(crate) fn to_f64<C: ShValue>(c: C) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (k, v) in out.iter_mut().enumerate().take(C::CHANNELS) {
        *v = c.channel(k).to_f64();
    }
    out
}

/// A value whose channels are `v` (rounded to the scalar type).
pub(crate) fn from_f64<C: ShValue>(v: [f64; 3]) -> C {
    let mut c = C::ZERO;
    for (k, x) in v.iter().enumerate().take(C::CHANNELS) {
        c.set_channel(k, C::Scalar::from_f64(*x));
    }
    c
}

/// The degree-1 vector of channel `c` of radiance coefficients `f` (lmax
/// at least 1): `(-f_1^1, -f_1^-1, f_1^0)`, which with the Condon-Shortley
/// phase is `sqrt(3/4π) ∫ L(ω) ω dω` in world axes.
pub(crate) fn band1_vector<C: ShValue>(f: &[C], c: usize) -> DVec3 {
    DVec3::new(
        -f[3].channel(c).to_f64(),
        -f[1].channel(c).to_f64(),
        f[2].channel(c).to_f64(),
    )
}
