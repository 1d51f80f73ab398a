//! [`BackSides`]: the other side of a scene's double-sided triangles, as
//! vertices of their own, so that light gathered per vertex is gathered on
//! both sides.
//!
//! A glTF material with `doubleSided` reflects (and, emitting, emits) from
//! both faces ([`shlight_mesh::Material::double_sided`]). Light is
//! gathered per vertex, over the hemisphere its normal faces, so the back
//! face of such a triangle needs vertices of its own: each vertex of a
//! double-sided triangle gets a *back copy* at the same position with the
//! normal negated (its rays start off the back side), its albedo and
//! emission those of the vertex it copies; each double-sided triangle gets
//! a *back triangle* over the back copies of its corners, wound the other
//! way (corners `[a', c', b']` for `[a, b, c]`, so that its winding faces
//! its normals), appended after the mesh's triangles. A ray that meets the
//! back of a double-sided triangle reads the light of its back triangle,
//! the hit's weights `(w_a, w_b, w_c)` becoming `(w_a, w_c, w_b)`
//! ([`BackSides::back_hit`]). Only the double-sided part grows: a scene
//! without a double-sided triangle has no back sides at all.

use shlight_mesh::{Mesh, Subdivision, Surfaces};

/// The back sides of a mesh's double-sided triangles (the module
/// documentation states what they are): the mesh extended by them is its
/// *two-sided* mesh ([`BackSides::two_sided`]), the mesh's vertices and
/// triangles first, then the back copies and back triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct BackSides {
    /// Vertices of the mesh (the back copies' indices start here).
    pub front_vertices: usize,
    /// Per back copy (vertex `front_vertices + k` of the two-sided mesh),
    /// the vertex of the mesh it copies; in increasing order.
    pub copies: Vec<u32>,
    /// Per triangle of the mesh, its back triangle's index in the
    /// two-sided mesh, or [`BackSides::NONE`] for a one-sided triangle.
    pub back_triangles: Vec<u32>,
    /// The back triangles, corners indexing the two-sided mesh's vertices,
    /// in order of the triangles they are the back of.
    pub triangles: Vec<[u32; 3]>,
}

impl BackSides {
    /// [`BackSides::back_triangles`] of a one-sided triangle.
    pub const NONE: u32 = u32::MAX;

