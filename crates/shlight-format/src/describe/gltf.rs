//! glTF and GLB assets: `shlight prt -o MESH.gltf|glb`'s mesh with its
//! transfer (`_SH_TRANSFER_k` attributes, the `.shprt` header in the
//! mesh's `extras.shlight_prt`), an `EXT_lights_image_based` light
//! (`--format gltf`, `convert --into`), or both.

use serde_json::Value;

use super::light::read_back;
use super::{Header, baked, plain};
use crate::Result;
use crate::export::gltf::{EXTENSION, read};

/// What `shlight lightmap -o` wrote: the root's `SHLIGHT_lightmap` `m`
/// and the nodes that carry one (docs/lightmaps.md).
fn lightmap_fields(h: &mut Header, v: &Value, m: &Value) {
    let text = |key: &str| m.get(key).map(plain).unwrap_or_default();
    h.field(
        "lightmap",
        format!(
            "{} for {} ({} reconstruction), texels in {}",
            text("basis"),
            text("engine"),
            text("reconstruction"),
            text("units")
        ),
    );
    let size = m
        .get("size")
        .and_then(Value::as_array)
        .map(|s| s.iter().map(plain).collect::<Vec<_>>().join(" x "))
        .unwrap_or_default();
    let layers = m
        .get("layers")
        .and_then(Value::as_array)
        .map(|l| l.iter().map(plain).collect::<Vec<_>>().join(", "))
        .unwrap_or_default();
    h.field(
        "atlas",
        format!(
            "{size} texels on TEXCOORD_{}, {} texels per metre; layers {layers} (half-float KTX2 pages)",
            text("texCoord"),
            text("texelsPerMetre")
        ),
    );
    let nodes = v.get("nodes").and_then(Value::as_array).map_or(0, |n| {
        n.iter()
            .filter(|n| n.pointer("/extensions/SHLIGHT_lightmap").is_some())
            .count()
    });
    h.field("baked nodes", nodes.to_string());
    h.field(
        "baked with",
        format!(
            "{} rays per texel, {} bounces, denoised over {} texels, lmax {} of {}, seed {}, lights in {} units; {}",
            text("samples"),
            text("bounces"),
            text("denoise"),
            text("lmax"),
            text("environment"),
            text("seed"),
            text("lightUnits"),
            text("generator")
        ),
    );
}

/// The asset's document `v` (a GLB's JSON chunk when `binary`).
pub(super) fn describe(v: &Value, name: &str, binary: bool) -> Result<Header> {
    let count = |key: &str| v.get(key).and_then(Value::as_array).map_or(0, Vec::len);
    let prt: Vec<&Value> = v
        .get("meshes")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|m| m.pointer("/extras/shlight_prt"))
        .collect();
    let light = v.pointer(&format!("/extensions/{EXTENSION}"));
    let lightmap = v.pointer("/extensions/SHLIGHT_lightmap");
    let holds = match (prt.is_empty(), light.is_none()) {
        (true, true) if lightmap.is_some() => ": a scene with shlight's lightmap",
        (false, false) => {
            ": a mesh with shlight's PRT transfer, and an EXT_lights_image_based light"
        }
        (false, true) => ": a mesh with shlight's PRT transfer",
        (true, false) => ": an EXT_lights_image_based light",
        (true, true) => "",
    };
    let mut h = Header::new(format!(
        "glTF {} asset ({}){holds}",
        v.pointer("/asset/version").map(plain).unwrap_or_default(),
        if binary {
            ".glb, binary"
        } else {
            ".gltf, JSON"
        }
    ));
    if let Some(g) = v.pointer("/asset/generator") {
        h.field("generator", plain(g));
    }
    h.field(
        "contents",
        format!(
            "{} scenes, {} nodes, {} meshes, {} accessors, {} images",
            count("scenes"),
            count("nodes"),
            count("meshes"),
            count("accessors"),
            count("images")
        ),
    );
    if let Some(m) = lightmap {
        lightmap_fields(&mut h, v, m);
    }
    for header in prt {
        let attributes = v
            .get("meshes")
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
            .filter(|m| m.pointer("/extras/shlight_prt") == Some(header))
            .filter_map(|m| {
                m.pointer("/primitives/0/attributes")
                    .and_then(Value::as_object)
            })
            .flat_map(|a| a.keys().filter(|k| k.starts_with("_SH_TRANSFER_")))
            .count();
        h.field(
            "transfer",
            format!(
                "_SH_TRANSFER_0 .. _SH_TRANSFER_{}: {attributes} VEC4 float attributes per \
                 vertex, the .shprt values in fours (padded with zeros)",
                attributes.saturating_sub(1)
            ),
        );
        baked::prt_fields(&mut h, header, name)?;
    }
    if light.is_some() {
        let imported = read(v, name)?;
        let lights = v
            .pointer(&format!("/extensions/{EXTENSION}/lights"))
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        let scene = v.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
        let index = v
            .get("scenes")
            .and_then(|s| s.get(scene))
            .and_then(|s| s.pointer(&format!("/extensions/{EXTENSION}/light")))
            .and_then(Value::as_u64)
            .unwrap_or(0) as usize;
        let l = v
            .pointer(&format!("/extensions/{EXTENSION}/lights/{index}"))
            .cloned()
            .unwrap_or(Value::Null);
        h.field(
            "light",
            format!(
                "\"{}\", light {index} of {lights}, used by scene {scene}",
                l.get("name").map(plain).unwrap_or_default()
            ),
        );
        h.field(
            "irradiance",
            "9 coefficients E_lm = A_l L_lm (lmax 2, Condon-Shortley phase), in Babylon.js's \
             world as its loader reads the light",
        );
        if let Some(i) = l.get("intensity") {
            h.field("intensity", plain(i));
        }
        h.field(
            "specular",
            match l.get("specularImages").and_then(Value::as_array) {
                Some(mips) => {
                    let size = l.get("specularImageSize").map(plain).unwrap_or_default();
                    let faces: usize = mips.iter().map(|m| m.as_array().map_or(0, Vec::len)).sum();
                    format!(
                        "{} mips from {size}x{size}, {faces} face images (the map prefiltered \
                         with the GGX lobe, RGBD PNG)",
                        mips.len()
                    )
                }
                None => "none (the light was written from coefficients alone)".into(),
            },
        );
        h.rows = read_back(&imported);
    }
    Ok(h)
}
