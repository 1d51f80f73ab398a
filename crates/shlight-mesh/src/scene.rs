//! A scene as a glTF file holds it: unique geometry placed by instances,
//! materials with textures, and punctual lights; and the scene flattened
//! into one world-space [`Mesh`] with what each triangle's surface needs
//! ([`Surfaces`]).
//!
//! A [`Primitive`] is one glTF mesh primitive in its mesh's own space, with
//! one material; an [`Instance`] places a primitive in the world (a node
//! using a mesh, or an `EXT_mesh_gpu_instancing` instance). A primitive
//! used by several instances is stored once.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use crate::material::{Material, SurfaceSample};
use crate::punctual_light::PunctualLight;
use crate::texture::Texture;
use crate::{Mesh, MeshError};

/// One mesh primitive in its own space.
#[derive(Clone, Debug)]
pub struct Primitive {
    /// Positions, normals and triangles in the mesh's space; `colors` is
    /// `COLOR_0`'s RGB (linear) when the primitive has one.
    pub mesh: Mesh,
    /// `TEXCOORD_0`, `TEXCOORD_1`, ... (at most 8 sets; a set missing
    /// below one that is given reads as zeros): one UV per vertex per set.
    pub uvs: Vec<Vec<Vec2>>,
    /// `COLOR_0`'s alpha, when it has one.
    pub color_alpha: Option<Vec<f32>>,
    /// Index into [`Scene::materials`]; `None`: the default material, whose
    /// albedo the bake's settings give.
    pub material: Option<usize>,
    /// Which glTF mesh and primitive it came from, for messages
    /// (`"mesh 2 (Chair) primitive 0"`).
    pub label: String,
}

impl Primitive {
    /// A primitive of `mesh` with no UV sets and no `COLOR_0` alpha (a
    /// scene built in code rather than read), of material `material`,
    /// named `label` in messages.
    pub fn new(mesh: Mesh, material: Option<usize>, label: impl Into<String>) -> Self {
        Primitive {
            mesh,
            uvs: Vec::new(),
            color_alpha: None,
            material,
            label: label.into(),
        }
    }
}

/// A primitive placed in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::primitives`].
    pub primitive: usize,
    /// Mesh space to world space (finite, invertible).
    pub transform: Mat4,
}

/// A loaded scene.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The file the scene came from (named in messages).
    pub source: PathBuf,
    /// Unique geometry.
    pub primitives: Vec<Primitive>,
    /// Placements, in the file's order (scene nodes depth-first in document
    /// order, a node's primitives in order; a node with
    /// `EXT_mesh_gpu_instancing` places its primitives once per instance,
    /// in instance order, instead of once).
    pub instances: Vec<Instance>,
    /// Materials, in the file's order.
    pub materials: Vec<Material>,
    /// Decoded textures (one per glTF texture used).
    pub textures: Vec<Texture>,
    /// Punctual lights, in world space.
    pub lights: Vec<PunctualLight>,
    /// What the loader passed over and says so (an optional extension it
    /// does not use, a primitive that is not triangles).
    pub notes: Vec<String>,
    /// Per instance, where the file placed it ([`InstanceSource`]); empty
    /// for a scene built in code or read from a file without scenes.
    pub instance_sources: Vec<InstanceSource>,
}

/// Where an [`Instance`] of a loaded scene came from: the glTF node that
/// placed it and the glTF mesh it belongs to (the primitives of one mesh
/// share its UV layouts), and which `EXT_mesh_gpu_instancing` instance
/// of the node it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct InstanceSource {
    /// Index of the node in the file's `nodes`.
    pub node: usize,
    /// Index of the mesh in the file's `meshes`.
    pub mesh: usize,
    /// The node's GPU instance (`EXT_mesh_gpu_instancing`), if it has them.
    pub gpu_instance: Option<u32>,
}

/// The scene flattened: every instance's triangles in world space, and per
/// triangle and vertex what its surface needs.
#[derive(Clone, Debug)]
pub struct Surfaces {
    /// The world-space mesh. Its `colors` hold the diffuse albedo at each
    /// vertex (material, texture at the vertex's UV, vertex colour), and its
    /// `emission` the emitted radiance there, for code that reads light per
    /// vertex; [`Surfaces::sample`] gives both at any point of a triangle.
    pub mesh: Mesh,
    /// Per vertex of `mesh`, its UV sets (as many per vertex as
    /// [`Surfaces::uv_sets`]).
    pub uvs: Vec<Vec2>,
    /// UV sets per vertex in `uvs`.
    pub uv_sets: usize,
    /// Per vertex of `mesh`, `COLOR_0` (linear RGBA; white without one).
    pub colors: Vec<Vec4>,
    /// Per triangle of `mesh`, its material (an index into
    /// [`Surfaces::materials`]).
    pub triangle_material: Vec<u32>,
    /// The materials; the last is the default material, with the albedo
    /// the flattening was given.
    pub materials: Vec<Material>,
    /// The textures the materials read.
    pub textures: Vec<Texture>,
    /// The scene's geometry and placements (its primitives and instances;
    /// no materials, textures or lights) when some primitive is placed
    /// more than once: what a hierarchy of the unique primitives is built
    /// from, so that rays need not be cast against every copy
    /// (`shlight_rays::Occluder::for_surfaces`). `None` when every
    /// primitive is placed once.
    pub placement: Option<Arc<Scene>>,
}

