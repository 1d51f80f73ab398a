//! Texel formats against shlight's irradiance: each engine's shader port,
//! fed the packed texel, gives Ramamoorthi & Hanrahan's `E(n)` (or
//! `E/pi`) from shlight-core's `ShL1Rgb::eval_irradiance`; clamping where
//! packings clamp; MonoSH's exactness and error bound; Geomerics'
//! reconstruction against its own closed form and the light's irradiance;
//! the units of a uniform sky.

use core::f64::consts::PI;

use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_core::sh::{ShCoeffs, ShL1Rgb, closed_form, gauss_legendre};
use shlight_lightmap::{
    DiffuseL1, Engine, L1Reconstruction, PackedTexel, TexelBasis, TexelFormat, TexelUnits,
    geomerics_l1,
};

fn unit(rng: &mut StdRng) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

fn colour(rng: &mut StdRng) -> DVec3 {
    DVec3::new(
        rng.random_range(0.0..3.0),
        rng.random_range(0.0..3.0),
        rng.random_range(0.0..3.0),
    )
}

/// Radiance that is nowhere negative: one to four directional lights,
/// clamped-cosine lobes or caps, sometimes a constant sky, each of its own
/// colour (or all of `tint` when given), projected exactly to lmax 1.
fn plausible(rng: &mut StdRng, tint: Option<DVec3>) -> ShL1Rgb<f64> {
    let mut f: ShCoeffs<DVec3> = ShCoeffs::zeros(1);
    let c = |rng: &mut StdRng| tint.unwrap_or_else(|| colour(rng));
    for _ in 0..rng.random_range(1..=4) {
        let d = unit(rng);
        let col = c(rng);
        let g = match rng.random_range(0..3) {
            0 => closed_form::directional(1, d, col),
            1 => closed_form::cosine_lobe(1, d, col),
            _ => closed_form::cap(1, d, rng.random_range(0.05..PI), col),
        };
        f += &g;
    }
    if rng.random_bool(0.3) {
        let col = c(rng) * 0.2;
        f += &closed_form::constant(1, col);
    }
    ShL1Rgb::from_coeffs(&f)
}

fn fmt(engine: Engine, basis: TexelBasis, r: L1Reconstruction) -> TexelFormat {
    TexelFormat::new(basis, engine, r).unwrap()
}

/// shlight-core's R&H irradiance in `units`.
fn reference(sh: &ShL1Rgb<f64>, n: DVec3, units: TexelUnits) -> DVec3 {
    sh.eval_irradiance(n) * units.scale()
}

fn max_mean(sh: &ShL1Rgb<f64>, units: TexelUnits) -> f64 {
    DiffuseL1::from_radiance(sh, units).constant.max_element()
}

#[test]
fn every_linear_port_reproduces_the_irradiance_of_plausible_light() {
    let formats = [
        fmt(Engine::ThreeJs, TexelBasis::ShL1, L1Reconstruction::Linear),
        fmt(Engine::Godot, TexelBasis::ShL1, L1Reconstruction::Linear),
        fmt(Engine::Unity, TexelBasis::ShL1, L1Reconstruction::Linear),
    ];
    let mut rng = StdRng::seed_from_u64(39);
    let mut worst = [0.0f64; 3];
    for _ in 0..2000 {
        let sh = plausible(&mut rng, None);
        for (k, f) in formats.iter().enumerate() {
            let texel = f.pack(&sh, DVec3::Y);
            assert!(!texel.clamped(), "{f:?} clamped plausible light");
            assert_eq!(texel.layers().len(), 4);
            let scale = max_mean(&sh, f.units());
            for _ in 0..8 {
                let n = unit(&mut rng);
                let want = reference(&sh, n, f.units());
                let got = f.reconstruct(&texel, n.as_vec3()).as_dvec3();
                let err = (got - want).abs().max_element() / scale;
                worst[k] = worst[k].max(err);
            }
        }
    }
    // f32 arithmetic on values of size `scale`: a few units in the last place.
    for (k, w) in worst.iter().enumerate() {
        assert!(*w < 2e-6, "format {k}: relative error {w:e}");
    }
    eprintln!(
        "worst error / max L0 (three.js, Godot, Unity): {:.2e} {:.2e} {:.2e}",
        worst[0], worst[1], worst[2]
    );
}

