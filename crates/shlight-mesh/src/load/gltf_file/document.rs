//! A glTF or GLB file to a validated document and its buffers' bytes.
//!
//! The JSON is parsed as `gltf::json::Root` (a GLB's chunks are split
//! here), the extensions shlight handles are taken out of
//! `extensionsRequired`, and `gltf::Document::from_json` runs every other
//! validation. A required extension shlight does not know is refused by
//! name; an optional one is ignored with a note.

use std::path::Path;

use gltf::json;

use super::{meshopt, uri};
use crate::{LoadOptions, MeshError};

/// The extensions the loader reads (`KHR_texture_basisu` is refused per
/// texture, where a material uses one without a PNG or JPEG fallback).
pub(super) const HANDLED: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_texture_transform",
    "KHR_materials_emissive_strength",
    "KHR_mesh_quantization",
    "EXT_mesh_gpu_instancing",
    "KHR_texture_basisu",
    super::meshopt::NAME,
];

/// Extensions whose data shlight cannot read: a file requiring one is
/// refused with the reason.
const UNREAD: &[(&str, &str)] = &[
    ("KHR_draco_mesh_compression", "Draco-compressed geometry"),
    (
        "KHR_meshopt_compression",
        "meshoptimizer-compressed buffers, Khronos's version",
    ),
];

/// A file read and validated.
pub(crate) struct Parsed {
    /// The validated document.
    pub root: json::Root,
    /// Each buffer's bytes (at least its `byteLength`).
    pub buffers: Vec<Vec<u8>>,
    /// What was passed over (optional extensions not read).
    pub notes: Vec<String>,
}

/// Parses `bytes` (glTF JSON or GLB); `path` names the file in errors and
/// locates external buffers.
pub(crate) fn parse(path: &Path, bytes: &[u8], options: &LoadOptions) -> Result<Parsed, MeshError> {
    let parse_error = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message,
    };
    let (json_bytes, bin) = if bytes.starts_with(b"glTF") {
        split_glb(bytes).map_err(|e| parse_error(format!("not a valid glTF file: {e}")))?
    } else {
        (bytes, None)
    };
    let mut root = json::Root::from_slice(json_bytes)
        .map_err(|e| parse_error(format!("not a valid glTF file: {e}")))?;

    let mut notes = Vec::new();
    let mut required = Vec::new();
    for name in std::mem::take(&mut root.extensions_required) {
        if HANDLED.contains(&name.as_str()) {
            continue;
        }
        if let Some((_, what)) = UNREAD.iter().find(|(n, _)| *n == name) {
            return Err(parse_error(format!(
                "requires extension {name} ({what}), which shlight does not read"
            )));
        }
        required.push(name);
    }
    if let Some(name) = required.first() {
        return Err(parse_error(format!(
            "requires extension {name}, which shlight does not read"
        )));
    }
    for name in &root.extensions_used {
        if !HANDLED.contains(&name.as_str()) {
            notes.push(format!(
                "the file uses extension {name}, which shlight does not read; ignored"
            ));
        }
    }

    // The gltf crate's validation indexes the accessor list with each
    // POSITION without a check (a panic): checked here first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive.attributes.get(&json::validation::Checked::Valid(
                json::mesh::Semantic::Positions,
            ));
            if let Some(a) = position
                && a.value() >= root.accessors.len()
            {
                return Err(parse_error(format!(
                    "not a valid glTF file: mesh {m} primitive {p}: POSITION names accessor {}, which does not exist",
                    a.value()
                )));
            }
        }
    }
    let mut buffers = load_buffers(path, &root, bin)?;
    meshopt::decode(path, &mut root, &mut buffers, options)?;
    let root = gltf::Document::from_json(root)
        .map_err(|e| parse_error(format!("not a valid glTF file: {}", short(&e.to_string()))))?
        .into_json();
    Ok(Parsed {
        root,
        buffers,
        notes,
    })
}

/// A validation report cut to its first few hundred characters (a broken
/// file may list thousands of faults).
fn short(message: &str) -> String {
    const MAX: usize = 400;
    match message.char_indices().nth(MAX) {
        Some((at, _)) => format!("{} ...", &message[..at]),
        None => message.to_string(),
    }
}

/// A GLB's JSON chunk and its BIN chunk, if any.
pub(crate) fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        bytes
            .get(at..at + 4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
    };
    let version = word(4).ok_or("the GLB header is cut short")?;
    if version != 2 {
        return Err(format!("GLB version {version}, expected 2"));
    }
    let length = word(8).ok_or("the GLB header is cut short")? as usize;
    if length < 12 || length > bytes.len() {
        return Err(format!(
            "the GLB header gives a length of {length} bytes, the file holds {}",
            bytes.len()
        ));
    }
    let bytes = &bytes[..length];
    let chunk = |at: usize| -> Result<Option<(u32, &[u8])>, String> {
        if at >= bytes.len() {
            return Ok(None);
        }
        let (Some(len), Some(kind)) = (word(at), word(at + 4)) else {
            return Err(format!("the chunk header at byte {at} is cut short"));
        };
        let start = at + 8;
        let end = start
            .checked_add(len as usize)
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| format!("the chunk at byte {at} ({len} bytes) runs past the file"))?;
        Ok(Some((kind, &bytes[start..end])))
    };
    const JSON: u32 = 0x4E4F_534A;
    const BIN: u32 = 0x004E_4942;
    let Some((JSON, json)) = chunk(12)? else {
        return Err("the first GLB chunk is not JSON".into());
    };
    let next = (12 + 8 + json.len()).next_multiple_of(4);
    let bin = match chunk(next)? {
        Some((BIN, bin)) => Some(bin),
        _ => None,
    };
    Ok((json, bin))
}

/// Every buffer's bytes: the GLB's BIN chunk for the first buffer without
/// a URI, data URIs and files beside the glTF file for the others. A
/// buffer shorter than its `byteLength` is an error.
fn load_buffers(
    path: &Path,
    root: &json::Root,
    bin: Option<&[u8]>,
) -> Result<Vec<Vec<u8>>, MeshError> {
    let parse_error = |message: String| MeshError::Parse {
        path: path.to_path_buf(),
        message,
    };
    let mut buffers = Vec::with_capacity(root.buffers.len());
    for (i, b) in root.buffers.iter().enumerate() {
        let data = match &b.uri {
            Some(u) => {
                uri::read(path, u)
                    .map_err(|e| parse_error(format!("buffer {i}: {e}")))?
                    .0
            }
            None if i == 0 => bin
                .ok_or_else(|| parse_error(format!("buffer {i} refers to a missing GLB chunk")))?
                .to_vec(),
            None if is_meshopt_fallback(b) => Vec::new(),
            None => {
                return Err(parse_error(format!(
                    "buffer {i} has no URI and is not the GLB's binary chunk"
                )));
            }
        };
        if (data.len() as u64) < b.byte_length.0 && !is_meshopt_fallback(b) {
            return Err(parse_error(format!(
                "buffer {i} holds {} bytes, the file says {}",
                data.len(),
                b.byte_length.0
            )));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// Whether a buffer is `EXT_meshopt_compression`'s placeholder for
/// decompressed data (it holds no bytes of its own).
fn is_meshopt_fallback(buffer: &json::Buffer) -> bool {
    buffer
        .extensions
        .as_ref()
        .and_then(|e| e.others.get("EXT_meshopt_compression"))
        .and_then(|m| m.get("fallback"))
        .and_then(serde_json::Value::as_bool)
        == Some(true)
}
