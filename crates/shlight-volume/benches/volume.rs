//! Volume speed: the bake (a 16x8x16 grid, 2,048 probes, 4,096 rays
//! per probe, 2 bounces, in the Cornell box subdivided to about 100k
//! triangles) and relighting every probe after a rotation of the
//! environment. divan's "items/s" is rays per second for the bake (the
//! surfaces' and the probes'), probes per second for the relight. The bake
//! runs twice: the 32-triangle room subdivided by the bake itself
//! (`max_edge`, so rays can be cast against the 32 triangles), and the
//! subdivided room given as the scene (dense from the start). Each runs
//! with the default relocation and distance maps and without either, so
//! their cost shows as the ratio of the two.
//!
//! A third bake is of a scanned scene's size (`scan_scene`: a room and two
//! dense surfaces, about 145k triangles and 73k vertices), whose own
//! vertices the bake samples.
//!
//! The three.js export of a 32x16x32 volume (16,384 probes, lmax 2, a
//! tenth invalid, so dilation works) to its JSON document, half and f32:
//! items/s is probes per second.
//!
//! `cargo bench -p shlight-volume --bench volume`

use divan::Bencher;
use divan::counter::ItemsCount;
use glam::{DQuat, DVec3, Vec3};
use shlight_baked::ProbeGrid;
use shlight_core::sh::{ShRotation, closed_form};
use shlight_mesh::generate;
use shlight_volume::{VolumeOptions, bake, bake_surfaces};

#[path = "support/scan_scene.rs"]
mod scan_scene;
use scan_scene::scan_scene;

fn main() {
    divan::main();
}

fn options() -> VolumeOptions {
    VolumeOptions {
        lmax: 2,
        samples: 4096,
        bounces: 2,
        surface_samples: 256,
        max_edge: Some(0.0088),
        ..VolumeOptions::default()
    }
}

/// Bakes the 16x8x16 grid around the Cornell box in `scene`, counting
/// rays; `visibility`: with relocation and distance maps (the default),
/// else with neither.
fn bench_bake(bencher: Bencher, scene: &shlight_mesh::Mesh, visibility: bool) {
    let grid = ProbeGrid::around([16, 8, 16], generate::cornell_box().bounds()).unwrap();
    let options = if visibility {
        options()
    } else {
        VolumeOptions {
            relocate: false,
            visibility_size: 0,
            ..options()
        }
    };
    let rays = bake(Some(scene), &grid, &options, &|_, _, _| {})
        .unwrap()
        .rays;
    bencher
        .counter(ItemsCount::new(rays))
        .bench(|| bake(Some(scene), &grid, &options, &|_, _, _| {}).unwrap());
}

/// The room's 32 triangles, subdivided by the bake itself (`max_edge`) to
/// 119,808.
#[divan::bench(sample_count = 1, sample_size = 1, args = [true, false])]
fn cornell_100k_16x8x16_4096_rays(bencher: Bencher, visibility: bool) {
    let room = generate::cornell_box();
    let fine = room.subdivided(0.0088);
    eprintln!("{} triangles after subdivision", fine.triangle_count());
    bench_bake(bencher, &room, visibility);
}

/// The scanned scene ([`scan_scene`]) baked on the same grid: the
/// cost of a scene whose own vertices are many.
#[divan::bench(sample_count = 1, sample_size = 1)]
fn scan_scene_145k_16x8x16_4096_rays(bencher: Bencher) {
    let scene = scan_scene();
    eprintln!(
        "{} triangles, {} vertices",
        scene.triangle_count(),
        scene.vertex_count()
    );
    bench_bake(bencher, &scene, true);
}

/// The same bake with the scene dense to begin with: the 119,808
/// triangles given as the scene (no coarser surface to cast against), as a
/// scanned or modelled scene of that size would be.
#[divan::bench(sample_count = 1, sample_size = 1, args = [true, false])]
fn cornell_dense_input_100k_16x8x16_4096_rays(bencher: Bencher, visibility: bool) {
    bench_bake(
        bencher,
        &generate::cornell_box().subdivided(0.0088),
        visibility,
    );
}

