//! glTF 2.0 (`.gltf` with embedded or external buffers and images, and
//! binary `.glb`) as a [`Scene`], and flattened into one [`Mesh`] for
//! [`crate::load`].
//!
//! The JSON is parsed and validated by the `gltf` crate
//! ([`document`]: required extensions shlight does not read are refused by
//! name, optional ones noted); everything else is read here from the
//! validated JSON: accessors by one reader ([`accessor`]: every component
//! type, `normalized`, strides, sparse, bounds), the node hierarchy of the
//! default scene, or the first ([`node`]: transforms, mesh instances,
//! `EXT_mesh_gpu_instancing`, lights), primitives ([`primitive`]),
//! materials ([`material`]) and their textures ([`texture`]).
//!
//! Read: `TRIANGLES`, `TRIANGLE_STRIP` and `TRIANGLE_FAN` primitives
//! (points and lines are skipped with a note, as is a primitive whose
//! triangles are all degenerate), with `POSITION`, `NORMAL`, every
//! `TEXCOORD_n` and `COLOR_0` in float or (`KHR_mesh_quantization`)
//! integer form; `KHR_lights_punctual`, `KHR_texture_transform`,
//! `KHR_materials_emissive_strength`; `EXT_meshopt_compression` ([`meshopt`]);
//! PNG and JPEG textures. Without any
//! scene, every mesh is placed once, untransformed.
//!
//! Flattened ([`read`]), the vertex order is: scene nodes depth-first in
//! document order (a node, then its children), each node's primitives in
//! order (for each GPU instance, in instance order), each primitive's
//! vertices in accessor order; a mesh used by two nodes appears twice. The
//! mesh's colours are the diffuse albedo ([`Scene::flatten`] with white
//! for primitives without a material), or none when nothing in the file
//! gives albedo (no `COLOR_0`, no base colour texture, every
//! `baseColorFactor` white and every `metallicFactor` 0); its emission is
//! each material's emitted radiance (with its emissive texture), or none
//! when nothing emits.

pub(crate) mod accessor;
pub(crate) mod document;
mod light;
mod material;
mod meshopt;
mod node;
mod primitive;
mod texture;
pub(crate) mod uri;

use std::path::Path;

use glam::Vec3;

use crate::scene::Scene;
use crate::{LoadOptions, Mesh, MeshError};

/// Reads `bytes` (glTF JSON or GLB) as a scene; `path` names it in errors
/// and locates external buffers and images (relative to its directory).
pub(crate) fn read_scene(
    path: &Path,
    bytes: &[u8],
    options: &LoadOptions,
) -> Result<Scene, MeshError> {
    let parsed = document::parse(path, bytes, options)?;
    let root = &parsed.root;
    let data = accessor::Data {
        root,
        buffers: &parsed.buffers,
    };
    let mut walk = node::Walk::new(path, data, *options);
    let scene = root
        .scene
        .map(|s| s.value())
        .or((!root.scenes.is_empty()).then_some(0))
        .and_then(|s| root.scenes.get(s));
    match scene {
        Some(scene) => {
            let roots: Vec<usize> = scene.nodes.iter().map(|n| n.value()).collect();
            walk.scene(&roots)?;
        }
        None => walk.every_mesh()?,
    }
    let mut scene = walk.scene;
    let mut notes = parsed.notes;
    notes.append(&mut scene.notes);
    scene.notes = notes;

    let mut used = vec![false; root.materials.len()];
    for instance in &scene.instances {
        if let Some(m) = scene.primitives[instance.primitive].material
            && let Some(u) = used.get_mut(m)
        {
            *u = true;
        }
    }
    let mut textures = texture::Textures::new(path, data, *options);
    scene.materials = (0..root.materials.len())
        .map(|i| material::read(path, root, i, used[i], &mut textures))
        .collect::<Result<_, _>>()?;
    scene.textures = textures.decoded;
    Ok(scene)
}

/// Reads `bytes` as glTF or GLB, flattened into one world-space mesh (see
/// the module documentation).
pub(crate) fn read(path: &Path, bytes: &[u8], options: &LoadOptions) -> Result<Mesh, MeshError> {
    let scene = read_scene(path, bytes, options)?;
    if scene.instances.is_empty() {
        let mut message = "the scene places no triangles".to_string();
        if !scene.notes.is_empty() {
            message = format!("{message} ({})", scene.notes.join("; "));
        }
        return Err(MeshError::Invalid {
            path: path.to_path_buf(),
            message,
        });
    }
    let gives_albedo = scene.instances.iter().any(|instance| {
        let p = &scene.primitives[instance.primitive];
        p.mesh.colors.is_some()
            || p.material
                .and_then(|m| scene.materials.get(m))
                .is_some_and(|m| {
                    m.base_color.truncate() != Vec3::ONE
                        || m.base_color_texture.is_some()
                        || m.metallic != 0.0
                })
    });
    let mut mesh = scene.flatten(Vec3::ONE)?.mesh;
    if !gives_albedo {
        mesh.colors = None;
    }
    // What validating each primitive found, once per placement, as when the
    // whole file was validated at once.
    for instance in &scene.instances {
        let report = &scene.primitives[instance.primitive].mesh.report;
        mesh.report.degenerate_triangles += report.degenerate_triangles;
        mesh.report.computed_normals += report.computed_normals;
    }
    Ok(mesh)
}
