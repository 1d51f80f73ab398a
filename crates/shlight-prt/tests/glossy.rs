//! Glossy transfer matrices against independent numbers: the identity of
//! an unshadowed convex sphere and the closed-form exit radiance
//! `sum Lambda_l L_lm Y_lm(R)`, a brute-force reference written here
//! (its own directions, visibility by the brute-force tracer, projection
//! and lobe; for Phong and for GGX, `ggx_reference`), the bowl's closed-form bounce light, and the mirror limit of
//! the Phong lobe.

use core::f64::consts::{FRAC_1_SQRT_2, PI};

use glam::{DVec3, Vec3};
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_core::sh::{ShCoeffs, closed_form, lm_from_index, sh_count, sh_eval};
use shlight_mesh::{Mesh, generate};
use shlight_prt::{
    Albedo, BakeOptions, Brdf, BrdfLobe, Mode, Observer, bake_glossy, glossy_bytes,
    glossy_exit_radiance as exit_radiance,
};
use shlight_rays::brute_force_closest_hit as closest_hit;

mod ggx_reference;

fn options(lmax: usize, samples: usize, mode: Mode, albedo: f32) -> BakeOptions {
    BakeOptions {
        lmax,
        samples,
        mode,
        albedo: Albedo::Constant([albedo; 3]),
        seed: 7,
        emission: None,
        surfaces: None,
        direct_irradiance: None,
    }
}

/// A smooth RGB light to lmax 4: a bright cap, a gradient and a floor.
fn test_light() -> ShCoeffs<DVec3> {
    let mut light = closed_form::cap(
        4,
        DVec3::new(0.3, 0.8, -0.4).normalize(),
        0.6,
        DVec3::new(3.0, 2.0, 1.0),
    );
    light += &closed_form::linear_gradient(
        4,
        DVec3::new(0.0, 1.0, 0.2).normalize(),
        DVec3::new(0.5, 0.6, 0.7),
        DVec3::splat(0.3),
    );
    light
}

/// `sum_lm Lambda_l f_lm Y_lm(d)` per channel, written out here.
fn lobe_at(f: &[DVec3], lambda: &[f64], d: DVec3) -> DVec3 {
    let lmax = (f.len() as f64).sqrt() as usize - 1;
    sh_eval(lmax, d)
        .iter()
        .enumerate()
        .map(|(i, y)| f[i] * lambda[lm_from_index(i).0] * *y)
        .sum()
}

fn mirror(w_o: DVec3, n: DVec3) -> DVec3 {
    2.0 * n.dot(w_o) * n - w_o
}

/// The diffuse base under the glossy layer (`shade`, what `sample
/// --albedo` and the GPU evaluate): on an unshadowed sphere (`M` the
/// identity but for sampling), `rho/pi E(n)` with `E` the light's
/// irradiance by Ramamoorthi & Hanrahan's closed-form `A_l` (pi, 2 pi/3,
/// pi/4), plus the closed-form glossy layer.
#[test]
fn the_diffuse_base_is_the_irradiance_of_the_transferred_radiance() {
    use shlight_baked::{GlossyMatrices, GlossyView};
    let sphere = generate::uv_sphere(1.0, 16, 8);
    let t = bake_glossy(
        &sphere,
        &options(2, 4096, Mode::Unshadowed, 0.8),
        &|_, _, _| {},
    );
    let matrices = GlossyView::new(
        2,
        1,
        t.vertex_count,
        GlossyMatrices::Full(std::borrow::Cow::Borrowed(&t.matrices)),
    )
    .unwrap();
    let light = test_light().resized(2);
    let lambda = Brdf::Phong { exponent: 6.0 }.lambda(2).unwrap();
    let rho = DVec3::new(0.2, 0.5, 0.9);
    let a = [PI, 2.0 * PI / 3.0, PI / 4.0];
    let eye = DVec3::new(0.5, 3.0, 4.0);
    let transferred = matrices.transferred(light.as_slice());
    let got = shlight_prt::glossy_shade(
        &matrices,
        &transferred,
        &sphere.positions,
        &sphere.normals,
        &BrdfLobe::Zonal(lambda.clone()),
        rho,
        Observer::Eye(eye),
    );
    let glossy_only = shlight_prt::glossy_shade(
        &matrices,
        &transferred,
        &sphere.positions,
        &sphere.normals,
        &BrdfLobe::Zonal(lambda.clone()),
        DVec3::ZERO,
        Observer::Eye(eye),
    );
    for (v, (g, layer)) in got.iter().zip(&glossy_only).enumerate() {
        let n = sphere.normals[v].as_dvec3();
        let p = sphere.positions[v].as_dvec3();
        let irradiance: DVec3 = sh_eval(2, n)
            .iter()
            .enumerate()
            .map(|(i, y)| light.as_slice()[i] * a[lm_from_index(i).0] * *y)
            .sum();
        let base = rho / PI * irradiance;
        let w_o = (eye - p).normalize();
        let want = base + lobe_at(light.as_slice(), &lambda, mirror(w_o, n));
        assert!(
            (*g - want).abs().max_element() < 0.02 * want.max_element().max(1.0),
            "vertex {v}: {g} vs {want}"
        );
        // The base adds to the layer, channel by channel.
        assert!(
            (*g - *layer - base).abs().max_element() < 0.01 * base.max_element().max(1.0),
            "vertex {v}: base {} vs {base}",
            *g - *layer
        );
    }
}

