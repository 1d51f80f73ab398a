//! Light gathered at surface points (what a lightmap's texels hold)
//! against closed forms: an open floor under a constant sky (`E = pi L`,
//! and the hemisphere's SH), a point light over a floor (`E = I cos /
//! d^2`), a sun shadowed by a slab (its lmax-1 SH read back for tilted
//! normals as `E (1/4 + n . t / 2)`), a closed furnace of albedo `a`
//! glowing with `Le` (`E = pi Le / (1 - a)`), a black wall hiding half
//! the sky (`E = pi L / 2`, unbiased), a point inside a box (back
//! faces), and the same bits at any thread count and in any company.

use core::f64::consts::PI;
use std::sync::Arc;

use glam::{DVec3, Mat4, Vec3};
use rand::{Rng, SeedableRng, rngs::StdRng};
use shlight_core::sh::{ShBasis, closed_form};
use shlight_mesh::{
    Instance, LightKind, LightUnits, Material, Mesh, Primitive, PunctualLight, Scene, Surfaces,
    generate,
};
use shlight_volume::{SurfaceLight, SurfacePoint, VolumeOptions, gather_at_surface_points};

/// A scene of `parts` (mesh, albedo, emission), each placed once.
fn scene(parts: Vec<(Mesh, Vec3, Vec3)>) -> Arc<Surfaces> {
    let mut scene = Scene {
        source: "points.glb".into(),
        ..Scene::default()
    };
    for (k, (mesh, albedo, emissive)) in parts.into_iter().enumerate() {
        scene.materials.push(Material {
            base_color: albedo.extend(1.0),
            emissive,
            ..Material::default()
        });
        scene
            .primitives
            .push(Primitive::new(mesh, Some(k), format!("part {k}")));
        scene.instances.push(Instance {
            primitive: k,
            transform: Mat4::IDENTITY,
        });
    }
    Arc::new(scene.flatten(Vec3::splat(0.5)).unwrap())
}

fn options(samples: usize, bounces: u32) -> VolumeOptions {
    VolumeOptions {
        lmax: 2,
        samples,
        bounces,
        surface_samples: 64,
        relocate: false,
        visibility_size: 0,
        light_units: LightUnits::AsWritten,
        ..VolumeOptions::default()
    }
}

fn gather(
    surfaces: &Arc<Surfaces>,
    lights: &[PunctualLight],
    env: DVec3,
    points: &[SurfacePoint],
    options: &VolumeOptions,
) -> Vec<SurfaceLight> {
    let env = closed_form::constant(options.lmax, env);
    gather_at_surface_points(surfaces, lights, &env, points, options, &|_, _, _| {})
        .unwrap()
        .light
}

/// `n` points on the floor `y = 0` within `half` of the origin, facing up.
fn floor_points(n: usize, half: f32, seed: u64) -> Vec<SurfacePoint> {
    let mut rng = StdRng::seed_from_u64(seed);
    (0..n)
        .map(|i| SurfacePoint {
            position: Vec3::new(
                rng.random_range(-half..half),
                0.0,
                rng.random_range(-half..half),
            ),
            normal: Vec3::Y,
            id: i as u64,
        })
        .collect()
}

fn y1(d: Vec3) -> [f64; 4] {
    let mut y = [0.0; 4];
    ShBasis::<f64>::new(1).eval(d.as_dvec3(), &mut y);
    y
}

/// The irradiance for normal `n` from lmax-1 radiance SH: the clamped
/// cosine's zonal factors `pi` and `2 pi / 3` (Ramamoorthi & Hanrahan).
fn irradiance_l1(sh: &[DVec3; 4], n: Vec3) -> DVec3 {
    let y = y1(n);
    sh[0] * (PI * y[0]) + (sh[1] * y[1] + sh[2] * y[2] + sh[3] * y[3]) * (2.0 * PI / 3.0)
}

