//! Where each instance's triangles land in a flattened scene
//! ([`Scene::flatten`]), found without flattening it: for code that keeps
//! the unique primitives and their placements (a two-level ray-casting
//! hierarchy) but must name triangles as the flattened [`Surfaces`] does.
//!
//! [`Surfaces`]: crate::Surfaces

use glam::{Mat3, Vec3};

use crate::mesh::{bounds, is_degenerate};
use crate::{MeshError, Scene};

/// Per instance of a [`Scene`], the index in [`Scene::flatten`]'s mesh of
/// its first triangle, and which of its primitive's triangles the
/// flattening drops as degenerate in world space (a primitive placed very
/// small beside a large scene: [`crate::Mesh::new`]'s test, on the world
/// box). The flattened mesh numbers triangles instance by instance, in
/// [`Scene::instances`]' order, each instance's in its primitive's order,
/// the dropped ones left out.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FlatLayout {
    first: Vec<u32>,
    /// Per instance, its dropped triangles (the primitive's indices),
    /// ascending; empty for almost every instance.
    dropped: Vec<Box<[u32]>>,
    count: u32,
}

impl FlatLayout {
    /// The flattened mesh's triangle for triangle `local` of instance
    /// `instance`'s primitive, `None` when the flattening drops it.
    #[inline]
    #[must_use]
    pub fn triangle(&self, instance: usize, local: u32) -> Option<u32> {
        let dropped = &self.dropped[instance];
        if dropped.is_empty() {
            return Some(self.first[instance] + local);
        }
        match dropped.binary_search(&local) {
            Ok(_) => None,
            Err(before) => Some(self.first[instance] + local - before as u32),
        }
    }

    /// The instance and the primitive's triangle of the flattened mesh's
    /// triangle `triangle` (the inverse of [`triangle`](Self::triangle)).
    ///
    /// # Panics
    /// If `triangle` is not below [`triangle_count`](Self::triangle_count).
    #[must_use]
    pub fn locate(&self, triangle: u32) -> (usize, u32) {
        assert!(
            triangle < self.count,
            "triangle {triangle} of {}",
            self.count
        );
        // The last instance whose first triangle is at most `triangle` and
        // that keeps any (an instance keeping none shares its `first`).
        let instance = self.first.partition_point(|&f| f <= triangle) - 1;
        let instance = (0..=instance)
            .rev()
            .find(|&i| self.kept(i) > 0)
            .unwrap_or(instance);
        let mut local = triangle - self.first[instance];
        // Step over the dropped triangles below it, in order.
        for &d in self.dropped[instance].iter() {
            if d <= local {
                local += 1;
            } else {
                break;
            }
        }
        (instance, local)
    }

    /// Triangles of the flattened mesh.
    #[must_use]
    pub fn triangle_count(&self) -> u32 {
        self.count
    }

    /// Instances.
    #[must_use]
    pub fn instance_count(&self) -> usize {
        self.first.len()
    }

    /// Triangles instance `instance` keeps.
    fn kept(&self, instance: usize) -> u32 {
        self.first.get(instance + 1).copied().unwrap_or(self.count) - self.first[instance]
    }

    /// Bytes this layout holds on the heap.
    #[must_use]
    pub fn heap_bytes(&self) -> usize {
        self.first.capacity() * 4
            + self.dropped.capacity() * size_of::<Box<[u32]>>()
            + self.dropped.iter().map(|d| d.len() * 4).sum::<usize>()
    }
}

impl Scene {
    /// Where [`Scene::flatten`] puts each instance's triangles, found
    /// without building the flattened mesh (the world positions are
    /// computed instance by instance, twice: once for the world box the
    /// degenerate test reads, once for the test).
    ///
    /// # Errors
    /// As [`Scene::flatten`]: a non-finite or singular transform (naming
    /// the primitive), no instances, a non-finite world position, or no
    /// triangle left.
    pub fn flat_layout(&self) -> Result<FlatLayout, MeshError> {
        let invalid = |message: String| MeshError::Invalid {
            path: self.source.clone(),
            message,
        };
        let mut world = Vec::new();
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for instance in &self.instances {
            self.check_transform(instance)?;
            let m = &self.primitives[instance.primitive].mesh;
            world.clear();
            world.extend(
                m.positions
                    .iter()
                    .map(|&x| instance.transform.transform_point3(x)),
            );
            if let Some(p) = world.iter().find(|p| !p.is_finite()) {
                return Err(invalid(format!(
                    "{} is placed at a non-finite position ({p:?})",
                    self.primitives[instance.primitive].label
                )));
            }
            let (a, b) = bounds(&world);
            (lo, hi) = (lo.min(a), hi.max(b));
        }
        if self.instances.is_empty() {
            return Err(invalid("the mesh has no vertices".into()));
        }
        let diag2 = (hi - lo).length_squared();
        let (mut first, mut dropped) = (Vec::new(), Vec::new());
        let mut count = 0u32;
        for instance in &self.instances {
            let m = &self.primitives[instance.primitive].mesh;
            let mirrored = Mat3::from_mat4(instance.transform).determinant() < 0.0;
            world.clear();
            world.extend(
                m.positions
                    .iter()
                    .map(|&x| instance.transform.transform_point3(x)),
            );
            let gone: Box<[u32]> = (0..m.triangles.len() as u32)
                .filter(|&t| {
                    let t = m.triangles[t as usize];
                    let tri = if mirrored { [t[0], t[2], t[1]] } else { t };
                    is_degenerate(tri, &world, diag2)
                })
                .collect();
            first.push(count);
            count += (m.triangles.len() - gone.len()) as u32;
            dropped.push(gone);
        }
        if count == 0 {
            return Err(invalid("the mesh has no usable triangles".into()));
        }
        Ok(FlatLayout {
            first,
            dropped,
            count,
        })
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Quat};