#[test]
fn an_unshadowed_convex_sphere_has_identity_matrices_and_the_closed_form_exit() {
    let sphere = generate::uv_sphere(1.0, 16, 8);
    let bake = |samples| {
        bake_glossy(
            &sphere,
            &options(4, samples, Mode::Unshadowed, 0.8),
            &|_, _, _| {},
        )
    };
    let nc = sh_count(4);
    let worst = |t: &shlight_prt::GlossyTransfer| {
        let mut worst = 0.0f64;
        for m in t.matrices.chunks_exact(nc * nc) {
            for i in 0..nc {
                for j in 0..nc {
                    let want = if i == j { 1.0 } else { 0.0 };
                    worst = worst.max((f64::from(m[i * nc + j]) - want).abs());
                }
            }
        }
        worst
    };
    let (coarse, t) = (bake(1024), bake(4096));
    assert_eq!((t.channels, t.vertex_count), (1, sphere.vertex_count()));
    // A jittered equal-area grid integrates products of degree-4
    // harmonics (degree-8 polynomials) to ~1e-2 at 4096 directions, the
    // error shrinking with more; a wrong weight (a missing 4 pi, half the
    // sphere) is off by 0.5 or more.
    let (w1, w4) = (worst(&coarse), worst(&t));
    eprintln!("max |M - I|: {w1} at 1024 directions, {w4} at 4096");
    assert!(w4 < 0.015 && w4 < 0.6 * w1, "max |M - I| = {w4}, {w1}");
    let light = test_light();
    let brdf = Brdf::Phong { exponent: 12.0 };
    let lambda = brdf.lambda(4).unwrap();
    let mut rng = StdRng::seed_from_u64(1);
    for _ in 0..4 {
        let view = DVec3::new(
            rng.random::<f64>() - 0.5,
            rng.random::<f64>() - 0.5,
            rng.random::<f64>() - 0.5,
        );
        let got = t.exit_radiance(&sphere, brdf, light.as_slice(), Observer::Direction(view));
        for (v, g) in got.iter().enumerate() {
            let n = sphere.normals[v].as_dvec3();
            let want = lobe_at(light.as_slice(), &lambda, mirror(view.normalize(), n));
            assert!(
                (*g - want).abs().max_element() < 0.02 * want.max_element().max(1.0),
                "vertex {v}: {g} vs {want}"
            );
        }
    }
}