#[test]
fn an_open_floor_under_a_constant_sky_gets_pi_l_and_the_hemispheres_sh() {
    let floor = scene(vec![(
        generate::plane(8.0, 2),
        Vec3::splat(0.5),
        Vec3::ZERO,
    )]);
    let sky = DVec3::new(1.0, 2.0, 3.0);
    let points = floor_points(24, 3.0, 1);
    let light = gather(&floor, &[], sky, &points, &options(256, 2));
    let y = y1(Vec3::Y);
    let y00 = y[0];
    for l in &light {
        assert_eq!(l.backfaces, 0.0);
        // E = pi L; the stratified cosine's error is about 0.6 / N.
        let rel = (l.irradiance / (PI * sky) - 1.0).abs().max_element();
        assert!(rel < 5e-3, "E {:?} against {:?}", l.irradiance, PI * sky);
        // c_00 = 2 pi L Y_00; c_1m = L int_hemisphere Y_1m = pi L Y_1m(n).
        let rel = (l.sh[0] / (2.0 * PI * y00 * sky) - 1.0).abs().max_element();
        assert!(rel < 1e-9, "c00 {:?}", l.sh[0]);
        for m in 1..4 {
            let want = sky * (PI * y[m]);
            let err = (l.sh[m] - want).abs().max_element();
            assert!(
                err < 0.02 * sky.max_element(),
                "c1{m} {:?} against {want:?}",
                l.sh[m]
            );
        }
        // The lmax-1 reading of a constant hemisphere is exact at n.
        let e = irradiance_l1(&l.sh, Vec3::Y);
        assert!((e / (PI * sky) - 1.0).abs().max_element() < 0.01, "{e:?}");
    }
}

#[test]
fn a_point_light_over_a_floor_gives_i_cos_over_d_squared_and_nothing_behind() {
    let floor = scene(vec![(
        generate::plane(8.0, 2),
        Vec3::splat(0.5),
        Vec3::ZERO,
    )]);
    let lamp = PunctualLight {
        name: None,
        kind: LightKind::Point,
        color: Vec3::new(1.0, 0.5, 0.25),
        intensity: 10.0,
        range: None,
        position: Vec3::new(0.3, 1.5, -0.2),
        direction: Vec3::NEG_Z,
    };
    let mut points = floor_points(32, 3.0, 2);
    // The floor is one-sided: from below, the lamp is behind.
    points.push(SurfacePoint {
        position: Vec3::new(0.1, 0.0, 0.1),
        normal: Vec3::NEG_Y,
        id: 99,
    });
    let light = gather(
        &floor,
        std::slice::from_ref(&lamp),
        DVec3::ZERO,
        &points,
        &options(64, 1),
    );
    for (p, l) in points.iter().zip(&light) {
        let to = lamp.position - p.position;
        let toward = to.normalize();
        let cos = f64::from(p.normal.dot(toward)).max(0.0);
        let perp = lamp.color.as_dvec3() * 10.0 / f64::from(to.length_squared());
        let want = perp * cos;
        let err = (l.irradiance - want).abs().max_element();
        assert!(
            err <= 1e-5 * perp.max_element(),
            "{:?}: {:?} against {want:?}",
            p.position,
            l.irradiance
        );
        let y = y1(toward);
        for m in 0..4 {
            let want = if cos > 0.0 { perp * y[m] } else { DVec3::ZERO };
            assert!((l.sh[m] - want).abs().max_element() <= 1e-5 * perp.max_element());
        }
    }
}

/// Whether the segment from `p` along `d` (to infinity) meets the box
/// `lo..hi` (the slab test).
fn ray_meets_box(p: Vec3, d: Vec3, lo: Vec3, hi: Vec3) -> bool {
    let (mut t0, mut t1) = (0.0f32, f32::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-12 {
            if p[k] < lo[k] || p[k] > hi[k] {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo[k] - p[k]) / d[k], (hi[k] - p[k]) / d[k]);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    t0 <= t1
}

#[test]
fn a_sun_is_shadowed_by_a_slab_and_its_l1_sh_gives_the_closed_form_for_tilted_normals() {
    let (centre, half) = (Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.8, 0.1, 0.5));
    let mut slab = generate::cuboid(half);
    for p in &mut slab.positions {
        *p += centre;
    }
    // A black slab and a black sky: the floor's light is the sun's alone.
    let surfaces = scene(vec![
        (generate::plane(8.0, 2), Vec3::splat(0.5), Vec3::ZERO),
        (slab, Vec3::ZERO, Vec3::ZERO),
    ]);
    let direction = Vec3::new(0.3, -1.0, 0.2).normalize();
    let sun = PunctualLight {
        name: None,
        kind: LightKind::Directional,
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
        position: Vec3::ZERO,
        direction,
    };
    let points = floor_points(200, 2.0, 3);
    let light = gather(
        &surfaces,
        std::slice::from_ref(&sun),
        DVec3::ZERO,
        &points,
        &options(16, 1),
    );
    let toward = -direction;
    let (mut lit, mut shadowed) = (0, 0);
    let mut rng = StdRng::seed_from_u64(4);
    for (p, l) in points.iter().zip(&light) {
        let blocked = ray_meets_box(p.position, toward, centre - half, centre + half);
        let perp = 3.0;
        let want = if blocked {
            0.0
        } else {
            perp * f64::from(toward.y)
        };
        assert!(
            (l.irradiance - DVec3::splat(want)).abs().max_element() < 1e-5,
            "{:?} (shadowed {blocked}): {:?}, want {want}",
            p.position,
            l.irradiance
        );
        if blocked {
            shadowed += 1;
            continue;
        }
        lit += 1;
        // Read back for tilted normals: E(n) = E_perp (1/4 + n . t / 2).
        for _ in 0..4 {
            let n = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(0.2..1.0),
                rng.random_range(-1.0..1.0),
            )
            .normalize();
            let e = irradiance_l1(&l.sh, n);
            let want = perp * (0.25 + 0.5 * f64::from(n.dot(toward)));
            assert!(
                (e - DVec3::splat(want)).abs().max_element() < 1e-5,
                "{e:?} against {want}"
            );
        }
    }
    assert!(lit > 20 && shadowed > 20, "{lit} lit, {shadowed} shadowed");
}