    use super::*;
    use crate::{Instance, Primitive, generate};

    #[test]
    fn the_layout_names_triangles_as_the_flattened_mesh_does() {
        // A sphere placed four ways (mirrored among them) and once so small
        // beside the rest that some of its triangles are degenerate in the
        // world box, and a plane: the flattened mesh's triangles, in its
        // order, are the layout's, corner for corner.
        let primitive = |mesh, label: &str| Primitive::new(mesh, None, label);
        let scene = Scene {
            source: "layout.glb".into(),
            primitives: vec![
                primitive(generate::uv_sphere(1.0, 12, 6), "sphere"),
                primitive(generate::plane(2.0, 3), "plane"),
            ],
            instances: [
                (0, Mat4::IDENTITY),
                (1, Mat4::from_translation(Vec3::new(0.0, -1.0, 0.0))),
                (
                    0,
                    Mat4::from_scale_rotation_translation(
                        Vec3::new(1.0, -0.5, 2.0),
                        Quat::from_rotation_y(0.7),
                        Vec3::new(3.0, 0.0, 0.0),
                    ),
                ),
                (0, Mat4::from_scale(Vec3::splat(2.4e-3))),
                (0, Mat4::from_translation(Vec3::new(-1e3, 0.0, 0.0))),
            ]
            .map(|(primitive, transform)| Instance {
                primitive,
                transform,
            })
            .to_vec(),
            ..Scene::default()
        };
        let layout = scene.flat_layout().unwrap();
        let flat = scene.flatten(Vec3::ONE).unwrap().mesh;
        assert_eq!(layout.triangle_count() as usize, flat.triangle_count());
        let mut seen = vec![false; flat.triangle_count()];
        let mut dropped = 0;
        for (i, instance) in scene.instances.iter().enumerate() {
            let m = &scene.primitives[instance.primitive].mesh;
            let mirrored = instance.transform.determinant() < 0.0;
            for (local, t) in m.triangles.iter().enumerate() {
                let Some(g) = layout.triangle(i, local as u32) else {
                    dropped += 1;
                    continue;
                };
                assert_eq!(layout.locate(g), (i, local as u32));
                seen[g as usize] = true;
                let want = t.map(|v| instance.transform.transform_point3(m.positions[v as usize]));
                let want = if mirrored {
                    [want[0], want[2], want[1]]
                } else {
                    want
                };
                let got = flat.triangles[g as usize].map(|v| flat.positions[v as usize]);
                assert_eq!(got, want, "instance {i} triangle {local}");
            }
        }
        assert!(seen.iter().all(|&s| s));
        // The tiny sphere loses some triangles (not all).
        assert!(dropped > 0 && dropped < scene.primitives[0].mesh.triangle_count());
    }

    #[test]
    fn a_layout_refuses_what_flattening_refuses() {
        let scene = Scene {
            source: "bad.glb".into(),
            primitives: vec![Primitive::new(
                generate::plane(1.0, 1),
                None,
                "mesh 0 primitive 0",
            )],
            instances: vec![Instance {
                primitive: 0,
                transform: Mat4::from_scale(Vec3::new(1.0, 1.0, 0.0)),
            }],
            ..Scene::default()
        };
        let e = scene.flat_layout().unwrap_err().to_string();
        assert!(
            e.contains("bad.glb") && e.contains("mesh 0 primitive 0"),
            "{e}"
        );
        assert!(scene.flatten(Vec3::ONE).is_err());
        let empty = Scene {
            instances: Vec::new(),
            ..scene
        };
        assert!(empty.flat_layout().is_err() && empty.flatten(Vec3::ONE).is_err());
    }
}
