//! The lightmaps a lightmapped GLB holds ([`crate::write_lightmapped_glb`]'s
//! output), read back: the root's and the nodes' `SHLIGHT_lightmap`
//! extensions and the bytes of the pages the root names.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use crate::MeshError;
use crate::load::gltf_file::document::split_glb;

/// What [`read_lightmap_pages`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct LightmapPages {
    /// The root's `extensions.SHLIGHT_lightmap`.
    pub root: Value,
    /// Each node's `extensions.SHLIGHT_lightmap`, by node index.
    pub nodes: BTreeMap<usize, Value>,
    /// The encoded pages, in the order of the root's `images` (names of
    /// the file's images).
    pub pages: Vec<Vec<u8>>,
}

/// Reads the lightmaps of the GLB file `path`.
///
/// # Errors
/// A file that cannot be read, is not a GLB, has no root
/// `SHLIGHT_lightmap`, or whose named images are missing or lie outside
/// its binary chunk (each named).
pub fn read_lightmap_pages(path: &Path) -> Result<LightmapPages, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    lightmap_pages_from_bytes(path, &bytes)
}

/// The lightmaps of `path` when it is a GLB file with a root
/// `SHLIGHT_lightmap` extension (a scene `shlight lightmap` wrote), read
/// as [`read_lightmap_pages`] reads them; `None` for any other file (a
/// `.gltf`, a GLB without the extension), which a renderer then draws
/// without a lightmap.
///
/// # Errors
/// A file that cannot be read; a GLB with the extension whose pages
/// [`read_lightmap_pages`] refuses.
pub fn read_lightmap_pages_if_any(path: &Path) -> Result<Option<LightmapPages>, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if !bytes.starts_with(b"glTF") {
        return Ok(None);
    }
    let Ok((json, _)) = split_glb(&bytes) else {
        return Ok(None);
    };
    let has_root = serde_json::from_slice::<Value>(json)
        .is_ok_and(|doc| doc["extensions"]["SHLIGHT_lightmap"].is_object());
    if !has_root {
        return Ok(None);
    }
    lightmap_pages_from_bytes(path, &bytes).map(Some)
}

/// [`read_lightmap_pages`] of `bytes`, the file `path` (named in errors).
///
/// # Errors
/// As [`read_lightmap_pages`], the reading aside.
pub fn lightmap_pages_from_bytes(path: &Path, bytes: &[u8]) -> Result<LightmapPages, MeshError> {
    let fail = |message: String| MeshError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    if !bytes.starts_with(b"glTF") {
        return Err(fail(
            "a lightmapped scene is a binary glTF (.glb) file".into(),
        ));
    }
    let (json, bin) = split_glb(bytes).map_err(|e| fail(format!("not a valid GLB: {e}")))?;
    let doc: Value =
        serde_json::from_slice(json).map_err(|e| fail(format!("its JSON chunk: {e}")))?;
    let root = doc["extensions"]["SHLIGHT_lightmap"].clone();
    if !root.is_object() {
        return Err(fail(
            "it holds no SHLIGHT_lightmap extension: not a lightmap shlight wrote".into(),
        ));
    }
    let nodes = doc["nodes"]
        .as_array()
        .map(|nodes| {
            nodes
                .iter()
                .enumerate()
                .filter_map(|(k, n)| {
                    let e = &n["extensions"]["SHLIGHT_lightmap"];
                    e.is_object().then(|| (k, e.clone()))
                })
                .collect()
        })
        .unwrap_or_default();
    let bin = bin.unwrap_or_default();
    let names = root["images"].as_array().cloned().unwrap_or_default();
    let images = doc["images"].as_array().cloned().unwrap_or_default();
    let mut pages = Vec::with_capacity(names.len());
    for name in &names {
        let image = images
            .iter()
            .find(|i| i["name"] == *name)
            .ok_or_else(|| fail(format!("its lightmap page {name} is not among its images")))?;
        let view = image["bufferView"]
            .as_u64()
            .and_then(|v| doc["bufferViews"].get(v as usize))
            .ok_or_else(|| fail(format!("its lightmap page {name} has no buffer view")))?;
        let at = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = view["byteLength"].as_u64().unwrap_or(0) as usize;
        let page = at
            .checked_add(len)
            .and_then(|end| bin.get(at..end))
            .ok_or_else(|| {
                fail(format!(
                    "its lightmap page {name} lies outside its binary chunk"
                ))
            })?;
        pages.push(page.to_vec());
    }
    Ok(LightmapPages { root, nodes, pages })
}
