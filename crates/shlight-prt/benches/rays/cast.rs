//! Casting the rays baking casts (`transfer::cast_rays`) as packets, shared
//! by `benches/rays.rs` and `examples/prt_rays.rs`.

use glam::Vec3;
use rayon::prelude::*;
use shlight_prt::packet::{Direction, LANES, Packet, PacketBvh};

/// Casts `per_dir`'s rays through `tree` (built over `positions`), eight
/// parallel rays per packet, directions in parallel; returns the hits.
pub fn cast_packets(
    tree: &PacketBvh,
    positions: &[Vec3],
    per_dir: &[(Vec3, Vec<Vec3>)],
    closest: bool,
) -> u32 {
    per_dir
        .par_iter()
        .map(|(d, origins)| {
            let dir = Direction::new(*d);
            let local: Vec<[f32; 4]> = positions.iter().map(|p| dir.to_ray_space(*p)).collect();
            origins
                .chunks(LANES)
                .map(|o| {
                    let packet = Packet::new(&dir, o);
                    if closest {
                        tree.closest(&dir, &local, &packet).mask.count_ones()
                    } else {
                        tree.occluded(&dir, &local, &packet).count_ones()
                    }
                })
                .sum::<u32>()
        })
        .sum()
}
