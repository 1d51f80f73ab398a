//! The GGX microfacet BRDF written out from its formulas, and its
//! integral against band-limited radiance summed direction by direction:
//! the references of `ggx.rs` and `glossy.rs`.

use core::f64::consts::PI;

use glam::DVec3;
use shlight_core::sh::{gauss_legendre, sh_eval};

/// `f(w_o, w_i) (n.w_i)` of the GGX microfacet BRDF, from the formulas.
pub fn brdf_cos(n: DVec3, w_o: DVec3, w_i: DVec3, alpha: f64, f0: f64) -> f64 {
    let (mu_o, mu_i) = (n.dot(w_o), n.dot(w_i));
    if mu_o <= 0.0 || mu_i <= 0.0 {
        return 0.0;
    }
    let h = (w_o + w_i).normalize();
    let a2 = alpha * alpha;
    let c = n.dot(h);
    let d = a2 / (PI * (c * c * (a2 - 1.0) + 1.0).powi(2));
    // Smith's Lambda for GGX: (-1 + sqrt(1 + alpha^2 tan^2 theta)) / 2.
    let lambda = |mu: f64| 0.5 * (-1.0 + (1.0 + a2 * (1.0 - mu * mu) / (mu * mu)).sqrt());
    let g2 = 1.0 / (1.0 + lambda(mu_o) + lambda(mu_i));
    let f = f0 + (1.0 - f0) * (1.0 - w_o.dot(h)).powi(5);
    d * g2 * f / (4.0 * mu_o * mu_i) * mu_i
}

/// `int T(w) f(w_o, w) (n.w) dw` over the hemisphere about the normal:
/// Gauss-Legendre in `n.w` from 0 to 1 (so the horizon, where the
/// integrand stops, is the grid's edge), even steps in azimuth.
pub fn integrated(t: &[DVec3], n: DVec3, w_o: DVec3, alpha: f64, f0: f64) -> DVec3 {
    let lmax = (t.len() as f64).sqrt() as usize - 1;
    let (u, v) = n.any_orthonormal_pair();
    let (nodes, weights) = gauss_legendre(1000);
    let azimuths = 2000;
    let mut sum = DVec3::ZERO;
    for (x, wx) in nodes.iter().zip(&weights) {
        // n.w = (x + 1) / 2 over (0, 1).
        let z = 0.5 * (x + 1.0);
        let s = (1.0 - z * z).max(0.0).sqrt();
        for k in 0..azimuths {
            let phi = 2.0 * PI * (k as f64 + 0.5) / azimuths as f64;
            let w = z * n + s * (phi.cos() * u + phi.sin() * v);
            let g = brdf_cos(n, w_o, w, alpha, f0);
            let tw: DVec3 = sh_eval(lmax, w).iter().zip(t).map(|(y, c)| *c * *y).sum();
            sum += tw * (g * 0.5 * wx * 2.0 * PI / azimuths as f64);
        }
    }
    sum
}
