//! Ray casting by brute force in `f64`: Möller-Trumbore against every
//! triangle, O(triangles) per ray. The independent reference that the
//! hierarchy, the packets and the bakes are tested against; too slow for
//! anything else.

use glam::{DVec3, Vec3};
use shlight_mesh::Mesh;

use crate::cut_outs::{CutOuts, coverage_sample};

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
    nearest(mesh, o, d, t_min, |_, _, _| true)
}

/// [`brute_force_closest_hit`] of the ray from `o` along `d` through the
/// cut-outs `cut_outs`: each hit on a triangle that cuts out asks its
/// opacity at the hit's weights, here in `f64`, and is taken when it is 1,
/// passed over when 0, and decided by [`coverage_sample`] of `o`, `d` and
/// the triangle in between, as the crate documentation states.
#[must_use]
pub fn brute_force_closest_hit_through(
    mesh: &Mesh,
    cut_outs: &dyn CutOuts,
    o: Vec3,
    d: Vec3,
    t_min: f64,
) -> Option<(f64, usize, f64, f64)> {
    nearest(mesh, o.as_dvec3(), d.as_dvec3(), t_min, |k, u, v| {
        let k = k as u32;
        if !cut_outs.cuts_out(k) {
            return true;
        }
        let w = [1.0 - u - v, u, v].map(|x| x as f32);
        let opacity = cut_outs.opacity(k, w);
        opacity >= 1.0 || opacity > 0.0 && coverage_sample(o, d, k) < opacity
    })
}

/// The nearest hit with `t > t_min` that `take(triangle, u, v)` takes.
fn nearest(
    mesh: &Mesh,
    o: DVec3,
    d: DVec3,
    t_min: f64,
    take: impl Fn(usize, f64, f64) -> bool,
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
        if u >= 0.0
            && v >= 0.0
            && u + v <= 1.0
            && t > t_min
            && best.is_none_or(|b| t < b.0)
            && take(k, u, v)
        {
            best = Some((t, k, u, v));
        }
    }
    best
}
