//! Generated meshes: shapes with known geometry for tests and demos.
//!
//! Every generator documents its vertex order (it fixes the layout of a
//! `.shprt` file baked from the mesh), uses +Y as up, gives exact analytic
//! normals, and winds triangles counter-clockwise seen from the side the
//! normals face.

use core::f32::consts::{PI, TAU};

use glam::Vec3;

use crate::Mesh;

pub use crate::cornell_box::cornell_box;

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

/// A square of side `size` in the plane `y = 0`, centred on the origin,
/// facing +Y, cut into `divisions x divisions` squares of two triangles.
///
/// Vertex `(i, j)`, `i, j` in `0..=divisions`, is at
/// `(-size/2 + size i/divisions, 0, -size/2 + size j/divisions)` with index
/// `i (divisions + 1) + j`. With an even `divisions` one vertex sits at the
/// origin.
///
/// # Panics
/// If `divisions` is 0 or `size` is not positive and finite.
#[must_use]
pub fn plane(size: f32, divisions: u32) -> Mesh {
    assert!(divisions >= 1, "plane needs divisions >= 1");
    assert!(
        size.is_finite() && size > 0.0,
        "plane needs a positive size"
    );
    let n = divisions;
    let mut positions = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let at = |k: u32| size * (k as f32 / n as f32 - 0.5);
            positions.push(Vec3::new(at(i), 0.0, at(j)));
        }
    }
    let index = |i: u32, j: u32| i * (n + 1) + j;
    let mut triangles = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i, j + 1),
                index(i + 1, j + 1),
            );
            triangles.push([a, c, b]);
            triangles.push([b, c, d]);
        }
    }
    let normals = vec![Vec3::Y; positions.len()];
    Mesh::new("generated plane", positions, triangles, Some(normals), None)
        .expect("a generated plane is a valid mesh")
}

/// An axis-aligned box centred on the origin with the given half extents:
/// six faces of four vertices each (24 vertices, flat face normals), in the
/// order +X, -X, +Y, -Y, +Z, -Z; each face's corners go `c - u - v`,
/// `c + u - v`, `c + u + v`, `c - u + v` with `u x v` the outward normal.
///
/// # Panics
/// If a half extent is not positive and finite.
#[must_use]
pub fn cuboid(half_extents: Vec3) -> Mesh {
    assert!(
        half_extents.is_finite() && half_extents.min_element() > 0.0,
        "cuboid needs positive half extents"
    );
    let h = half_extents;
    let faces = [
        (Vec3::X, Vec3::Y, Vec3::Z),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::Z, Vec3::X),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::Y, Vec3::X),
    ];
    let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
    for (n, u, v) in faces {
        let (c, u, v) = (n * h, u * h, v * h);
        let base = positions.len() as u32;
        positions.extend([c - u - v, c + u - v, c + u + v, c - u + v]);
        normals.extend([n; 4]);
        triangles.push([base, base + 1, base + 2]);
        triangles.push([base, base + 2, base + 3]);
    }
    Mesh::new("generated box", positions, triangles, Some(normals), None)
        .expect("a generated box is a valid mesh")
}

/// A torus about the +Y axis: tube centre radius `major`, tube radius
/// `minor`, `segments` steps around +Y and `rings` steps around the tube
/// (no duplicated seam), `2 segments rings` triangles.
///
/// Vertex `(i, j)` has index `i rings + j` and, with `phi = 2 pi i/segments`,
/// `theta = 2 pi j/rings`, position
/// `((major + minor cos theta) cos phi, minor sin theta, -(major + minor cos theta) sin phi)`
/// and normal `(cos theta cos phi, sin theta, -cos theta sin phi)`.
///
/// # Panics
/// If `segments < 3`, `rings < 3` or not `0 < minor < major` (finite).
#[must_use]
pub fn torus(major: f32, minor: f32, segments: u32, rings: u32) -> Mesh {
    assert!(
        segments >= 3 && rings >= 3,
        "torus needs segments, rings >= 3"
    );
    assert!(
        minor > 0.0 && minor < major && major.is_finite(),
        "torus needs 0 < minor < major"
    );
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    for i in 0..segments {
        let (sp, cp) = (TAU * i as f32 / segments as f32).sin_cos();
        for j in 0..rings {
            let (st, ct) = (TAU * j as f32 / rings as f32).sin_cos();
            let r = major + minor * ct;
            positions.push(Vec3::new(r * cp, minor * st, -r * sp));
            normals.push(Vec3::new(ct * cp, st, -ct * sp));
        }
    }
    let index = |i: u32, j: u32| (i % segments) * rings + j % rings;
    let mut triangles = Vec::new();
    for i in 0..segments {
        for j in 0..rings {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i, j + 1),
                index(i + 1, j + 1),
            );
            triangles.push([a, b, d]);
            triangles.push([a, d, c]);
        }
    }
    Mesh::new("generated torus", positions, triangles, Some(normals), None)
        .expect("a generated torus is a valid mesh")
}

