//! [`legendre_study`]: why code evaluates Legendre polynomials by their
//! recurrence and not by Rodrigues' formula, in numbers
//! (`shlight accuracy --legendre`).
//!
//! Rodrigues' formula `P_l(x) = 1/(2^l l!) d^l/dx^l (x^2 - 1)^l`, expanded,
//! is the power series
//!
//! ```text
//! P_l(x) = 2^-l sum_{k=0}^{l/2} (-1)^k C(l, k) C(2l - 2k, l) x^(l - 2k)
//! ```
//!
//! whose terms grow like `4^l` while their sum stays below 1: in `f64` the
//! cancellation loses digits from degree 24 at `x = 0.5`, all of them by
//! degree 256, and the
//! binomials overflow past degree 1000. The three-term recurrence
//! (`shlight_core::sh::Legendre`, normalised, with an extended exponent)
//! keeps full accuracy to any degree; its check is the addition theorem
//! `sum_m |Y_l^m(d)|^2 = (2l+1)/(4 pi)` at every direction, here near a pole
//! where the sectoral terms underflow `f64`.

use std::f64::consts::PI;
use std::fmt::Write as _;

use shlight_core::sh::{Legendre, legendre_count, legendre_index};

/// Degrees the study reports, to lmax 2800.
pub const DEGREES: [usize; 12] = [1, 2, 4, 8, 16, 24, 32, 48, 64, 256, 1024, 2800];

/// Where Legendre polynomials are compared: `x = cos(theta) = 0.5`.
pub const X: f64 = 0.5;

/// Polar angle of the sum-rule check, degrees from the pole.
pub const POLE_DEGREES: f64 = 1.0;

/// One degree of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendreRow {
    /// The degree `l`.
    pub l: usize,
    /// `P_l(X)` by the normalised recurrence (shlight's `Legendre`),
    /// divided by `K_l^0 = sqrt((2l+1)/(4 pi))`.
    pub recurrence: f64,
    /// `P_l(X)` by the expanded Rodrigues formula in `f64`: inf or NaN once
    /// the binomials overflow.
    pub rodrigues: f64,
    /// `|sum_m |Y_l^m|^2 * 4 pi / (2l+1) - 1|` at `POLE_DEGREES` from the
    /// pole, by the recurrence.
    pub sum_rule_error: f64,
}

impl LegendreRow {
    /// `|rodrigues - recurrence|`, NaN when Rodrigues overflowed.
    #[must_use]
    pub fn rodrigues_error(&self) -> f64 {
        let e = (self.rodrigues - self.recurrence).abs();
        if e.is_finite() { e } else { f64::NAN }
    }
}

/// `P_l(x)` by Rodrigues' formula expanded into its power series, summed in
/// `f64` as a textbook would (the coefficients as products of binomials).
#[must_use]
pub fn rodrigues(l: usize, x: f64) -> f64 {
    let mut sum = 0.0;
    for k in 0..=l / 2 {
        let c = binomial(l, k) * binomial(2 * l - 2 * k, l);
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        sum += sign * c * x.powi((l - 2 * k) as i32);
    }
    sum / 2f64.powi(l as i32)
}

/// `C(n, k)` as an `f64` product (overflows to inf for large `n`).
fn binomial(n: usize, k: usize) -> f64 {
    let k = k.min(n - k);
    (0..k).fold(1.0, |c, i| c * (n - i) as f64 / (i + 1) as f64)
}

/// The study at every degree of `degrees`.
#[must_use]
pub fn legendre_study(degrees: &[usize]) -> Vec<LegendreRow> {
    let lmax = degrees.iter().copied().max().unwrap_or(0);
    let leg = Legendre::<f64>::new(lmax);
    let mut at_x = vec![0.0; legendre_count(lmax)];
    leg.eval(X, &mut at_x);
    let mut near_pole = vec![0.0; legendre_count(lmax)];
    leg.eval(POLE_DEGREES.to_radians().cos(), &mut near_pole);
    degrees
        .iter()
        .map(|&l| {
            let k = ((2 * l + 1) as f64 / (4.0 * PI)).sqrt();
            let sum: f64 = (0..=l)
                .map(|m| {
                    let p = near_pole[legendre_index(l, m)];
                    if m == 0 { p * p } else { 2.0 * p * p }
                })
                .sum();
            LegendreRow {
                l,
                recurrence: at_x[legendre_index(l, 0)] / k,
                rodrigues: rodrigues(l, X),
                sum_rule_error: (sum / (k * k) - 1.0).abs(),
            }
        })
        .collect()
}

