//! `--brdf ggx:ALPHA[,F0]` against independent numbers: the exit radiance
//! integrated direction by direction over the hemisphere with the
//! microfacet BRDF written out here (GGX's distribution, Smith's
//! height-correlated `G_2 = 1 / (1 + Lambda(mu_o) + Lambda(mu_i))`,
//! Schlick's Fresnel), the white furnace against shlight-specular's DFG
//! estimator, and a shadowed bake against a brute-force reference.

use core::f64::consts::PI;

use glam::DVec3;
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_core::sh::{gauss_legendre, sh_count, sh_eval};
use shlight_mesh::generate;
use shlight_prt::brdf::{Brdf, Lobe};
use shlight_prt::brute_force::closest_hit;
use shlight_prt::ggx_lobe::GgxLobe;
use shlight_prt::glossy::{View, bake_glossy};
use shlight_prt::transfer::{Albedo, BakeOptions, Mode};

/// `f(w_o, w_i) (n.w_i)` of the GGX microfacet BRDF, from the formulas.
fn brdf_cos(n: DVec3, w_o: DVec3, w_i: DVec3, alpha: f64, f0: f64) -> f64 {
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
fn integrated(t: &[DVec3], n: DVec3, w_o: DVec3, alpha: f64, f0: f64) -> DVec3 {
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

fn random_unit(rng: &mut StdRng) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.random::<f64>() * 2.0 - 1.0,
            rng.random::<f64>() * 2.0 - 1.0,
            rng.random::<f64>() * 2.0 - 1.0,
        );
        if v.length_squared() > 0.01 && v.length_squared() < 1.0 {
            return v.normalize();
        }
    }
}

/// Random band-limited radiance to lmax 4 at random normals and views
/// above the surface: the tabulated projection, rotated into each
/// vertex's frame, gives the integral of the BRDF written out above.
#[test]
fn exit_radiance_is_the_brdf_integrated_over_the_hemisphere() {
    let mut rng = StdRng::seed_from_u64(5);
    let lmax = 4;
    for (alpha, f0) in [(0.15, 1.0), (0.4, 0.04), (0.8, 1.0)] {
        let lobe = GgxLobe::new(lmax, alpha, f0);
        let mut scratch = vec![0.0; sh_count(lmax)];
        let mut worst = 0.0f64;
        for case in 0..5 {
            // A positive light: a constant plus smaller random terms.
            let mut t: Vec<DVec3> = (0..sh_count(lmax))
                .map(|_| {
                    DVec3::new(rng.random(), rng.random(), rng.random()) * 0.6 - DVec3::splat(0.3)
                })
                .collect();
            t[0] += DVec3::splat(3.0);
            let n = random_unit(&mut rng);
            // Views from near the normal to 89 degrees from it.
            let mu_o = if case == 0 {
                0.02
            } else {
                0.02 + 0.98 * rng.random::<f64>()
            };
            let side = (random_unit(&mut rng).reject_from(n)).normalize();
            let w_o = mu_o * n + (1.0 - mu_o * mu_o).sqrt() * side;
            let got = lobe.exit_radiance(n, w_o, &t, &mut scratch);
            let want = integrated(&t, n, w_o, alpha, f0);
            let err = (got - want).abs().max_element() / want.max_element();
            worst = worst.max(err);
            assert!(
                err < 1e-4,
                "alpha {alpha} F0 {f0} case {case} (mu_o {mu_o:.3}): {got} against {want}"
            );
        }
        eprintln!("alpha {alpha} F0 {f0}: worst relative error {worst:.2e}");
        // From below, nothing.
        let n = DVec3::Y;
        let t = vec![DVec3::ONE; sh_count(lmax)];
        let below = lobe.exit_radiance(n, DVec3::new(0.6, -0.1, 0.0).normalize(), &t, &mut scratch);
        assert_eq!(below, DVec3::ZERO);
    }
}

