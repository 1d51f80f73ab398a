//! `--brdf ggx:ALPHA[,F0]` against independent numbers: the exit radiance
//! integrated direction by direction over the hemisphere with the
//! microfacet BRDF written out here (GGX's distribution, Smith's
//! height-correlated `G_2 = 1 / (1 + Lambda(mu_o) + Lambda(mu_i))`,
//! Schlick's Fresnel), and the white furnace against shlight-specular's
//! DFG estimator. `glossy.rs` holds a shadowed GGX bake to a brute-force
//! reference.

use core::f64::consts::PI;

use glam::DVec3;
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_core::sh::sh_count;
use shlight_prt::GgxLobe;

mod ggx_reference;
use ggx_reference::integrated;

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
                shlight_specular::MaskingShadowing::HeightCorrelated,
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