/// A concave bowl: the lower half (`y <= 0`) of the sphere of `radius` about
/// the origin, one-sided, its normals facing the centre (inwards and up).
/// `segments` steps around +Y, `rings` steps from the bottom to the rim.
///
/// Vertex 0 is the bottom `(0, -radius, 0)`; then ring `r` in `1..=rings`
/// (polar angle `theta = (pi/2) r/rings` from the bottom), vertex `s` in
/// `0..segments` at `radius (sin theta cos phi, -cos theta, -sin theta sin phi)`,
/// `phi = 2 pi s/segments`, index `1 + (r - 1) segments + s`. The rim is at
/// `y = 0`. Normals are `-p / radius`.
///
/// Seen from any point of its inside, the bowl covers exactly half of the
/// cosine-weighted hemisphere (the sphere's interior form factor is
/// `dA / (4 pi radius^2)` from every point), which makes the bowl a test
/// shape with closed-form interreflection.
///
/// # Panics
/// If `segments < 3`, `rings < 1` or `radius` is not positive and finite.
#[must_use]
pub fn bowl(radius: f32, segments: u32, rings: u32) -> Mesh {
    assert!(
        segments >= 3 && rings >= 1,
        "bowl needs segments >= 3, rings >= 1"
    );
    assert!(
        radius.is_finite() && radius > 0.0,
        "bowl needs a positive radius"
    );
    let mut units = vec![Vec3::NEG_Y];
    for r in 1..=rings {
        let (st, ct) = (0.5 * PI * r as f32 / rings as f32).sin_cos();
        for s in 0..segments {
            let (sp, cp) = (TAU * s as f32 / segments as f32).sin_cos();
            units.push(Vec3::new(st * cp, -ct, -st * sp));
        }
    }
    let row = |r: u32, s: u32| 1 + (r - 1) * segments + s % segments;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, row(1, s), row(1, s + 1)]);
    }
    for r in 1..rings {
        for s in 0..segments {
            let (a, b, c, d) = (row(r, s), row(r, s + 1), row(r + 1, s), row(r + 1, s + 1));
            triangles.push([a, d, b]);
            triangles.push([a, c, d]);
        }
    }
    let positions = units.iter().map(|u| *u * radius).collect();
    let normals = units.iter().map(|u| -*u).collect();
    Mesh::new("generated bowl", positions, triangles, Some(normals), None)
        .expect("a generated bowl is a valid mesh")
}

/// A sphere resting on a square: [`uv_sphere`] of `radius` (`segments`,
/// `rings`) centred at `(0, radius, 0)`, so its south pole touches the
/// origin, and [`plane`] of `size` and `divisions` in `y = 0`, in one mesh.
/// The sphere's vertices come first, in [`uv_sphere`]'s order, then the
/// plane's in [`plane`]'s order (offset by the sphere's vertex count). With
/// an even `divisions`, a plane vertex sits at the contact point.
///
/// # Panics
/// As [`uv_sphere`] and [`plane`].
#[must_use]
pub fn plane_under_sphere(
    radius: f32,
    segments: u32,
    rings: u32,
    size: f32,
    divisions: u32,
) -> Mesh {
    let sphere = uv_sphere(radius, segments, rings);
    let ground = plane(size, divisions);
    let offset = Vec3::new(0.0, radius, 0.0);
    let base = sphere.vertex_count() as u32;
    let positions = sphere
        .positions
        .iter()
        .map(|p| *p + offset)
        .chain(ground.positions.iter().copied())
        .collect();
    let normals = sphere
        .normals
        .iter()
        .chain(&ground.normals)
        .copied()
        .collect();
    let triangles = sphere
        .triangles
        .iter()
        .copied()
        .chain(ground.triangles.iter().map(|t| t.map(|i| i + base)))
        .collect();
    Mesh::new(
        "generated plane under sphere",
        positions,
        triangles,
        Some(normals),
        None,
    )
    .expect("a generated plane under a sphere is a valid mesh")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle's face normal points the way its vertex normals do.
    fn assert_wound_like_normals(m: &Mesh) {
        for tri in &m.triangles {
            let [a, b, c] = tri.map(|i| m.positions[i as usize]);
            let face = (b - a).cross(c - a);
            for &i in tri {
                assert!(
                    face.dot(m.normals[i as usize]) > 0.0,
                    "triangle {tri:?} is wound against its normals"
                );
            }
        }
    }

    #[test]
    fn generated_shapes_have_their_areas_and_windings() {
        let pi = core::f64::consts::PI;
        let cases: [(Mesh, f64, f64); 5] = [
            (plane(2.0, 4), 4.0, 1e-6),
            (
                cuboid(Vec3::new(1.0, 2.0, 3.0)),
                8.0 * (2.0 + 3.0 + 6.0),
                1e-6,
            ),
            // A polyhedral torus's area converges to 4 pi^2 R r from below.
            (torus(2.0, 0.5, 128, 64), 4.0 * pi * pi * 2.0 * 0.5, 2e-3),
            (bowl(1.0, 128, 64), 2.0 * pi, 2e-3),
            (
                plane_under_sphere(1.0, 128, 64, 4.0, 8),
                4.0 * pi + 16.0,
                2e-3,
            ),
        ];
        for (m, area, tol) in &cases {
            assert_eq!(m.report.degenerate_triangles, 0);
            assert_eq!(m.report.computed_normals, 0);
            let rel = (m.surface_area() - area) / area;
            assert!(
                rel <= 1e-6 && rel > -tol,
                "area {} vs {area}",
                m.surface_area()
            );
            assert_wound_like_normals(m);
        }
        let t = torus(2.0, 0.5, 12, 6);
        assert_eq!((t.vertex_count(), t.triangle_count()), (72, 144));
        let b = bowl(1.0, 8, 3);
        assert_eq!(b.positions[0], Vec3::NEG_Y);
        assert!(b.positions[1 + 2 * 8..].iter().all(|p| p.y.abs() < 1e-6));
        let pus = plane_under_sphere(1.0, 8, 4, 4.0, 2);
        let contact = uv_sphere(1.0, 8, 4).vertex_count() + 4; // plane vertex (1, 1)
        assert_eq!(pus.positions[contact], Vec3::ZERO);
        assert!(pus.positions.iter().all(|p| p.y >= -1e-6));
    }

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
