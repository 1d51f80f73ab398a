//! Writes the PRT rays of the benchmark torus (69,696 triangles; every 8th
//! direction of the 1024-direction grid, the vertices facing each in the
//! order baking casts them) for other ray casters, and times shlight's
//! packet traversal on the same rays, on one thread and on all.
//!
//! `cargo run --release -p shlight-rays --example prt_rays -- OUT.bin`
//! (`benches/prt_peers.sh` runs it and Embree on the file).
//!
//! File: little-endian `u32` vertex count, triangle count and ray count;
//! the vertices (3 `f32` each), the triangles (3 `u32`), the rays (origin
//! and unit direction, 6 `f32`).

use std::io::Write;

use std::time::Instant;

use glam::Vec3;
use shlight_core::map::montecarlo::stratified_directions;
use shlight_mesh::generate;
use shlight_rays::Occluder;

#[path = "../benches/rays/cast.rs"]
mod cast;

fn main() -> std::io::Result<()> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "prt_rays.bin".into());
    let mesh = generate::torus(1.0, 0.4, 264, 132);
    let dirs: Vec<Vec3> = stratified_directions(1024, 0)
        .iter()
        .map(|d| d.as_vec3())
        .step_by(8)
        .collect();
    let occluder = Occluder::new(&mesh);
    let per_dir = cast::bake_rays(&mesh, &occluder, &dirs);
    let count: usize = per_dir.iter().map(|(_, o)| o.len()).sum();

    let mut bytes = Vec::new();
    for n in [mesh.vertex_count(), mesh.triangle_count(), count] {
        bytes.extend((n as u32).to_le_bytes());
    }
    let floats = mesh.positions.iter().flat_map(|p| p.to_array());
    bytes.extend(floats.flat_map(f32::to_le_bytes));
    bytes.extend(
        mesh.triangles
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes()),
    );
    for (d, origins) in &per_dir {
        for o in origins {
            let ray = o.to_array().into_iter().chain(d.to_array());
            bytes.extend(ray.flat_map(f32::to_le_bytes));
        }
    }
    std::fs::File::create(&out)?.write_all(&bytes)?;
    println!("{count} rays written to {out}");

    let cast = |closest: bool| cast::cast_packets(&occluder, &per_dir, closest);
    let threads = rayon::current_num_threads();
    for n in [1, threads] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap();
        for (name, closest) in [("occluded", false), ("closest", true)] {
            let best = (0..3)
                .map(|_| {
                    let start = Instant::now();
                    let hits = pool.install(|| cast(closest));
                    (start.elapsed().as_secs_f64(), hits)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap();
            println!(
                "shlight packets {name}, {n} thread(s): {count} rays in {:.3} s -> {:.2} M rays/s ({} hit)",
                best.0,
                count as f64 / best.0 / 1e6,
                best.1
            );
        }
    }
    Ok(())
}
