//! Writes the volume bench's scanned scene (a room and two dense scans,
//! about 145k triangles, `benches/support/scan_scene.rs`) as an OBJ file
//! with its MTL (albedo `Kd`, emission `Ke`), so that `shlight volume` can
//! be timed on it end to end, reading the file included
//! (`benches/scan_room.sh`).
//!
//! `cargo run --release -p shlight-volume --example scan_scene -- DIR`
//! writes `DIR/scan_scene.obj` and `DIR/scan_scene.mtl`.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::PathBuf;

#[path = "../benches/support/scan_scene.rs"]
mod scan_scene;

fn main() -> std::io::Result<()> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    let mesh = scan_scene::scan_scene();
    let colors = mesh.colors.as_ref().expect("the scan scene has colours");
    let emission = mesh.emission.as_ref().expect("the scan scene emits");
    // One material per distinct (albedo, emission) of a triangle's first
    // corner, in order of first use.
    let key = |v: u32| {
        let (c, e) = (colors[v as usize], emission[v as usize]);
        [c.x, c.y, c.z, e.x, e.y, e.z].map(f32::to_bits)
    };
    let mut materials: HashMap<[u32; 6], usize> = HashMap::new();
    let mut mtl = String::new();
    let mut groups: Vec<Vec<[u32; 3]>> = Vec::new();
    for t in &mesh.triangles {
        let k = key(t[0]);
        let m = *materials.entry(k).or_insert_with(|| {
            let [r, g, b, er, eg, eb] = k.map(f32::from_bits);
            let _ = writeln!(
                mtl,
                "newmtl m{}\nKd {r} {g} {b}\nKe {er} {eg} {eb}\n",
                groups.len()
            );
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[m].push(*t);
    }
    let mut obj = String::from("mtllib scan_scene.mtl\n");
    for p in &mesh.positions {
        let _ = writeln!(obj, "v {} {} {}", p.x, p.y, p.z);
    }
    for n in &mesh.normals {
        let _ = writeln!(obj, "vn {} {} {}", n.x, n.y, n.z);
    }
    for (m, tris) in groups.iter().enumerate() {
        let _ = writeln!(obj, "usemtl m{m}");
        for t in tris {
            let [a, b, c] = t.map(|i| i + 1);
            let _ = writeln!(obj, "f {a}//{a} {b}//{b} {c}//{c}");
        }
    }
    std::fs::create_dir_all(&dir)?;
    std::fs::write(dir.join("scan_scene.mtl"), mtl)?;
    std::fs::write(dir.join("scan_scene.obj"), obj)?;
    eprintln!(
        "{}: {} triangles, {} vertices, {} materials",
        dir.join("scan_scene.obj").display(),
        mesh.triangle_count(),
        mesh.vertex_count(),
        groups.len()
    );
    Ok(())
}