/// The bake's exit radiance at random vertices and eyes, for Phong and for
/// GGX, against the transferred radiance projected here from the
/// brute-force tracer's visibility, shaded by each BRDF's reference: the
/// Phong lobe's zonal sum, GGX's integral direction by direction.
#[test]
fn shadowed_exit_radiance_matches_a_brute_force_reference() {
    let mesh = generate::plane_under_sphere(1.0, 16, 8, 4.0, 8);
    let t = bake_glossy(&mesh, &options(4, 4096, Mode::Shadowed, 0.8), &|_, _, _| {});
    let light = test_light();
    let phong = Brdf::Phong { exponent: 6.0 };
    let lambda = phong.lambda(4).unwrap();
    let (alpha, f0) = (0.35, 1.0);
    let ggx = Brdf::Ggx { alpha, f0 };
    let reference = |brdf: Brdf, tr: &[DVec3], n: DVec3, w_o: DVec3| match brdf {
        Brdf::Phong { .. } => lobe_at(tr, &lambda, mirror(w_o, n)),
        _ => ggx_reference::integrated(tr, n, w_o, alpha, f0),
    };
    // The reference's own directions: a jittered grid in (cos theta, phi).
    let mut rng = StdRng::seed_from_u64(21);
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
    let mut peak = [0.0f64; 2];
    let mut errors = Vec::new();
    for _ in 0..12 {
        let v = rng.random_range(0..mesh.vertex_count());
        let eye = DVec3::new(
            rng.random::<f64>() * 8.0 - 4.0,
            rng.random::<f64>() * 4.0 + 0.5,
            rng.random::<f64>() * 8.0 - 4.0,
        );
        let p = mesh.positions[v].as_dvec3();
        let n = mesh.normals[v].as_dvec3();
        // Transferred radiance: T_i = int V L Y_i, V from the brute-force
        // tracer above the tangent plane, 0 below.
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
        for (k, brdf) in [phong, ggx].into_iter().enumerate() {
            let want = reference(brdf, &tr, n, w_o);
            let got = t.exit_radiance(&mesh, brdf, light.as_slice(), Observer::Eye(eye))[v];
            peak[k] = peak[k].max(want.max_element());
            errors.push((k, brdf, v, got, want));
        }
    }
    assert_eq!(errors.len(), 24);
    for (k, brdf, v, got, want) in errors {
        // Two stratified estimates (4096 and 20,000 directions) of a
        // shadowed, band-limited integrand: ~1% of the peak apart; a
        // vertex lit through the sphere or a mirror taken the wrong way
        // is off by tens of percent.
        assert!(
            (got - want).abs().max_element() < 0.03 * peak[k],
            "{brdf}, vertex {v}: bake {got}, reference {want} (peak {})",
            peak[k]
        );
    }
}

#[test]
fn bounce_light_in_a_bowl_follows_the_closed_form() {
    // At the bottom of a hemispherical bowl of radius 1 the sky is a cone
    // of half-angle 45 degrees about the normal (the rim); the rest of
    // the upper hemisphere is bowl, which under constant radiance c leaves
    // E = rho c / 2 sum_{b < B} (rho/2)^b after B - 1 bounces of its own
    // (every point of a sphere's inside sees half bowl, cosine-weighted).
    // So T_00 = (c Omega_sky + E Omega_bowl) / sqrt(4 pi).
    let bowl = generate::bowl(1.0, 48, 12);
    let rho = 0.6f32;
    let c = 1.0;
    let light = closed_form::constant(4, DVec3::splat(c));
    let sky = 2.0 * PI * (1.0 - FRAC_1_SQRT_2);
    let rest = 2.0 * PI - sky;
    let mut t00 = Vec::new();
    for bounces in [0u32, 1, 3] {
        let mode = if bounces == 0 {
            Mode::Shadowed
        } else {
            Mode::Interreflected { bounces }
        };
        let t = bake_glossy(
            &bowl,
            &BakeOptions {
                albedo: Albedo::Constant([rho, rho * 0.5, rho]),
                ..options(2, 8192, mode, rho)
            },
            &|_, _, _| {},
        );
        assert_eq!(t.channels, if bounces == 0 { 1 } else { 3 });
        let nc = sh_count(2);
        let stride = t.channels * nc * nc;
        // Vertex 0 is the bottom: T = M L, L only its constant term.
        let m = &t.matrices[..stride];
        for ch in 0..t.channels {
            let r = f64::from([rho, rho * 0.5, rho][ch]);
            let e: f64 = if bounces == 0 {
                0.0
            } else {
                r * c / 2.0 * (0..bounces).map(|b| (r / 2.0).powi(b as i32)).sum::<f64>()
            };
            let want = (c * sky + e * rest) / (4.0 * PI).sqrt();
            let got = f64::from(m[ch * nc * nc]) * light.as_slice()[0].x;
            // The polygonal bowl and 8192 directions: within 2%; the
            // bounce terms are 20% to 40% of the total.
            assert!(
                (got - want).abs() < 0.02 * want,
                "{bounces} bounces, channel {ch}: T_00 {got} vs {want}"
            );
            if ch == 0 {
                t00.push(got);
            }
        }
    }
    assert!(t00[0] < t00[1] && t00[1] < t00[2], "{t00:?}");
}

