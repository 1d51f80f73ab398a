//! What the fixed-size SH types share, on plain coefficient arrays: their
//! evaluation (the basis constants of the hard-coded low-degree polynomials
//! folded into the coefficients, then one dot product with the monomials of
//! the direction), the clamped-cosine eigenvalues of degrees 0 to 2, and
//! truncating or zero-padding an expansion to `N` coefficients.

use core::f64::consts::PI;

use crate::sh::glam_real::GlamReal;
use crate::sh::low_degree::{K00, K1, K2_2, K20, K22, eval_low_degree};

/// `A_l` for `l = 0, 1, 2`: `pi, 2 pi / 3, pi / 4`, the Funk-Hecke
/// eigenvalues of the clamped cosine (Ramamoorthi & Hanrahan 2001, eq. 8;
/// [`crate::sh::clamped_cosine_eigenvalue`] for every `l`).
pub(crate) const A_L: [f64; 3] = [PI, 2.0 * PI / 3.0, PI / 4.0];

/// `sum_i a_i b_i`, in index order (a fixed chain the compiler keeps in registers).
#[inline(always)]
pub(crate) fn dot<T: crate::sh::real::Real, const N: usize>(a: &[T; N], b: &[T; N]) -> T {
    let mut acc = a[0] * b[0];
    for i in 1..N {
        acc += a[i] * b[i];
    }
    acc
}

/// The degree of flat index `i < 9`.
const BAND: [usize; 9] = [0, 1, 1, 1, 2, 2, 2, 2, 2];

/// The highest degree held by `n = 4` or `9` coefficients.
pub(crate) const fn lmax_of(n: usize) -> usize {
    if n == 4 { 1 } else { 2 }
}

/// `Y_i(d)`, `i < N` (`N = 4` or `9`), from [`crate::sh::low_degree`]'s polynomials.
#[inline(always)]
pub(crate) fn basis<T: GlamReal, const N: usize>(d: T::Vec3) -> [T; N] {
    let [x, y, z] = T::vec3_to_array(d);
    let mut out = [<T as crate::sh::real::Real>::ZERO; N];
    eval_low_degree(lmax_of(N), x, y, z, &mut out);
    out
}

/// The weights `w` with `f(d) = sum_i w_i p_i(d)` for the monomials
/// `p = [1, y, z, x, xy, yz, z^2, xz, x^2 - y^2]` of [`monomials`]: the
/// basis constants and signs of [`crate::sh::low_degree`] folded into the
/// coefficients, and `Y_2^0 = K20 (3 z^2 - 1)` split between `z^2` and the
/// constant. Evaluation then costs one product per coefficient and the
/// basis constants are applied once per expansion, not once per direction
/// (inside a loop the compiler lifts this out).
#[inline(always)]
pub(crate) fn monomial_weights<T: GlamReal, const N: usize>(c: &[T; N]) -> [T; N] {
    let k = T::from_f64;
    let mut w = [<T as crate::sh::real::Real>::ZERO; N];
    w[0] = c[0] * k(K00);
    w[1] = -c[1] * k(K1);
    w[2] = c[2] * k(K1);
    w[3] = -c[3] * k(K1);
    if N == 9 {
        let c: [T; 9] = core::array::from_fn(|i| c[i]);
        let tail = [
            c[4] * k(K2_2),
            -c[5] * k(K2_2),
            c[6] * k(3.0 * K20),
            -c[7] * k(K2_2),
            c[8] * k(K22),
        ];
        w[0] -= c[6] * k(K20);
        w[4..9].copy_from_slice(&tail);
    }
    w
}

/// `[1, y, z, x]` or `[1, y, z, x, xy, yz, z^2, xz, x^2 - y^2]` at `d`.
#[inline(always)]
pub(crate) fn monomials<T: GlamReal, const N: usize>(d: T::Vec3) -> [T; N] {
    let [x, y, z] = T::vec3_to_array(d);
    let mut p = [T::ONE; N];
    p[1] = y;
    p[2] = z;
    p[3] = x;
    if N == 9 {
        let tail = [x * y, y * z, z * z, x * z, x * x - y * y];
        p[4..9].copy_from_slice(&tail);
    }
    p
}

/// `E_i = A_l L_i`, `l` the degree of `i`.
#[inline(always)]
pub(crate) fn irradiance<T: GlamReal, const N: usize>(c: &[T; N]) -> [T; N] {
    core::array::from_fn(|i| c[i] * T::from_f64(A_L[BAND[i]]))
}

/// The first `N` coefficients of `s`, channel `ch`, zero past its end.
pub(crate) fn take<C: crate::sh::sh_value::ShValue, const N: usize>(
    s: &[C],
    ch: usize,
) -> [C::Scalar; N] {
    core::array::from_fn(|i| {
        s.get(i)
            .map_or(<C::Scalar as crate::sh::real::Real>::ZERO, |v| {
                v.channel(ch)
            })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::zonal::clamped_cosine_eigenvalue;

    #[test]
    fn eigenvalues_match_the_general_formula() {
        for (l, a) in A_L.iter().enumerate() {
            assert!((a - clamped_cosine_eigenvalue(l)).abs() < 1e-15, "l = {l}");
        }
    }

    #[test]
    fn dot_sums_every_product() {
        let a = [1.0f64, 2.0, 3.0, 4.0];
        let b = [0.5, -1.0, 2.0, 0.25];
        assert_eq!(dot(&a, &b), 0.5 - 2.0 + 6.0 + 1.0);
    }
}