/// A box seen from inside: `generate::cuboid` with its winding and normals
/// turned inward.
fn inward_box(half: Vec3) -> Mesh {
    let b = generate::cuboid(half);
    let triangles = b.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let normals = b.normals.iter().map(|n| -*n).collect();
    Mesh::new(
        "inward box",
        b.positions.clone(),
        triangles,
        Some(normals),
        None,
    )
    .unwrap()
}

#[test]
fn a_closed_furnace_of_albedo_a_glowing_le_holds_pi_le_over_one_minus_a() {
    let (albedo, le) = (0.5f32, Vec3::new(0.2, 0.1, 0.05));
    let half = Vec3::new(1.0, 0.75, 0.5);
    let surfaces = scene(vec![(inward_box(half), Vec3::splat(albedo), le)]);
    // On each face, facing in.
    let mut rng = StdRng::seed_from_u64(5);
    let points: Vec<SurfacePoint> = (0..24)
        .map(|i| {
            let axis = i % 3;
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            let mut p = Vec3::new(
                rng.random_range(-0.9..0.9) * half.x,
                rng.random_range(-0.9..0.9) * half.y,
                rng.random_range(-0.9..0.9) * half.z,
            );
            p[axis] = sign * half[axis];
            let mut n = Vec3::ZERO;
            n[axis] = -sign;
            SurfacePoint {
                position: p,
                normal: n,
                id: i as u64,
            }
        })
        .collect();
    // 16 bounces: the series 1 + a + ... is short of 1/(1-a) by a^18.
    let light = gather(&surfaces, &[], DVec3::ZERO, &points, &options(64, 16));
    let want = PI * le.as_dvec3() / (1.0 - f64::from(albedo));
    for (p, l) in points.iter().zip(&light) {
        assert_eq!(l.backfaces, 0.0);
        let rel = (l.irradiance / want - 1.0).abs().max_element();
        assert!(
            rel < 2e-3,
            "{:?}: {:?} against {want:?}",
            p.position,
            l.irradiance
        );
    }
}

#[test]
fn a_point_inside_a_closed_box_sees_only_back_faces() {
    let mut slab = generate::cuboid(Vec3::splat(0.5));
    for p in &mut slab.positions {
        *p += Vec3::new(0.0, 2.0, 0.0);
    }
    let surfaces = scene(vec![
        (generate::plane(8.0, 2), Vec3::splat(0.5), Vec3::ZERO),
        (slab, Vec3::splat(0.5), Vec3::ZERO),
    ]);
    let points = [
        SurfacePoint {
            position: Vec3::new(0.1, 2.0, 0.05),
            normal: Vec3::Y,
            id: 0,
        },
        SurfacePoint {
            position: Vec3::new(3.0, 0.0, 3.0),
            normal: Vec3::Y,
            id: 1,
        },
    ];
    let light = gather(&surfaces, &[], DVec3::ONE, &points, &options(64, 1));
    assert_eq!(light[0].backfaces, 1.0);
    assert_eq!(light[0].irradiance, DVec3::ZERO);
    assert!(light[1].backfaces < 0.1);
}

