//! A glTF scene rewritten as one GLB with its lightmaps: everything the
//! input held (nodes, meshes, materials, textures, lights, extensions,
//! extras) kept as it was, and the baker's pages, textures and references
//! added.
//!
//! The input (GLB, or `.gltf` with external or data-URI buffers and
//! images) is read and validated as [`crate::load_scene`] reads it, and
//! its JSON is edited as JSON, so that nothing shlight does not model is
//! lost. The output:
//! - every buffer merged into the GLB's one BIN chunk, each 8-byte
//!   aligned, buffer views re-pointed (an `EXT_meshopt_compression`
//!   view's compressed source too; its byte-less fallback buffers stay
//!   buffers of their own); images given by URI embedded as buffer views
//!   (their `mimeType` from their first bytes when the input gave none);
//! - each [`LightmapImage`] appended as an image (a buffer view, its MIME
//!   type, its name) with a texture and one shared sampler (linear
//!   filtering without mips, clamp to edge); a KTX2 image is the texture's
//!   source through `KHR_texture_basisu` (`extensionsUsed`, not required),
//!   and the texture has no plain `source`;
//! - each material of a baked primitive given `MOZ_lightmap`
//!   (`{"index": texture, "texCoord": 1, "intensity": ...}`); a material
//!   also used by primitives that are not baked, or baked with another
//!   texture, is copied once per texture (the original kept for the
//!   others), and a primitive without a material gets a new default one;
//! - each baked node given `extensions.SHLIGHT_lightmap` (the caller's
//!   JSON), and the root `extensions.SHLIGHT_lightmap` (the caller's
//!   JSON);
//! - for a node baked with [`BakedNode::unshare`], a copy of its mesh
//!   whose primitives read a new `TEXCOORD_1` (float `VEC2`,
//!   `uv * scale + offset` of the original, integer and normalized
//!   `KHR_mesh_quantization` sets decoded first), every other attribute
//!   shared, so that a loader without per-node rectangles (three.js) reads
//!   the node's own texels.
//!
//! A baked primitive without `TEXCOORD_1` gets no `MOZ_lightmap` and no
//! new texture coordinates; it is named in [`LightmappedGlb::notes`].

mod bin_chunk;
mod json_lists;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use gltf::json::accessor::Type;
use serde_json::{Map, Value, json};

use crate::load::gltf_file::{accessor, document, uri};
use crate::{LoadOptions, MeshError};
use bin_chunk::BinChunk;
use json_lists::{array, array_mut, push};

/// An encoded lightmap page to embed.
#[derive(Clone, Debug)]
pub struct LightmapImage {
    /// The image's name in the file.
    pub name: String,
    /// How `bytes` are encoded.
    pub format: LightmapImageFormat,
    /// The encoded file (a PNG, or a KTX2 file such as
    /// `shlight_io::encode_ktx2` makes).
    pub bytes: Vec<u8>,
    /// `MOZ_lightmap.intensity` of the materials that read this page.
    pub intensity: f32,
}

/// The encoding of a [`LightmapImage`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightmapImageFormat {
    /// `image/png`, the texture's plain `source`.
    Png,
    /// `image/ktx2`, the texture's source through `KHR_texture_basisu`.
    Ktx2,
}

impl LightmapImageFormat {
    fn mime_type(self) -> &'static str {
        match self {
            Self::Png => "image/png",
            Self::Ktx2 => "image/ktx2",
        }
    }
}

/// One baked node (a mesh instance) and its rectangle of the atlas.
#[derive(Clone, Debug)]
pub struct BakedNode {
    /// The node's index in the input.
    pub node: usize,
    /// The rectangle: the node's lightmap coordinates are
    /// `TEXCOORD_1 * scale + offset` (Bevy's `Lightmap::uv_rect`, Unity's
    /// `lightmapScaleOffset`).
    pub scale: [f32; 2],
    /// See [`BakedNode::scale`].
    pub offset: [f32; 2],
    /// The [`LightmapRequest::images`] index that the node's materials get
    /// as `MOZ_lightmap`, or none for no `MOZ_lightmap`.
    pub image: Option<usize>,
    /// Whether the node gets its own copy of its mesh with the rectangle
    /// applied to `TEXCOORD_1` (see the module documentation). Nodes that
    /// share a mesh without it share its materials, so they must name the
    /// same image.
    pub unshare: bool,
    /// The node's `extensions.SHLIGHT_lightmap`.
    pub extension: Value,
}

