//! Zonal functions: kernels symmetric about an axis, their SH coefficients,
//! convolution with them (Funk-Hecke), and their rotation to any direction.
//!
//! A zonal function `h(d) = h(d . axis)` has only `m = 0` coefficients `h_l`
//! about its axis. Two facts carry all of this module:
//!
//! ```text
//! rotation to axis a:   f_l^m = sqrt(4 pi/(2l+1)) h_l Y_l^m(a)
//! convolution (Funk-Hecke): (h * f)_l^m = Lambda_l f_l^m,
//!     Lambda_l = sqrt(4 pi/(2l+1)) h_l = 2 pi int_{-1}^{1} h(t) P_l(t) dt
//! ```
//!
//! [`ZonalKernel`] stores the eigenvalues `Lambda_l`. The clamped cosine
//! `max(t, 0)` has `Lambda_l = A_l` (Ramamoorthi & Hanrahan 2001, eq. 8-9), so
//! irradiance is `E_l^m = A_l L_l^m` ([`irradiance`]).

use core::f64::consts::PI;

use glam::DVec3;

use crate::sh::basis::ShBasis;
use crate::sh::real::Real;
use crate::sh::sh_coeffs::ShCoeffs;
use crate::sh::sh_value::ShValue;

/// Legendre polynomials `P_0(x) .. P_lmax(x)` (unnormalised, `P_l(1) = 1`) by
/// Bonnet's recurrence `(l+1) P_{l+1} = (2l+1) x P_l - l P_{l-1}`.
#[must_use]
pub fn legendre_polynomials(lmax: usize, x: f64) -> Vec<f64> {
    let mut p = vec![0.0; lmax + 1];
    p[0] = 1.0;
    if lmax >= 1 {
        p[1] = x;
    }
    for l in 1..lmax {
        let lf = l as f64;
        p[l + 1] = ((2.0 * lf + 1.0) * x * p[l] - lf * p[l - 1]) / (lf + 1.0);
    }
    p
}

/// `A_l`, the Funk-Hecke eigenvalue of the clamped cosine `max(cos, 0)`, in
/// closed form for every `l` (Ramamoorthi & Hanrahan 2001, eq. 8):
///
/// ```text
/// A_0 = pi,  A_1 = 2 pi / 3,  A_l = 0 for odd l > 1,
/// A_l = 2 pi (-1)^(l/2 - 1) / ((l+2)(l-1)) * l! / (2^l ((l/2)!)^2)  for even l >= 2.
/// ```
///
/// The factor `l!/(2^l ((l/2)!)^2) = C(l, l/2) / 2^l` is built as a running
/// product `prod_{k=1}^{l/2} (2k-1)/(2k)`, so no factorial overflows.
///
/// ```
/// use shlight_core::sh::clamped_cosine_eigenvalue as a;
/// assert!((a(2) - std::f64::consts::PI / 4.0).abs() < 1e-15);
/// assert!((a(4) + 0.130900).abs() < 1e-6);
/// ```
#[must_use]
pub fn clamped_cosine_eigenvalue(l: usize) -> f64 {
    match l {
        0 => PI,
        1 => 2.0 * PI / 3.0,
        l if l % 2 == 1 => 0.0,
        l => {
            let half = l / 2;
            let central: f64 = (1..=half)
                .map(|k| (2 * k - 1) as f64 / (2 * k) as f64)
                .product();
            let sign = if half % 2 == 1 { 1.0 } else { -1.0 };
            2.0 * PI * sign / (((l + 2) * (l - 1)) as f64) * central
        }
    }
}

/// A rotationally symmetric convolution kernel, stored as its Funk-Hecke
/// eigenvalues `Lambda_l`, `l = 0..=lmax` (degrees past the end count as 0).
#[derive(Clone, Debug, PartialEq)]
pub struct ZonalKernel {
    /// `Lambda_l` for `l = 0..eigenvalues.len()`.
    pub eigenvalues: Vec<f64>,
}

impl ZonalKernel {
    /// The clamped cosine `max(n . d, 0)`: `Lambda_l = A_l`. Convolving
    /// radiance with it gives irradiance.
    #[must_use]
    pub fn clamped_cosine(lmax: usize) -> Self {
        Self {
            eigenvalues: (0..=lmax).map(clamped_cosine_eigenvalue).collect(),
        }
    }