#[test]
fn a_points_light_is_the_same_bits_at_any_thread_count_and_in_any_company() {
    let mut slab = generate::cuboid(Vec3::new(0.8, 0.1, 0.5));
    for p in &mut slab.positions {
        *p += Vec3::Y;
    }
    let surfaces = scene(vec![
        (
            generate::plane(6.0, 4),
            Vec3::new(0.6, 0.5, 0.4),
            Vec3::ZERO,
        ),
        (slab, Vec3::splat(0.7), Vec3::new(0.0, 0.3, 0.0)),
    ]);
    let lamp = PunctualLight {
        name: None,
        kind: LightKind::Point,
        color: Vec3::ONE,
        intensity: 5.0,
        range: None,
        position: Vec3::new(1.5, 2.0, 0.5),
        direction: Vec3::NEG_Z,
    };
    let points = floor_points(40, 2.5, 6);
    let opts = options(64, 2);
    let run = |threads: usize, points: &[SurfacePoint]| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                gather(
                    &surfaces,
                    std::slice::from_ref(&lamp),
                    DVec3::new(0.5, 0.6, 0.7),
                    points,
                    &opts,
                )
            })
    };
    let one = run(1, &points);
    let two = run(2, &points);
    let half = run(2, &points[17..]);
    for (a, b) in one.iter().zip(&two) {
        assert_eq!(
            a.irradiance.to_array().map(f64::to_bits),
            b.irradiance.to_array().map(f64::to_bits)
        );
        assert_eq!(a.sh, b.sh);
    }
    for (a, b) in one[17..].iter().zip(&half) {
        assert_eq!(a, b);
    }
    // Not a constant: the slab's shadow and glow make the points differ.
    assert!(
        one.iter()
            .any(|l| (l.irradiance - one[0].irradiance).abs().max_element() > 0.05)
    );
}

#[test]
fn a_point_that_is_not_finite_is_refused_by_number() {
    let floor = scene(vec![(
        generate::plane(2.0, 1),
        Vec3::splat(0.5),
        Vec3::ZERO,
    )]);
    let points = [SurfacePoint {
        position: Vec3::new(f32::NAN, 0.0, 0.0),
        normal: Vec3::Y,
        id: 0,
    }];
    let env = closed_form::constant(2, DVec3::ONE);
    let e = gather_at_surface_points(&floor, &[], &env, &points, &options(16, 1), &|_, _, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("surface point 0 is not finite"), "{e}");
}

#[test]
fn a_black_wall_beside_a_floor_takes_half_the_sky_without_bias() {
    // A tall, wide black wall in the plane x = 0 facing -x: from the
    // floor at x < 0 it hides every direction with s_x > 0 (but a sliver
    // over its top), so E = pi L / 2: light that is not one radiance over
    // the hemisphere, where the control variate does not make the
    // estimate exact. Each point within 5%, their mean within 1%.
    let mut wall = generate::plane(100.0, 4);
    for p in &mut wall.positions {
        *p = Vec3::new(0.0, p.x + 50.0, p.z);
    }
    for n in &mut wall.normals {
        *n = Vec3::NEG_X;
    }
    // (x, y, z) -> (0, x + 50, z) mirrors, so the plane's winding now
    // faces -x, as its normals say.
    let wall = Mesh::new(
        "wall",
        wall.positions.clone(),
        wall.triangles.clone(),
        Some(wall.normals.clone()),
        None,
    )
    .unwrap();
    let surfaces = scene(vec![
        (generate::plane(100.0, 4), Vec3::ZERO, Vec3::ZERO),
        (wall, Vec3::ZERO, Vec3::ZERO),
    ]);
    let points: Vec<SurfacePoint> = (0..40)
        .map(|i| SurfacePoint {
            position: Vec3::new(-0.2 - 0.01 * i as f32, 0.0, 0.03 * i as f32),
            normal: Vec3::Y,
            id: i,
        })
        .collect();
    let light = gather(&surfaces, &[], DVec3::ONE, &points, &options(256, 1));
    let mut sum = 0.0;
    for l in &light {
        assert_eq!(l.backfaces, 0.0);
        let rel = l.irradiance.x / (PI / 2.0) - 1.0;
        assert!(rel.abs() < 0.05, "{rel}");
        sum += rel;
    }
    let bias = sum / light.len() as f64;
    assert!(bias.abs() < 0.01, "bias {bias}");
}