/// What to add to a scene.
#[derive(Clone, Debug, Default)]
pub struct LightmapRequest {
    /// The pages, in the order their textures are appended.
    pub images: Vec<LightmapImage>,
    /// The baked nodes, each at most once.
    pub nodes: Vec<BakedNode>,
    /// The root's `extensions.SHLIGHT_lightmap` (basis, units, packing).
    pub root_extension: Value,
    /// The limits the input is read under, as [`crate::load_scene`]'s.
    pub load_options: LoadOptions,
}

/// What [`write_lightmapped_glb`] made.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LightmappedGlb {
    /// The texture index of each [`LightmapRequest::images`] entry.
    pub textures: Vec<usize>,
    /// The mesh each baked node places in the output, in
    /// [`LightmapRequest::nodes`] order (a new mesh where unshared).
    pub meshes: Vec<usize>,
    /// What was passed over or may surprise (a baked primitive without
    /// `TEXCOORD_1`, a baked mesh also placed by a node not baked).
    pub notes: Vec<String>,
}

/// Reads the glTF file `input`, adds `request`'s lightmaps and writes
/// the result to `output` as one GLB, atomically.
///
/// # Errors
/// [`MeshError`] naming `input` when it cannot be read or is not valid
/// glTF, or when the request names nodes, meshes or images that do not
/// exist (or shared meshes with different images), and naming `output`
/// when it cannot be written.
pub fn write_lightmapped_glb(
    input: &Path,
    output: &Path,
    request: &LightmapRequest,
) -> Result<LightmappedGlb, MeshError> {
    let bytes = std::fs::read(input).map_err(|source| MeshError::Io {
        path: input.to_path_buf(),
        source,
    })?;
    let (glb, made) = lightmapped_glb(input, &bytes, request)?;
    shlight_io::write_atomically(output, |w| w.write_all(&glb)).map_err(MeshError::Write)?;
    Ok(made)
}

/// [`write_lightmapped_glb`] of `bytes` (the file `input`, which locates
/// external buffers and images), giving the GLB's bytes.
///
/// # Errors
/// As [`write_lightmapped_glb`], less the write.
pub fn lightmapped_glb(
    input: &Path,
    bytes: &[u8],
    request: &LightmapRequest,
) -> Result<(Vec<u8>, LightmappedGlb), MeshError> {
    let invalid = |message: String| MeshError::Invalid {
        path: input.to_path_buf(),
        message,
    };
    let parse_error = |message: String| MeshError::Parse {
        path: input.to_path_buf(),
        message,
    };
    let parsed = document::parse(input, bytes, &request.load_options)?;
    let json_bytes = if bytes.starts_with(b"glTF") {
        document::split_glb(bytes)
            .map_err(|e| parse_error(format!("not a valid glTF file: {e}")))?
            .0
    } else {
        bytes
    };
    let mut doc: Value = serde_json::from_slice(json_bytes)
        .map_err(|e| parse_error(format!("not a valid glTF file: {e}")))?;
    let root = doc
        .as_object_mut()
        .ok_or_else(|| parse_error("not a valid glTF file: the JSON is not an object".into()))?;
    check_request(root, request).map_err(invalid)?;

    let mut bin = BinChunk::default();
    merge_buffers(root, &parsed.buffers, &mut bin);
    embed_images(input, root, &mut bin).map_err(invalid)?;
    let textures = add_images(root, &request.images, &mut bin);

    let data = accessor::Data {
        root: &parsed.root,
        buffers: &parsed.buffers,
    };
    let mut notes = Vec::new();
    let mut meshes = Vec::with_capacity(request.nodes.len());
    // The image each output primitive (mesh, primitive) is baked with.
    let mut baked: BTreeMap<(usize, usize), Option<usize>> = BTreeMap::new();
    let mut baked_by: BTreeMap<usize, (usize, Option<usize>)> = BTreeMap::new();
    for n in &request.nodes {
        let original = node_mesh(root, n.node).expect("checked");
        let mesh = if n.unshare {
            unshare(root, data, &mut bin, n, original).map_err(invalid)?
        } else {
            if let Some(&(other, image)) = baked_by.get(&original)
                && image != n.image
            {
                return Err(invalid(format!(
                    "nodes {other} and {} place mesh {original} with different lightmap images; \
                     they need their own copies of it (unshared)",
                    n.node
                )));
            }
            baked_by.insert(original, (n.node, n.image));
            original
        };
        meshes.push(mesh);
        set_extension(
            &mut root["nodes"][n.node],
            "SHLIGHT_lightmap",
            n.extension.clone(),
        );
        for (p, primitive) in primitives(root, mesh).iter().enumerate() {
            if primitive.pointer("/attributes/TEXCOORD_1").is_none() {
                notes.push(format!(
                    "node {}: mesh {original} primitive {p} has no TEXCOORD_1; it gets no lightmap",
                    n.node
                ));
                continue;
            }
            baked.insert((mesh, p), n.image);
        }
    }
    for (mesh, (node, _)) in &baked_by {
        for (n, _) in placing_nodes(root).filter(|(_, m)| m == mesh) {
            if !request.nodes.iter().any(|b| b.node == n) {
                notes.push(format!(
                    "mesh {mesh} is baked for node {node} and also placed by node {n}, which is not \
                     baked; its materials read the lightmap there too"
                ));
            }
        }
    }
    let any_lightmap = assign_materials(root, &baked, &textures, &request.images);

    set_extension_in(root, "SHLIGHT_lightmap", request.root_extension.clone());
    let mut used = vec!["SHLIGHT_lightmap"];
    if any_lightmap {
        used.push("MOZ_lightmap");
    }
    if request
        .images
        .iter()
        .any(|i| i.format == LightmapImageFormat::Ktx2)
    {
        used.push("KHR_texture_basisu");
    }
    let list = root
        .entry("extensionsUsed")
        .or_insert_with(|| Value::Array(Vec::new()));
    if let Value::Array(list) = list {
        for name in used {
            if !list.iter().any(|v| v == name) {
                list.push(name.into());
            }
        }
    }

    let glb = bin.into_glb(root).map_err(invalid)?;
    Ok((
        glb,
        LightmappedGlb {
            textures,
            meshes,
            notes,
        },
    ))
}

