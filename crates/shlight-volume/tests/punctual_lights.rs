//! Punctual lights in a volume's bake, against closed forms and a brute-force
//! sum written here: the exact SH projection of a light's delta at a probe,
//! the irradiance it gives as lmax grows (the truncation error of the
//! clamped-cosine series, computed here from Legendre polynomials), a floor
//! lit by a point light as a probe sees it (a quadrature over the floor),
//! a spot's cones, a sun's shadow, one-sided surfaces, the units, and the
//! same bits at any thread count.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};
use shlight_baked::ProbeGrid;
use shlight_core::sh::{ShBasis, sh_count};
use shlight_mesh::{LightKind, LightUnits, Mesh, PunctualLight, generate};
use shlight_volume::{VolumeBake, VolumeOptions, bake_with_lights};

/// A square floor of side `size` in `z = 0`, facing +Z, `divisions`
/// cells a side ([`generate::plane`] turned from y-up: `(x, y, z) -> (x,
/// -z, y)`, a rotation, exact).
fn floor(size: f32, divisions: u32) -> Mesh {
    let p = generate::plane(size, divisions);
    let turn = |v: &Vec3| Vec3::new(v.x, -v.z, v.y);
    Mesh::new(
        "floor",
        p.positions.iter().map(turn).collect(),
        p.triangles.clone(),
        Some(p.normals.iter().map(turn).collect()),
        None,
    )
    .unwrap()
}

fn light(kind: LightKind, position: Vec3, direction: Vec3, intensity: f32) -> PunctualLight {
    PunctualLight {
        name: None,
        kind,
        color: Vec3::new(1.0, 0.5, 0.25),
        intensity,
        range: None,
        position,
        direction: direction.normalize(),
    }
}

/// Options of a bake that sees the lights' direct part and the surfaces'
/// light due to them: no relocation (the probes stay where the test puts
/// them), no distance maps.
fn options(lmax: usize, albedo: f32, bounces: u32) -> VolumeOptions {
    VolumeOptions {
        lmax,
        samples: 64,
        surface_samples: 16,
        bounces,
        albedo: [albedo; 3],
        relocate: false,
        visibility_size: 0,
        ..VolumeOptions::default()
    }
}

/// One probe at `at` (the centre of a small box around it).
fn one_probe(at: Vec3) -> ProbeGrid {
    ProbeGrid::new([1, 1, 1], at - Vec3::splat(0.05), at + Vec3::splat(0.05)).unwrap()
}

/// Probe `p`'s static light, `(lmax+1)^2` rows of `[r, g, b]`, in `f64`.
fn emitted(bake: &VolumeBake, p: usize) -> Vec<DVec3> {
    let nc = sh_count(bake.lmax);
    bake.emitted[p * 3 * nc..][..3 * nc]
        .chunks_exact(3)
        .map(|c| DVec3::new(c[0].into(), c[1].into(), c[2].into()))
        .collect()
}

/// `E_perp Y_lm(toward)` per channel, `E_perp` the light's colour times
/// `e`: the SH of a delta.
fn delta(lmax: usize, toward: DVec3, e: f64) -> Vec<DVec3> {
    let basis = ShBasis::<f64>::new(lmax);
    let mut y = vec![0.0; basis.count()];
    basis.eval(toward, &mut y);
    let colour = DVec3::new(1.0, 0.5, 0.25);
    y.iter().map(|y| e * y * colour).collect()
}

/// Clamped-cosine coefficient `A_l` (Ramamoorthi & Hanrahan 2001), from
/// its closed form: `pi`, `2 pi / 3`, 0 for odd `l > 1`, and for even `l`
/// `2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) l! / (2^l ((l/2)!)^2)`.
fn a_l(l: usize) -> f64 {
    match l {
        0 => PI,
        1 => 2.0 * PI / 3.0,
        _ if l % 2 == 1 => 0.0,
        _ => {
            // l! / (2^l ((l/2)!)^2) = prod_{k=1}^{l/2} (2k - 1) / (2k).
            let central: f64 = (1..=l / 2)
                .map(|k| (2 * k - 1) as f64 / (2 * k) as f64)
                .product();
            let sign = if (l / 2 - 1).is_multiple_of(2) {
                1.0
            } else {
                -1.0
            };
            2.0 * PI * sign * central / ((l + 2) as f64 * (l - 1) as f64)
        }
    }
}