/// The study as the plain-text table `shlight accuracy --legendre` prints.
#[must_use]
pub fn legendre_table(rows: &[LegendreRow]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:>5} {:>24} {:>24} {:>10} {:>10}",
        "l", "P_l(0.5) recurrence", "P_l(0.5) Rodrigues", "|diff|", "sum rule"
    );
    for r in rows {
        let _ = writeln!(
            out,
            "{:>5} {:>24.16e} {:>24.16e} {:>10.2e} {:>10.2e}",
            r.l,
            r.recurrence,
            r.rodrigues,
            r.rodrigues_error(),
            r.sum_rule_error
        );
    }
    let _ = writeln!(
        out,
        "|diff|: Rodrigues' expanded power series in f64 against the recurrence (NaN: overflow).\n\
         sum rule: |sum_m Y_lm^2 * 4pi/(2l+1) - 1| at {POLE_DEGREES} degree from the pole, by the recurrence."
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `P_l(x)` by Bonnet's unnormalised recurrence, written here apart
    /// from the core's normalised one.
    fn bonnet(l: usize, x: f64) -> f64 {
        let (mut p0, mut p1) = (1.0, x);
        if l == 0 {
            return p0;
        }
        for n in 1..l {
            let nf = n as f64;
            let p2 = ((2.0 * nf + 1.0) * x * p1 - nf * p0) / (nf + 1.0);
            p0 = p1;
            p1 = p2;
        }
        p1
    }

    #[test]
    fn rodrigues_matches_closed_forms_at_low_degree() {
        // P_2 = (3x^2 - 1)/2, P_3 = (5x^3 - 3x)/2, P_4 = (35x^4 - 30x^2 + 3)/8.
        for x in [-0.9, -0.3, 0.0, 0.5, 0.8] {
            let x2 = x * x;
            assert!((rodrigues(2, x) - (3.0 * x2 - 1.0) / 2.0).abs() < 1e-15);
            assert!((rodrigues(3, x) - (5.0 * x2 * x - 3.0 * x) / 2.0).abs() < 1e-15);
            assert!((rodrigues(4, x) - (35.0 * x2 * x2 - 30.0 * x2 + 3.0) / 8.0).abs() < 1e-15);
        }
    }

    #[test]
    fn recurrence_matches_bonnet_and_rodrigues_fails_at_high_degree() {
        let rows = legendre_study(&DEGREES);
        for r in &rows {
            let want = bonnet(r.l, X);
            assert!(
                (r.recurrence - want).abs() < 1e-13,
                "l {}: {} vs Bonnet {want}",
                r.l,
                r.recurrence
            );
            assert!(r.sum_rule_error < 1e-10, "l {}: {}", r.l, r.sum_rule_error);
        }
        let at = |l: usize| rows.iter().find(|r| r.l == l).unwrap();
        assert!(at(8).rodrigues_error() < 1e-14);
        // Cancellation: digits go at degree 24, all of them by degree 256.
        assert!(at(24).rodrigues_error() > 1e-14, "{:?}", at(24));
        assert!(at(64).rodrigues_error() > 1e-7, "{:?}", at(64));
        assert!(at(256).rodrigues_error() > 1.0, "{:?}", at(256));
        // Overflow: the binomials are inf by degree 1024.
        assert!(at(1024).rodrigues_error().is_nan());
        assert!(at(2800).recurrence.is_finite());
    }

    #[test]
    fn table_has_a_line_per_degree() {
        let rows = legendre_study(&[2, 64]);
        let table = legendre_table(&rows);
        assert_eq!(table.lines().count(), 1 + 2 + 2);
        assert!(table.lines().nth(1).unwrap().trim_start().starts_with("2 "));
    }
}