impl Surfaces {
    /// Albedo and alpha at barycentric coordinates `bary` (weights of the
    /// triangle's three corners) of triangle `triangle` of
    /// [`Surfaces::mesh`].
    pub fn sample(&self, triangle: u32, bary: [f32; 3]) -> SurfaceSample {
        let tri = self.mesh.triangles[triangle as usize];
        let material = &self.materials[self.triangle_material[triangle as usize] as usize];
        let mut color = Vec4::ZERO;
        for (&v, &w) in tri.iter().zip(&bary) {
            color += w * self.colors[v as usize];
        }
        if !material.is_textured() {
            // Most hits: no texture to look up, so no UVs to interpolate.
            return material.surface(&self.textures, &[], color);
        }
        let mut uvs = [Vec2::ZERO; MAX_UV_SETS];
        for (&v, &w) in tri.iter().zip(&bary) {
            let v = v as usize;
            for (k, uv) in uvs.iter_mut().enumerate().take(self.uv_sets) {
                *uv += w * self.uvs[v * self.uv_sets + k];
            }
        }
        material.surface(&self.textures, &uvs[..self.uv_sets], color)
    }

    /// The diffuse albedo a ray hitting triangle `triangle` at barycentric
    /// coordinates `bary` reflects with: [`Surfaces::sample`]'s, each
    /// channel clamped to `0..=1` (a surface reflects no more than it
    /// receives).
    pub fn reflectance(&self, triangle: u32, bary: [f32; 3]) -> Vec3 {
        self.sample(triangle, bary)
            .albedo
            .clamp(Vec3::ZERO, Vec3::ONE)
    }

    /// The material of triangle `triangle`.
    pub fn material(&self, triangle: u32) -> &Material {
        &self.materials[self.triangle_material[triangle as usize] as usize]
    }

    /// Whether triangle `triangle`'s material is double-sided: its back
    /// reflects (and emits) as its front does.
    pub fn double_sided(&self, triangle: u32) -> bool {
        self.material(triangle).double_sided
    }

    /// Whether any triangle's material is double-sided.
    pub fn any_double_sided(&self) -> bool {
        self.triangle_material
            .iter()
            .any(|&m| self.materials[m as usize].double_sided)
    }

    /// Whether any triangle's material cuts out (`MASK` or `BLEND`).
    pub fn any_cut_out(&self) -> bool {
        self.materials.iter().any(Material::cuts_out)
    }
}

/// The most UV sets [`Surfaces`] keeps per vertex.
pub const MAX_UV_SETS: usize = 4;

impl Scene {
    /// `instance`'s linear part and its determinant.
    ///
    /// # Errors
    /// A non-finite or singular transform, naming the primitive.
    pub(crate) fn check_transform(&self, instance: &Instance) -> Result<(Mat3, f32), MeshError> {
        let linear = Mat3::from_mat4(instance.transform);
        let det = linear.determinant();
        if !instance.transform.is_finite() || det == 0.0 || !det.is_finite() {
            return Err(MeshError::Invalid {
                path: self.source.clone(),
                message: format!(
                    "{} is placed by a non-finite or singular transform",
                    self.primitives[instance.primitive].label
                ),
            });
        }
        Ok((linear, det))
    }

    /// The primitives some instance places, and their triangles (each
    /// counted once, however many instances place it).
    pub fn unique_geometry(&self) -> (usize, usize) {
        let mut used = vec![false; self.primitives.len()];
        self.instances.iter().for_each(|i| used[i.primitive] = true);
        self.primitives
            .iter()
            .zip(&used)
            .filter(|(_, u)| **u)
            .fold((0, 0), |(n, t), (p, _)| {
                (n + 1, t + p.mesh.triangle_count())
            })
    }

    /// Whether some primitive is placed by more than one instance.
    pub fn repeats_primitives(&self) -> bool {
        let mut placed = vec![false; self.primitives.len()];
        self.instances
            .iter()
            .any(|i| std::mem::replace(&mut placed[i.primitive], true))
    }