/// `P_0(x) .. P_n(x)` by Bonnet's recurrence.
fn legendre(n: usize, x: f64) -> Vec<f64> {
    let mut p = vec![1.0, x];
    for l in 1..n {
        let l = l as f64;
        p.push(((2.0 * l + 1.0) * x * p[l as usize] - l * p[l as usize - 1]) / (l + 1.0));
    }
    p.truncate(n + 1);
    p
}

/// The irradiance on a surface facing `n` that radiance SH `coeffs` give,
/// `sum_l A_l sum_m L_lm Y_lm(n)`, with this file's `A_l`.
fn irradiance_at(coeffs: &[DVec3], lmax: usize, n: DVec3) -> DVec3 {
    let basis = ShBasis::<f64>::new(lmax);
    let mut y = vec![0.0; basis.count()];
    basis.eval(n, &mut y);
    let mut e = DVec3::ZERO;
    for l in 0..=lmax {
        for i in l * l..(l + 1) * (l + 1) {
            e += a_l(l) * y[i] * coeffs[i];
        }
    }
    e
}

#[test]
fn a_point_light_projects_exactly_and_its_irradiance_approaches_the_cosine_law() {
    // A 20 m floor, black (only the light's direct part reaches the
    // probe), and a probe 0.5 m above it; a point light of 683 x 9 cd
    // (Blender's units: 9 W/sr) 1.5 m straight above the probe gives
    // E_perp = 9 / 1.5^2 = 4 W/m2 from +Z, the basis's pole, where
    // Y_lm(+Z) = sqrt((2l + 1) / (4 pi)) for m = 0 and 0 otherwise.
    let scene = floor(20.0, 1);
    let at = Vec3::new(0.3, -0.2, 0.5);
    let grid = one_probe(at);
    let x = grid.centres()[0];
    let lamp = light(
        LightKind::Point,
        x + Vec3::new(0.0, 0.0, 1.5),
        Vec3::NEG_Z,
        683.0 * 9.0,
    );
    let lmax = 8;
    let bake = bake_with_lights(
        Some(&scene),
        &[lamp],
        &grid,
        &options(lmax, 0.0, 0),
        &|_, _, _| {},
    )
    .unwrap();
    let got = emitted(&bake, 0);
    let colour = DVec3::new(1.0, 0.5, 0.25);
    for l in 0..=lmax {
        for m in -(l as i64)..=l as i64 {
            let i = (l * (l + 1)) as i64 + m;
            let want = if m == 0 {
                4.0 * ((2 * l + 1) as f64 / (4.0 * PI)).sqrt() * colour
            } else {
                DVec3::ZERO
            };
            let g = got[i as usize];
            assert!(
                (g - want).abs().max_element() <= 1e-6 * 4.0,
                "l {l} m {m}: {g} vs {want}"
            );
        }
    }

    // The irradiance these give a surface facing the floor's normal, +Z,
    // against I cos(theta) / d^2, for lights at theta = 0 (above) and 50
    // degrees, and lmax 2, 4, 8. The SH of a delta carry the whole
    // clamped-cosine series cut at lmax: E_lmax = E_perp sum_{l <= lmax}
    // A_l (2l + 1) / (4 pi) P_l(cos theta), so the error expected is the
    // series' tail, E_perp sum_{l > lmax} A_l (2l + 1) / (4 pi) P_l(cos
    // theta) (summed here to l = 20000; the terms fall as l^-2 and
    // alternate in sign, the rest is below 1e-8), e.g. at theta = 0 a
    // relative -6.25% at lmax 2 (1.0625 for 1), 3.13% at lmax 4 and 1.37%
    // at lmax 8 (at 50 degrees 3.4%, -0.61% and 0.081%);
    // the probes must show exactly that error (to f32 rounding) and it
    // must shrink as lmax grows.
    let tail = |lmax: usize, cos: f64| -> f64 {
        let p = legendre(20000, cos);
        (lmax + 1..=20000)
            .map(|l| a_l(l) * (2 * l + 1) as f64 / (4.0 * PI) * p[l])
            .sum()
    };
    for theta in [0.0f64, 50.0] {
        let (s, c) = theta.to_radians().sin_cos();
        let d = 1.5f32;
        let lamp = light(
            LightKind::Point,
            x + d * Vec3::new(s as f32, 0.0, c as f32),
            Vec3::NEG_Z,
            683.0 * 9.0,
        );
        let e_perp = 9.0 / f64::from(d * d);
        let truth = e_perp * c;
        let mut last = f64::INFINITY;
        for lmax in [2usize, 4, 8] {
            let bake = bake_with_lights(
                Some(&scene),
                std::slice::from_ref(&lamp),
                &grid,
                &options(lmax, 0.0, 0),
                &|_, _, _| {},
            )
            .unwrap();
            let e = irradiance_at(&emitted(&bake, 0), lmax, DVec3::Z).x;
            let expected = e_perp * tail(lmax, c);
            let error = truth - e;
            println!(
                "theta {theta}, lmax {lmax}: E {e:.6} vs I cos / d^2 {truth:.6}: error {:.4}% (the series' tail: {:.4}%)",
                100.0 * error / e_perp,
                100.0 * expected / e_perp
            );
            assert!(
                (error - expected).abs() <= 2e-6 * e_perp,
                "theta {theta} lmax {lmax}: error {error} where the tail is {expected}"
            );
            assert!(error.abs() < last, "lmax {lmax}: {error} not below {last}");
            last = error.abs();
        }
        assert!(last < 0.015 * e_perp, "{last}");
    }
}