    /// The back sides of `mesh`, whose triangles are those of
    /// `surfaces.mesh` or, with `map`, were subdivided from them
    /// ([`Mesh::subdivided_with_map`]): a triangle is double-sided when
    /// the material of its (original) triangle is. `None` when no triangle
    /// is.
    ///
    /// # Panics
    /// If `surfaces` has another triangle count than `mesh` (or than the
    /// mesh `map` maps from).
    #[must_use]
    pub fn find(mesh: &Mesh, map: Option<&Subdivision>, surfaces: &Surfaces) -> Option<Self> {
        if !surfaces.any_double_sided() {
            return None;
        }
        let originals: Vec<u32> = match map {
            Some(m) => {
                assert_eq!(m.original_triangles(), surfaces.mesh.triangle_count());
                m.originals()
            }
            None => {
                assert_eq!(mesh.triangle_count(), surfaces.mesh.triangle_count());
                (0..mesh.triangle_count() as u32).collect()
            }
        };
        let double: Vec<bool> = originals
            .iter()
            .map(|&t| surfaces.double_sided(t))
            .collect();
        let n = mesh.vertex_count();
        let mut copy_of = vec![Self::NONE; n];
        for (tri, _) in mesh.triangles.iter().zip(&double).filter(|(_, d)| **d) {
            for &v in tri {
                copy_of[v as usize] = 0;
            }
        }
        let mut copies = Vec::new();
        for (v, c) in copy_of.iter_mut().enumerate() {
            if *c == 0 {
                *c = (n + copies.len()) as u32;
                copies.push(v as u32);
            }
        }
        if copies.is_empty() {
            return None;
        }
        let mut back_triangles = vec![Self::NONE; mesh.triangle_count()];
        let mut triangles = Vec::new();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            if double[t] {
                back_triangles[t] = (mesh.triangle_count() + triangles.len()) as u32;
                let [a, b, c] = tri.map(|v| copy_of[v as usize]);
                triangles.push([a, c, b]);
            }
        }
        Some(Self {
            front_vertices: n,
            copies,
            back_triangles,
            triangles,
        })
    }

    /// Back copies.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.copies.len()
    }

    /// Vertices of the two-sided mesh.
    #[must_use]
    pub fn two_sided_vertices(&self) -> usize {
        self.front_vertices + self.copies.len()
    }

    /// Per-vertex values of the mesh (`front`), extended to the two-sided
    /// mesh: each back copy takes its vertex's.
    ///
    /// # Panics
    /// If `front` has another length than the mesh's vertices.
    #[must_use]
    pub fn extend<T: Copy>(&self, front: &[T]) -> Vec<T> {
        assert_eq!(front.len(), self.front_vertices, "one value per vertex");
        let mut out = front.to_vec();
        out.extend(self.copies.iter().map(|&v| front[v as usize]));
        out
    }

    /// The two-sided mesh of `mesh`: its vertices, then the back copies
    /// (normals negated; colours and emission copied), its triangles, then
    /// the back triangles.
    ///
    /// # Panics
    /// If `mesh` is not the mesh these back sides were found for.
    #[must_use]
    pub fn two_sided(&self, mesh: &Mesh) -> Mesh {
        assert_eq!(mesh.vertex_count(), self.front_vertices);
        assert_eq!(mesh.triangle_count(), self.back_triangles.len());
        let mut normals = mesh.normals.clone();
        normals.extend(self.copies.iter().map(|&v| -mesh.normals[v as usize]));
        let mut triangles = mesh.triangles.clone();
        triangles.extend_from_slice(&self.triangles);
        Mesh {
            positions: self.extend(&mesh.positions),
            normals,
            colors: mesh.colors.as_deref().map(|c| self.extend(c)),
            emission: mesh.emission.as_deref().map(|e| self.extend(e)),
            triangles,
            report: mesh.report.clone(),
        }
    }

    /// A ray's hit on the back of triangle `triangle` of the mesh, with
    /// the barycentric weights `b1`, `b2` of its corners 1 and 2: the back
    /// triangle and its weights of corners 1 and 2, when the triangle is
    /// double-sided.
    #[inline]
    #[must_use]
    pub fn back_hit(&self, triangle: u32, b1: f32, b2: f32) -> Option<(u32, f32, f32)> {
        match self.back_triangles[triangle as usize] {
            Self::NONE => None,
            back => Some((back, b2, b1)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec4};
    use shlight_mesh::{Instance, Material, Primitive, Scene, generate};

    /// A unit plane (facing +Y) beside a box, the plane's material
    /// double-sided or not.
    fn scene(double_sided: bool) -> Surfaces {
        let plane = generate::plane(1.0, 2);
        let cube = generate::cuboid(Vec3::splat(0.5));
        let primitive = |mesh: Mesh, material| Primitive::new(mesh, Some(material), "test");
        Scene {
            source: "sides.glb".into(),
            primitives: vec![primitive(plane, 0), primitive(cube, 1)],
            instances: vec![
                Instance {
                    primitive: 0,
                    transform: glam::Mat4::IDENTITY,
                },
                Instance {
                    primitive: 1,
                    transform: glam::Mat4::from_translation(Vec3::new(2.0, 0.0, 0.0)),
                },
            ],
            materials: vec![
                Material {
                    double_sided,
                    emissive: Vec3::new(1.0, 2.0, 3.0),
                    ..Material::default()
                },
                Material {
                    base_color: Vec4::new(0.2, 0.4, 0.6, 1.0),
                    ..Material::default()
                },
            ],
            ..Scene::default()
        }
        .flatten(Vec3::splat(0.5))
        .unwrap()
    }

    #[test]
    fn back_copies_face_the_other_way_over_the_double_sided_part_only() {
        assert!(BackSides::find(&scene(false).mesh, None, &scene(false)).is_none());
        let s = scene(true);
        let (fine, map) = s.mesh.subdivided_with_map(0.2);
        let sides = BackSides::find(&fine, Some(&map), &s).unwrap();
        let two = sides.two_sided(&fine);
        let n = fine.vertex_count();
        assert_eq!(two.vertex_count(), n + sides.vertex_count());
        // The back copies: the plane's vertices (y = 0, within the unit
        // square), none of the box's.
        assert!(sides.vertex_count() > 9);
        for (k, &v) in sides.copies.iter().enumerate() {
            let p = fine.positions[v as usize];
            assert!(p.y == 0.0 && p.x.abs() <= 0.5 && p.z.abs() <= 0.5, "{p}");
            assert_eq!(two.positions[n + k], p);
            assert_eq!(two.normals[n + k], Vec3::NEG_Y);
            assert_eq!(
                two.emission.as_ref().unwrap()[n + k],
                Vec3::new(1.0, 2.0, 3.0)
            );
        }
        // Every plane triangle has a back triangle whose winding faces down
        // and whose corners sit where the front's do; the box's have none.
        let mut backs = 0;
        for (t, tri) in fine.triangles.iter().enumerate() {
            let centroid = tri
                .iter()
                .map(|&i| fine.positions[i as usize])
                .sum::<Vec3>();
            let on_plane = centroid.x.abs() < 1.5;
            let Some((back, b1, b2)) = sides.back_hit(t as u32, 0.25, 0.125) else {
                assert!(!on_plane);
                continue;
            };
            assert!(on_plane);
            backs += 1;
            let [a, b, c] = two.triangles[back as usize].map(|i| two.positions[i as usize]);
            assert!((b - a).cross(c - a).dot(Vec3::NEG_Y) > 0.0);
            // The same point through the front's weights and the back's.
            let [p, q, r] = tri.map(|i| fine.positions[i as usize]);
            let front = p * 0.625 + q * 0.25 + r * 0.125;
            let back_point = a * (1.0 - b1 - b2) + b * b1 + c * b2;
            assert!(front.distance(back_point) < 1e-6);
        }
        assert_eq!(backs, sides.triangles.len());
        assert_eq!(two.triangle_count(), fine.triangle_count() + backs);
    }
}