/// Checks the request against the document: nodes that exist, once each,
/// with a mesh; images that exist.
fn check_request(root: &Map<String, Value>, request: &LightmapRequest) -> Result<(), String> {
    let node_count = array(root, "nodes").len();
    let mut seen = BTreeSet::new();
    for n in &request.nodes {
        if n.node >= node_count {
            return Err(format!(
                "the lightmap names node {}, which does not exist (the file has {node_count} nodes)",
                n.node
            ));
        }
        if !seen.insert(n.node) {
            return Err(format!("the lightmap names node {} twice", n.node));
        }
        if node_mesh(root, n.node).is_none() {
            return Err(format!(
                "the lightmap names node {}, which places no mesh",
                n.node
            ));
        }
        if let Some(i) = n.image
            && i >= request.images.len()
        {
            return Err(format!(
                "node {} is given lightmap image {i}, which does not exist ({} images)",
                n.node,
                request.images.len()
            ));
        }
    }
    Ok(())
}

/// The mesh node `node` places, if any.
fn node_mesh(root: &Map<String, Value>, node: usize) -> Option<usize> {
    array(root, "nodes")
        .get(node)?
        .get("mesh")?
        .as_u64()
        .map(|m| m as usize)
}

/// Every (node, mesh) pair of the document.
fn placing_nodes(root: &Map<String, Value>) -> impl Iterator<Item = (usize, usize)> + '_ {
    (0..array(root, "nodes").len()).filter_map(|n| node_mesh(root, n).map(|m| (n, m)))
}

/// Mesh `mesh`'s primitives.
fn primitives(root: &Map<String, Value>, mesh: usize) -> Vec<Value> {
    array(root, "meshes")
        .get(mesh)
        .and_then(|m| m.get("primitives"))
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default()
}

/// Sets `extensions.NAME` of `object` (a JSON object) to `value`.
fn set_extension(object: &mut Value, name: &str, value: Value) {
    let Some(object) = object.as_object_mut() else {
        return;
    };
    set_extension_in(object, name, value);
}

fn set_extension_in(object: &mut Map<String, Value>, name: &str, value: Value) {
    let extensions = object
        .entry("extensions")
        .or_insert_with(|| Value::Object(Map::new()));
    if !extensions.is_object() {
        *extensions = Value::Object(Map::new());
    }
    extensions
        .as_object_mut()
        .expect("an object")
        .insert(name.to_string(), value);
}

