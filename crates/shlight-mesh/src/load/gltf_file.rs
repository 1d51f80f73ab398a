//! glTF 2.0 (`.gltf` with embedded or external buffers, and binary `.glb`)
//! through the `gltf` crate (maintained, validates the document; images are
//! never decoded).
//!
//! Read: every triangle primitive (`TRIANGLES`, `TRIANGLE_STRIP`,
//! `TRIANGLE_FAN`; points and lines are skipped) of every mesh instance in
//! the default scene (or the first scene; or, with no scenes, every mesh once
//! untransformed), each with its node's world transform applied: positions by
//! the matrix, normals by its inverse transpose, and winding reversed under
//! a mirroring transform. `NORMAL` when every primitive has it; per-vertex
//! albedo `COLOR_0` (linear, RGB) times the material's `baseColorFactor`, or
//! the factor alone; none at all when no primitive has `COLOR_0` and every
//! factor is white. Emitted radiance per vertex: the material's
//! `emissiveFactor` times `KHR_materials_emissive_strength` (emissive
//! textures are not read); none when no material emits.
//!
//! Vertex order: scene nodes depth-first in document order (a node, then its
//! children), each node's primitives in order, each primitive's vertices in
//! accessor order; a mesh used by two nodes appears twice.
//!
//! Refused: a node that appears twice in the scene's hierarchy (a cycle, or
//! a node with two parents: glTF nodes form trees), and accessor counts
//! beyond the [`LoadOptions`] limits, checked before an accessor is read.

use std::path::Path;

use base64::Engine as _;
use glam::{Mat3, Mat4, Vec3};
use gltf::mesh::Mode;

use crate::{LoadOptions, Mesh, MeshError};

/// Reads `bytes` as glTF or GLB; `path` names it in errors and locates
/// external buffers (relative to its directory).
pub(crate) fn read(path: &Path, bytes: &[u8], options: &LoadOptions) -> Result<Mesh, MeshError> {
    let parse = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message,
    };
    let gltf =
        gltf::Gltf::from_slice(bytes).map_err(|e| parse(format!("not a valid glTF file: {e}")))?;
    let buffers =
        gltf.document
            .buffers()
            .map(|b| -> Result<Vec<u8>, MeshError> {
                let data = match b.source() {
                    gltf::buffer::Source::Bin => gltf.blob.clone().ok_or_else(|| {
                        parse(format!(
                            "buffer {} refers to a missing GLB chunk",
                            b.index()
                        ))
                    })?,
                    gltf::buffer::Source::Uri(uri) => load_uri(path, uri)
                        .map_err(|e| parse(format!("buffer {}: {e}", b.index())))?,
                };
                if data.len() < b.length() {
                    return Err(parse(format!(
                        "buffer {} holds {} bytes, the file says {}",
                        b.index(),
                        data.len(),
                        b.length()
                    )));
                }
                Ok(data)
            })
            .collect::<Result<Vec<_>, _>>()?;

    let mut out = Gathered {
        options: *options,
        visited: vec![false; gltf.document.nodes().len()],
        ..Gathered::default()
    };
    let scene = gltf
        .document
        .default_scene()
        .or_else(|| gltf.document.scenes().next());
    match scene {
        Some(scene) => {
            for node in scene.nodes() {
                visit(path, &node, Mat4::IDENTITY, &buffers, &mut out)?;
            }
        }
        None => {
            for mesh in gltf.document.meshes() {
                add_mesh(path, &mesh, Mat4::IDENTITY, &buffers, &mut out)?;
            }
        }
    }
    let colors = out.any_color.then_some(out.colors);
    let normals = out.all_normals.then_some(out.normals);
    let emission = out.emission;
    let mesh = Mesh::new(path, out.positions, out.triangles, normals, colors)?;
    if emission.iter().any(|e| *e != Vec3::ZERO) {
        mesh.with_emission(path, emission)
    } else {
        Ok(mesh)
    }
}

#[derive(Default)]
struct Gathered {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    colors: Vec<Vec3>,
    emission: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    any_color: bool,
    all_normals: bool,
    primitives: usize,
    options: LoadOptions,
    /// The nodes met so far, by index.
    visited: Vec<bool>,
}

fn visit(
    path: &Path,
    node: &gltf::Node,
    parent: Mat4,
    buffers: &[Vec<u8>],
    out: &mut Gathered,
) -> Result<(), MeshError> {
    // glTF nodes form trees; a node met twice (a cycle, or two parents)
    // would recurse forever or multiply the mesh without bound.
    match out.visited.get_mut(node.index()) {
        Some(seen @ false) => *seen = true,
        _ => {
            return Err(MeshError::Parse {
                path: path.to_path_buf(),
                message: format!(
                    "node {} appears twice in the scene's hierarchy (glTF nodes form trees)",
                    node.index()
                ),
            });
        }
    }
    let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
    if let Some(mesh) = node.mesh() {
        add_mesh(path, &mesh, world, buffers, out)?;
    }
    for child in node.children() {
        visit(path, &child, world, buffers, out)?;
    }
    Ok(())
}

