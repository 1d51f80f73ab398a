//! The memory and time of a volume bake through N instances (default
//! 1,000) of a 10,000-triangle torus on a floor, its rays cast through the
//! unique torus and its instances (two levels), or, with `copies`, through
//! the same scene with every instance a primitive of its own (one
//! hierarchy of every triangle, as a file that copies its meshes bakes).
//! Prints the occluder's bytes, the bake's time and the process's peak
//! resident memory (`VmHWM`); run each way in its own process.
//!
//! `cargo run --release -p shlight-volume --example instance_bake -- 1000 [copies]`

use std::sync::Arc;
use std::time::Instant;

use glam::{Mat4, Quat, Vec3, Vec4};
use shlight_baked::ProbeGrid;
use shlight_mesh::{Instance, Material, Primitive, Scene, generate};
use shlight_rays::Occluder;
use shlight_volume::{VolumeOptions, bake_surfaces};

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(1000);
    let copies = args.next().is_some_and(|a| a == "copies");
    let torus = generate::torus(0.4, 0.12, 100, 50);
    let side = (n as f64).sqrt().ceil() as usize;
    let extent = side as f32 * 1.2;
    let floor = generate::plane(extent + 2.0, 8);
    let mut primitives = vec![Primitive::new(floor, Some(0), "floor")];
    let mut instances = vec![Instance {
        primitive: 0,
        transform: Mat4::from_translation(Vec3::new(extent / 2.0, 0.0, extent / 2.0)),
    }];
    for i in 0..n {
        let primitive = if copies || i == 0 {
            primitives.push(Primitive::new(torus.clone(), Some(1), format!("torus {i}")));
            primitives.len() - 1
        } else {
            1
        };
        instances.push(Instance {
            primitive,
            transform: Mat4::from_rotation_translation(
                Quat::from_rotation_y(i as f32) * Quat::from_rotation_x(1.2),
                Vec3::new(
                    (i % side) as f32 * 1.2 + 0.6,
                    0.5,
                    (i / side) as f32 * 1.2 + 0.6,
                ),
            ),
        });
    }
    let colour = |r, g, b| Material {
        base_color: Vec4::new(r, g, b, 1.0),
        ..Material::default()
    };
    let scene = Scene {
        source: "tori.glb".into(),
        primitives,
        instances,
        materials: vec![colour(0.7, 0.7, 0.7), colour(0.8, 0.4, 0.2)],
        ..Scene::default()
    };
    let start = Instant::now();
    let surfaces = Arc::new(scene.flatten(Vec3::ONE).expect("a valid scene"));
    drop(scene);
    let occluder = Occluder::for_surfaces(&surfaces);
    println!(
        "{n} tori{}: {} triangles flattened; occluder {} ({} bytes), made in {:.2} s",
        if copies { " (copies)" } else { "" },
        surfaces.mesh.triangle_count(),
        if occluder.is_two_level() {
            "two levels"
        } else {
            "one hierarchy"
        },
        occluder.heap_bytes(),
        start.elapsed().as_secs_f64()
    );
    drop(occluder);
    let (lo, hi) = surfaces.mesh.bounds();
    let grid = ProbeGrid::new([8, 2, 8], lo, hi + Vec3::Y).expect("a grid");
    let options = VolumeOptions {
        lmax: 2,
        samples: 256,
        surface_samples: 16,
        bounces: 1,
        relocate: false,
        visibility_size: 0,
        ..VolumeOptions::default()
    };
    let start = Instant::now();
    let bake = bake_surfaces(&surfaces, &[], &grid, &options, &|_, _, _| {}).expect("a bake");
    println!(
        "baked {} probes, {} rays, in {:.2} s; peak resident memory {}",
        bake.probe_count(),
        bake.rays,
        start.elapsed().as_secs_f64(),
        peak_memory()
    );
}

/// The process's peak resident memory, as Linux reports it.
fn peak_memory() -> String {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM"))
                .map(|l| l.trim_start_matches("VmHWM:").trim().to_string())
        })
        .unwrap_or_else(|| "unknown (no /proc/self/status)".into())
}