#[test]
fn a_sharpening_phong_lobe_approaches_the_mirror_reflection() {
    // Identity matrices (light arrives unchanged): the exit radiance is the
    // light convolved with the lobe at R, and as S grows, Lambda_l -> 1 and
    // it becomes the band-limited light itself at R.
    let lmax = 4;
    let nc = sh_count(lmax);
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
    let normals = vec![Vec3::Y, Vec3::new(0.6, 0.8, 0.0), Vec3::Z];
    let mut matrices = vec![0.0f32; positions.len() * nc * nc];
    for m in matrices.chunks_exact_mut(nc * nc) {
        for i in 0..nc {
            m[i * nc + i] = 1.0;
        }
    }
    let light = test_light();
    let view = DVec3::new(0.2, 0.9, 0.3);
    let exponents = [4.0, 40.0, 400.0, 4e4];
    let errors: Vec<f64> = exponents
        .iter()
        .map(|&s| {
            let brdf = Brdf::Phong { exponent: s };
            let lambda = brdf.lambda(lmax).unwrap();
            // Lambda_l -> 1 from below, more slowly for higher l.
            assert!(lambda.windows(2).all(|w| w[1] < w[0]), "{lambda:?}");
            let got = exit_radiance(
                &matrices,
                lmax,
                1,
                &positions,
                &normals,
                &BrdfLobe::Zonal(lambda.clone()),
                light.as_slice(),
                Observer::Direction(view),
            );
            got.iter()
                .zip(&normals)
                .map(|(g, n)| {
                    let r = mirror(view.normalize(), n.as_dvec3());
                    let mirror_light = lobe_at(light.as_slice(), &[1.0; 5], r);
                    (*g - mirror_light).abs().max_element()
                })
                .fold(0.0, f64::max)
        })
        .collect();
    // The error falls like 1/S (1 - Lambda_l ~ l(l+1)/(2S)) once the lobe
    // is narrow: error times S settles (to ~4 here).
    let settled = errors[3] * exponents[3];
    for k in 1..3 {
        let scaled = errors[k] * exponents[k];
        assert!((scaled / settled - 1.0).abs() < 0.1, "{errors:?}");
    }
    assert!(errors[0] > 0.1 && errors[3] < 1e-3, "{errors:?}");
}

#[test]
fn a_view_turns_radiance_by_the_mirror_direction_and_the_sizes_are_counted() {
    // Two views mirror images of each other about a vertex's normal give
    // the same R only when they are the same: check that w_o and R are
    // not swapped (R of w_o = n is n itself).
    let positions = vec![Vec3::ZERO];
    let normals = vec![Vec3::Y];
    let nc = sh_count(2);
    let mut m = vec![0.0f32; nc * nc];
    for i in 0..nc {
        m[i * nc + i] = 1.0;
    }
    let sun = closed_form::directional(2, DVec3::new(1.0, 1.0, 0.0).normalize(), DVec3::ONE);
    let lambda = Brdf::Phong { exponent: 1e5 }.lambda(2).unwrap();
    let at = |view: DVec3| {
        exit_radiance(
            &m,
            2,
            1,
            &positions,
            &normals,
            &BrdfLobe::Zonal(lambda.clone()),
            sun.as_slice(),
            Observer::Direction(view),
        )[0]
        .x
    };
    // A viewer at (-1, 1, 0) sees the sun's mirror image; one at
    // (1, 1, 0) looks towards (-1, 1, 0), away from it.
    let toward = at(DVec3::new(-1.0, 1.0, 0.0));
    let away = at(DVec3::new(1.0, 1.0, 0.0));
    assert!(toward > 5.0 * away.abs(), "{toward} vs {away}");
    // Eye at a point: the same as the direction from the vertex to it.
    let eye = exit_radiance(
        &m,
        2,
        1,
        &positions,
        &normals,
        &BrdfLobe::Zonal(lambda.clone()),
        sun.as_slice(),
        Observer::Eye(DVec3::new(-3.0, 3.0, 0.0)),
    )[0]
    .x;
    assert!((eye - toward).abs() < 1e-9);
    assert_eq!(glossy_bytes(10, 3, 4), Some(4 * 10 * (3 * 625 + 6)));
    assert_eq!(glossy_bytes(usize::MAX, 3, 4), None);
}