/// Moves every buffer's bytes into `bin` and re-points the buffer views;
/// `EXT_meshopt_compression` fallback buffers (no bytes) stay buffers of
/// their own. `bytes[i]` is buffer `i`'s content as loaded.
fn merge_buffers(root: &mut Map<String, Value>, bytes: &[Vec<u8>], bin: &mut BinChunk) {
    let buffers = std::mem::take(array_mut(root, "buffers"));
    // Buffer 0 is the merged one; fallbacks follow.
    let mut kept = vec![Value::Null];
    let mut moved: Vec<(usize, usize)> = Vec::with_capacity(buffers.len());
    for (i, buffer) in buffers.into_iter().enumerate() {
        let fallback = buffer
            .pointer("/extensions/EXT_meshopt_compression/fallback")
            .and_then(Value::as_bool)
            == Some(true);
        if fallback {
            let mut buffer = buffer;
            if let Some(b) = buffer.as_object_mut() {
                b.remove("uri");
            }
            kept.push(buffer);
            moved.push((kept.len() - 1, 0));
            continue;
        }
        let length = buffer
            .get("byteLength")
            .and_then(Value::as_u64)
            .unwrap_or(0) as usize;
        let data = bytes.get(i).map_or(&[][..], |b| &b[..length.min(b.len())]);
        moved.push((0, bin.push(data)));
    }
    for view in array_mut(root, "bufferViews") {
        repoint(view, &moved);
        if let Some(ext) = view.pointer_mut("/extensions/EXT_meshopt_compression") {
            repoint(ext, &moved);
        }
    }
    bin.set_buffers(kept);
}

/// `buffer` and `byteOffset` of `view` moved by `moved[buffer]`.
fn repoint(view: &mut Value, moved: &[(usize, usize)]) {
    let Some(view) = view.as_object_mut() else {
        return;
    };
    let Some(&(buffer, offset)) = view
        .get("buffer")
        .and_then(Value::as_u64)
        .and_then(|b| moved.get(b as usize))
    else {
        return;
    };
    let old = view.get("byteOffset").and_then(Value::as_u64).unwrap_or(0);
    view.insert("buffer".into(), buffer.into());
    if old + offset as u64 != 0 || view.contains_key("byteOffset") {
        view.insert("byteOffset".into(), (old + offset as u64).into());
    }
}

/// Embeds every image given by URI (a data URI or a file beside `input`)
/// as a buffer view.
fn embed_images(
    input: &Path,
    root: &mut Map<String, Value>,
    bin: &mut BinChunk,
) -> Result<(), String> {
    let count = array(root, "images").len();
    for i in 0..count {
        let Some(uri) = root["images"][i].get("uri").and_then(Value::as_str) else {
            continue;
        };
        let (bytes, _) = uri::read(input, uri).map_err(|e| format!("image {i}: {e}"))?;
        let mime = root["images"][i]
            .get("mimeType")
            .and_then(Value::as_str)
            .map(str::to_string)
            .or_else(|| sniff_mime_type(&bytes).map(str::to_string))
            .ok_or_else(|| {
                format!("image {i}: neither a MIME type nor a PNG, JPEG, WebP or KTX2 signature")
            })?;
        let view = bin.push_view(root, &bytes);
        let image = root["images"][i].as_object_mut().expect("an object");
        image.remove("uri");
        image.insert("bufferView".into(), view.into());
        image.insert("mimeType".into(), mime.into());
    }
    Ok(())
}

/// The MIME type of an image file's first bytes, if known.
fn sniff_mime_type(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some("image/png")
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        Some("image/jpeg")
    } else if bytes.starts_with(b"\xABKTX 20\xBB") {
        Some("image/ktx2")
    } else if bytes.len() >= 12 && bytes.starts_with(b"RIFF") && &bytes[8..12] == b"WEBP" {
        Some("image/webp")
    } else {
        None
    }
}

/// Appends the lightmap images, one sampler and a texture per image,
/// giving the textures' indices.
fn add_images(
    root: &mut Map<String, Value>,
    images: &[LightmapImage],
    bin: &mut BinChunk,
) -> Vec<usize> {
    if images.is_empty() {
        return Vec::new();
    }
    // LINEAR (9729) both ways, no mips; CLAMP_TO_EDGE (33071).
    let sampler = push(
        root,
        "samplers",
        json!({"magFilter": 9729, "minFilter": 9729, "wrapS": 33071, "wrapT": 33071}),
    );
    images
        .iter()
        .map(|image| {
            let view = bin.push_view(root, &image.bytes);
            let source = push(
                root,
                "images",
                json!({"bufferView": view, "mimeType": image.format.mime_type(), "name": image.name}),
            );
            let texture = match image.format {
                LightmapImageFormat::Png => {
                    json!({"source": source, "sampler": sampler, "name": image.name})
                }
                LightmapImageFormat::Ktx2 => json!({
                    "sampler": sampler,
                    "name": image.name,
                    "extensions": {"KHR_texture_basisu": {"source": source}},
                }),
            };
            push(root, "textures", texture)
        })
        .collect()
}

