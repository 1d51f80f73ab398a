//! Normalised associated Legendre functions by stable recurrences, to any degree.

use crate::sh::real::Real;

/// Number of `Pbar_l^m` with `0 <= m <= l <= lmax`: `(lmax+1)(lmax+2)/2`.
#[inline]
#[must_use]
pub const fn legendre_count(lmax: usize) -> usize {
    (lmax + 1) * (lmax + 2) / 2
}

/// Index of `Pbar_l^m` (`0 <= m <= l`) in the triangular layout filled by
/// [`Legendre::eval`]: `l (l+1) / 2 + m`.
#[inline]
#[must_use]
pub const fn legendre_index(l: usize, m: usize) -> usize {
    l * (l + 1) / 2 + m
}

/// Precomputed recurrence coefficients for SH-normalised associated Legendre
/// functions up to degree `lmax`, in scalar type `T`.
///
/// Building costs `O(lmax^2)` square roots once; every evaluation then runs
/// the recurrences with multiplications only.
///
/// ```
/// use shlight_core::sh::{Legendre, legendre_count, legendre_index};
/// let leg = Legendre::<f64>::new(2);
/// let mut p = vec![0.0; legendre_count(2)];
/// leg.eval(0.5, &mut p);
/// // Pbar_1^0(x) = sqrt(3/(4 pi)) x
/// let want = (3.0 / (4.0 * std::f64::consts::PI)).sqrt() * 0.5;
/// assert!((p[legendre_index(1, 0)] - want).abs() < 1e-15);
/// ```
///
/// # Recurrences
///
/// The functions are the *SH-normalised* associated Legendre functions
///
/// ```text
/// Pbar_l^m(x) = K_l^m P_l^m(x),   K_l^m = sqrt((2l+1)/(4 pi) * (l-m)!/(l+m)!),   0 <= m <= l,
/// ```
///
/// with the Condon-Shortley phase `(-1)^m` included in `P_l^m`, so that the
/// real SH are `Y_l^0 = Pbar_l^0(cos t)` and `Y_l^{+-m} = sqrt(2) Pbar_l^m(cos t) {cos, sin}(m phi)`
/// ([`ShBasis`](crate::sh::ShBasis)). No factorial is ever formed; the recurrences run
/// directly on normalised values (`s = sqrt(1 - x^2)`):
///
/// ```text
/// Pbar_0^0     = 1 / sqrt(4 pi)
/// Pbar_m^m     = -sqrt((2m+1)/(2m)) s Pbar_{m-1}^{m-1}                  (sectoral)
/// Pbar_{m+1}^m = sqrt(2m+3) x Pbar_m^m
/// Pbar_l^m     = a_l^m (x Pbar_{l-1}^m - b_l^m Pbar_{l-2}^m),
///     a_l^m = sqrt((4l^2-1)/(l^2-m^2)),  b_l^m = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1)) = 1/a_{l-1}^m
/// ```
///
/// # Underflow
///
/// The sectoral values behave like `s^m`, which underflows
/// `f64` (about `1e-308`) near the poles once `m` is in the hundreds, although
/// the column recurrence later grows those columns back to significant
/// values. Each column therefore carries an integer exponent `k <= 0`: the
/// true value is `p * SMALL^(-k)` with `SMALL = 2^-600` (`2^-60` for `f32`).
/// A sectoral value that falls under `SMALL` is multiplied by `BIG = 1/SMALL`
/// and `k` decreases; a column value that grows past `BIG` while `k < 0` is
/// multiplied by `SMALL` and `k` increases. A value is emitted as `p` when
/// `k = 0`, `p * SMALL` when `k = -1`, and `0` when it is smaller than that
/// (below `2^-600`, it cannot matter). This is the extended-exponent scheme of
/// SHTns and ducc0; it keeps the orthonormality of the computed functions at
/// about `1e-12` at degree 2048 and beyond (see the tests).
#[derive(Clone, Debug)]
pub struct Legendre<T> {
    lmax: usize,
    /// `-sqrt((2m+1)/(2m))` for `m >= 1` (index `m`); unused at 0.
    sectoral: Vec<T>,
    /// `sqrt(2m+3)` for each `m`.
    diagonal: Vec<T>,
    /// `(a_l^m, a_l^m b_l^m)` for `l >= m+2`, column by column (`m` outer, `l` inner).
    ab: Vec<[T; 2]>,
}

impl<T: Real> Legendre<T> {
    /// Builds the recurrence tables for degrees `0..=lmax`.
    #[must_use]
    pub fn new(lmax: usize) -> Self {
        let mut sectoral = vec![T::ZERO; lmax + 1];
        let mut diagonal = vec![T::ZERO; lmax + 1];
        let mut ab = Vec::with_capacity(legendre_count(lmax));
        for m in 0..=lmax {
            let mf = m as f64;
            if m > 0 {
                sectoral[m] = T::from_f64(-((2.0 * mf + 1.0) / (2.0 * mf)).sqrt());
            }
            diagonal[m] = T::from_f64((2.0 * mf + 3.0).sqrt());
            for l in m + 2..=lmax {
                let lf = l as f64;
                let a = ((4.0 * lf * lf - 1.0) / ((lf - mf) * (lf + mf))).sqrt();
                let l1 = lf - 1.0;
                let b = ((l1 - mf) * (l1 + mf) / (4.0 * l1 * l1 - 1.0)).sqrt();
                ab.push([T::from_f64(a), T::from_f64(a * b)]);
            }
        }
        Self {
            lmax,
            sectoral,
            diagonal,
            ab,
        }
    }

