//! The scene a bake reads: its mesh and, for a glTF scene, its surfaces
//! (materials with textures), which the PRT and volume bakes take so that
//! cut-outs let rays through and a ray takes the albedo of the texel it
//! hits ([`shlight_mesh::Surfaces`]), and its punctual lights, which the
//! volume bake takes.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use shlight_mesh::{LoadOptions, Mesh, MeshFormat, PunctualLight, Surfaces};

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

/// A glTF scene's punctual lights (`KHR_lights_punctual`, in world space),
/// from [`shlight_mesh::load_scene`]; none for another format.
///
/// # Errors
/// A file the loader refuses.
pub(crate) fn load_scene_lights(path: &Path) -> Result<Vec<PunctualLight>> {
    // A second reading of the file beside `load_scene_surfaces`' (which
    // reads it as a mesh); one `load_scene` can give both once the surfaces
    // are read from it.
    if MeshFormat::from_path(path) != Some(MeshFormat::Gltf) {
        return Ok(Vec::new());
    }
    Ok(shlight_mesh::load_scene(path, &LoadOptions::default())?.lights)
}
