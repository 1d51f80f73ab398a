//! Probe volumes against closed forms: an empty scene, a black sphere's
//! occluded cap, a lit floor, a closed box (no leaks; the furnace limit
//! with emitters), relighting under a rotated sky, interpolation with
//! invalid probes, and determinism.

use std::f64::consts::PI;

use glam::{DQuat, DVec3, Vec3};
use shlight_baked::ProbeGrid;
use shlight_core::sh::{ShCoeffs, ShRotation, closed_form, irradiance, sh_count};
use shlight_mesh::{Mesh, generate};
use shlight_volume::{Lookup, PreparedLookup, VolumeOptions, bake};

fn options(lmax: usize, samples: usize, bounces: u32, albedo: f32) -> VolumeOptions {
    VolumeOptions {
        lmax,
        samples,
        bounces,
        surface_samples: 1024,
        albedo: [albedo; 3],
        seed: 3,
        ..VolumeOptions::default()
    }
}

/// One probe at `p`.
fn at(p: Vec3) -> ProbeGrid {
    ProbeGrid::new([1, 1, 1], p - 0.01, p + 0.01).unwrap()
}

/// Probe `i`'s radiance coefficients from a relit buffer.
fn probe(radiance: &[f32], lmax: usize, i: usize) -> ShCoeffs<DVec3> {
    let nc = sh_count(lmax);
    ShCoeffs::from_vec(
        radiance[i * 3 * nc..][..3 * nc]
            .chunks_exact(3)
            .map(|c| Vec3::from_slice(c).as_dvec3())
            .collect(),
    )
    .unwrap()
}

fn max_difference(a: &ShCoeffs<DVec3>, b: &ShCoeffs<DVec3>) -> f64 {
    a.as_slice()
        .iter()
        .zip(b.as_slice())
        .map(|(x, y)| (*x - *y).abs().max_element())
        .fold(0.0, f64::max)
}

/// A sky that varies in every band up to 2: a gradient plus a lobe.
fn sky(lmax: usize) -> ShCoeffs<DVec3> {
    let g = closed_form::linear_gradient(lmax, DVec3::new(0.3, 1.0, -0.2).normalize(), 1.0, 0.6);
    let lobe = closed_form::cosine_lobe(lmax, DVec3::new(1.0, 0.5, 0.0).normalize(), 0.7);
    ShCoeffs::from_vec(
        g.as_slice()
            .iter()
            .zip(lobe.as_slice())
            .map(|(a, b)| DVec3::new(a + b, 0.8 * a + 0.3 * b, 0.5 * a + b))
            .collect(),
    )
    .unwrap()
}

/// The mesh turned inside out: normals and winding reversed, so a closed
/// shape faces its inside.
fn inside_out(mesh: &Mesh) -> Mesh {
    Mesh::new(
        "inside out",
        mesh.positions.clone(),
        mesh.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
        Some(mesh.normals.iter().map(|n| -*n).collect()),
        None,
    )
    .unwrap()
}

#[test]
fn an_empty_scene_gives_the_environment_at_every_probe() {
    let grid = ProbeGrid::new([3, 2, 2], Vec3::splat(-1.0), Vec3::ONE).unwrap();
    let env = sky(4);
    let volume = bake(None, &grid, &options(4, 256, 2, 0.8), &|_, _, _| {}).unwrap();
    let radiance = volume.relight(&env);
    for i in 0..grid.probe_count() {
        assert!(max_difference(&probe(&radiance, 4, i), &env) < 1e-6);
    }
    assert_eq!(volume.invalid_count(), 0);
}

#[test]
fn a_black_sphere_removes_its_cap_from_a_constant_sky() {
    // A probe at distance D from the centre of a black sphere of radius R
    // sees the sky L everywhere but in the cap of half-angle asin(R/D)
    // towards the sphere: L_probe = L (constant - cap).
    let (r, d) = (1.0f32, 2.5f32);
    let sphere = generate::uv_sphere(r, 128, 64);
    let probe_at = Vec3::new(0.0, 0.0, d);
    let lmax = 4;
    let volume = bake(
        Some(&sphere),
        &at(probe_at),
        &options(lmax, 16384, 0, 0.0),
        &|_, _, _| {},
    )
    .unwrap();
    let light = DVec3::new(1.0, 0.5, 2.0);
    let got = probe(
        &volume.relight(&closed_form::constant(lmax, light)),
        lmax,
        0,
    );
    let half = f64::from(r / d).asin();
    let cap = closed_form::cap(lmax, DVec3::NEG_Z, half, light);
    let constant = closed_form::constant(lmax, light);
    let want = ShCoeffs::from_vec(
        constant
            .as_slice()
            .iter()
            .zip(cap.as_slice())
            .map(|(a, b)| *a - *b)
            .collect(),
    )
    .unwrap();
    // Tolerance: the stratified estimate of a 0.84 sr cap with 16k rays
    // (about 1e-3 of L_00) and the tessellated sphere, inscribed in the
    // true one (its cap 0.03% smaller).
    let err = max_difference(&got, &want);
    assert!(
        err < 4e-3 * want.as_slice()[0].max_element(),
        "error {err}: {got:?} vs {want:?}"
    );
    // And the cap is really there: without it the error would be the cap.
    assert!(max_difference(&constant, &want) > 0.1);
}