    /// The normalised power-cosine (Phong) lobe `h(t) = (n+1)/(2 pi) max(t, 0)^n`,
    /// which integrates to 1 over the sphere, for real `n > -1` (glossy
    /// prefiltering; `n = 1` is the clamped cosine divided by pi).
    ///
    /// `Lambda_l = (n+1) I_l` with `I_l = int_0^1 t^n P_l(t) dt`, from
    /// `I_0 = 1/(n+1)`, `I_1 = 1/(n+2)`, `I_l = (n - l + 2)/(n + l + 1) I_{l-2}`.
    #[must_use]
    pub fn phong(lmax: usize, n: f64) -> Self {
        assert!(n > -1.0, "Phong exponent must exceed -1");
        let mut i = vec![0.0; lmax + 1];
        for l in 0..=lmax {
            let lf = l as f64;
            i[l] = match l {
                0 => 1.0 / (n + 1.0),
                1 => 1.0 / (n + 2.0),
                _ => (n - lf + 2.0) / (n + lf + 1.0) * i[l - 2],
            };
        }
        Self {
            eigenvalues: i.iter().map(|v| (n + 1.0) * v).collect(),
        }
    }

    /// From the zonal coefficients `h_l` (coefficients of `Y_l^0` of the
    /// kernel about +Z): `Lambda_l = sqrt(4 pi/(2l+1)) h_l`.
    #[must_use]
    pub fn from_zonal(h: &[f64]) -> Self {
        Self {
            eigenvalues: h
                .iter()
                .enumerate()
                .map(|(l, h)| zonal_factor(l) * h)
                .collect(),
        }
    }

    /// The zonal coefficients `h_l = Lambda_l / sqrt(4 pi/(2l+1))`.
    #[must_use]
    pub fn zonal(&self) -> Vec<f64> {
        self.eigenvalues
            .iter()
            .enumerate()
            .map(|(l, e)| e / zonal_factor(l))
            .collect()
    }

    /// `Lambda_l`, or 0 past the stored degrees.
    #[must_use]
    pub fn eigenvalue(&self, l: usize) -> f64 {
        self.eigenvalues.get(l).copied().unwrap_or(0.0)
    }

    /// The convolution `(h * f)_l^m = Lambda_l f_l^m`.
    #[must_use]
    pub fn apply<C: ShValue>(&self, f: &ShCoeffs<C>) -> ShCoeffs<C> {
        f.scaled_per_band(|l| C::Scalar::from_f64(self.eigenvalue(l)))
    }
}

/// `sqrt(4 pi / (2l+1))`, the factor between zonal coefficients and
/// Funk-Hecke eigenvalues.
#[inline]
#[must_use]
pub fn zonal_factor(l: usize) -> f64 {
    (4.0 * PI / (2 * l + 1) as f64).sqrt()
}

/// Irradiance from radiance: `E_l^m = A_l L_l^m` (Ramamoorthi & Hanrahan 2001).
///
/// `E(n) = int L(w) max(n . w, 0) dw` then evaluates as `sum E_l^m Y_l^m(n)`.
#[must_use]
pub fn irradiance<C: ShValue>(radiance: &ShCoeffs<C>) -> ShCoeffs<C> {
    ZonalKernel::clamped_cosine(radiance.lmax()).apply(radiance)
}

/// Rotates a zonal function with coefficients `h_l` about +Z to point along
/// the unit vector `axis`: `f_l^m = sqrt(4 pi/(2l+1)) h_l Y_l^m(axis)`.
///
/// ```
/// use shlight_core::sh::zonal_to_sh;
/// let f = zonal_to_sh(&[1.0, 2.0], glam::DVec3::Z);
/// assert!((f[(1, 0)] - 2.0).abs() < 1e-15); // along +Z nothing changes
/// ```
#[must_use]
pub fn zonal_to_sh(h: &[f64], axis: DVec3) -> ShCoeffs<f64> {
    let lmax = h.len().saturating_sub(1);
    let basis = ShBasis::<f64>::new(lmax);
    let mut y = vec![0.0; basis.count()];
    basis.eval(axis, &mut y);
    ShCoeffs::from_fn(lmax, |l, m| {
        zonal_factor(l) * h[l] * y[crate::sh::index::sh_index(l, m)]
    })
}

/// Zonal coefficients of the indicator of a spherical cap of half-angle
/// `half_angle` (radians) about +Z:
/// `h_0 = sqrt(pi) (1 - cos a)`, `h_l = sqrt(pi/(2l+1)) (P_{l-1}(cos a) - P_{l+1}(cos a))`.
#[must_use]
pub fn cap_zonal(lmax: usize, half_angle: f64) -> Vec<f64> {
    let c = half_angle.cos();
    let p = legendre_polynomials(lmax + 1, c);
    (0..=lmax)
        .map(|l| {
            if l == 0 {
                PI.sqrt() * (1.0 - c)
            } else {
                (PI / (2 * l + 1) as f64).sqrt() * (p[l - 1] - p[l + 1])
            }
        })
        .collect()
}

