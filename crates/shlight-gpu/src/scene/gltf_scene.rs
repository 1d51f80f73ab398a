//! [`GltfScene`]: a glTF file as `render-mesh` and `view` draw it, with its
//! materials, textures and instances, and [`SceneGeometry`], what a pass
//! draws as the scene (such a scene, or a plain mesh).

use std::path::Path;

use glam::Vec3;
use shlight_mesh::{LoadOptions, Mesh, MeshFormat, Surfaces};

use super::SceneError;

/// A glTF scene and its flattening.
#[derive(Clone, Debug)]
pub struct GltfScene {
    /// Unique primitives placed by instances, materials and textures, as
    /// loaded: what the SH, encoded and volume passes draw (each primitive
    /// once, per instance).
    pub scene: shlight_mesh::Scene,
    /// The scene flattened to world space, primitives without a material
    /// of the default albedo: the mesh a `.shprt` or `.shvol` file was
    /// baked for, the bounds a camera frames, and what PRT draws (its
    /// transfer is per world vertex).
    pub surfaces: Surfaces,
    /// The albedo of primitives without a material.
    pub default_albedo: [f32; 3],
}

impl GltfScene {
    /// `scene` with its flattening, primitives without a material of
    /// `default_albedo`.
    ///
    /// # Errors
    /// A transform or a world-space mesh the flattening refuses, naming
    /// the file.
    pub fn new(scene: shlight_mesh::Scene, default_albedo: [f32; 3]) -> Result<Self, SceneError> {
        let surfaces = scene.flatten(Vec3::from_array(default_albedo))?;
        Ok(Self {
            scene,
            surfaces,
            default_albedo,
        })
    }

    /// The glTF scene of `path` when it names a `.gltf` or `.glb` file
    /// (shlight-mesh's `load_scene`, under the default limits), with its
    /// flattening; `None` for the other formats, read as plain meshes.
    ///
    /// # Errors
    /// A file the glTF scene loader refuses, naming it.
    pub(super) fn read(path: &Path, default_albedo: [f32; 3]) -> Result<Option<Self>, SceneError> {
        if MeshFormat::from_path(path) != Some(MeshFormat::Gltf) {
            return Ok(None);
        }
        let scene = shlight_mesh::load_scene(path, &LoadOptions::default())?;
        Ok(Some(Self::new(scene, default_albedo)?))
    }

    /// The flattened scene's world-space mesh.
    #[must_use]
    pub fn mesh(&self) -> &Mesh {
        &self.surfaces.mesh
    }
}

/// What a pass draws as the scene.
#[derive(Clone, Copy, Debug)]
pub enum SceneGeometry<'a> {
    /// A mesh (OBJ, PLY, OFF), of its vertex colours or the albedo given.
    Mesh(&'a Mesh),
    /// A glTF scene, with its materials, textures and instances.
    Gltf(&'a GltfScene),
}
