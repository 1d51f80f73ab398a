//! Where a vertex's rays start: off its surface, never across the mesh.
//!
//! A vertex's rays start at `p + eps (n + c)`, `eps` = [`OFFSET`] times the
//! mesh's bounding box diagonal, so a vertex does not shadow itself; `c` is
//! the unit tangent from the vertex towards the mean centroid of its
//! triangles, so a vertex on a concave edge (where a wall meets a ceiling)
//! starts off the other surface's plane instead of on it, where its rays
//! would slip out between the two. The segment from `p` to the origin is
//! tested against the surface cast against, and shortened along the normal
//! when it would cross it.

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use shlight_mesh::Mesh;

use crate::bvh::Ray;

/// Ray origins are offset along the normal by this times the bounding box
/// diagonal.
pub const OFFSET: f32 = 1e-4;

/// Normal-only offsets tried, each a quarter of the last, when the
/// concave-edge offset of a vertex's rays would cross the mesh.
pub const SHORTER_OFFSETS: usize = 8;

/// Hits on a segment from `p` nearer than this fraction of its length are
/// the triangles through `p` itself (its own), which it leaves, not crosses.
const OWN_TRIANGLES: f32 = 1e-3;

/// [`Occluder::ray_origins`](crate::Occluder::ray_origins): the segment
/// from each vertex of `mesh` to its rays' origin tested with `occluded`
/// against the surface cast against (the mesh's own, or the one it was
/// subdivided from), every triangle opaque.
pub(crate) fn ray_origins(mesh: &Mesh, occluded: impl Fn(&Ray) -> bool + Sync) -> Vec<Vec3> {
    let bounds = mesh.bounds();
    let eps = OFFSET * (bounds.1 - bounds.0).length();
    let mut centroids = vec![(DVec3::ZERO, 0u32); mesh.vertex_count()];
    for t in &mesh.triangles {
        let c = t
            .iter()
            .map(|&i| mesh.positions[i as usize].as_dvec3())
            .sum::<DVec3>()
            / 3.0;
        for &i in t {
            let e = &mut centroids[i as usize];
            e.0 += c;
            e.1 += 1;
        }
    }
    // Whether the segment from `p` to `p + offset` crosses a triangle
    // other than those through `p`.
    let crosses = |p: Vec3, offset: Vec3| {
        let start = p + OWN_TRIANGLES * offset;
        occluded(&Ray::new(start, offset, 1.0 - OWN_TRIANGLES))
    };
    mesh.positions
        .par_iter()
        .zip(&mesh.normals)
        .zip(&centroids)
        .map(|((p, n), &(sum, count))| {
            let inward = if count == 0 {
                Vec3::ZERO
            } else {
                let c = sum / f64::from(count) - p.as_dvec3();
                let n = n.as_dvec3();
                (c - c.dot(n) * n)
                    .try_normalize()
                    .map_or(Vec3::ZERO, |c| c.as_vec3())
            };
            let offset = eps * (*n + inward);
            if !crosses(*p, offset) {
                return *p + offset;
            }
            let mut offset = eps * *n;
            for _ in 1..SHORTER_OFFSETS {
                if !crosses(*p, offset) {
                    break;
                }
                offset *= 0.25;
            }
            *p + offset
        })
        .collect()
}