/// The SH of a function by dense quadrature.
fn project(lmax: usize, f: impl Fn(DVec3) -> DVec3) -> ShCoeffs<DVec3> {
    ShCoeffs::project_fn(lmax, 400, f)
}

#[test]
fn a_floor_reflects_the_sky_it_sees_and_relights_under_a_rotated_sky() {
    // A large floor (y = 0, normal +y) of albedo rho, a probe at height 1
    // over its centre. Under sky L the floor leaves rho/pi E(+y), E the
    // irradiance of the sky's upper half (all of the floor sees it), so the
    // probe sees L above the horizon and that constant below (the floor's
    // finite size, 400 units wide, misses directions within 0.3 degrees of
    // the horizon).
    let rho = 0.6;
    let floor = generate::plane(400.0, 4);
    assert!(floor.normals.iter().all(|n| *n == Vec3::Y));
    let lmax = 2;
    let volume = bake(
        Some(&floor),
        &at(Vec3::new(0.0, 1.0, 0.0)),
        &VolumeOptions {
            max_edge: Some(40.0),
            ..options(lmax, 16384, 1, rho as f32)
        },
        &|_, _, _| {},
    )
    .unwrap();
    for rotation in [
        DQuat::IDENTITY,
        DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 1.1),
    ] {
        let env = ShRotation::from_quat(lmax, rotation).apply(&sky(lmax));
        let got = probe(&volume.relight(&env), lmax, 0);
        // E(+y) of the upper hemisphere is the clamped-cosine convolution,
        // exact for a sky of lmax 2.
        let e_up = irradiance(&env).eval(DVec3::Y);
        let below = rho / PI * e_up;
        let want = project(lmax, |s| if s.y > 0.0 { env.eval(s) } else { below });
        let err = max_difference(&got, &want);
        assert!(
            err < 0.01 * want.as_slice()[0].max_element(),
            "{rotation}: error {err}\n{got:?}\n{want:?}"
        );
    }
}

#[test]
fn a_closed_box_lets_no_sky_in_and_its_emitting_walls_reach_the_furnace_limit() {
    let room = inside_out(&generate::cuboid(Vec3::new(2.0, 1.5, 3.0)));
    let grid = ProbeGrid::new(
        [3, 2, 3],
        Vec3::new(-1.5, -1.0, -2.5),
        Vec3::new(1.5, 1.0, 2.5),
    )
    .unwrap();
    let lmax = 2;
    let bright = sky(lmax);
    let volume = bake(
        Some(&room),
        &grid,
        &options(lmax, 512, 2, 0.8),
        &|_, _, _| {},
    )
    .unwrap();
    assert_eq!(volume.invalid_count(), 0, "the walls face the probes");
    for x in volume.relight(&bright) {
        assert!(x.abs() < 1e-6, "sky light leaked in: {x}");
    }
    // Every wall emits Le with albedo rho: after B bounces each point
    // leaves Le (1 + rho + ... + rho^B), and every probe sees that from
    // every direction, L_00 = sqrt(4 pi) times it, the other bands 0 (to
    // the stratified estimate's error for Y_lm of 2048 rays, about 1%).
    let rho = 0.5f32;
    let le = Vec3::new(1.0, 0.5, 0.25);
    let lamp = room
        .clone()
        .with_emission("room", vec![le; room.vertex_count()])
        .unwrap();
    let mut last = 0.0;
    for bounces in [0u32, 1, 2, 6] {
        let v = bake(
            Some(&lamp),
            &grid,
            &options(lmax, 2048, bounces, rho),
            &|_, _, _| {},
        )
        .unwrap();
        let sum: f64 = (0..=bounces).map(|b| f64::from(rho).powi(b as i32)).sum();
        let want = (4.0 * PI).sqrt() * sum;
        let radiance = v.relight(&ShCoeffs::zeros(lmax));
        for i in 0..grid.probe_count() {
            let p = probe(&radiance, lmax, i);
            let l00 = p.as_slice()[0];
            assert!(
                (l00 - want * le.as_dvec3()).abs().max_element() < 1e-4 * want,
                "{bounces}: {l00} vs {want}"
            );
            assert!(
                p.as_slice()[1..]
                    .iter()
                    .all(|c| c.abs().max_element() < 0.02 * want),
                "{p:?}"
            );
        }
        assert!(want > last);
        last = want;
    }
}