#[test]
fn irradiance_texels_hold_the_irradiance_at_the_texel_normal() {
    let mut rng = StdRng::seed_from_u64(7);
    for engine in [Engine::ThreeJs, Engine::Bevy, Engine::Godot, Engine::Unity] {
        let f = fmt(engine, TexelBasis::Irradiance, L1Reconstruction::NonLinear);
        assert_eq!(f.reconstruction(), L1Reconstruction::Linear);
        for _ in 0..200 {
            let sh = plausible(&mut rng, None);
            let n = unit(&mut rng);
            let texel = f.pack(&sh, n);
            assert_eq!(texel.layers().len(), 1);
            let want = reference(&sh, n, engine.units());
            // The reconstruction ignores the shading normal.
            let got = f.reconstruct(&texel, -n.as_vec3()).as_dvec3();
            assert!((got - want).abs().max_element() <= 1e-6 * max_mean(&sh, f.units()) * 4.0);
        }
    }
}

#[test]
fn a_uniform_white_sky_of_radiance_one_is_pi_for_threejs_and_one_elsewhere() {
    let sky = ShL1Rgb::from_coeffs(&closed_form::constant(1, DVec3::ONE));
    let n = DVec3::new(0.3, 0.9, -0.3).normalize();
    for (engine, want) in [
        (Engine::ThreeJs, PI),
        (Engine::Bevy, 1.0),
        (Engine::Godot, 1.0),
        (Engine::Unity, 1.0),
    ] {
        let t = fmt(engine, TexelBasis::Irradiance, L1Reconstruction::Linear).pack(&sky, n);
        for c in 0..3 {
            assert!(
                (f64::from(t.layers()[0][c]) - want).abs() < 1e-6,
                "{engine:?}"
            );
        }
    }
    let godot = fmt(Engine::Godot, TexelBasis::ShL1, L1Reconstruction::Linear).pack(&sky, n);
    let bakery = fmt(Engine::Unity, TexelBasis::ShL1, L1Reconstruction::Linear).pack(&sky, n);
    let three = fmt(Engine::ThreeJs, TexelBasis::ShL1, L1Reconstruction::Linear).pack(&sky, n);
    for c in 0..3 {
        assert!((godot.layers()[0][c] - 1.0).abs() < 1e-6);
        assert!((bakery.layers()[0][c] - 1.0).abs() < 1e-6);
        assert!((f64::from(three.layers()[0][c]) - PI).abs() < 1e-6);
        for k in 1..4 {
            assert_eq!(godot.layers()[k][c], 0.5);
            assert_eq!(bakery.layers()[k][c], 0.5);
            assert_eq!(three.layers()[k][c], 0.0);
        }
    }
}

#[test]
fn godot_layers_run_y_z_x_and_bakery_layers_x_y_z() {
    // A white directional light of irradiance 1 from +y: a = 1/(4 pi),
    // b = (0, 1/(2 pi), 0) in E/pi; Godot's y layer 1/(2 pi) / (8/(4 pi)) + 1/2
    // = 3/4, Bakery's y layer (_RNM1) 1/(2 pi) / (4/(4 pi)) + 1/2 = 1.
    let sh = ShL1Rgb::from_coeffs(&closed_form::directional(1, DVec3::Y, DVec3::ONE));
    let g = fmt(Engine::Godot, TexelBasis::ShL1, L1Reconstruction::Linear).pack(&sh, DVec3::Y);
    let b = fmt(Engine::Unity, TexelBasis::ShL1, L1Reconstruction::Linear).pack(&sh, DVec3::Y);
    let l0 = 1.0 / (4.0 * PI) as f32;
    for c in 0..3 {
        assert!((g.layers()[0][c] - l0).abs() < 1e-7);
        assert!((g.layers()[1][c] - 0.75).abs() < 1e-6);
        assert!((g.layers()[2][c] - 0.5).abs() < 1e-6);
        assert!((g.layers()[3][c] - 0.5).abs() < 1e-6);
        assert!((b.layers()[1][c] - 0.5).abs() < 1e-6);
        assert!((b.layers()[2][c] - 1.0).abs() < 1e-6);
        assert!((b.layers()[3][c] - 0.5).abs() < 1e-6);
    }
    assert!(
        !b.clamped(),
        "|L1| = 2 L0 is Bakery's range's edge, not beyond it"
    );
}

