//! The GGX (Trowbridge-Reitz) microfacet lobe: its distribution, the
//! importance sampling of half vectors, the masking-shadowing terms, and
//! the Hammersley points every estimator here is driven by.
//!
//! Roughness `alpha` is the *linear* roughness of the distribution
//! (`alpha = perceptual^2`, Burley 2012), in `[0, 1]`.

use glam::{DVec2, DVec3};

/// `D(h) = alpha^2 / (π ((n·h)^2 (alpha^2 - 1) + 1)^2)`, the GGX normal
/// distribution (Walter et al. 2007, eq. 33), normalised so that
/// `∫ D(h) (n·h) dω_h = 1` over the hemisphere.
#[must_use]
pub fn d_ggx(n_dot_h: f64, alpha: f64) -> f64 {
    // (a-1)(a+1) rather than a^2-1: the better rounding near alpha = 1.
    let f = (alpha - 1.0) * ((alpha + 1.0) * (n_dot_h * n_dot_h)) + 1.0;
    alpha * alpha / (std::f64::consts::PI * f * f)
}

/// The half vector (about `+Z`) that GGX importance sampling gives for the
/// point `u` of the unit square: `φ = 2π u.x`,
/// `cos²θ = (1 - u.y) / (1 + (alpha² - 1) u.y)`; its density is
/// `D(h) (n·h)` (Karis 2013, "Real Shading in Unreal Engine 4", the
/// `ImportanceSampleGGX` listing).
#[must_use]
pub fn sample_ggx_half(u: DVec2, alpha: f64) -> DVec3 {
    let phi = std::f64::consts::TAU * u.x;
    let cos2 = (1.0 - u.y) / (1.0 + (alpha + 1.0) * ((alpha - 1.0) * u.y));
    let cos = cos2.sqrt();
    let sin = (1.0 - cos2).max(0.0).sqrt();
    DVec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// Point `i` of the `n`-point Hammersley set, `(i / n, radical inverse of
/// i in base 2)`: the fixed low-discrepancy sequence that makes every
/// estimate here deterministic.
#[must_use]
pub fn hammersley(i: u32, n: u32) -> DVec2 {
    DVec2::new(
        f64::from(i) / f64::from(n),
        f64::from(i.reverse_bits()) * (1.0 / 4_294_967_296.0),
    )
}

/// How a DFG table masks and shadows: the term `V = G / (4 (n·l)(n·v))`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaskingShadowing {
    /// Smith's height-correlated GGX masking-shadowing (Heitz 2014,
    /// "Understanding the Masking-Shadowing Function", eq. 99): Filament's
    /// `Visibility`, Babylon's `smithVisibility_GGXCorrelated`.
    HeightCorrelated,
    /// Schlick's approximation of separable Smith with `k = alpha / 2`
    /// (Karis 2013, `G_Smith` of the IBL listing): Unreal's.
    SchlickSmith,
}

impl MaskingShadowing {
    /// `V(n·v, n·l) = G / (4 (n·l)(n·v))` for roughness `alpha`.
    #[must_use]
    pub fn eval(self, n_dot_v: f64, n_dot_l: f64, alpha: f64) -> f64 {
        match self {
            MaskingShadowing::HeightCorrelated => {
                let a2 = alpha * alpha;
                let ggx_l = n_dot_v * ((n_dot_l - n_dot_l * a2) * n_dot_l + a2).sqrt();
                let ggx_v = n_dot_l * ((n_dot_v - n_dot_v * a2) * n_dot_v + a2).sqrt();
                0.5 / (ggx_v + ggx_l)
            }
            MaskingShadowing::SchlickSmith => {
                let k = alpha / 2.0;
                let g1 = |x: f64| x / (x * (1.0 - k) + k);
                g1(n_dot_v) * g1(n_dot_l) / (4.0 * n_dot_l * n_dot_v)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `∫ D(h) (n·h) dω = 1`, by a midpoint rule in `cos θ`.
    #[test]
    fn the_distribution_is_normalised() {
        for alpha in [0.05, 0.2, 0.5, 1.0] {
            let n = 200_000;
            let sum: f64 = (0..n)
                .map(|i| {
                    let c = (i as f64 + 0.5) / n as f64;
                    d_ggx(c, alpha) * c * std::f64::consts::TAU / n as f64
                })
                .sum();
            assert!((sum - 1.0).abs() < 1e-3, "alpha {alpha}: {sum}");
        }
    }

    /// The sampled half vectors' mean of `cos θ` matches the density's
    /// own, `∫ cos θ D cos θ dω`, computed by the midpoint rule.
    #[test]
    fn half_vectors_follow_the_density() {
        for alpha in [0.1, 0.4, 0.9] {
            let n = 4096;
            let mean: f64 = (0..n)
                .map(|i| sample_ggx_half(hammersley(i, n), alpha).z)
                .sum::<f64>()
                / f64::from(n);
            let m = 200_000;
            let want: f64 = (0..m)
                .map(|i| {
                    let c = (i as f64 + 0.5) / m as f64;
                    c * d_ggx(c, alpha) * c * std::f64::consts::TAU / m as f64
                })
                .sum();
            assert!(
                (mean - want).abs() < 2e-3,
                "alpha {alpha}: {mean} vs {want}"
            );
        }
    }
}
