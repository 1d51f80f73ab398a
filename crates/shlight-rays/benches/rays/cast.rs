//! The rays baking casts, and casting them as packets, shared by
//! `benches/rays.rs` and `examples/prt_rays.rs`.

use glam::Vec3;
use rayon::prelude::*;
use shlight_mesh::Mesh;
use shlight_rays::{Direction, LANES, Occluder, Packet, vertex_order};

/// The rays a PRT bake of `mesh` casts along each of `dirs` (`occluder`
/// being `mesh` made ready): the direction, and the origins
/// ([`Occluder::ray_origins`]) of the vertices facing it (`n.d > 0`) in
/// Morton order.
pub fn bake_rays(mesh: &Mesh, occluder: &Occluder, dirs: &[Vec3]) -> Vec<(Vec3, Vec<Vec3>)> {
    let start = occluder.ray_origins(mesh);
    let order = vertex_order(&mesh.positions, mesh.bounds());
    dirs.iter()
        .map(|d| {
            let origins = order
                .iter()
                .filter(|&&v| mesh.normals[v as usize].dot(*d) > 0.0)
                .map(|&v| start[v as usize])
                .collect();
            (*d, origins)
        })
        .collect()
}

/// Casts `per_dir`'s rays against `occluder`, eight parallel rays per
/// packet, directions in parallel; returns the hits.
pub fn cast_packets(occluder: &Occluder, per_dir: &[(Vec3, Vec<Vec3>)], closest: bool) -> u32 {
    per_dir
        .par_iter()
        .map(|(d, origins)| {
            let dir = Direction::new(*d);
            let local: Vec<[f32; 4]> = occluder.ray_space(&dir).collect();
            origins
                .chunks(LANES)
                .map(|o| {
                    let packet = Packet::new(&dir, o);
                    if closest {
                        occluder
                            .packet_closest(&dir, &local, &packet)
                            .mask
                            .count_ones()
                    } else {
                        occluder.packet_occluded(&dir, &local, &packet).count_ones()
                    }
                })
                .sum::<u32>()
        })
        .sum()
}