/// A solid block `2 half_x` thick (4 high and deep) in the middle of a
/// 3x1x1 grid of unit cells: the middle probe's centre is inside it.
fn block_and_grid(half_x: f32) -> (Mesh, ProbeGrid) {
    let block = generate::cuboid(Vec3::new(half_x, 2.0, 2.0));
    let grid = ProbeGrid::new(
        [3, 1, 1],
        Vec3::new(-1.5, -0.5, -0.5),
        Vec3::new(1.5, 0.5, 0.5),
    )
    .unwrap();
    (block, grid)
}

#[test]
fn probes_inside_geometry_are_invalid_and_take_no_weight() {
    // Left where they are (no relocation), the middle probe sees only
    // back faces.
    let (block, grid) = block_and_grid(0.3);
    let lmax = 1;
    let volume = bake(
        Some(&block),
        &grid,
        &VolumeOptions {
            relocate: false,
            ..options(lmax, 256, 1, 0.5)
        },
        &|_, _, _| {},
    )
    .unwrap();
    assert!(volume.offsets.is_none());
    assert_eq!(volume.valid, vec![true, false, true]);
    assert!(volume.backfaces[1] == 1.0 && volume.backfaces[0] < 0.5);
    let radiance = volume.relight(&closed_form::constant(lmax, DVec3::ONE));
    // Halfway between the left and the middle probe: only the left counts.
    let p = grid.centre([0, 0, 0]).lerp(grid.centre([1, 0, 0]), 0.5);
    let got = PreparedLookup::new(&volume.view(&radiance), Lookup::Trilinear, lmax)
        .radiance_at(p, Vec3::Y)
        .unwrap();
    assert!(max_difference(&got, &probe(&radiance, lmax, 0)) < 1e-6);
    // A grid of only invalid probes has nothing to give: a probe in a cell
    // too small to leave the block stays inside and invalid, relocation or
    // not.
    let inside = bake(
        Some(&block),
        &at(Vec3::ZERO),
        &options(lmax, 64, 0, 0.5),
        &|_, _, _| {},
    )
    .unwrap();
    let inside_radiance = inside.relight(&closed_form::constant(lmax, DVec3::ONE));
    assert!(
        PreparedLookup::new(&inside.view(&inside_radiance), Lookup::Trilinear, lmax)
            .radiance_at(Vec3::ZERO, Vec3::Y)
            .is_none()
    );
    assert!(!inside.valid[0] && inside.relocated_count() == 0);
}

#[test]
fn a_probe_inside_a_wall_is_moved_out_and_is_then_valid() {
    // A wall 0.1 thick: the middle probe can leave it only along x (it is
    // 4 wide along y and z). Its nearest free place on the candidate
    // lattice (steps of 0.15 of a cell, up to 0.45) is 0.3 to the side,
    // 0.25 from the wall's face, beyond the clearance of 0.2; 0.15 to the
    // side would be only 0.1 from it. Lattice ties go to the lower offset:
    // -x.
    let (block, grid) = block_and_grid(0.05);
    let volume = bake(Some(&block), &grid, &options(1, 256, 1, 0.5), &|_, _, _| {}).unwrap();
    let offsets = volume.offsets.as_ref().unwrap();
    assert_eq!(&offsets[..3], &[0.0; 3], "probe 0 was free");
    assert_eq!(&offsets[6..], &[0.0; 3], "probe 2 was free");
    assert!(
        (offsets[3] + 0.3).abs() < 1e-6 && offsets[4] == 0.0 && offsets[5] == 0.0,
        "{offsets:?}"
    );
    assert_eq!(volume.valid, vec![true, true, true]);
    assert_eq!(volume.backfaces[1], 0.0);
    assert_eq!(volume.relocated_count(), 1);
    // Moved to x = -0.3, it sees the wall fill the +x half of its sky less
    // the part beyond the wall's edges: under a white sky its L_00 lies
    // between half (a wall of infinite extent) and all of it, the wall
    // being lit grey on its face.
    let radiance = volume.relight(&closed_form::constant(1, DVec3::ONE));
    let sky = closed_form::constant(1, DVec3::ONE).as_slice()[0].x;
    let l00 = f64::from(radiance[12]);
    assert!(l00 > 0.5 * sky && l00 < sky, "{l00} of {sky}");
}

#[test]
fn the_bake_is_the_same_at_any_thread_count() {
    let scene = generate::plane_under_sphere(0.5, 24, 12, 3.0, 6);
    let grid = ProbeGrid::around([3, 2, 3], scene.bounds()).unwrap();
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| bake(Some(&scene), &grid, &options(2, 256, 2, 0.7), &|_, _, _| {}).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one, two);
    assert_ne!(
        one,
        bake(
            Some(&scene),
            &grid,
            &VolumeOptions {
                seed: 4,
                ..options(2, 256, 2, 0.7)
            },
            &|_, _, _| {}
        )
        .unwrap()
    );
}
