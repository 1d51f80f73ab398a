//! The scanned scene of the volume bench (`scan_scene`), shared with the
//! example that writes it as a file for the command line's end-to-end
//! timing (`cargo run --release -p shlight-volume --example scan_scene`).

use glam::Vec3;
use shlight_mesh::generate;

/// A room with two scans in it, the size of a scanned scene: the Cornell
/// box subdivided to about 14,000 triangles, and on its floor two dense
/// closed surfaces standing for scans (a torus and a sphere of about
/// 65,000 triangles each, generated): about 145,000 triangles and 73,000
/// vertices in all, every one of them a surface point the bake samples.
pub fn scan_scene() -> shlight_mesh::Mesh {
    let room = generate::cornell_box().subdivided(0.0257);
    let (lo, hi) = room.bounds();
    let size = hi - lo;
    let floor = lo.y + 0.15 * size.y;
    let place = |m: shlight_mesh::Mesh, x: f32| {
        let at = Vec3::new(lo.x + x * size.x, floor, lo.z + 0.5 * size.z);
        (m.positions.iter().map(|&p| p + at).collect::<Vec<_>>(), m)
    };
    let r = 0.12 * size.x;
    let scans = [
        place(generate::torus(r, 0.4 * r, 256, 128), 0.3),
        place(generate::uv_sphere(r, 256, 128), 0.7),
    ];
    let mut positions = room.positions.clone();
    let mut normals = room.normals.clone();
    let mut triangles = room.triangles.clone();
    let mut colors = room
        .colors
        .clone()
        .unwrap_or_else(|| vec![Vec3::splat(0.7); positions.len()]);
    let mut emission = room
        .emission
        .clone()
        .unwrap_or_else(|| vec![Vec3::ZERO; positions.len()]);
    for (moved, mesh) in scans {
        let offset = positions.len() as u32;
        triangles.extend(mesh.triangles.iter().map(|t| t.map(|i| i + offset)));
        colors.extend(std::iter::repeat_n(Vec3::splat(0.7), moved.len()));
        emission.extend(std::iter::repeat_n(Vec3::ZERO, moved.len()));
        normals.extend(&mesh.normals);
        positions.extend(moved);
    }
    shlight_mesh::Mesh::new(
        "scan scene",
        positions,
        triangles,
        Some(normals),
        Some(colors),
    )
    .and_then(|m| m.with_emission("scan scene", emission))
    .unwrap()
}