/// Radiance whose linear form is `a + b . n` in E/pi units, per channel
/// the same: `L_0^0 = a / (pi^-1 sqrt(pi)/2)`, band 1 from `b` (not
/// plausible when `|b| > 2 a`).
fn from_linear(a: f64, b: DVec3) -> ShL1Rgb<f64> {
    let k0 = 0.5 * PI.sqrt() / PI;
    let k1 = (PI / 3.0).sqrt() / PI;
    let ch = [a / k0, -b.y / k1, b.z / k1, -b.x / k1];
    ShL1Rgb {
        r: ch,
        g: ch,
        b: ch,
    }
}

#[test]
fn packings_clamp_beyond_their_ranges_and_the_ports_saturate_there() {
    // Godot: |b_i| <= 4 a. Bakery: |b_i| <= 2 a. Past them the decoded L1
    // is the range's edge.
    let godot = fmt(Engine::Godot, TexelBasis::ShL1, L1Reconstruction::Linear);
    let bakery = fmt(Engine::Unity, TexelBasis::ShL1, L1Reconstruction::Linear);
    let sh = from_linear(1.0, DVec3::new(5.0, -3.0, 1.0));
    let n = Vec3::new(0.6, 0.0, 0.8);
    let g = godot.pack(&sh, DVec3::Z);
    assert!(g.clamped());
    let got = godot.reconstruct(&g, n);
    let want = 1.0 + 4.0 * 0.6 + 1.0 * 0.8; // x clamped to 4, z within range
    assert!(
        (got - Vec3::splat(want)).abs().max_element() < 1e-5,
        "{got}"
    );
    let b = bakery.pack(&sh, DVec3::Z);
    assert!(b.clamped());
    let got = bakery.reconstruct(&b, n);
    let want = 1.0 + 2.0 * 0.6 + 1.0 * 0.8; // x clamped to 2
    assert!(
        (got - Vec3::splat(want)).abs().max_element() < 1e-5,
        "{got}"
    );
    // Between the two ranges Godot is exact and Bakery clamps.
    let sh = from_linear(1.0, DVec3::new(0.0, 3.0, 0.0));
    assert!(!godot.pack(&sh, DVec3::Y).clamped());
    assert!(bakery.pack(&sh, DVec3::Y).clamped());
    let got = godot.reconstruct(&godot.pack(&sh, DVec3::Y), Vec3::Y);
    assert!((got - Vec3::splat(4.0)).abs().max_element() < 1e-5);
}

#[test]
fn monosh_is_exact_for_light_of_one_colour() {
    // Every channel the same function times a colour: b_c / a_c is shared,
    // so the one direction loses nothing.
    let mono = fmt(Engine::Unity, TexelBasis::MonoSh, L1Reconstruction::Linear);
    let mut rng = StdRng::seed_from_u64(11);
    let mut worst = 0.0f64;
    for _ in 0..1000 {
        let tint = colour(&mut rng) + DVec3::splat(0.01);
        let sh = plausible(&mut rng, Some(tint));
        let texel = mono.pack(&sh, DVec3::Y);
        assert!(!texel.clamped());
        assert_eq!(texel.layers().len(), 2);
        let scale = max_mean(&sh, mono.units());
        for _ in 0..8 {
            let n = unit(&mut rng);
            let want = reference(&sh, n, mono.units());
            let got = mono.reconstruct(&texel, n.as_vec3()).as_dvec3();
            worst = worst.max((got - want).abs().max_element() / scale);
        }
    }
    assert!(worst < 2e-6, "{worst:e}");
}