/// A copy of mesh `mesh` for node `n`, its primitives' `TEXCOORD_1`
/// replaced by `uv * scale + offset` in a new float accessor; the node
/// placed with it. Gives the new mesh's index.
fn unshare(
    root: &mut Map<String, Value>,
    data: accessor::Data,
    bin: &mut BinChunk,
    n: &BakedNode,
    mesh: usize,
) -> Result<usize, String> {
    let mut copy = array(root, "meshes")
        .get(mesh)
        .cloned()
        .ok_or_else(|| format!("node {} places mesh {mesh}, which does not exist", n.node))?;
    if let Some(name) = copy.get("name").and_then(Value::as_str) {
        copy["name"] = format!("{name} (lightmapped for node {})", n.node).into();
    }
    let count = copy
        .get("primitives")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    for p in 0..count {
        let primitive = &mut copy["primitives"][p];
        let Some(uv) = primitive
            .pointer("/attributes/TEXCOORD_1")
            .and_then(Value::as_u64)
        else {
            continue;
        };
        let floats = accessor::read_floats(data, uv as usize, &[Type::Vec2], usize::MAX)
            .map_err(|e| format!("mesh {mesh} primitive {p}: TEXCOORD_1: {e}"))?;
        let moved: Vec<[f32; 2]> = floats
            .elements::<2>()
            .map(|[u, v]| {
                [
                    (f64::from(u) * f64::from(n.scale[0]) + f64::from(n.offset[0])) as f32,
                    (f64::from(v) * f64::from(n.scale[1]) + f64::from(n.offset[1])) as f32,
                ]
            })
            .collect();
        let accessor = bin.push_vec2_accessor(root, &moved);
        primitive["attributes"]["TEXCOORD_1"] = accessor.into();
    }
    let index = push(root, "meshes", copy);
    root["nodes"][n.node]["mesh"] = index.into();
    Ok(index)
}

/// Gives each baked primitive's material `MOZ_lightmap`, copying
/// materials shared with primitives not baked or baked with another
/// image, and making a default material for primitives without one.
/// Whether any material got one.
fn assign_materials(
    root: &mut Map<String, Value>,
    baked: &BTreeMap<(usize, usize), Option<usize>>,
    textures: &[usize],
    images: &[LightmapImage],
) -> bool {
    // Who uses each material (None: the default material): the images it
    // is baked with, and whether a placed primitive reads it unbaked.
    let placed: BTreeSet<usize> = placing_nodes(root).map(|(_, m)| m).collect();
    let mut users: BTreeMap<Option<usize>, (BTreeSet<usize>, bool)> = BTreeMap::new();
    for &mesh in &placed {
        for (p, primitive) in primitives(root, mesh).iter().enumerate() {
            let material = primitive
                .get("material")
                .and_then(Value::as_u64)
                .map(|m| m as usize);
            let entry = users.entry(material).or_default();
            match baked.get(&(mesh, p)) {
                Some(Some(image)) => {
                    entry.0.insert(*image);
                }
                Some(None) => {}
                None => entry.1 = true,
            }
        }
    }
    // The material each (original material, image) pair becomes.
    let mut chosen: BTreeMap<(Option<usize>, usize), usize> = BTreeMap::new();
    for (&material, (with, unbaked)) in &users {
        for &image in with {
            let lightmap = json!({
                "index": textures[image],
                "texCoord": 1,
                "intensity": images[image].intensity,
            });
            let target = match material {
                Some(m) if with.len() == 1 && !unbaked => m,
                Some(m) => {
                    let mut copy = root["materials"][m].clone();
                    if let Some(name) = copy.get("name").and_then(Value::as_str) {
                        copy["name"] = format!("{name} (lightmap {})", images[image].name).into();
                    }
                    push(root, "materials", copy)
                }
                None => push(
                    root,
                    "materials",
                    json!({"name": format!("default (lightmap {})", images[image].name)}),
                ),
            };
            set_extension(&mut root["materials"][target], "MOZ_lightmap", lightmap);
            chosen.insert((material, image), target);
        }
    }
    for (&(mesh, p), image) in baked {
        let Some(image) = image else { continue };
        let primitive = &mut root["meshes"][mesh]["primitives"][p];
        let material = primitive
            .get("material")
            .and_then(Value::as_u64)
            .map(|m| m as usize);
        if let Some(&target) = chosen.get(&(material, *image)) {
            primitive["material"] = target.into();
        }
    }
    !chosen.is_empty()
}