    /// `-sqrt((2m+1)/(2m))`, the sectoral step from `Pbar_{m-1}^{m-1}` to `Pbar_m^m` (over `s`), `m >= 1`.
    #[inline]
    #[must_use]
    pub fn sectoral_factor(&self, m: usize) -> T {
        self.sectoral[m]
    }

    /// `sqrt(2m+3)`, the step from `Pbar_m^m` to `Pbar_{m+1}^m` (over `x`).
    #[inline]
    #[must_use]
    pub fn diagonal_factor(&self, m: usize) -> T {
        self.diagonal[m]
    }

    /// `(a_l^m, a_l^m b_l^m)` for `l = m+2..=lmax`.
    #[inline]
    #[must_use]
    pub fn column_factors(&self, m: usize) -> &[[T; 2]] {
        let start = m * self.lmax.saturating_sub(1) - m * m.saturating_sub(1) / 2;
        &self.ab[start..start + self.lmax.saturating_sub(m + 1)]
    }

    /// The highest degree these tables reach.
    #[must_use]
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// Every `Pbar_l^m(x)`, `0 <= m <= l <= lmax`, for one `x = cos(theta)` in
    /// `[-1, 1]`, in one pass; written at [`legendre_index`]`(l, m)`.
    ///
    /// Panics if `out.len() < legendre_count(lmax)`.
    pub fn eval(&self, x: T, out: &mut [T]) {
        assert!(out.len() >= legendre_count(self.lmax), "output too short");
        let s = (T::ONE - x * x).sqrt();
        self.columns::<1>(&[x], &[s], |l, m, p| out[legendre_index(l, m)] = p[0]);
    }

    /// Runs the recurrences on `N` lanes at once and hands every value to
    /// `emit(l, m, values)`, column by column: `m = 0..=lmax` outer and
    /// `l = m..=lmax` inner. `x` holds `cos(theta)` and `s` holds
    /// `sin(theta) >= 0` per lane.
    ///
    /// The lane loops are written so that the compiler vectorises them.
    #[inline(always)]
    pub fn columns<const N: usize>(
        &self,
        x: &[T; N],
        s: &[T; N],
        mut emit: impl FnMut(usize, usize, &[T; N]),
    ) {
        let big = T::BIG;
        let small = T::SMALL;
        // Sectoral value and its exponent count (0 or negative, kept as T so
        // the lane loops stay branch-free).
        let mut pmm = [T::from_f64(0.5 / core::f64::consts::PI.sqrt()); N];
        let mut kmm = [T::ZERO; N];
        let mut offset = 0;
        for m in 0..=self.lmax {
            if m > 0 {
                let f = self.sectoral[m];
                for j in 0..N {
                    let p = pmm[j] * f * s[j];
                    let tiny = p.abs() < small;
                    pmm[j] = if tiny { p * big } else { p };
                    kmm[j] = if tiny { kmm[j] - T::ONE } else { kmm[j] };
                }
            }
            let scaled = kmm.iter().any(|&k| k != T::ZERO);
            let mut p1 = pmm;
            let mut k = kmm;
            emit(m, m, &unscale(&p1, &k, scaled));
            if m == self.lmax {
                break;
            }
            let d = self.diagonal[m];
            let mut p2 = [T::ZERO; N];
            for j in 0..N {
                p2[j] = d * x[j] * p1[j];
            }
            emit(m + 1, m, &unscale(&p2, &k, scaled));
            // Coefficients for l = m+2..=lmax.
            let column = &self.ab[offset..offset + self.lmax - m - 1];
            offset += column.len();
            if !scaled {
                // Fast path: no lane needs exponent tracking in this column.
                for (i, &[a, ab_]) in column.iter().enumerate() {
                    let mut p3 = [T::ZERO; N];
                    for j in 0..N {
                        p3[j] = a * x[j] * p2[j] - ab_ * p1[j];
                    }
                    p1 = p2;
                    p2 = p3;
                    emit(m + 2 + i, m, &p2);
                }
            } else {
                for (i, &[a, ab_]) in column.iter().enumerate() {
                    let mut p3 = [T::ZERO; N];
                    for j in 0..N {
                        let v = a * x[j] * p2[j] - ab_ * p1[j];
                        let grow = k[j] < T::ZERO && v.abs() > big;
                        p3[j] = if grow { v * small } else { v };
                        p2[j] = if grow { p2[j] * small } else { p2[j] };
                        k[j] = if grow { k[j] + T::ONE } else { k[j] };
                    }
                    p1 = p2;
                    p2 = p3;
                    emit(m + 2 + i, m, &unscale(&p2, &k, true));
                }
            }
        }
    }
}