/// Under constant radiance 1 the exit radiance is the BRDF's directional
/// albedo `F0 A + B`, with `(A, B)` shlight-specular's DFG estimate
/// (65,536 Hammersley half vectors, not this quadrature; within 6e-4 of
/// a direct integration over the hemisphere, while the table is within
/// 2e-5 of it).
#[test]
fn the_white_furnace_gives_the_dfg_albedo() {
    let t = {
        let mut t = vec![DVec3::ZERO; sh_count(2)];
        t[0] = DVec3::splat((4.0 * PI).sqrt());
        t
    };
    let mut scratch = vec![0.0; sh_count(2)];
    for (alpha, f0) in [(0.05, 1.0), (0.3, 0.04), (0.7, 0.5), (1.0, 1.0)] {
        let lobe = GgxLobe::new(2, alpha, f0);
        for mu_o in [1.0, 0.8, 0.5, 0.2, 0.05] {
            let w_o = DVec3::new((1.0f64 - mu_o * mu_o).sqrt(), 0.0, mu_o);
            let got = lobe.exit_radiance(DVec3::Z, w_o, &t, &mut scratch).x;
            let [a, b] = shlight_specular::dfg(
                mu_o,
                alpha,
                shlight_specular::Visibility::HeightCorrelated,
                1 << 16,
            );
            let want = f0 * a + b;
            assert!(
                (got - want).abs() < 1e-3,
                "alpha {alpha} F0 {f0} mu_o {mu_o}: {got} against DFG {want}"
            );
        }
    }
}

/// A sphere over a plane, shadowed, lmax 4: the bake's GGX exit radiance
/// at random vertices and eyes against the transferred radiance projected
/// here from the brute-force tracer's visibility, integrated against the
/// BRDF direction by direction.
#[test]
fn shadowed_ggx_matches_a_brute_force_reference() {
    let mesh = generate::plane_under_sphere(1.0, 16, 8, 4.0, 8);
    let options = BakeOptions {
        lmax: 4,
        samples: 4096,
        mode: Mode::Shadowed,
        albedo: Albedo::Constant([0.8; 3]),
        seed: 7,
        emission: None,
    };
    let t = bake_glossy(&mesh, &options, &|_, _, _| {});
    let mut light = shlight_core::sh::closed_form::cap(
        4,
        DVec3::new(0.3, 0.8, -0.4).normalize(),
        0.6,
        DVec3::new(3.0, 2.0, 1.0),
    );
    light += &shlight_core::sh::closed_form::constant(4, DVec3::splat(0.4));
    let (alpha, f0) = (0.35, 1.0);
    let brdf = Brdf::Ggx { alpha, f0 };
    assert!(matches!(brdf.lobe(4), Lobe::Ggx(_)));
    let mut rng = StdRng::seed_from_u64(8);
    let (rows, cols) = (100, 200);
    let dirs: Vec<DVec3> = (0..rows * cols)
        .map(|k| {
            let z = -1.0 + 2.0 * ((k / cols) as f64 + rng.random::<f64>()) / rows as f64;
            let phi = 2.0 * PI * ((k % cols) as f64 + rng.random::<f64>()) / cols as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            DVec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect();
    let light_at = |d: DVec3| -> DVec3 {
        sh_eval(4, d)
            .iter()
            .zip(light.as_slice())
            .map(|(y, l)| *l * *y)
            .sum()
    };
    let mut cases = Vec::new();
    let mut peak = 0.0f64;
    for _ in 0..8 {
        let v = rng.random_range(0..mesh.vertex_count());
        let eye = DVec3::new(
            rng.random::<f64>() * 8.0 - 4.0,
            rng.random::<f64>() * 4.0 + 0.5,
            rng.random::<f64>() * 8.0 - 4.0,
        );
        let p = mesh.positions[v].as_dvec3();
        let n = mesh.normals[v].as_dvec3();
        let o = p + n * 1e-5;
        let mut tr = vec![DVec3::ZERO; sh_count(4)];
        for d in &dirs {
            if n.dot(*d) <= 0.0 || closest_hit(&mesh, o, *d, 1e-9).is_some() {
                continue;
            }
            let l = light_at(*d);
            for (ti, y) in tr.iter_mut().zip(sh_eval(4, *d)) {
                *ti += l * y * (4.0 * PI / dirs.len() as f64);
            }
        }
        let w_o = (eye - p).normalize();
        let want = integrated(&tr, n, w_o, alpha, f0);
        let got = t.exit_radiance(&mesh, brdf, light.as_slice(), View::Eye(eye))[v];
        peak = peak.max(want.max_element());
        cases.push((v, got, want));
    }
    for (v, got, want) in cases {
        // Two stratified estimates of a shadowed integrand (4096 and
        // 20,000 directions): about 1% of the peak apart.
        assert!(
            (got - want).abs().max_element() < 0.03 * peak,
            "vertex {v}: bake {got}, reference {want} (peak {peak})"
        );
    }
}
