//! Hard-coded polynomial forms of the real SH for `lmax <= 4`.
//!
//! These are the Cartesian polynomials of [`crate::basis`]'s functions on the
//! unit sphere (Condon-Shortley phase included), e.g.
//! `Y_1^{-1} = -sqrt(3/(4pi)) y`, `Y_2^{-2} = sqrt(15/(4pi)) x y`,
//! `Y_2^0 = sqrt(5/(16pi)) (3z^2 - 1)`. They are the fast path for the common
//! low degrees and are tested against the general recurrence. Constants are
//! computed from their formulas at compile time, not typed as decimals.
//!
//! Precondition: `(x, y, z)` is a unit vector (the forms use `x^2+y^2+z^2 = 1`).

use crate::Real;

const PI: f64 = core::f64::consts::PI;

/// `sqrt` usable in constants (Newton iteration to full `f64` precision).
const fn csqrt(v: f64) -> f64 {
    let mut g = if v > 1.0 { v } else { 1.0 };
    let mut i = 0;
    while i < 64 {
        g = 0.5 * (g + v / g);
        i += 1;
    }
    g
}

// Degree 0..4 normalisation constants, from K_l^m = sqrt((2l+1)/(4pi) (l-m)!/(l+m)!) (times sqrt 2 for m != 0)
// and the polynomial factors of P_l^m.
const K00: f64 = 0.5 / csqrt(PI);
const K1: f64 = csqrt(3.0 / (4.0 * PI));
const K2_2: f64 = 0.5 * csqrt(15.0 / PI); // xy, yz, xz
const K20: f64 = 0.25 * csqrt(5.0 / PI); // 3z^2 - 1
const K22: f64 = 0.25 * csqrt(15.0 / PI); // x^2 - y^2
const K33: f64 = 0.25 * csqrt(35.0 / (2.0 * PI)); // y(3x^2 - y^2), x(x^2 - 3y^2)
const K3_2: f64 = 0.5 * csqrt(105.0 / PI); // xyz
const K32: f64 = 0.25 * csqrt(105.0 / PI); // z(x^2 - y^2)
const K31: f64 = 0.25 * csqrt(21.0 / (2.0 * PI)); // (5z^2 - 1) y, x
const K30: f64 = 0.25 * csqrt(7.0 / PI); // z(5z^2 - 3)
const K4_4: f64 = 0.75 * csqrt(35.0 / PI); // xy(x^2 - y^2)
const K44: f64 = 0.1875 * csqrt(35.0 / PI); // x^4 - 6x^2y^2 + y^4
const K43: f64 = 0.75 * csqrt(35.0 / (2.0 * PI)); // z y(3x^2 - y^2), z x(x^2 - 3y^2)
const K4_2: f64 = 0.75 * csqrt(5.0 / PI); // xy(7z^2 - 1)
const K42: f64 = 0.375 * csqrt(5.0 / PI); // (x^2 - y^2)(7z^2 - 1)
const K41: f64 = 0.75 * csqrt(5.0 / (2.0 * PI)); // z(7z^2 - 3) y, x
const K40: f64 = 0.1875 * csqrt(1.0 / PI); // 35z^4 - 30z^2 + 3

/// Writes `Y_l^m(x, y, z)` for `l <= lmax <= 4` to `out[l*(l+1)+m]`.
///
/// Panics if `lmax > 4` or `out` is shorter than `(lmax+1)^2`.
#[inline(always)]
pub fn eval_hardcoded<T: Real>(lmax: usize, x: T, y: T, z: T, out: &mut [T]) {
    assert!(lmax <= 4, "hard-coded forms exist up to lmax 4");
    let out = &mut out[..(lmax + 1) * (lmax + 1)];
    let c = T::from_f64;
    out[0] = c(K00);
    if lmax == 0 {
        return;
    }
    out[1] = -c(K1) * y;
    out[2] = c(K1) * z;
    out[3] = -c(K1) * x;
    if lmax == 1 {
        return;
    }
    let (x2, y2, z2) = (x * x, y * y, z * z);
    out[4] = c(K2_2) * x * y;
    out[5] = -c(K2_2) * y * z;
    out[6] = c(K20) * (c(3.0) * z2 - T::ONE);
    out[7] = -c(K2_2) * x * z;
    out[8] = c(K22) * (x2 - y2);
    if lmax == 2 {
        return;
    }
    let t31 = c(5.0) * z2 - T::ONE;
    out[9] = -c(K33) * y * (c(3.0) * x2 - y2);
    out[10] = c(K3_2) * x * y * z;
    out[11] = -c(K31) * y * t31;
    out[12] = c(K30) * z * (c(5.0) * z2 - c(3.0));
    out[13] = -c(K31) * x * t31;
    out[14] = c(K32) * z * (x2 - y2);
    out[15] = -c(K33) * x * (x2 - c(3.0) * y2);
    if lmax == 3 {
        return;
    }
    let t42 = c(7.0) * z2 - T::ONE;
    let t41 = z * (c(7.0) * z2 - c(3.0));
    out[16] = c(K4_4) * x * y * (x2 - y2);
    out[17] = -c(K43) * z * y * (c(3.0) * x2 - y2);
    out[18] = c(K4_2) * x * y * t42;
    out[19] = -c(K41) * y * t41;
    out[20] = c(K40) * (c(35.0) * z2 * z2 - c(30.0) * z2 + c(3.0));
    out[21] = -c(K41) * x * t41;
    out[22] = c(K42) * (x2 - y2) * t42;
    out[23] = -c(K43) * z * x * (x2 - c(3.0) * y2);
    out[24] = c(K44) * (x2 * x2 - c(6.0) * x2 * y2 + y2 * y2);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn const_sqrt_is_exact_enough() {
        for v in [0.1, 1.0, 2.0, 3.0 / (4.0 * PI), 105.0 / PI, 1e-6] {
            assert!((csqrt(v) - v.sqrt()).abs() <= 2.0 * f64::EPSILON * v.sqrt());
        }
    }

    #[test]
    fn band_one_matches_the_reference_values() {
        // Y_1^-1 = -0.488603 y, Y_1^0 = 0.488603 z, Y_1^1 = -0.488603 x.
        let mut out = [0.0f64; 4];
        eval_hardcoded(1, 0.0, 0.0, 1.0, &mut out);
        assert!((out[2] - 0.488603).abs() < 1e-6);
        eval_hardcoded(1, 1.0, 0.0, 0.0, &mut out);
        assert!((out[3] + 0.488603).abs() < 1e-6);
        eval_hardcoded(1, 0.0, 1.0, 0.0, &mut out);
        assert!((out[1] + 0.488603).abs() < 1e-6);
        assert!((out[0] - 0.282095).abs() < 1e-6);
    }
}
