//! Ray casting by brute force in `f64`: Möller-Trumbore against every
//! triangle, O(triangles) per ray. The independent reference that the
//! hierarchy, the packets and the bakes are tested against; too slow for
//! anything else.

use glam::DVec3;
use shlight_mesh::Mesh;

/// The nearest triangle of `mesh` hit by the ray `o + t d` with
/// `t > t_min`: `(t, triangle, u, v)`, with `u, v` the barycentric weights
/// of the triangle's corners 1 and 2. Both sides of a triangle are hit;
/// triangles the ray runs parallel to are missed.
#[must_use]
pub fn brute_force_closest_hit(
    mesh: &Mesh,
    o: DVec3,
    d: DVec3,
    t_min: f64,
) -> Option<(f64, usize, f64, f64)> {
    let mut best: Option<(f64, usize, f64, f64)> = None;
    for (k, t) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-300 {
            continue;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let t = e2.dot(q) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > t_min && best.is_none_or(|b| t < b.0) {
            best = Some((t, k, u, v));
        }
    }
    best
}