    /// Every instance's triangles in world space: positions by the
    /// transform, normals by its inverse transpose, the winding reversed
    /// under a mirroring transform. Primitives without a material take
    /// `default_albedo`.
    ///
    /// # Errors
    /// A non-finite or singular transform (naming the primitive), or a
    /// world-space mesh [`Mesh::new`] refuses.
    pub fn flatten(&self, default_albedo: Vec3) -> Result<Surfaces, MeshError> {
        let invalid = |message: String| MeshError::Invalid {
            path: self.source.clone(),
            message,
        };
        let uv_sets = self
            .primitives
            .iter()
            .map(|p| p.uvs.len())
            .max()
            .unwrap_or(0)
            .min(MAX_UV_SETS);
        let mut materials = self.materials.clone();
        let default_material = materials.len() as u32;
        materials.push(Material {
            base_color: default_albedo.extend(1.0),
            ..Material::default()
        });
        let (mut positions, mut normals, mut uvs, mut colors) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut triangles, mut triangle_material) = (Vec::new(), Vec::new());
        for instance in &self.instances {
            let p = &self.primitives[instance.primitive];
            let (linear, det) = self.check_transform(instance)?;
            let normal_matrix = linear.inverse().transpose();
            let base = positions.len() as u32;
            let m = &p.mesh;
            positions.extend(
                m.positions
                    .iter()
                    .map(|&x| instance.transform.transform_point3(x)),
            );
            normals.extend(
                m.normals
                    .iter()
                    .map(|&n| (normal_matrix * n).normalize_or_zero()),
            );
            for v in 0..m.vertex_count() {
                for k in 0..uv_sets {
                    uvs.push(p.uvs.get(k).map_or(Vec2::ZERO, |set| set[v]));
                }
                let rgb = m.colors.as_ref().map_or(Vec3::ONE, |c| c[v]);
                let a = p.color_alpha.as_ref().map_or(1.0, |a| a[v]);
                colors.push(rgb.extend(a));
            }
            let material = p.material.map_or(default_material, |i| i as u32);
            for t in &m.triangles {
                let t = t.map(|i| i + base);
                triangles.push(if det < 0.0 { [t[0], t[2], t[1]] } else { t });
                triangle_material.push(material);
            }
        }
        let (mesh, kept) = Mesh::new_keeping(
            self.source.clone(),
            positions,
            triangles,
            Some(normals),
            None,
        )?;
        let triangle_material: Vec<u32> = kept
            .iter()
            .map(|&t| triangle_material[t as usize])
            .collect();
        let mut surfaces = Surfaces {
            mesh,
            uvs,
            uv_sets,
            colors,
            triangle_material,
            materials,
            textures: self.textures.clone(),
            placement: self.repeats_primitives().then(|| {
                Arc::new(Scene {
                    source: self.source.clone(),
                    primitives: self.primitives.clone(),
                    instances: self.instances.clone(),
                    ..Scene::default()
                })
            }),
        };
        // Per-vertex albedo and emission, at each vertex's own UV, with
        // the material of a triangle that uses it.
        let n = surfaces.mesh.vertex_count();
        let mut albedo = vec![default_albedo; n];
        let mut emission = vec![Vec3::ZERO; n];
        for (t, tri) in surfaces.mesh.triangles.iter().enumerate() {
            let material = &surfaces.materials[surfaces.triangle_material[t] as usize];
            for &v in tri {
                let v = v as usize;
                let vertex_uvs = &surfaces.uvs[v * uv_sets..][..uv_sets];
                albedo[v] = material
                    .surface(&surfaces.textures, vertex_uvs, surfaces.colors[v])
                    .albedo;
                emission[v] = material.emission(&surfaces.textures, vertex_uvs);
            }
        }
        if albedo.iter().any(|a| !a.is_finite()) {
            return Err(invalid("a material gives a non-finite albedo".into()));
        }
        surfaces.mesh.colors = Some(albedo);
        surfaces.mesh = surfaces.mesh.with_emission(self.source.clone(), emission)?;
        Ok(surfaces)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate;

    fn quad_scene() -> Scene {
        let plane = generate::plane(1.0, 1);
        let uv = plane
            .positions
            .iter()
            .map(|p| Vec2::new(p.x + 0.5, p.z + 0.5))
            .collect();
        Scene {
            source: "quad.glb".into(),
            primitives: vec![Primitive {
                mesh: plane,
                uvs: vec![uv],
                color_alpha: None,
                material: None,
                label: "mesh 0 primitive 0".into(),
            }],
            instances: vec![
                Instance {
                    primitive: 0,
                    transform: Mat4::IDENTITY,
                },
                Instance {
                    primitive: 0,
                    transform: Mat4::from_translation(Vec3::Y)
                        * Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)),
                },
            ],
            ..Scene::default()
        }
    }

    #[test]
    fn instances_become_world_triangles_and_mirrors_keep_their_facing() {
        let scene = quad_scene();
        let s = scene.flatten(Vec3::splat(0.5)).unwrap();
        let m = &scene.primitives[0].mesh;
        assert_eq!(s.mesh.vertex_count(), 2 * m.vertex_count());
        assert_eq!(s.mesh.triangle_count(), 2 * m.triangle_count());
        // Each triangle's geometric normal agrees with its vertex normals.
        for t in &s.mesh.triangles {
            let [a, b, c] = t.map(|i| s.mesh.positions[i as usize]);
            let face = (b - a).cross(c - a);
            assert!(face.dot(s.mesh.normals[t[0] as usize]) > 0.0);
        }
        assert_eq!(s.mesh.colors.as_ref().unwrap()[0], Vec3::splat(0.5));
    }

    #[test]
    fn a_singular_transform_is_refused_by_name() {
        let mut scene = quad_scene();
        scene.instances[1].transform = Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0));
        let e = scene.flatten(Vec3::ONE).unwrap_err().to_string();
        assert!(
            e.contains("quad.glb") && e.contains("mesh 0 primitive 0"),
            "{e}"
        );
    }
}