#[test]
fn monosh_error_for_coloured_light_stays_within_its_bound() {
    // MonoSH decodes L1_c = 2 a_c d with the shared d = sum b / (2 sum a):
    // the channel sum is exact, and each channel is off by
    // |(2 a_c d - b_c) . n| <= |2 a_c d - b_c| <= 4 a_c (|d| <= 1, |b_c| <= 2 a_c).
    let mono = fmt(Engine::Unity, TexelBasis::MonoSh, L1Reconstruction::Linear);
    let mut rng = StdRng::seed_from_u64(12);
    let mut worst_ratio = 0.0f64;
    for _ in 0..2000 {
        let sh = plausible(&mut rng, None);
        let lin = DiffuseL1::from_radiance(&sh, mono.units());
        let texel = mono.pack(&sh, DVec3::Y);
        assert!(!texel.clamped());
        let d = (lin.linear[0] + lin.linear[1] + lin.linear[2])
            / (2.0 * (lin.constant.x + lin.constant.y + lin.constant.z));
        let scale = lin.constant.max_element();
        for _ in 0..8 {
            let n = unit(&mut rng);
            let full = reference(&sh, n, mono.units());
            let got = mono.reconstruct(&texel, n.as_vec3()).as_dvec3();
            let tol = 4e-6 * scale;
            assert!(((got - full).element_sum()).abs() <= 3.0 * tol, "luma");
            for c in 0..3 {
                let a = lin.constant[c];
                let bound = (2.0 * a * d - lin.linear[c]).length();
                let err = (got[c] - full[c]).abs();
                assert!(err <= bound + tol, "channel {c}: {err} > {bound}");
                assert!(bound <= 4.0 * a + tol);
                if a > 1e-3 * scale {
                    worst_ratio = worst_ratio.max(err / a);
                }
            }
        }
    }
    eprintln!("MonoSH: worst |error| / a_c over random coloured light: {worst_ratio:.3}");
    // The bound is tight: a dim red light from +x against bright
    // green and blue from -x gives d ~ -x, so red's L1 flips: error -> 4 a.
    let red = closed_form::directional(1, DVec3::X, DVec3::new(0.01, 0.0, 0.0));
    let cyan = closed_form::directional(1, -DVec3::X, DVec3::new(0.0, 10.0, 10.0));
    let sh = ShL1Rgb::from_coeffs(&(&red + &cyan));
    let texel = mono.pack(&sh, DVec3::X);
    let a = DiffuseL1::from_radiance(&sh, mono.units()).constant.x;
    let err = (mono.reconstruct(&texel, Vec3::X).x as f64
        - reference(&sh, DVec3::X, mono.units()).x)
        .abs();
    assert!(err > 3.99 * a && err < 4.0 * a + 1e-6, "{}", err / a);
}

#[test]
fn geomerics_is_never_negative_and_keeps_the_mean() {
    let mut rng = StdRng::seed_from_u64(13);
    let (t, w) = gauss_legendre(64);
    for _ in 0..2000 {
        let l0: f32 = rng.random_range(0.001..10.0);
        let r = rng.random_range(0.0..=1.0f64);
        let dir = unit(&mut rng);
        let l1 = (dir * 2.0 * r * f64::from(l0)).as_vec3();
        for _ in 0..8 {
            let n = unit(&mut rng).as_vec3();
            assert!(geomerics_l1(l0, l1, n) >= 0.0);
        }
        // The mean over normals is L0: f is zonal about L1, so it is half
        // the integral over t = cos of the angle to L1.
        let perp = dir.any_orthonormal_vector();
        let mean: f64 = t
            .iter()
            .zip(&w)
            .map(|(&t, &w)| {
                let n = (dir * t + perp * (1.0 - t * t).sqrt()).as_vec3();
                w * f64::from(geomerics_l1(l0, l1, n))
            })
            .sum::<f64>()
            / 2.0;
        assert!(
            (mean - f64::from(l0)).abs() < 2e-4 * f64::from(l0),
            "{mean} vs {l0}"
        );
    }
}