#[test]
fn the_floor_a_point_light_lights_is_seen_as_a_brute_force_sum_over_it_says() {
    // A 6 m floor of albedo 0.5, no bounce, a point light of 10 W/sr (as
    // written) 1 m above its centre: the floor leaves rho / pi I h / r^3
    // at a point r from the light. A probe at (0.4, 0.3, 0.5) sees it over
    // the lower hemisphere; its SH beyond the light's own delta are
    //   L_lm = int_floor rho / pi E(q) Y_lm(s(q)) cos_q / |q - x|^2 dA,
    // summed here by the midpoint rule on 1500 x 1500 cells (an error far
    // below the bake's). The bake estimates it from 16384 stratified rays
    // and a floor subdivided to 5 cm, whose vertices hold E (linear
    // between them: at most 0.1% off at the light's foot).
    let (size, rho, intensity) = (6.0f32, 0.5f64, 10.0f32);
    let scene = floor(size, 1);
    let grid = one_probe(Vec3::new(0.4, 0.3, 0.5));
    let x = grid.centres()[0].as_dvec3();
    let lamp_at = DVec3::new(0.0, 0.0, 1.0);
    let lamp = light(LightKind::Point, lamp_at.as_vec3(), Vec3::NEG_Z, intensity);
    let lmax = 2;
    let opts = VolumeOptions {
        samples: 16384,
        max_edge: Some(0.05),
        light_units: LightUnits::AsWritten,
        ..options(lmax, rho as f32, 0)
    };
    let bake = bake_with_lights(Some(&scene), &[lamp], &grid, &opts, &|_, _, _| {}).unwrap();
    let direct = delta(
        lmax,
        (lamp_at - x).normalize(),
        f64::from(intensity) / (lamp_at - x).length_squared(),
    );
    let seen: Vec<DVec3> = emitted(&bake, 0)
        .iter()
        .zip(&direct)
        .map(|(e, d)| *e - *d)
        .collect();

    let basis = ShBasis::<f64>::new(lmax);
    let nc = basis.count();
    let cells = 1500;
    let step = f64::from(size) / cells as f64;
    let mut want = vec![0.0f64; nc];
    let mut y = vec![0.0; nc];
    for i in 0..cells {
        for j in 0..cells {
            let q = DVec3::new(
                -f64::from(size) / 2.0 + (i as f64 + 0.5) * step,
                -f64::from(size) / 2.0 + (j as f64 + 0.5) * step,
                0.0,
            );
            let to_light = lamp_at - q;
            let r = to_light.length();
            let e = f64::from(intensity) * to_light.z / (r * r * r);
            let to_q = q - x;
            let dist = to_q.length();
            let s = to_q / dist;
            let solid_angle = x.z / dist * step * step / (dist * dist);
            basis.eval(s, &mut y);
            for (w, yi) in want.iter_mut().zip(&y) {
                *w += rho / PI * e * yi * solid_angle;
            }
        }
    }
    let colour = DVec3::new(1.0, 0.5, 0.25);
    let scale = want[0].abs();
    for (i, w) in want.iter().enumerate() {
        let w = *w * colour;
        let g = seen[i];
        println!(
            "L[{i}]: bake {:.6} vs brute force {:.6} ({:+.3}% of L_00)",
            g.x,
            w.x,
            100.0 * (g.x - w.x) / scale
        );
        assert!(
            (g - w).abs().max_element() <= 0.005 * scale,
            "coefficient {i}: {g} vs {w}"
        );
    }
    // Half of the floor's light in the probe's lower hemisphere: the test
    // is not trivially small.
    assert!(
        want[0] > 0.1 * direct[0].x,
        "{} vs {}",
        want[0],
        direct[0].x
    );
}

