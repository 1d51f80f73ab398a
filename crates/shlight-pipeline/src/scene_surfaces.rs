//! The scene a bake reads: its mesh and, for a glTF scene, its surfaces
//! (materials with textures), which the PRT and volume bakes take so that
//! cut-outs let rays through and a ray takes the albedo of the texel it
//! hits ([`shlight_mesh::Surfaces`]).

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use shlight_mesh::{Mesh, Surfaces};

use crate::Result;

/// The mesh read from `path` and, for a glTF scene, its surfaces (whose
/// mesh it then is); `default_albedo` is the albedo of primitives without
/// a material.
///
/// # Errors
/// A file the loader refuses.
pub(crate) fn load_scene_surfaces(
    path: &Path,
    default_albedo: Vec3,
) -> Result<(Mesh, Option<Arc<Surfaces>>)> {
    // glTF scenes: once shlight-mesh reads a glTF file as a `Scene`
    // (`shlight_mesh::load_scene`), a `.gltf` or `.glb` path is read here
    // as one and its surfaces passed on:
    //
    //     let scene = shlight_mesh::load_scene(path)?;
    //     let surfaces = Arc::new(scene.flatten(default_albedo)?);
    //     return Ok((surfaces.mesh.clone(), Some(surfaces)));
    //
    // Until then every file is read as a mesh and baked without surfaces.
    let _ = default_albedo;
    Ok((shlight_mesh::load(path)?, None))
}
