//! The ring transform's column pass: for one order `m`, the Legendre sums
//! `L_l^{±m} = sum_pairs Pbar_l^m(cos θ) w_{l+m parity}` over the blocks of
//! row pairs, by the recurrence with a unit coefficient on `l - 2`
//! ([`UnitRecurrence`]) started from the sectoral values in extended
//! exponent, blocks past the turning point left out ([`turning_margin`]),
//! and the plain steps run in tiles of [`TILE`] degrees so that a tile's
//! sums stay in the L1 cache.

#[cfg(target_arch = "x86_64")]
use crate::cpu_features::avx_fma;
use crate::map::projection::ring_transform::blocks::{BlockStart, BlockWeights, LANES, Partial};
use crate::map::projection::ring_transform::kernels::{add_scaled, run_plain};
use crate::sh::legendre::Legendre;
use crate::sh::real::Real;

/// Everything phase 2 reads, `[block][m]` (and `xs` per block).
pub(crate) struct ColumnInput<'a> {
    pub(crate) leg: &'a Legendre<f64>,
    pub(crate) lmax: usize,
    pub(crate) xs: &'a [[f64; LANES]],
    pub(crate) weights: &'a [BlockWeights],
    pub(crate) starts: &'a [BlockStart],
}

/// The sums of column `m`: entry `l - m` for `l = m..=lmax`.
pub(crate) fn column(input: &ColumnInput<'_>, m: usize) -> Vec<[f64; 6]> {
    #[cfg(target_arch = "x86_64")]
    if avx_fma() {
        // SAFETY: the CPU has the features the function is compiled for.
        return unsafe { column_avx(input, m) };
    }
    column_body::<false>(input, m)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,fma")]
unsafe fn column_avx(input: &ColumnInput<'_>, m: usize) -> Vec<[f64; 6]> {
    column_body::<true>(input, m)
}

/// The column sums leave out a block of rings for the orders `m` beyond
/// every lane's turning point `m = lmax sin θ` by more than
/// [`turning_margin`]: there `Pbar_l^m(cos θ)` decays faster than
/// exponentially for every `l <= lmax` (the associated Legendre functions
/// are evanescent past `m = l sin θ`), so those rings add nothing above
/// rounding, while their recurrence, mostly in extended exponent near the
/// poles, is the dearest part of the column. The same cut-off as libsharp's
/// and ducc0's `get_mlim` (Reinecke & Seljebotn 2013), checked against the
/// direct sums up to lmax 2100 in the tests.
///
/// The margin past the turning point: `max(100, lmax / 100)` orders
/// (libsharp's `sharp_get_mlim` for spin 0).
#[inline(always)]
fn turning_margin(lmax: usize) -> f64 {
    (lmax as f64 * 0.01).max(100.0)
}

/// The largest `sin θ` of a block's lanes (`x = cos θ`; padding lanes have
/// `x = 0`, hence `sin θ = 1`, and never let a block be left out).
#[inline(always)]
fn block_sin_max(x: &[f64; LANES]) -> f64 {
    x.iter()
        .map(|c| (1.0 - c * c).max(0.0).sqrt())
        .fold(0.0, f64::max)
}

/// The column's recurrence with a unit coefficient on `l - 2`.
///
/// [`Legendre`] steps `P_l = A_l x P_{l-1} - B_l P_{l-2}` (`B_l > 0`). With
/// `P_l = c_l Q_l`, `c_m = c_{m+1} = 1` and `c_l = B_l c_{l-2}`, the same
/// functions come from
///
/// ```text
/// Q_l = alpha_l x Q_{l-1} - Q_{l-2},   alpha_l = A_l c_{l-1} / c_l,
/// ```
///
/// a multiply and a fused multiply-subtract per lane instead of three
/// operations (libsharp's and ducc0's form). The sums are taken of `Q_l`
/// and scaled by `c_l` once per degree at the end. `c_l` stays within
/// `[0.16, 1.13]` for every `m <= l <= 4096`, so nothing overflows or
/// underflows, and the extended exponent of the start values works on `Q`
/// as on `P`.
struct UnitRecurrence {
    /// `alpha_l` for `l = m+2..=lmax` (index `l - m - 2`).
    alpha: Vec<f64>,
    /// `c_l` for `l = m..=lmax` (index `l - m`).
    scale: Vec<f64>,
}

impl UnitRecurrence {
    fn new(factors: &[[f64; 2]]) -> Self {
        let mut scale = Vec::with_capacity(factors.len() + 2);
        scale.extend([1.0, 1.0]);
        let mut alpha = Vec::with_capacity(factors.len());
        for (i, &[a, ab]) in factors.iter().enumerate() {
            let c = ab * scale[i];
            alpha.push(a * scale[i + 1] / c);
            scale.push(c);
        }
        Self { alpha, scale }
    }
}

/// Degrees per tile of a column's plain recurrence: the sums of a tile
/// (`TILE x 192` bytes) stay in the L1 cache while every block of rings
/// runs through it, instead of streaming the whole column's sums through
/// the cache once per block.
const TILE: usize = 48;

/// A block of rings whose lanes are all at `k = 0` from step `from` on,
/// with `(Q_{l-2}, Q_{l-1})` for the step `from` is about to take.
struct PlainRun {
    block: usize,
    from: usize,
    p1: [f64; LANES],
    p2: [f64; LANES],
}

#[inline(always)]
fn column_body<const FMA: bool>(input: &ColumnInput<'_>, m: usize) -> Vec<[f64; 6]> {
    let lmax = input.lmax;
    let cols = lmax + 1;
    let mut acc: Vec<Partial> = vec![[[0.0; 4]; 6]; lmax - m + 1];
    let (big, small) = (f64::BIG, f64::SMALL);
    let diag = input.leg.diagonal_factor(m);
    let rec = UnitRecurrence::new(input.leg.column_factors(m));
    let n = rec.alpha.len();
    let margin = turning_margin(lmax);
    let mut runs = Vec::with_capacity(input.xs.len());
    for (b, x) in input.xs.iter().enumerate() {
        if m as f64 > lmax as f64 * block_sin_max(x) + margin {
            continue;
        }
        let w = &input.weights[b * cols + m];
        let BlockStart {
            value: mut p1,
            exponent: mut k,
        } = input.starts[b * cols + m];
        // Blocks near the poles start far below f64's range (extended
        // exponent); once every lane is back at `k = 0` the plain
        // recurrence takes over.
        let mut scaled = k.iter().any(|&e| e != 0.0);
        add_scaled::<FMA>(&mut acc[0], &p1, &k, scaled, &w[0]);
        if m == lmax {
            continue;
        }
        let mut p2 = [0.0; LANES];
        for j in 0..LANES {
            p2[j] = diag * x[j] * p1[j];
        }
        add_scaled::<FMA>(&mut acc[1], &p2, &k, scaled, &w[1]);
        let mut i = 0;
        while scaled && i < n {
            let a = rec.alpha[i];
            let mut p3 = [0.0; LANES];
            for j in 0..LANES {
                let v = a * x[j] * p2[j] - p1[j];
                let grow = k[j] < 0.0 && v.abs() > big;
                p3[j] = if grow { v * small } else { v };
                p2[j] = if grow { p2[j] * small } else { p2[j] };
                k[j] = if grow { k[j] + 1.0 } else { k[j] };
            }
            scaled = k.iter().any(|&e| e != 0.0);
            p1 = p2;
            p2 = p3;
            add_scaled::<FMA>(&mut acc[i + 2], &p2, &k, scaled, &w[i % 2]);
            i += 1;
        }
        if i < n {
            runs.push(PlainRun {
                block: b,
                from: i,
                p1,
                p2,
            });
        }
    }
    // The plain steps tile by tile, every block through each tile.
    for t0 in (0..n).step_by(TILE) {
        let t1 = (t0 + TILE).min(n);
        for run in &mut runs {
            let from = run.from.max(t0);
            if from >= t1 {
                continue;
            }
            run_plain::<FMA>(
                &input.xs[run.block],
                &mut run.p1,
                &mut run.p2,
                &rec.alpha[from..t1],
                &mut acc[from + 2..t1 + 2],
                &input.weights[run.block * cols + m],
                from % 2,
            );
        }
    }
    acc.iter()
        .zip(&rec.scale)
        .map(|(a, &c)| a.map(|v| ((v[0] + v[1]) + (v[2] + v[3])) * c))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit recurrence's scales `c_l` stay within the range its docs
    /// give, `[0.16, 1.13]`, for every column to degree 4096.
    #[test]
    fn unit_recurrence_scales_stay_in_range() {
        let lmax = 4096;
        let leg = Legendre::<f64>::new(lmax);
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for m in 0..=lmax {
            for &c in &UnitRecurrence::new(leg.column_factors(m)).scale {
                lo = lo.min(c);
                hi = hi.max(c);
            }
        }
        assert!(lo >= 0.16 && hi <= 1.13, "c_l in [{lo}, {hi}]");
    }
}
