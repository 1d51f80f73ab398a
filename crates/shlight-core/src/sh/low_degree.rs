//! Hard-coded polynomial forms of the real SH for `lmax <= 4`.
//!
//! These are the Cartesian polynomials of [`crate::sh::ShBasis`]'s functions on the
//! unit sphere (Condon-Shortley phase included), e.g.
//! `Y_1^{-1} = -sqrt(3/(4pi)) y`, `Y_2^{-2} = sqrt(15/(4pi)) x y`,
//! `Y_2^0 = sqrt(5/(16pi)) (3z^2 - 1)`. They are the fast path for the common
//! low degrees and are tested against the general recurrence. Constants are
//! computed from their formulas at compile time, not typed as decimals.
//!
//! Precondition: `(x, y, z)` is a unit vector (the forms use `x^2+y^2+z^2 = 1`).

use core::ops::{Add, Mul, Neg, Sub};

use crate::sh::real::Real;

/// Arithmetic the hard-coded forms need: a scalar, or [`Lanes`] of scalars
/// (so one source serves the scalar and the vectorised batch paths).
pub trait Arith:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    /// Every lane set to the constant `v`.
    fn constant(v: f64) -> Self;
}

impl<T: Real> Arith for T {
    #[inline(always)]
    fn constant(v: f64) -> Self {
        T::from_f64(v)
    }
}

/// `N` values processed together; every operation is a fixed-length lane
/// loop, which the compiler turns into SIMD instructions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lanes<T, const N: usize>(pub [T; N]);

macro_rules! lanes_binop {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<T: Real, const N: usize> $tr for Lanes<T, N> {
            type Output = Self;
            #[inline(always)]
            fn $f(self, o: Self) -> Self {
                let mut r = self.0;
                for j in 0..N {
                    r[j] = self.0[j] $op o.0[j];
                }
                Lanes(r)
            }
        }
    };
}
lanes_binop!(Add, add, +);
lanes_binop!(Sub, sub, -);
lanes_binop!(Mul, mul, *);

impl<T: Real, const N: usize> Neg for Lanes<T, N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let mut r = self.0;
        for v in &mut r {
            *v = -*v;
        }
        Lanes(r)
    }
}

impl<T: Real, const N: usize> Arith for Lanes<T, N> {
    #[inline(always)]
    fn constant(v: f64) -> Self {
        Lanes([T::from_f64(v); N])
    }
}

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
pub(crate) const K00: f64 = 0.5 / csqrt(PI);
pub(crate) const K1: f64 = csqrt(3.0 / (4.0 * PI));
pub(crate) const K2_2: f64 = 0.5 * csqrt(15.0 / PI); // xy, yz, xz
pub(crate) const K20: f64 = 0.25 * csqrt(5.0 / PI); // 3z^2 - 1
pub(crate) const K22: f64 = 0.25 * csqrt(15.0 / PI); // x^2 - y^2
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
pub fn eval_low_degree<T: Arith>(lmax: usize, x: T, y: T, z: T, out: &mut [T]) {
    let out = &mut out[..(lmax + 1) * (lmax + 1)];
    eval_low_degree_with(
        lmax,
        x,
        y,
        z,
        #[inline(always)]
        |i, v| out[i] = v,
    );
}

/// Hands `(l*(l+1)+m, Y_l^m(x, y, z))` to `emit` for every `l <= lmax <= 4`,
/// in index order. With [`Lanes`] this evaluates many directions at once
/// without materialising the basis.
///
/// Panics if `lmax > 4`.
#[inline(always)]
pub fn eval_low_degree_with<T: Arith>(
    lmax: usize,
    x: T,
    y: T,
    z: T,
    mut emit: impl FnMut(usize, T),
) {
    assert!(lmax <= 4, "hard-coded forms exist up to lmax 4");
    let c = T::constant;
    emit(0, c(K00));
    if lmax == 0 {
        return;
    }
    emit(1, -c(K1) * y);
    emit(2, c(K1) * z);
    emit(3, -c(K1) * x);
    if lmax == 1 {
        return;
    }
    let (x2, y2, z2) = (x * x, y * y, z * z);
    emit(4, c(K2_2) * x * y);
    emit(5, -c(K2_2) * y * z);
    emit(6, c(K20) * (c(3.0) * z2 - c(1.0)));
    emit(7, -c(K2_2) * x * z);
    emit(8, c(K22) * (x2 - y2));
    if lmax == 2 {
        return;
    }
    let t31 = c(5.0) * z2 - c(1.0);
    emit(9, -c(K33) * y * (c(3.0) * x2 - y2));
    emit(10, c(K3_2) * x * y * z);
    emit(11, -c(K31) * y * t31);
    emit(12, c(K30) * z * (c(5.0) * z2 - c(3.0)));
    emit(13, -c(K31) * x * t31);
    emit(14, c(K32) * z * (x2 - y2));
    emit(15, -c(K33) * x * (x2 - c(3.0) * y2));
    if lmax == 3 {
        return;
    }
    let t42 = c(7.0) * z2 - c(1.0);
    let t41 = z * (c(7.0) * z2 - c(3.0));
    emit(16, c(K4_4) * x * y * (x2 - y2));
    emit(17, -c(K43) * z * y * (c(3.0) * x2 - y2));
    emit(18, c(K4_2) * x * y * t42);
    emit(19, -c(K41) * y * t41);
    emit(20, c(K40) * (c(35.0) * z2 * z2 - c(30.0) * z2 + c(3.0)));
    emit(21, -c(K41) * x * t41);
    emit(22, c(K42) * (x2 - y2) * t42);
    emit(23, -c(K43) * z * x * (x2 - c(3.0) * y2));
    emit(24, c(K44) * (x2 * x2 - c(6.0) * x2 * y2 + y2 * y2));
}