/// True value of extended-exponent lanes: `p` at `k = 0`, `p * SMALL` at
/// `k = -1`, else 0.
#[inline(always)]
fn unscale<T: Real, const N: usize>(p: &[T; N], k: &[T; N], scaled: bool) -> [T; N] {
    if !scaled {
        return *p;
    }
    let mut out = [T::ZERO; N];
    for j in 0..N {
        out[j] = if k[j] == T::ZERO {
            p[j]
        } else if k[j] == -T::ONE {
            p[j] * T::SMALL
        } else {
            T::ZERO
        };
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    /// Unnormalised P_l^m with CS phase by the textbook recurrence (small l only).
    fn plm_textbook(l: usize, m: usize, x: f64) -> f64 {
        let s = (1.0 - x * x).sqrt();
        let mut pmm = 1.0;
        for i in 1..=m {
            pmm *= -((2 * i - 1) as f64) * s;
        }
        if l == m {
            return pmm;
        }
        let mut pm1 = x * (2 * m + 1) as f64 * pmm;
        if l == m + 1 {
            return pm1;
        }
        let mut p = 0.0;
        for ll in m + 2..=l {
            p = (x * (2 * ll - 1) as f64 * pm1 - (ll + m - 1) as f64 * pmm) / (ll - m) as f64;
            pmm = pm1;
            pm1 = p;
        }
        p
    }

    fn factorial(n: usize) -> f64 {
        (1..=n).map(|i| i as f64).product()
    }

    #[test]
    fn matches_textbook_recurrence_with_factorials_at_low_degree() {
        let lmax = 12;
        let leg = Legendre::<f64>::new(lmax);
        let mut p = vec![0.0; legendre_count(lmax)];
        for &x in &[-0.93, -0.4, 0.0, 0.123, 0.77, 0.999] {
            leg.eval(x, &mut p);
            for l in 0..=lmax {
                for m in 0..=l {
                    let k = ((2 * l + 1) as f64 / (4.0 * PI) * factorial(l - m) / factorial(l + m))
                        .sqrt();
                    let want = k * plm_textbook(l, m, x);
                    let got = p[legendre_index(l, m)];
                    assert!(
                        (got - want).abs() <= 1e-13 * want.abs().max(1.0),
                        "l={l} m={m} x={x}: {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn zonal_values_at_the_pole_are_the_normalisation() {
        // Pbar_l^0(1) = sqrt((2l+1)/(4 pi)); Pbar_l^m(1) = 0 for m > 0.
        let lmax = 3000;
        let leg = Legendre::<f64>::new(lmax);
        let mut p = vec![0.0; legendre_count(lmax)];
        leg.eval(1.0, &mut p);
        for l in 0..=lmax {
            let want = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
            let got = p[legendre_index(l, 0)];
            assert!(
                (got - want).abs() < 1e-14 * l.max(1) as f64 * want,
                "l={l}: {got} vs {want}"
            );
            if l > 0 {
                assert_eq!(p[legendre_index(l, l)], 0.0);
            }
        }
    }

    #[test]
    fn sum_rule_holds_at_degree_2800_near_the_pole() {
        // Unsold: sum_m (2 - [m=0]) Pbar_l^m(x)^2 = (2l+1)/(4 pi) for every x.
        // Near the pole the sectoral values underflow f64 by hundreds of orders
        // of magnitude; without exponent tracking the sum collapses.
        let lmax = 2800;
        let leg = Legendre::<f64>::new(lmax);
        let mut p = vec![0.0; legendre_count(lmax)];
        for &x in &[0.0f64, 0.5, 0.9, 0.999, 0.99999, -0.9999999] {
            leg.eval(x, &mut p);
            let mut worst = 0.0f64;
            for l in (0..=lmax).step_by(7) {
                let mut sum = 0.0;
                for m in 0..=l {
                    let v = p[legendre_index(l, m)];
                    sum += if m == 0 { v * v } else { 2.0 * v * v };
                }
                let want = (2 * l + 1) as f64 / (4.0 * PI);
                worst = worst.max((sum / want - 1.0).abs());
            }
            assert!(
                worst < 1e-10,
                "x={x}: worst relative sum-rule error {worst:e}"
            );
        }
    }

    #[test]
    fn f32_tables_agree_with_f64() {
        let lmax = 64;
        let l64 = Legendre::<f64>::new(lmax);
        let l32 = Legendre::<f32>::new(lmax);
        let mut p64 = vec![0.0; legendre_count(lmax)];
        let mut p32 = vec![0.0f32; legendre_count(lmax)];
        for &x in &[-0.99f64, -0.3, 0.2, 0.95] {
            l64.eval(x, &mut p64);
            l32.eval(x as f32, &mut p32);
            for i in 0..p64.len() {
                assert!((p32[i] as f64 - p64[i]).abs() < 2e-5, "i={i}");
            }
        }
    }
}
