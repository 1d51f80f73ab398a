//! Standard errors of coefficients carried through a rotation.

use glam::DVec3;

use crate::sh::rotation::ShRotation;
use crate::sh::sh_coeffs::ShCoeffs;

/// The standard errors `se` after `rotation`: per degree `l` and channel,
/// `σ'_m = sqrt(Σ_n M_mn² σ_n²)` with `M` the rotation's `(2l+1)²` block.
/// Degrees above the rotation's lmax are returned as 0.
///
/// A Monte Carlo estimate comes with a standard error `σ_n` per
/// coefficient. Rotating the estimate mixes the coefficients of each degree
/// `l` by the rotation's block `M` ([`ShRotation::block`]); taking the
/// errors of one degree as independent, the rotated errors are
/// `σ'_m = sqrt(Σ_n M_mn² σ_n²)` (the variance of a linear combination of
/// independent variables), per colour channel.
pub fn rotate_std_error(rotation: &ShRotation, se: &ShCoeffs<DVec3>) -> ShCoeffs<DVec3> {
    let mut out = ShCoeffs::<DVec3>::zeros(se.lmax());
    for l in 0..=se.lmax().min(rotation.lmax()) {
        let n = 2 * l + 1;
        let block = rotation.block(l);
        let band = se.band(l);
        for (m, o) in out.band_mut(l).iter_mut().enumerate() {
            let var: DVec3 = (0..n)
                .map(|k| band[k] * band[k] * block[m * n + k] * block[m * n + k])
                .sum();
            *o = DVec3::new(var.x.sqrt(), var.y.sqrt(), var.z.sqrt());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat3;
    use rand::rngs::StdRng;
    use rand::{Rng, SeedableRng};

    #[test]
    fn std_errors_follow_a_quarter_turn() {
        // Rz(90°) swaps x and y up to sign: band 1 (-y, z, -x) errors swap.
        let rot = ShRotation::from_mat3(1, DMat3::from_rotation_z(std::f64::consts::FRAC_PI_2));
        let se = ShCoeffs::from_vec(vec![
            DVec3::splat(1.0),
            DVec3::splat(2.0),
            DVec3::splat(3.0),
            DVec3::splat(4.0),
        ])
        .unwrap();
        let out = rotate_std_error(&rot, &se);
        let got: Vec<f64> = out.as_slice().iter().map(|v| v.x).collect();
        for (g, w) in got.iter().zip([1.0, 4.0, 3.0, 2.0]) {
            assert!((g - w).abs() < 1e-12, "{got:?}");
        }
    }

    #[test]
    fn std_errors_match_the_spread_of_rotated_samples() {
        // Independent route: draw noisy coefficient sets with known σ_n,
        // rotate each with the rotation itself, and measure the spread.
        const DRAWS: usize = 40_000;
        // The sample standard deviation of 40 000 Gaussian draws is within
        // about 3 / sqrt(2 * 40 000) ≈ 1.1 % of the true one (3 sigma).
        const SPREAD: f64 = 0.02;
        let lmax = 2;
        let r = DMat3::from_euler(glam::EulerRot::ZYX, 0.4, -1.1, 2.3);
        let rot = ShRotation::from_mat3(lmax, r);
        let se = ShCoeffs::<DVec3>::from_fn(lmax, |l, m| {
            DVec3::new(1.0 + l as f64, 0.5 + 0.1 * m as f64 + l as f64, 2.0)
        });
        let mut rng = StdRng::seed_from_u64(7);
        let mut gauss = || {
            // Box-Muller.
            let (u, v): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        };
        let mut sum_sq = vec![DVec3::ZERO; se.as_slice().len()];
        for _ in 0..DRAWS {
            let noisy = ShCoeffs::<DVec3>::from_vec(
                se.as_slice()
                    .iter()
                    .map(|s| *s * DVec3::new(gauss(), gauss(), gauss()))
                    .collect(),
            )
            .unwrap();
            let turned = rot.apply(&noisy);
            for (acc, v) in sum_sq.iter_mut().zip(turned.as_slice()) {
                *acc += *v * *v;
            }
        }
        let want = rotate_std_error(&rot, &se);
        for (acc, w) in sum_sq.iter().zip(want.as_slice()) {
            let measured = (*acc / DRAWS as f64).to_array().map(f64::sqrt);
            for c in 0..3 {
                let rel = (measured[c] - w[c]).abs() / w[c];
                assert!(rel < SPREAD, "{measured:?} vs {w:?}");
            }
        }
    }
}
