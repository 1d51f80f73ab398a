//! Generated meshes: shapes with known geometry for tests and demos.

use core::f32::consts::{PI, TAU};

use glam::Vec3;

use crate::Mesh;

/// A UV sphere of `radius` about the origin with `segments` slices around
/// +Y and `rings` stacks from pole to pole (at least 3 and 2).
///
/// Vertex normals are the exact sphere normals `p / radius`. The seam column
/// is duplicated (so texture-like parameters stay continuous) and each pole
/// is one vertex; triangles face outwards.
///
/// # Panics
/// If `segments < 3`, `rings < 2` or `radius` is not positive and finite.
#[must_use]
pub fn uv_sphere(radius: f32, segments: u32, rings: u32) -> Mesh {
    assert!(
        segments >= 3 && rings >= 2,
        "uv_sphere needs segments >= 3 and rings >= 2"
    );
    assert!(
        radius.is_finite() && radius > 0.0,
        "uv_sphere needs a positive radius"
    );
    let mut normals = vec![Vec3::Y];
    for r in 1..rings {
        let theta = PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = TAU * s as f32 / segments as f32;
            normals.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ));
        }
    }
    normals.push(Vec3::NEG_Y);
    let south = (normals.len() - 1) as u32;
    let row = |r: u32| 1 + (r - 1) * (segments + 1);
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, row(1) + s, row(1) + s + 1]);
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            let (a, b) = (row(r) + s, row(r + 1) + s);
            triangles.push([a, b, b + 1]);
            triangles.push([a, b + 1, a + 1]);
        }
    }
    for s in 0..segments {
        triangles.push([south, row(rings - 1) + s + 1, row(rings - 1) + s]);
    }
    let positions = normals.iter().map(|n| *n * radius).collect();
    Mesh::new(
        "generated sphere",
        positions,
        triangles,
        Some(normals),
        None,
    )
    .expect("a generated sphere is a valid mesh")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_faces_outwards_and_its_area_converges() {
        let m = uv_sphere(2.0, 64, 32);
        assert_eq!(m.report.degenerate_triangles, 0);
        for tri in &m.triangles {
            let [a, b, c] = tri.map(|i| m.positions[i as usize]);
            let centroid = (a + b + c) / 3.0;
            assert!(
                (b - a).cross(c - a).dot(centroid) > 0.0,
                "triangle {tri:?} faces inwards"
            );
        }
        // The inscribed polyhedron's deficit falls as h^2: a quarter per doubling.
        let exact = 4.0 * core::f64::consts::PI * 4.0;
        let deficit = |s, r| (exact - uv_sphere(2.0, s, r).surface_area()) / exact;
        let (coarse, fine) = (deficit(64, 32), deficit(128, 64));
        assert!(coarse > 0.0 && coarse < 3e-3, "{coarse}");
        assert!((fine / coarse - 0.25).abs() < 0.01, "{coarse} -> {fine}");
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!((*p / 2.0 - *n).length() < 1e-6);
        }
    }
}