#[test]
fn a_spot_lights_inside_its_cones_only() {
    // A spot 2 m above a row of probes, pointing down, full within 0.3 rad
    // of its axis and dark beyond 0.5: nothing in the way. Probes at
    // x = -2, -1.5, ..., 2 (angles atan(|x| / 2): 0, 0.245, 0.464, 0.644,
    // 0.785 rad) are lit as the point light's closed form says, partly,
    // or not at all.
    let grid = ProbeGrid::new(
        [9, 1, 1],
        Vec3::new(-2.25, -0.5, -0.5),
        Vec3::new(2.25, 0.5, 0.5),
    )
    .unwrap();
    let spot = light(
        LightKind::Spot {
            inner_cone: 0.3,
            outer_cone: 0.5,
        },
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::NEG_Z,
        683.0 * 4.0,
    );
    let lmax = 2;
    let bake = bake_with_lights(
        None,
        std::slice::from_ref(&spot),
        &grid,
        &options(lmax, 0.0, 0),
        &|_, _, _| {},
    )
    .unwrap();
    for (p, x) in grid.centres().iter().enumerate() {
        let angle = (x.x.abs() / 2.0).atan();
        let got = emitted(&bake, p);
        let to_light = (spot.position - *x).as_dvec3();
        let full = delta(lmax, to_light.normalize(), 4.0 / to_light.length_squared());
        if angle < 0.3 {
            for (g, w) in got.iter().zip(&full) {
                assert!(
                    (*g - *w).abs().max_element() <= 1e-6,
                    "probe {p}: {g} vs {w}"
                );
            }
        } else if angle > 0.5 {
            assert!(
                got.iter().all(|g| *g == DVec3::ZERO),
                "probe {p} is outside"
            );
        } else {
            let ratio = got[0].x / full[0].x;
            assert!(ratio > 0.01 && ratio < 0.99, "probe {p}: {ratio}");
        }
    }
    assert_eq!(
        bake.lights
            .as_ref()
            .map(|l| (l.point, l.spot, l.directional)),
        Some((0, 1, 0))
    );
}

#[test]
fn a_sun_casts_a_shadow() {
    // A sun of 683 x 3 lux (3 W/m2) slanting down along (0.3, 0, -1), a
    // 1 m box 0.1 m thick at height 1 over the origin: a probe at height
    // 0.2 whose ray toward the sun passes through the box's middle
    // (x = 0.24: the ray goes 0.3 m back along x per metre up) gets no
    // direct light; one 3 m beside it gets 3 Y(toward).
    let slab = generate::cuboid(Vec3::new(0.5, 0.5, 0.05));
    let slab = Mesh::new(
        "slab",
        slab.positions.iter().map(|p| *p + Vec3::Z).collect(),
        slab.triangles.clone(),
        Some(slab.normals.clone()),
        None,
    )
    .unwrap();
    let grid = ProbeGrid::new(
        [2, 1, 1],
        Vec3::new(-1.26, -0.5, 0.1),
        Vec3::new(4.74, 0.5, 0.3),
    )
    .unwrap();
    let sun = light(
        LightKind::Directional,
        Vec3::ZERO,
        Vec3::new(0.3, 0.0, -1.0),
        683.0 * 3.0,
    );
    let lmax = 3;
    let bake = bake_with_lights(
        Some(&slab),
        std::slice::from_ref(&sun),
        &grid,
        &options(lmax, 0.0, 0),
        &|_, _, _| {},
    )
    .unwrap();
    let centres = grid.centres();
    assert!((centres[0].x - 0.24).abs() < 1e-5, "{}", centres[0]);
    assert!(
        emitted(&bake, 0).iter().all(|g| *g == DVec3::ZERO),
        "in the shadow"
    );
    let want = delta(lmax, -sun.direction.as_dvec3(), 3.0);
    for (g, w) in emitted(&bake, 1).iter().zip(&want) {
        assert!((*g - *w).abs().max_element() <= 1e-6, "{g} vs {w}");
    }
}