fn add_mesh(
    path: &Path,
    mesh: &gltf::Mesh,
    world: Mat4,
    buffers: &[Vec<u8>],
    out: &mut Gathered,
) -> Result<(), MeshError> {
    let parse = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message,
    };
    let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
    let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
    for prim in mesh.primitives() {
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            continue;
        }
        let what = format!("mesh {} primitive {}", mesh.index(), prim.index());
        // The counts, before anything is read: a sparse accessor needs no
        // buffer, so a small file may claim any count.
        let vertices = prim
            .get(&gltf::Semantic::Positions)
            .map_or(0, |a| a.count());
        out.options
            .check_vertices(path, out.positions.len().saturating_add(vertices))?;
        let corners = prim.indices().map_or(vertices, |a| a.count());
        let triangles = match mode {
            Mode::Triangles => corners / 3,
            _ => corners.saturating_sub(2),
        };
        out.options
            .check_triangles(path, out.triangles.len().saturating_add(triangles))?;
        for (semantic, accessor) in prim.attributes() {
            if matches!(
                semantic,
                gltf::Semantic::Normals | gltf::Semantic::Colors(0)
            ) && accessor.count() != vertices
            {
                return Err(parse(format!(
                    "{what}: {} {semantic:?} for {vertices} positions",
                    accessor.count()
                )));
            }
        }
        let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .ok_or_else(|| parse(format!("{what} has no POSITION")))?
            .map(|p| world.transform_point3(Vec3::from_array(p)))
            .collect();
        let n = positions.len() as u32;
        let base = out.positions.len() as u32;
        let indices: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..n).collect(),
        };
        if let Some(&bad) = indices.iter().find(|&&i| i >= n) {
            return Err(parse(format!(
                "{what}: index {bad} out of range ({n} vertices)"
            )));
        }
        let mut tris: Vec<[u32; 3]> = match mode {
            Mode::Triangles => indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
                .map(|k| {
                    let t = [indices[k], indices[k + 1], indices[k + 2]];
                    if k % 2 == 0 { t } else { [t[1], t[0], t[2]] }
                })
                .collect(),
            _ => (1..indices.len().saturating_sub(1))
                .map(|k| [indices[0], indices[k], indices[k + 1]])
                .collect(),
        };
        if mirrored {
            for t in &mut tris {
                t.swap(1, 2);
            }
        }
        out.triangles
            .extend(tris.iter().map(|t| t.map(|i| i + base)));

        let normals: Option<Vec<Vec3>> = reader
            .read_normals()
            .map(|it| it.map(|v| normal_matrix * Vec3::from_array(v)).collect());
        out.all_normals = (out.all_normals || out.primitives == 0) && normals.is_some();
        out.normals
            .extend(normals.unwrap_or_else(|| vec![Vec3::ZERO; positions.len()]));

        let factor = prim.material().pbr_metallic_roughness().base_color_factor();
        let factor = Vec3::new(factor[0], factor[1], factor[2]);
        let colors: Vec<Vec3> = match reader.read_colors(0) {
            Some(c) => {
                out.any_color = true;
                c.into_rgb_f32()
                    .map(|c| Vec3::from_array(c) * factor)
                    .collect()
            }
            None => vec![factor; positions.len()],
        };
        out.any_color |= factor != Vec3::ONE;
        if colors.len() != positions.len() {
            return Err(parse(format!(
                "{what}: {} colours for {} positions",
                colors.len(),
                positions.len()
            )));
        }
        out.colors.extend(colors);
        let material = prim.material();
        let emissive = Vec3::from_array(material.emissive_factor())
            * material.emissive_strength().unwrap_or(1.0);
        out.emission
            .extend(std::iter::repeat_n(emissive, positions.len()));
        out.positions.extend(positions);
        out.primitives += 1;
    }
    Ok(())
}

/// The bytes a buffer URI names: a base64 `data:` URI, or a file relative to
/// the glTF file's directory.
fn load_uri(path: &Path, uri: &str) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .ok_or("only base64 data URIs are supported")?;
        return base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| format!("bad base64 data: {e}"));
    }
    let file = path
        .parent()
        .unwrap_or(Path::new("."))
        .join(percent_decode(uri));
    std::fs::read(&file).map_err(|e| format!("cannot read {}: {e}", file.display()))
}

/// `%XX` escapes of a relative URI decoded (glTF URIs are percent-encoded).
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%'
            && i + 2 < b.len()
            && let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2]))
        {
            out.push((h * 16 + l) as u8);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}