/// The bundled Blender room (`meshes/room.glb`: a checker-textured floor,
/// alpha-masked leaves, three instanced chairs, a point lamp, a spot and a
/// sun) on the 16x8x16 grid, 4,096 rays per probe, 2 bounces, subdivided
/// to about 25k triangles: `true` as a glTF scene (texel albedo at every
/// hit, cut-outs, the lamps' shadow rays), `false` the same triangles
/// untextured and unlit (vertex colours, no lamps, no cut-outs). items/s
/// is rays per second, each bake's own rays (the lamps' shadow rays
/// counted).
#[divan::bench(sample_count = 1, sample_size = 1, args = [true, false])]
fn room_glb_16x8x16_4096_rays_textured_lit(bencher: Bencher, textured: bool) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/room.glb");
    let scene = shlight_mesh::load_scene(&path, &shlight_mesh::LoadOptions::default()).unwrap();
    let surfaces = std::sync::Arc::new(scene.flatten(Vec3::splat(0.8)).unwrap());
    let grid = ProbeGrid::around([16, 8, 16], surfaces.mesh.bounds()).unwrap();
    let options = VolumeOptions {
        max_edge: Some(0.06),
        ..options()
    };
    let run = || {
        if textured {
            bake_surfaces(&surfaces, &scene.lights, &grid, &options, &|_, _, _| {}).unwrap()
        } else {
            bake(Some(&surfaces.mesh), &grid, &options, &|_, _, _| {}).unwrap()
        }
    };
    let rays = run().rays;
    eprintln!("room.glb, textured and lit {textured}: {rays} rays");
    bencher.counter(ItemsCount::new(rays)).bench(run);
}

#[divan::bench]
fn relight_2048_probes_after_a_rotation(bencher: Bencher) {
    // Relighting is a matrix-vector product per probe and channel whatever
    // the matrices hold: an empty scene's bake gives the same work.
    let grid = ProbeGrid::new([16, 8, 16], Vec3::ZERO, Vec3::ONE).unwrap();
    let volume = bake(
        None,
        &grid,
        &VolumeOptions {
            samples: 16,
            ..options()
        },
        &|_, _, _| {},
    )
    .unwrap();
    let sky = closed_form::cosine_lobe(
        2,
        DVec3::new(0.3, 1.0, 0.2).normalize(),
        DVec3::new(1.0, 0.9, 0.8),
    );
    let mut out = vec![0.0f32; volume.emitted.len()];
    let mut angle = 0.0;
    bencher
        .counter(ItemsCount::new(volume.probe_count()))
        .bench_local(|| {
            angle += 0.01;
            let rotated = ShRotation::from_quat(2, DQuat::from_rotation_y(angle)).apply(&sky);
            volume.relight_into(&rotated, &mut out);
        });
}

/// A 32x16x32 lmax 2 volume's file, every tenth probe invalid.
fn volume_32x16x32() -> shlight_format::ShvolFile {
    let resolution = [32, 16, 32];
    let n: usize = resolution.iter().product();
    shlight_format::ShvolFile {
        lmax: 2,
        resolution,
        bounds: ([0.0; 3], [4.0, 2.0, 4.0]),
        frame: "y-up".into(),
        valid: (0..n).map(|k| k % 10 != 3).collect(),
        radiance: (0..n * 27)
            .map(|i| ((i * 7919) % 1000) as f32 / 500.0 - 0.5)
            .collect(),
        emitted: None,
        transfer: None,
        offsets: None,
        visibility: None,
        rays_per_probe: 1,
        bounces: 0,
        seed: 0,
        scene: "bench".into(),
        scene_hash: 0,
        environment: "bench".into(),
        generator: "bench".into(),
        lights: None,
    }
}

#[divan::bench(args = ["half", "f32"])]
fn threejs_export_32x16x32(bencher: Bencher, precision: &str) {
    use shlight_format::threejs_volume::{Precision, threejs_grid};
    let file = volume_32x16x32();
    let precision = if precision == "half" {
        Precision::Half
    } else {
        Precision::F32
    };
    bencher
        .counter(ItemsCount::new(file.probe_count()))
        .bench_local(|| threejs_grid(&file, precision).unwrap().text.len());
}