/// An expansion of degree `<= 2` written as the quadratic form
/// `f(d) = d^T Q d + b . d + c` (on unit `d`), which reconstructs with about
/// ten multiply-adds per direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraticForm<T> {
    /// `[xx, yy, zz, xy, yz, xz]`: the symmetric matrix's entries, off-diagonal
    /// ones doubled.
    pub q: [T; 6],
    /// The linear part `[x, y, z]`.
    pub b: [T; 3],
    /// The constant.
    pub c: T,
}

impl<T: Real> QuadraticForm<T> {
    /// Folds up to 9 coefficients (missing ones are zero) into the form.
    #[must_use]
    pub fn from_coeffs(f: &[T]) -> Self {
        let g = |i: usize| f.get(i).map_or(0.0, |v| v.to_f64());
        let c = g(0) * K00 - g(6) * K20;
        let q = [
            g(8) * K22,
            -g(8) * K22,
            3.0 * g(6) * K20,
            g(4) * K2_2,
            -g(5) * K2_2,
            -g(7) * K2_2,
        ];
        let b = [-g(3) * K1, -g(1) * K1, g(2) * K1];
        Self {
            q: q.map(T::from_f64),
            b: b.map(T::from_f64),
            c: T::from_f64(c),
        }
    }

    /// `f(d)` at a unit direction (also for [`Lanes`]).
    #[inline(always)]
    pub fn eval<V: Arith + From<T>>(&self, x: V, y: V, z: V) -> V {
        let k = |v: T| V::from(v);
        k(self.c)
            + x * (k(self.b[0]) + k(self.q[0]) * x + k(self.q[3]) * y + k(self.q[5]) * z)
            + y * (k(self.b[1]) + k(self.q[1]) * y + k(self.q[4]) * z)
            + z * (k(self.b[2]) + k(self.q[2]) * z)
    }
}

impl<T: Real, const N: usize> From<T> for Lanes<T, N> {
    #[inline(always)]
    fn from(v: T) -> Self {
        Lanes([v; N])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_form_reproduces_the_expansion() {
        let f: Vec<f64> = (0..9).map(|i| (i as f64 * 0.7).cos()).collect();
        let form = QuadraticForm::from_coeffs(&f);
        for d in [
            [0.0, 0.0, 1.0],
            [0.6, 0.0, 0.8],
            [0.48, -0.6, 0.64],
            [-1.0, 0.0, 0.0],
        ] {
            let mut y = [0.0; 9];
            eval_low_degree(2, d[0], d[1], d[2], &mut y);
            let want: f64 = y.iter().zip(&f).map(|(a, b)| a * b).sum();
            assert!((form.eval(d[0], d[1], d[2]) - want).abs() < 1e-14);
        }
    }

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
        eval_low_degree(1, 0.0, 0.0, 1.0, &mut out);
        assert!((out[2] - 0.488603).abs() < 1e-6);
        eval_low_degree(1, 1.0, 0.0, 0.0, &mut out);
        assert!((out[3] + 0.488603).abs() < 1e-6);
        eval_low_degree(1, 0.0, 1.0, 0.0, &mut out);
        assert!((out[1] + 0.488603).abs() < 1e-6);
        assert!((out[0] - 0.282095).abs() < 1e-6);
    }
}
