//! Bytes of the acceleration structures for a 10,000-triangle torus
//! placed N times (default 1,000) on a grid, flat (`Occluder` over the
//! flattened scene) and two-level (`InstancedOccluder`), with the time to
//! build each and the flattened mesh's own bytes.
//!
//! `cargo run --release -p shlight-rays --example instance_memory -- 1000`

use std::time::Instant;

use glam::{Mat4, Quat, Vec3};
use shlight_mesh::{Instance, Mesh, Primitive, Scene, generate};
use shlight_rays::{InstancedOccluder, Occluder};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1000);
    let torus = generate::torus(1.0, 0.3, 100, 50);
    let side = (n as f64).sqrt().ceil() as usize;
    let scene = Scene {
        source: "grid.glb".into(),
        primitives: vec![Primitive::new(torus, None, "torus")],
        instances: (0..n)
            .map(|i| Instance {
                primitive: 0,
                transform: Mat4::from_rotation_translation(
                    Quat::from_rotation_y(i as f32),
                    Vec3::new((i % side) as f32, 0.0, (i / side) as f32) * 3.0,
                ),
            })
            .collect(),
        ..Scene::default()
    };
    let unique = scene.primitives[0].mesh.triangle_count();
    let start = Instant::now();
    let two_level = InstancedOccluder::new(&scene).expect("a valid scene");
    let two_level_time = start.elapsed();
    println!(
        "{n} instances of {unique} triangles ({} flattened)",
        two_level.triangle_count()
    );
    println!(
        "two-level: {} bytes, built in {:.3} s",
        two_level.heap_bytes(),
        two_level_time.as_secs_f64()
    );
    drop(two_level);
    let start = Instant::now();
    let flat = scene.flatten(Vec3::ONE).expect("a valid scene").mesh;
    let flatten_time = start.elapsed();
    let start = Instant::now();
    let occluder = Occluder::new(&flat);
    println!(
        "flat: {} bytes, built in {:.3} s; the flattened mesh {} bytes more, flattened in {:.3} s",
        occluder.heap_bytes(),
        start.elapsed().as_secs_f64(),
        mesh_bytes(&flat),
        flatten_time.as_secs_f64()
    );
}

/// Positions, normals, colours, emission and triangles.
fn mesh_bytes(m: &Mesh) -> usize {
    let per_vertex = 12 * (2 + usize::from(m.colors.is_some()) + usize::from(m.emission.is_some()));
    m.vertex_count() * per_vertex + m.triangle_count() * 12
}
