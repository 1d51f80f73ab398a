//! Quadrature on the interval and the sphere: Gauss-Legendre nodes, product
//! rules exact for band-limited integrands, and Fibonacci point sets.

use core::f64::consts::PI;

use glam::DVec3;

/// Nodes `x_i` and weights `w_i` of the `n`-point Gauss-Legendre rule on
/// `[-1, 1]`: `sum_i w_i p(x_i) = int_{-1}^{1} p(x) dx` exactly for every
/// polynomial of degree `<= 2n - 1`.
///
/// Nodes are the roots of `P_n`, found by Newton's method from Tricomi's
/// asymptotic estimate; weights `w_i = 2 / ((1 - x_i^2) P_n'(x_i)^2)`. Nodes
/// are returned in decreasing order (`x_0` nearest `+1`), so `theta_i =
/// acos(x_i)` increases. Accurate to a few ulps for `n` into the thousands.
///
/// ```
/// let (x, w) = shlight_core::sh::gauss_legendre(3);
/// let integral: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(4)).sum();
/// assert!((integral - 0.4).abs() < 1e-15); // int x^4 = 2/5
/// ```
#[must_use]
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    let nf = n as f64;
    for i in 0..n.div_ceil(2) {
        // Tricomi's initial guess for the i-th root (descending).
        let k = i as f64 + 1.0;
        let theta = PI * (4.0 * k - 1.0) / (4.0 * nf + 2.0);
        let mut z = (1.0 - (nf - 1.0) / (8.0 * nf * nf * nf)) * theta.cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (p, d) = legendre_p_and_derivative(n, z);
            dp = d;
            let dz = p / d;
            z -= dz;
            if dz.abs() <= 1e-16 * z.abs().max(1e-3) {
                break;
            }
        }
        let (_, d) = legendre_p_and_derivative(n, z);
        if d != 0.0 {
            dp = d;
        }
        x[i] = z;
        x[n - 1 - i] = -z;
        let wi = 2.0 / ((1.0 - z * z) * dp * dp);
        w[i] = wi;
        w[n - 1 - i] = wi;
    }
    if n % 2 == 1 {
        x[n / 2] = 0.0;
    }
    (x, w)
}

/// `P_n(z)` and `P_n'(z)` by the three-term recurrence.
fn legendre_p_and_derivative(n: usize, z: f64) -> (f64, f64) {
    let mut p0 = 1.0;
    let mut p1 = z;
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * z * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (z * p1 - p0) / (z * z - 1.0);
    (p1, d)
}

/// A product quadrature rule on the unit sphere: Gauss-Legendre in
/// `cos(theta)` times the uniform rule in `phi`.
///
/// Built by [`SphereQuadrature::exact_to_degree`]`(d)`, it integrates every
/// spherical polynomial of degree `<= d` exactly (up to rounding), so it
/// projects band-limited functions to SH without error: a function of
/// degree `<= b` projected to `lmax` needs `d = b + lmax`.
#[derive(Clone, Debug)]
pub struct SphereQuadrature {
    /// Unit directions `(sin t cos p, sin t sin p, cos t)` in world axes.
    pub directions: Vec<DVec3>,
    /// Weights (solid angles), summing to `4 pi`.
    pub weights: Vec<f64>,
}

impl SphereQuadrature {
    /// The smallest product rule exact for spherical polynomials of degree `<= degree`:
    /// `ceil((degree+1)/2)` Gauss-Legendre rings of `degree+1` points each.
    #[must_use]
    pub fn exact_to_degree(degree: usize) -> Self {
        let rings = (degree + 2) / 2;
        let (xs, ws) = gauss_legendre(rings);
        let nphi = degree + 1;
        let mut directions = Vec::with_capacity(rings * nphi);
        let mut weights = Vec::with_capacity(rings * nphi);
        for (&x, &w) in xs.iter().zip(&ws) {
            let s = (1.0 - x * x).max(0.0).sqrt();
            for j in 0..nphi {
                let phi = 2.0 * PI * (j as f64 + 0.5) / nphi as f64;
                directions.push(DVec3::new(s * phi.cos(), s * phi.sin(), x));
                weights.push(w * 2.0 * PI / nphi as f64);
            }
        }
        Self {
            directions,
            weights,
        }
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.weights.len()
    }

    /// True when the rule has no points.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.weights.is_empty()
    }
}

/// `n` nearly uniformly spread unit directions (spherical Fibonacci lattice):
/// `z_i = 1 - (2i + 1)/n`, `phi_i = 2 pi i / golden_ratio`.
///
/// Used as a dense, deterministic set of test normals.
///
/// ```
/// let d = shlight_core::sh::fibonacci_sphere(1000);
/// assert_eq!(d.len(), 1000);
/// ```
#[must_use]
pub fn fibonacci_sphere(n: usize) -> Vec<DVec3> {
    let golden = (1.0 + 5f64.sqrt()) / 2.0;
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let s = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * (i as f64 / golden).fract();
            DVec3::new(s * phi.cos(), s * phi.sin(), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_up_to_2n_minus_1() {
        for n in [1usize, 2, 5, 17, 64, 513] {
            let (x, w) = gauss_legendre(n);
            assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-13);
            for k in [2 * n - 2, 2 * n - 1] {
                let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                let want = if k % 2 == 1 {
                    0.0
                } else {
                    2.0 / (k as f64 + 1.0)
                };
                assert!((got - want).abs() < 1e-13, "n={n} k={k}: {got} vs {want}");
            }
            // Degree 2n is no longer exact (the rule is not over-claimed).
            if n < 64 {
                let k = 2 * n;
                let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(k as i32)).sum();
                assert!((got - 2.0 / (k as f64 + 1.0)).abs() > 1e-10);
            }
        }
    }

    #[test]
    fn sphere_rule_weights_sum_to_four_pi_and_integrate_z_squared() {
        let q = SphereQuadrature::exact_to_degree(6);
        let total: f64 = q.weights.iter().sum();
        assert!((total - 4.0 * PI).abs() < 1e-13);
        let z2: f64 = q
            .directions
            .iter()
            .zip(&q.weights)
            .map(|(d, w)| w * d[2] * d[2])
            .sum();
        assert!((z2 - 4.0 * PI / 3.0).abs() < 1e-13);
    }

    #[test]
    fn fibonacci_points_are_unit_and_balanced() {
        let d = fibonacci_sphere(2000);
        let mut mean = [0.0; 3];
        for v in &d {
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            assert!((n - 1.0).abs() < 1e-14);
            for c in 0..3 {
                mean[c] += v[c] / d.len() as f64;
            }
        }
        assert!(mean.iter().all(|m| m.abs() < 1e-3), "{mean:?}");
    }
}
