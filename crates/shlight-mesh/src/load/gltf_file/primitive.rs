//! One glTF mesh primitive to a [`Primitive`]: positions, normals, every
//! `TEXCOORD_n`, `COLOR_0` and the triangles its mode draws, in the mesh's
//! own space, each attribute through the accessor reader (so quantized
//! attributes read as the node transform expects them).

use std::path::Path;

use glam::{Vec2, Vec3};
use gltf::json;
use json::accessor::{ComponentType, Type};
use json::mesh::{Mode, Semantic};
use json::validation::Checked;

use super::accessor::{self, Data};
use crate::scene::Primitive;
use crate::{Mesh, MeshError};

/// The most `TEXCOORD_n` sets read per primitive.
const MAX_SETS: usize = 8;

/// What a primitive claims before it is read: its vertex and triangle
/// counts, from its accessors' headers.
pub(super) fn claimed(
    data: Data,
    primitive: &json::mesh::Primitive,
) -> Result<(usize, usize), String> {
    let vertices = match position(primitive) {
        Some(i) => accessor::count(data, i)?,
        None => 0,
    };
    let corners = match primitive.indices {
        Some(i) => accessor::count(data, i.value())?,
        None => vertices,
    };
    let triangles = match primitive.mode {
        Checked::Valid(Mode::Triangles) => corners / 3,
        Checked::Valid(Mode::TriangleStrip | Mode::TriangleFan) => corners.saturating_sub(2),
        _ => 0,
    };
    Ok((vertices, triangles))
}

fn position(primitive: &json::mesh::Primitive) -> Option<usize> {
    primitive
        .attributes
        .get(&Checked::Valid(Semantic::Positions))
        .map(|i| i.value())
}

/// `"mesh 2 (Chair) primitive 0"`.
pub(super) fn label(mesh_index: usize, mesh: &json::Mesh, primitive: usize) -> String {
    match &mesh.name {
        Some(name) => format!("mesh {mesh_index} ({name}) primitive {primitive}"),
        None => format!("mesh {mesh_index} primitive {primitive}"),
    }
}

/// Reads primitive `index` of `mesh`: `Ok(Err(note))` when it is passed
/// over (not triangles, or no usable triangle), an error when its data is
/// broken. At most `max_vertices` and `max_triangles` are read (the caller
/// has checked the counts against the limits).
pub(super) fn read(
    path: &Path,
    data: Data,
    label: String,
    primitive: &json::mesh::Primitive,
    max_vertices: usize,
    max_triangles: usize,
) -> Result<Result<Primitive, String>, MeshError> {
    let fail = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message: format!("{label}: {message}"),
    };
    let mode = match primitive.mode {
        Checked::Valid(m @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)) => m,
        Checked::Valid(other) => {
            return Ok(Err(format!(
                "{label} draws {}, not triangles; skipped",
                match other {
                    Mode::Points => "points",
                    _ => "lines",
                }
            )));
        }
        Checked::Invalid => return Err(fail("an unknown primitive mode".into())),
    };
    let attribute = |semantic: Semantic| {
        primitive
            .attributes
            .get(&Checked::Valid(semantic))
            .map(|i| i.value())
    };
    let position = attribute(Semantic::Positions).ok_or_else(|| fail("no POSITION".into()))?;
    let positions: Vec<Vec3> = accessor::read_floats(data, position, &[Type::Vec3], max_vertices)
        .map_err(|e| fail(format!("POSITION: {e}")))?
        .elements()
        .map(Vec3::from_array)
        .collect();
    let n = positions.len();
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(fail(format!(
            "vertex {i} has a non-finite coordinate ({})",
            positions[i]
        )));
    }
    let same_count = |name: &str, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(fail(format!("{len} {name} values for {n} positions")))
        }
    };

    let normals = match attribute(Semantic::Normals) {
        Some(i) => {
            let normals: Vec<Vec3> = accessor::read_floats(data, i, &[Type::Vec3], max_vertices)
                .map_err(|e| fail(format!("NORMAL: {e}")))?
                .elements()
                .map(Vec3::from_array)
                .collect();
            same_count("NORMAL", normals.len())?;
            Some(normals)
        }
        None => None,
    };

    let sets = primitive
        .attributes
        .keys()
        .filter_map(|s| match s {
            Checked::Valid(Semantic::TexCoords(k)) if (*k as usize) < MAX_SETS => {
                Some(*k as usize + 1)
            }
            _ => None,
        })
        .max()
        .unwrap_or(0);
    // Sets past the eighth are not read (no material would name one), nor
    // the empty sets below a far one that a file could claim.
    let mut uvs = Vec::with_capacity(sets);
    for k in 0..sets {
        let set: Vec<Vec2> = match attribute(Semantic::TexCoords(k as u32)) {
            Some(i) => accessor::read_floats(data, i, &[Type::Vec2], max_vertices)
                .map_err(|e| fail(format!("TEXCOORD_{k}: {e}")))?
                .elements()
                .map(Vec2::from_array)
                .collect(),
            None => vec![Vec2::ZERO; n],
        };
        same_count(&format!("TEXCOORD_{k}"), set.len())?;
        uvs.push(set);
    }

    let (colors, color_alpha) = match attribute(Semantic::Colors(0)) {
        Some(i) => {
            let (component, normalized, name) =
                accessor::component(data, i).map_err(|e| fail(format!("COLOR_0: {e}")))?;
            if !matches!(
                (component, normalized),
                (ComponentType::F32, _) | (ComponentType::U8 | ComponentType::U16, true)
            ) {
                return Err(fail(format!(
                    "COLOR_0 holds {name}; glTF allows FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT"
                )));
            }
            let c = accessor::read_floats(data, i, &[Type::Vec3, Type::Vec4], max_vertices)
                .map_err(|e| fail(format!("COLOR_0: {e}")))?;
            same_count("COLOR_0", c.values.len() / c.components)?;
            if c.values.iter().any(|v| !v.is_finite()) {
                return Err(fail("COLOR_0 holds a non-finite value".into()));
            }
            let rgb = c
                .values
                .chunks_exact(c.components)
                .map(|v| Vec3::new(v[0], v[1], v[2]))
                .collect();
            let alpha =
                (c.components == 4).then(|| c.values.chunks_exact(4).map(|v| v[3]).collect());
            (Some(rgb), alpha)
        }
        None => (None, None),
    };

    let max_corners = max_triangles.saturating_mul(3).saturating_add(2);
    let indices: Vec<u32> = match primitive.indices {
        Some(i) => accessor::read_indices(data, i.value(), max_corners)
            .map_err(|e| fail(format!("indices: {e}")))?,
        None => (0..n as u32).collect(),
    };
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(fail(format!("index {bad} out of range ({n} vertices)")));
    }
    let triangles: Vec<[u32; 3]> = match mode {
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
    if n == 0 || triangles.is_empty() {
        return Ok(Err(format!("{label} has no triangles; skipped")));
    }
    let mesh = match Mesh::new(path, positions, triangles, normals, colors) {
        Ok(mesh) => mesh,
        Err(MeshError::Invalid { message, .. }) => {
            return Ok(Err(format!("{label}: {message}; skipped")));
        }
        Err(e) => return Err(e),
    };
    Ok(Ok(Primitive {
        mesh,
        uvs,
        color_alpha,
        material: primitive.material.map(|m| m.value()),
        label,
    }))
}