#[test]
fn a_light_behind_a_surface_lights_neither_it_nor_what_faces_it() {
    // The floor faces +Z; a point light 1 m under it. The probe above the
    // floor is shadowed by it and sees its unlit front: nothing at all,
    // with albedo 0.8 and two bounces. The probe below sees the light
    // directly and the floor's back, which brings nothing.
    let scene = floor(6.0, 1);
    let grid = ProbeGrid::new(
        [1, 1, 2],
        Vec3::new(0.1, 0.2, -1.0),
        Vec3::new(0.3, 0.4, 1.0),
    )
    .unwrap();
    let lamp = light(
        LightKind::Point,
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::NEG_Z,
        20.0,
    );
    let lmax = 2;
    let opts = VolumeOptions {
        light_units: LightUnits::AsWritten,
        ..options(lmax, 0.8, 2)
    };
    let bake = bake_with_lights(
        Some(&scene),
        std::slice::from_ref(&lamp),
        &grid,
        &opts,
        &|_, _, _| {},
    )
    .unwrap();
    let [below, above] = [grid.centres()[0], grid.centres()[1]];
    assert!(below.z < 0.0 && above.z > 0.0);
    assert!(
        emitted(&bake, 1).iter().all(|g| *g == DVec3::ZERO),
        "{:?}",
        emitted(&bake, 1)
    );
    let to_light = (lamp.position - below).as_dvec3();
    let want = delta(lmax, to_light.normalize(), 20.0 / to_light.length_squared());
    for (g, w) in emitted(&bake, 0).iter().zip(&want) {
        assert!(
            (*g - *w).abs().max_element() <= 1e-6 * want[0].x,
            "{g} vs {w}"
        );
    }
}

/// A floor with a ball on it, lit by a point, a spot and a sun.
fn lit_scene() -> (Mesh, Vec<PunctualLight>) {
    let scene = generate::plane_under_sphere(0.5, 16, 8, 4.0, 4);
    let lights = vec![
        light(
            LightKind::Point,
            Vec3::new(0.5, 2.0, 0.3),
            Vec3::NEG_Y,
            683.0 * 5.0,
        ),
        light(
            LightKind::Spot {
                inner_cone: 0.2,
                outer_cone: 0.6,
            },
            Vec3::new(-1.0, 1.5, 0.0),
            Vec3::new(0.5, -1.0, 0.0),
            683.0 * 8.0,
        ),
        light(
            LightKind::Directional,
            Vec3::ZERO,
            Vec3::new(0.2, -1.0, 0.4),
            683.0,
        ),
    ];
    (scene, lights)
}

#[test]
fn as_written_intensities_give_683_times_the_blender_bake() {
    // Every number of the static light scales with the lights (the probes'
    // direct part and the surfaces' bounced light alike); the transfer of
    // the environment does not change. (A spot also fades otherwise in
    // Blender's units, as Cycles fades it: the point and the sun only.)
    let (scene, mut lights) = lit_scene();
    lights.retain(|l| !matches!(l.kind, LightKind::Spot { .. }));
    let grid = ProbeGrid::around([3, 2, 3], scene.bounds()).unwrap();
    let run = |units| {
        let opts = VolumeOptions {
            light_units: units,
            ..options(2, 0.6, 1)
        };
        bake_with_lights(Some(&scene), &lights, &grid, &opts, &|_, _, _| {}).unwrap()
    };
    let (blender, written) = (run(LightUnits::Blender), run(LightUnits::AsWritten));
    assert_eq!(blender.transfer, written.transfer);
    let largest = blender.emitted.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    assert!(largest > 0.0);
    for (b, w) in blender.emitted.iter().zip(&written.emitted) {
        let want = 683.0 * f64::from(*b);
        assert!(
            (f64::from(*w) - want).abs() <= 1e-5 * 683.0 * f64::from(largest),
            "{w} vs 683 x {b}"
        );
    }
    assert_eq!(blender.lights.unwrap().units, "blender");
    assert_eq!(written.lights.unwrap().units, "as-written");
}

#[test]
fn bakes_with_lights_are_the_same_at_any_thread_count() {
    let (scene, lights) = lit_scene();
    let grid = ProbeGrid::around([3, 2, 3], scene.bounds()).unwrap();
    let opts = VolumeOptions {
        relocate: true,
        visibility_size: 4,
        ..options(2, 0.7, 2)
    };
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let run = |n| {
        pool(n).install(|| {
            bake_with_lights(Some(&scene), &lights, &grid, &opts, &|_, _, _| {}).unwrap()
        })
    };
    let (one, two) = (run(1), run(2));
    assert!(one.emitted.iter().any(|&e| e > 0.0));
    assert_eq!(one, two);
    let lights = one.lights.as_ref().unwrap();
    assert_eq!((lights.point, lights.spot, lights.directional), (1, 1, 1));
}
