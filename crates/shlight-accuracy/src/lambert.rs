//! Irradiance from a uniform spherical polygon: Lambert's formula, with the
//! polygon clipped to the hemisphere above the surface.
//!
//! For a polygon of unit radiance whose vertices `r_i` (unit vectors from
//! the shaded point) lie in the upper hemisphere of the normal `n` and are
//! ordered right-handed about the polygon's centre (Arvo 1995, "Applications
//! of Irradiance Tensors", eq. 7; sh-reference §4d):
//!
//! ```text
//! E = 1/2 Σ_i acos(r_i · r_{i+1}) n · (r_i × r_{i+1}) / |r_i × r_{i+1}|
//! ```
//!
//! A polygon partly below the horizon is first clipped against the great
//! circle `n · r = 0` (Sutherland-Hodgman on the sphere: a crossing edge is
//! cut where its chord meets the plane, projected back onto the sphere),
//! since light from below the surface does not count.

use glam::DVec3;

/// Irradiance at unit normal `n` from the unit-radiance convex spherical
/// polygon `vertices` (right-handed, see the module docs).
#[must_use]
pub fn polygon_irradiance(vertices: &[DVec3], n: DVec3) -> f64 {
    let clipped = clip_to_hemisphere(vertices, n);
    if clipped.len() < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..clipped.len() {
        let (a, b) = (clipped[i], clipped[(i + 1) % clipped.len()]);
        let c = a.cross(b);
        let len = c.length();
        if len > 0.0 {
            sum += a.dot(b).clamp(-1.0, 1.0).acos() * n.dot(c) / len;
        }
    }
    0.5 * sum
}

/// The part of the polygon with `n · r ≥ 0`, vertices in the same order.
fn clip_to_hemisphere(vertices: &[DVec3], n: DVec3) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(vertices.len() + 2);
    for i in 0..vertices.len() {
        let (a, b) = (vertices[i], vertices[(i + 1) % vertices.len()]);
        let (da, db) = (n.dot(a), n.dot(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            // The chord a + t (b - a) meets the plane at t = da / (da - db).
            let t = da / (da - db);
            out.push((a + (b - a) * t).normalize());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> Vec<DVec3> {
        [(-0.5, -0.3), (0.8, -0.3), (0.8, 0.6), (-0.5, 0.6)]
            .map(|(x, y)| DVec3::new(x, y, 1.0).normalize())
            .to_vec()
    }

    #[test]
    fn rectangle_matches_the_reference_anchor() {
        let e = polygon_irradiance(&rect(), DVec3::Z);
        assert!((e - 0.79446).abs() < 5e-6, "{e}");
    }

    #[test]
    fn clipped_polygon_matches_numerical_integration() {
        // Normals that put the horizon through the rectangle.
        for n in [
            DVec3::new(1.0, 0.0, 0.2).normalize(),
            DVec3::new(-0.3, 1.0, 0.1).normalize(),
        ] {
            let got = polygon_irradiance(&rect(), n);
            // Integrate over the plane z = 1: dω = dx dy / (x²+y²+1)^(3/2).
            let k = 1500;
            let (mut sum, dx, dy) = (0.0, 1.3 / k as f64, 0.9 / k as f64);
            for i in 0..k {
                for j in 0..k {
                    let p = DVec3::new(
                        -0.5 + (i as f64 + 0.5) * dx,
                        -0.3 + (j as f64 + 0.5) * dy,
                        1.0,
                    );
                    let r2 = p.length_squared();
                    sum += n.dot(p / r2.sqrt()).max(0.0) * dx * dy / (r2 * r2.sqrt());
                }
            }
            assert!((got - sum).abs() < 1e-5, "{n}: {got} vs {sum}");
        }
        // Wholly below the horizon: nothing.
        assert_eq!(polygon_irradiance(&rect(), -DVec3::Z), 0.0);
    }
}
