//! How errors are measured: relative irradiance error over a set of normals,
//! and the rate at which it falls.
//!
//! **Relative error** at a normal `n` is `|E_est(n) - E_ref(n)| / E_peak`,
//! with `E_peak = max_n |E_ref(n)|` over the same normals: the
//! normalisation of Ramamoorthi & Hanrahan 2001, whose figures for a
//! directional light (`3/32` at 90°, `0.0307` on average) are in units of
//! the irradiance facing the light. It stays finite where `E` vanishes
//! (half the sphere for a directional light or a small cap), where an error
//! relative to `E(n)` itself would be infinite. Where `E` is bounded away
//! from zero (real maps) [`pointwise`] also gives `|ΔE(n)| / E(n)`.

/// Mean and largest relative error over a set of normals.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorStats {
    /// Mean over the normals (equal-area normals give an area mean).
    pub mean: f64,
    /// Largest.
    pub max: f64,
    /// Root mean square. Its square is the mean squared error, which for
    /// an unbiased Monte Carlo estimate is exactly `variance / N`, so the
    /// rates are fitted to it.
    pub rms: f64,
}

impl ErrorStats {
    /// Statistics of the values `errors` (already relative).
    #[must_use]
    pub fn of(errors: impl IntoIterator<Item = f64>) -> Self {
        let (mut sum, mut sum2, mut max, mut n) = (0.0, 0.0, 0.0f64, 0usize);
        for e in errors {
            sum += e;
            sum2 += e * e;
            max = max.max(e);
            n += 1;
        }
        let n = n.max(1) as f64;
        Self {
            mean: sum / n,
            max,
            rms: (sum2 / n).sqrt(),
        }
    }
}

impl ErrorStats {
    /// Statistics of `errors` with the mean and RMS weighted by `weights`
    /// (e.g. texel solid angles, for an area mean over a map's texels).
    #[must_use]
    pub fn weighted(errors: &[f64], weights: &[f64]) -> Self {
        let (mut sum, mut sum2, mut total, mut max) = (0.0, 0.0, 0.0, 0.0f64);
        for (e, w) in errors.iter().zip(weights) {
            sum += w * e;
            sum2 += w * e * e;
            total += w;
            max = max.max(*e);
        }
        let total = if total > 0.0 { total } else { 1.0 };
        Self {
            mean: sum / total,
            max,
            rms: (sum2 / total).sqrt(),
        }
    }
}

/// `max |reference|`, the peak irradiance that errors are relative to.
#[must_use]
pub fn peak(reference: &[f64]) -> f64 {
    reference.iter().fold(0.0f64, |m, e| m.max(e.abs()))
}

/// Relative errors `|est - reference| / peak(reference)` (module docs).
#[must_use]
pub fn relative_to_peak(estimate: &[f64], reference: &[f64]) -> ErrorStats {
    ErrorStats::of(peak_relative_errors(estimate, reference))
}

/// The errors of [`relative_to_peak`], one per value.
#[must_use]
pub fn peak_relative_errors(estimate: &[f64], reference: &[f64]) -> Vec<f64> {
    let p = peak(reference).max(f64::MIN_POSITIVE);
    estimate
        .iter()
        .zip(reference)
        .map(|(e, r)| (e - r).abs() / p)
        .collect()
}

/// Pointwise relative errors `|est - reference| / |reference|`, for
/// references bounded away from zero; a reference below
/// `floor * peak(reference)` counts as that floor.
#[must_use]
pub fn pointwise(estimate: &[f64], reference: &[f64], floor: f64) -> ErrorStats {
    ErrorStats::of(pointwise_errors(estimate, reference, floor))
}

/// The errors of [`pointwise`], one per value.
#[must_use]
pub fn pointwise_errors(estimate: &[f64], reference: &[f64], floor: f64) -> Vec<f64> {
    let f = floor * peak(reference);
    estimate
        .iter()
        .zip(reference)
        .map(|(e, r)| (e - r).abs() / r.abs().max(f).max(f64::MIN_POSITIVE))
        .collect()
}

/// The least-squares slope of `ln y` against `ln x`: the exponent `p` of
/// `y ∝ x^p`. Points with `y <= 0` are skipped; `None` with fewer than two
/// points.
#[must_use]
pub fn log_log_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(x, y)| **x > 0.0 && **y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = pts.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_of_a_power_law_is_its_exponent() {
        let x = [1e2, 1e3, 1e4, 1e5];
        let y: Vec<f64> = x.iter().map(|x: &f64| 3.0 * x.powf(-0.5)).collect();
        assert!((log_log_slope(&x, &y).unwrap() + 0.5).abs() < 1e-12);
        assert_eq!(log_log_slope(&[1.0], &[1.0]), None);
    }

    #[test]
    fn relative_errors_use_the_peak() {
        let s = relative_to_peak(&[1.0, 0.1], &[2.0, 0.0]);
        assert_eq!(s.max, 0.5);
        assert_eq!(s.mean, (0.5 + 0.05) / 2.0);
        let p = pointwise(&[1.0, 0.1], &[2.0, 0.0], 0.1);
        assert_eq!(p.max, 0.5);
    }
}