#[test]
fn geomerics_for_one_directional_light_is_its_closed_form() {
    // A directional light of irradiance 1 (E/pi units: 1/pi) from d:
    // a = 1/(4 pi), |b| = 2 a, so p = 3, a_g = 0, f = 4 a ((1 + cos)/2)^3.
    // Against the light's true irradiance max(cos, 0)/pi the error peaks
    // at 1/8 of the peak (cos = 0); the linear form's at 1/4.
    let d = DVec3::new(0.2, 0.7, -0.4).normalize();
    let sh = ShL1Rgb::from_coeffs(&closed_form::directional(1, d, DVec3::ONE));
    let three = fmt(
        Engine::ThreeJs,
        TexelBasis::ShL1,
        L1Reconstruction::NonLinear,
    );
    let bakery = fmt(Engine::Unity, TexelBasis::ShL1, L1Reconstruction::NonLinear);
    let mono = fmt(
        Engine::Unity,
        TexelBasis::MonoSh,
        L1Reconstruction::NonLinear,
    );
    let t3 = three.pack(&sh, d);
    let (tb, tm) = (bakery.pack(&sh, d), mono.pack(&sh, d));
    let (mut worst_g, mut worst_lin) = (0.0f64, 0.0f64);
    let perp = d.any_orthonormal_vector();
    for k in 0..=400 {
        let c = -1.0 + 2.0 * f64::from(k) / 400.0;
        let n = d * c + perp * (1.0 - c * c).max(0.0).sqrt();
        let closed = ((1.0 + c) / 2.0).powi(3); // irradiance units, peak 1
        let truth = c.max(0.0);
        let g3 = f64::from(three.reconstruct(&t3, n.as_vec3()).x);
        assert!(
            (g3 - closed).abs() < 1e-5,
            "three.js at cos {c}: {g3} vs {closed}"
        );
        // Bakery fades its rescale to the linear form where the linear
        // value's channel sum is under 1/16 (an absolute level), then
        // clamps at 0.
        let linear_luma = 3.0 * (0.25 + 0.5 * c) / PI;
        for (f, t) in [(bakery, &tb), (mono, &tm)] {
            let g = f64::from(f.reconstruct(t, n.as_vec3()).y) * PI;
            if linear_luma * 16.0 >= 1.0 {
                assert!(
                    (g - closed).abs() < 1e-5,
                    "{f:?} at cos {c}: {g} vs {closed}"
                );
            } else {
                let w = (linear_luma * 16.0).max(0.0);
                let want = ((0.25 + 0.5 * c) * (1.0 - w) + closed * w).max(0.0);
                assert!((g - want).abs() < 1e-5, "{f:?} at cos {c}: {g} vs {want}");
            }
        }
        worst_g = worst_g.max((closed - truth).abs());
        worst_lin = worst_lin.max((0.25 + 0.5 * c - truth).abs());
    }
    assert!((worst_g - 0.125).abs() < 1e-9, "{worst_g}");
    assert!((worst_lin - 0.25).abs() < 1e-9, "{worst_lin}");
}

#[test]
fn bakery_non_linear_output_is_never_negative() {
    let mut rng = StdRng::seed_from_u64(14);
    for basis in [TexelBasis::ShL1, TexelBasis::MonoSh] {
        let f = fmt(Engine::Unity, basis, L1Reconstruction::NonLinear);
        for _ in 0..1000 {
            let sh = plausible(&mut rng, None);
            let t = f.pack(&sh, DVec3::Y);
            for _ in 0..8 {
                let n = unit(&mut rng).as_vec3();
                assert!(f.reconstruct(&t, n).min_element() >= 0.0);
            }
        }
    }
}

#[test]
fn texels_read_back_from_layers_reconstruct_the_same() {
    let f = fmt(Engine::Godot, TexelBasis::ShL1, L1Reconstruction::Linear);
    let sh = plausible(&mut StdRng::seed_from_u64(15), None);
    let t = f.pack(&sh, DVec3::Y);
    let back = PackedTexel::from_layers(t.layers());
    assert_eq!(f.reconstruct(&back, Vec3::X), f.reconstruct(&t, Vec3::X));
}

#[test]
fn engines_refuse_the_bases_they_cannot_read() {
    use {Engine::*, L1Reconstruction::*, TexelBasis::*};
    for (basis, engine, r) in [
        (ShL1, Bevy, Linear),
        (MonoSh, Bevy, Linear),
        (MonoSh, Godot, Linear),
        (MonoSh, ThreeJs, NonLinear),
        (ShL1, Godot, NonLinear),
    ] {
        let e = TexelFormat::new(basis, engine, r).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains(engine.name()) && msg.contains(basis.name()),
            "{msg}"
        );
    }
    assert_eq!(
        TexelFormat::new(ShL1, Godot, NonLinear)
            .unwrap_err()
            .to_string(),
        "Godot cannot read sh-l1 lightmaps with the non-linear reconstruction: \
         Godot's directional lightmaps reconstruct linearly only"
    );
}