#[test]
fn glossy_files_round_trip_and_shade_as_the_bake() {
    let mesh: Mesh = generate::plane_under_sphere(1.0, 8, 4, 3.0, 2);
    let t = bake_glossy(
        &mesh,
        &options(2, 256, Mode::Interreflected { bounces: 1 }, 0.7),
        &|_, _, _| {},
    );
    let brdf = Brdf::Phong { exponent: 20.0 };
    let file = t.to_shprt(&mesh, brdf, 7, Some([0.7; 3]), "m.obj");
    let back =
        shlight_format::ShprtFile::from_bytes(&file.to_bytes(), std::path::Path::new("m.shprt"))
            .unwrap();
    assert_eq!(back, file);
    let light = test_light();
    let view = Observer::Eye(DVec3::new(1.0, 5.0, 2.0));
    let from_file = shlight_prt::file_exit_radiance(&back, light.as_slice(), Some(view)).unwrap();
    assert_eq!(
        from_file,
        t.exit_radiance(&mesh, brdf, light.as_slice(), view)
    );
    let e = shlight_prt::file_exit_radiance(&back, light.as_slice(), None).unwrap_err();
    assert!(e.contains("depends on the view"), "{e}");
    let e = shlight_prt::file_exit_radiance(
        &back,
        light.as_slice(),
        Some(Observer::Direction(DVec3::ZERO)),
    )
    .unwrap_err();
    assert!(e.contains("zero length"), "{e}");
}

#[test]
fn glossy_bakes_are_the_same_at_any_thread_count() {
    let mesh = generate::plane_under_sphere(1.0, 12, 6, 3.0, 4);
    let options = BakeOptions {
        albedo: Albedo::Constant([0.9, 0.5, 0.2]),
        ..options(2, 128, Mode::Interreflected { bounces: 2 }, 0.5)
    };
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(|| bake_glossy(&mesh, &options, &|_, _, _| {}));
    let three = pool(3).install(|| bake_glossy(&mesh, &options, &|_, _, _| {}));
    assert_eq!(one.channels, 3);
    assert_eq!(one.matrices, three.matrices);
    // The channels differ where bounce light arrives: blue (0.2) gathers
    // less than red (0.9).
    let nn = sh_count(2) * sh_count(2);
    let (mut r, mut b) = (0.0f64, 0.0f64);
    for m in one.matrices.chunks_exact(3 * nn) {
        r += f64::from(m[0]);
        b += f64::from(m[2 * nn]);
    }
    assert!(b < r, "{b} vs {r}");
}

#[test]
fn cpca_at_its_most_clusters_or_vectors_reproduces_the_matrices() {
    let mesh = generate::plane_under_sphere(1.0, 10, 5, 3.0, 4);
    let t = bake_glossy(&mesh, &options(2, 256, Mode::Shadowed, 0.8), &|_, _, _| {});
    let dim = sh_count(2) * sh_count(2);
    let n = t.vertex_count;
    let peak = t.matrices.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    let worst = |c: usize, k: usize| {
        let z = shlight_prt::compress(&t.matrices, dim, c, k, 3).unwrap();
        z.reconstruct()
            .iter()
            .zip(&t.matrices)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max)
    };
    // A cluster per vertex, or every direction of a few clusters.
    assert_eq!(worst(n, 0), 0.0);
    assert!(worst(4, dim) < 1e-5 * peak, "{}", worst(4, dim));
    // Compressed harder, it errs more.
    let (k8, k2) = (worst(4, 8), worst(4, 2));
    assert!(k2 > k8 && k8 > 1e-5 * peak, "{k2} {k8}");
    // And the exit radiance of the reproduced matrices is the bake's.
    let z = shlight_prt::compress(&t.matrices, dim, n, 0, 3).unwrap();
    let brdf = Brdf::Phong { exponent: 8.0 };
    let light = test_light();
    let view = Observer::Direction(DVec3::new(0.1, 1.0, 0.4));
    let exit = |m: &[f32]| {
        exit_radiance(
            m,
            2,
            1,
            &mesh.positions,
            &mesh.normals,
            &BrdfLobe::Zonal(brdf.lambda(2).unwrap()),
            light.as_slice(),
            view,
        )
    };
    assert_eq!(exit(&z.reconstruct()), exit(&t.matrices));
}