/// The solid angle of a cap of half-angle `alpha`, `2π (1 - cos α)`,
/// written as `4π sin²(α/2)` to avoid cancellation at small `α`.
pub(crate) fn cap_solid_angle(alpha: f64) -> f64 {
    4.0 * PI * (alpha / 2.0).sin().powi(2)
}

/// Zonal coefficients of the clamped cosine `max(cos t, 0)` about +Z:
/// `h_l = A_l / sqrt(4 pi/(2l+1))` (`sqrt(pi)/2, sqrt(pi/3), sqrt(5 pi)/8, 0, -sqrt(pi)/16, ...`).
#[must_use]
pub fn clamped_cosine_zonal(lmax: usize) -> Vec<f64> {
    ZonalKernel::clamped_cosine(lmax).zonal()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sh::quadrature::gauss_legendre;

    /// `2 pi int_{-1}^{1} h(t) P_l(t) dt` by Gauss-Legendre on the part where
    /// `h` is smooth.
    fn eigen_numeric(lmax: usize, lo: f64, h: impl Fn(f64) -> f64) -> Vec<f64> {
        let (x, w) = gauss_legendre(200);
        let half = (1.0 - lo) / 2.0;
        let mut out = vec![0.0; lmax + 1];
        for (xi, wi) in x.iter().zip(&w) {
            let t = lo + half * (xi + 1.0);
            let p = legendre_polynomials(lmax, t);
            for l in 0..=lmax {
                out[l] += 2.0 * PI * half * wi * h(t) * p[l];
            }
        }
        out
    }

    #[test]
    // The table holds the published six-digit values, 3.141593 among them.
    #[allow(clippy::approx_constant)]
    fn clamped_cosine_eigenvalues_match_quadrature_and_the_table() {
        let num = eigen_numeric(40, 0.0, |t| t);
        for l in 0..=40 {
            let a = clamped_cosine_eigenvalue(l);
            assert!((a - num[l]).abs() < 1e-13, "l={l}: {a} vs {}", num[l]);
        }
        let table = [
            3.141593, 2.094395, 0.785398, 0.0, -0.130900, 0.0, 0.049087, 0.0, -0.024544,
        ];
        for (l, t) in table.iter().enumerate() {
            assert!((clamped_cosine_eigenvalue(l) - t).abs() < 1e-6);
        }
        // Far degrees stay finite and decay like l^(-5/2).
        let a1000 = clamped_cosine_eigenvalue(1000).abs();
        assert!(a1000 > 0.0 && a1000 < 1e-6);
    }

    #[test]
    fn clamped_cosine_zonal_coefficients_match_the_reference() {
        let z = clamped_cosine_zonal(4);
        let want = [
            PI.sqrt() / 2.0,
            (PI / 3.0).sqrt(),
            (5.0 * PI).sqrt() / 8.0,
            0.0,
            -PI.sqrt() / 16.0,
        ];
        for l in 0..5 {
            assert!((z[l] - want[l]).abs() < 1e-15, "l={l}");
        }
    }

    #[test]
    fn cap_coefficients_match_quadrature() {
        for a in [0.2f64, 30f64.to_radians(), 1.3, 2.5] {
            let c = a.cos();
            let num = eigen_numeric(30, c, |_| 1.0);
            let z = cap_zonal(30, a);
            for l in 0..=30 {
                let want = num[l] / zonal_factor(l);
                assert!((z[l] - want).abs() < 1e-12, "a={a} l={l}");
            }
        }
    }

    #[test]
    fn phong_lobe_matches_quadrature_and_reduces_to_the_cosine() {
        for n in [1.0f64, 2.5, 16.0, 100.0] {
            let k = ZonalKernel::phong(20, n);
            let num = eigen_numeric(20, 0.0, |t| (n + 1.0) / (2.0 * PI) * t.powf(n));
            for l in 0..=20 {
                assert!((k.eigenvalues[l] - num[l]).abs() < 1e-12, "n={n} l={l}");
            }
            assert!((k.eigenvalues[0] - 1.0).abs() < 1e-15, "normalised");
        }
        let cos = ZonalKernel::clamped_cosine(10);
        let phong1 = ZonalKernel::phong(10, 1.0);
        for l in 0..=10 {
            assert!((cos.eigenvalues[l] / PI - phong1.eigenvalues[l]).abs() < 1e-15);
        }
    }
}
