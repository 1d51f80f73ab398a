//! A mesh's vertices along a Morton (Z-order) curve: neighbours in the
//! list are neighbours in space, so rays from consecutive vertices make
//! coherent packets, and the vertices a packet's triangles read sit
//! together in memory.

use glam::Vec3;

/// Vertex indices sorted along a Morton (Z-order) curve through the
/// bounding box `(lo, hi)`, 10 bits per axis ([`shlight_baked::morton_code`]):
/// `order[s]` is the vertex of rank `s`. Neighbours in the list are
/// neighbours in space, so consecutive vertices make coherent ray packets.
#[must_use]
pub fn vertex_order(positions: &[Vec3], (lo, hi): (Vec3, Vec3)) -> Vec<u32> {
    let scale = Vec3::splat(1023.0) / (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
    shlight_baked::morton_order(positions.iter().map(|p| {
        let q = ((*p - lo) * scale).clamp(Vec3::ZERO, Vec3::splat(1023.0));
        shlight_baked::morton_code(q.x as u32, q.y as u32, q.z as u32)
    }))
}

/// `triangles` with each corner replaced by its rank in `order` (a
/// permutation of the vertices, `order[s]` the vertex of rank `s`, as
/// [`vertex_order`] makes it): the same triangles over the vertices taken
/// in `order`.
///
/// # Panics
/// If a corner is not a vertex of `order`.
#[must_use]
pub fn ranked_triangles(triangles: &[[u32; 3]], order: &[u32]) -> Vec<[u32; 3]> {
    let rank = ranks(order);
    triangles
        .iter()
        .map(|t| t.map(|i| rank[i as usize]))
        .collect()
}

/// The inverse of the permutation `order`: `ranks(order)[order[s]] = s`.
fn ranks(order: &[u32]) -> Vec<u32> {
    let mut rank = vec![0u32; order.len()];
    for (s, &v) in order.iter().enumerate() {
        rank[v as usize] = s as u32;
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_corners_of_a_cube_follow_the_z_curve_and_triangles_keep_their_corners() {
        // The eight corners of the unit cube, listed backwards: the Morton
        // order interleaves x (lowest bit), y and z.
        let positions: Vec<Vec3> = (0..8u32)
            .rev()
            .map(|k| Vec3::new((k & 1) as f32, (k >> 1 & 1) as f32, (k >> 2) as f32))
            .collect();
        let order = vertex_order(&positions, (Vec3::ZERO, Vec3::ONE));
        assert_eq!(order, [7, 6, 5, 4, 3, 2, 1, 0]);
        let triangles = [[0, 3, 5], [7, 1, 2], [6, 4, 0]];
        let ranked = ranked_triangles(&triangles, &order);
        for (t, r) in triangles.iter().zip(&ranked) {
            for k in 0..3 {
                assert_eq!(order[r[k] as usize], t[k]);
            }
        }
    }
}
