//! Baked files: `.shprt` transfer (and its header as a glTF's
//! `extras.shlight_prt`), `.shvol` volumes and their JSON form, and
//! three.js's grid made from a volume.

use std::path::Path;

use serde_json::Value;
use shlight_core::sh::sh_count;

use super::{Header, plain, uint};
use crate::{FormatError, Result, ShprtFile, ShvolFile, shprt, shvol};

/// A `.shprt` or `.shvol` file (a header line of JSON naming its format,
/// then binary data), read and checked whole; `None` for other bytes.
pub(super) fn describe_binary(bytes: &[u8], name: &str) -> Result<Option<Header>> {
    if bytes.first() != Some(&b'{') {
        return Ok(None);
    }
    let Some(end) = bytes
        .iter()
        .take(shvol::MAX_HEADER)
        .position(|&b| b == b'\n')
    else {
        return Ok(None);
    };
    let Ok(head) = serde_json::from_slice::<Value>(&bytes[..end]) else {
        return Ok(None);
    };
    let path = Path::new(name);
    match head.get("format").and_then(Value::as_str) {
        Some(shprt::FORMAT) => {
            let file = ShprtFile::from_bytes(bytes, path)?;
            let header = file.header();
            let mut h = Header::new(format!(
                "shlight PRT transfer (.shprt, format_version {}): {}",
                plain(&header["format_version"]),
                if file.glossy.is_some() {
                    "glossy"
                } else {
                    "diffuse"
                }
            ));
            prt_fields(&mut h, &header, name)?;
            Ok(Some(h))
        }
        // The JSON form is one line too: it holds the coefficients.
        Some(shvol::FORMAT) if head.get("coefficients").is_none() => {
            let file = ShvolFile::from_bytes(bytes, path)?;
            let header = file.header();
            let invalid = file.valid.iter().filter(|&&v| !v).count();
            let mut h = Header::new(format!(
                "shlight irradiance volume (.shvol, format_version {})",
                file.version()
            ));
            volume_fields(&mut h, &header, invalid, name)?;
            Ok(Some(h))
        }
        _ => Ok(None),
    }
}

/// The facts of a `.shprt` header (docs/shprt.md), from a file or a
/// glTF's `extras.shlight_prt`.
pub(super) fn prt_fields(h: &mut Header, header: &Value, name: &str) -> Result<()> {
    let what = "a PRT header";
    let lmax = uint(header, "lmax", what, name)? as usize;
    let nc = sh_count(lmax);
    let text = |key: &str| header.get(key).map(plain).unwrap_or_default();
    let glossy = text("mode") == "glossy";
    let mut holds = if glossy {
        format!(
            "a {nc}x{nc} transfer matrix per vertex and channel (rows: the transferred \
             radiance's coefficients, columns: the light's), and each vertex's position and normal"
        )
    } else {
        format!("a transfer vector of {nc} coefficients per vertex and channel (index l*(l+1)+m)")
    };
    if let Some((c, k)) = text("compression")
        .strip_prefix("cpca:")
        .and_then(|r| r.split_once(','))
    {
        holds.push_str(&format!(
            ", compressed by clustered PCA: {c} clusters of {k} basis vectors"
        ));
    }
    h.field("holds", holds);
    h.field("lmax", lmax.to_string());
    h.field(
        "vertices",
        uint(header, "vertex_count", what, name)?.to_string(),
    );
    h.field(
        "channels",
        match uint(header, "channels", what, name)? {
            1 => "1 (grey)".to_string(),
            3 => "3 (linear RGB)".to_string(),
            n => n.to_string(),
        },
    );
    if glossy {
        h.field("mode", format!("glossy, {} transport", text("transport")));
        h.field("brdf", text("brdf"));
    } else {
        h.field("mode", text("mode"));
    }
    h.field(
        "albedo",
        match header.get("albedo") {
            Some(Value::String(s)) if s == "vertex" => "per vertex (the mesh's colours)".into(),
            Some(a) => plain(a),
            None => String::new(),
        },
    );
    h.field("samples", format!("{} directions", text("samples")));
    h.field("bounces", text("bounces"));
    h.field("seed", text("seed"));
    h.field("mesh", format!("{} ({})", text("mesh"), text("mesh_hash")));
    if let Some(s) = header.get("static") {
        let lights = s.get("lights").filter(|l| !l.is_null()).map(|l| {
            let count = |k: &str| l.get(k).map(plain).unwrap_or_default();
            format!(
                "{} point, {} spot, {} directional lights ({} units)",
                count("point"),
                count("spot"),
                count("directional"),
                l.get("units").map(plain).unwrap_or_default()
            )
        });
        let emission = (s.get("emission") == Some(&Value::Bool(true)))
            .then(|| "emissive materials".to_string());
        let sources: Vec<String> = lights.into_iter().chain(emission).collect();
        h.field(
            "static",
            format!(
                "exit radiance per vertex added to T . L: {}",
                sources.join(" and ")
            ),
        );
    }
    Ok(())
}

/// The facts of a volume's header (docs/shvol.md), from a `.shvol` file's
/// header line or its JSON form; `invalid` probes are inside geometry.
fn volume_fields(h: &mut Header, header: &Value, invalid: usize, name: &str) -> Result<()> {
    let what = "a volume";
    let lmax = uint(header, "lmax", what, name)? as usize;
    let resolution = header
        .get("resolution")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_u64).collect::<Vec<_>>())
        .filter(|r| r.len() == 3)
        .ok_or_else(|| {
            FormatError::invalid(name, "a volume, but \"resolution\" is not [nx, ny, nz]")
        })?;
    let text = |key: &str| header.get(key).map(plain).unwrap_or_default();
    let holds: Vec<String> = header
        .get("holds")
        .and_then(Value::as_array)
        .map(|a| a.iter().map(plain).collect())
        .unwrap_or_default();
    let relightable = holds.iter().any(|s| s == "transfer");
    h.field(
        "holds",
        format!(
            "{}: {}",
            holds.join(", "),
            if relightable {
                "relightable (per probe and channel a transfer matrix M: L_probe = M L_env + L_emitted)"
            } else {
                "static (the radiance under the bake's environment)"
            }
        ),
    );
    let nc = sh_count(lmax);
    h.field(
        "lmax",
        format!("{lmax} ({nc} coefficients per probe and channel)"),
    );
    let [nx, ny, nz] = [resolution[0], resolution[1], resolution[2]];
    h.field(
        "grid",
        format!(
            "{nx} x {ny} x {nz} = {} probes at the cells' centres, x fastest",
            nx * ny * nz
        ),
    );
    h.field("invalid", format!("{invalid} probes (inside geometry)"));
    if let Some(moved) = header.get("relocated").and_then(Value::as_array) {
        h.field(
            "relocated",
            format!("{} probes moved out of geometry", moved.len()),
        );
    }
    let bounds = header.get("bounds");
    let corner = |k: &str| bounds.and_then(|b| b.get(k)).map(plain).unwrap_or_default();
    h.field(
        "bounds",
        format!("min {}, max {}", corner("min"), corner("max")),
    );
    h.field("frame", text("frame"));
    if let Some(v) = header.get("visibility") {
        let size = v.get("size").map(plain).unwrap_or_default();
        h.field(
            "visibility",
            format!(
                "a {size}x{size} octahedral map of distances per probe, max distance {}",
                v.get("max_distance").map(plain).unwrap_or_default()
            ),
        );
    }
    if let Some(l) = header.get("lights") {
        let count = |k: &str| l.get(k).map(plain).unwrap_or_default();
        let units = l.get("units").map(plain).unwrap_or_default();
        h.field(
            "lights",
            format!(
                "{} point, {} spot, {} directional (punctual, in the static light); intensities {}",
                count("point"),
                count("spot"),
                count("directional"),
                match units.as_str() {
                    "blender" => "divided by 683 (blender)".to_string(),
                    "as-written" => "as written".to_string(),
                    other => other.to_string(),
                }
            ),
        );
    }
    h.field("samples", format!("{} rays per probe", text("samples")));
    h.field("bounces", text("bounces"));
    h.field("seed", text("seed"));
    h.field(
        "scene",
        format!("{} ({})", text("scene"), text("scene_hash")),
    );
    h.field("environment", text("environment"));
    h.field("generator", text("generator"));
    Ok(())
}

/// A volume's JSON form (`shlight volume --format json`).
pub(super) fn describe_volume_json(v: &Value, name: &str) -> Result<Header> {
    let version = uint(v, "format_version", "a volume's JSON form", name)?;
    let valid = v.get("valid").and_then(Value::as_array).ok_or_else(|| {
        FormatError::invalid(
            name,
            "a volume's JSON form, but \"valid\" is missing or not a list",
        )
    })?;
    let invalid = valid.iter().filter(|b| b.as_bool() == Some(false)).count();
    let mut h = Header::new(format!(
        "shlight irradiance volume, JSON form (shlight volume --format json, format_version {version})"
    ));
    volume_fields(&mut h, v, invalid, name)?;
    Ok(h)
}

/// three.js's `LightProbeGridWebGL` document (`--format threejs` of a
/// volume; shlight-format's `threejs_volume`).
pub(super) fn describe_threejs_grid(v: &Value, name: &str) -> Result<Header> {
    let what = "three.js's LightProbeGrid document";
    let lmax = uint(v, "lmax", what, name)?;
    let mut h = Header::new(format!(
        "three.js LightProbeGrid ({} version {}): a volume as the atlas three.js's \
         LightProbeGridWebGL samples, for web/shlight-three.js's loadLightProbeGrid",
        crate::threejs_volume::DOCUMENT_TYPE,
        v.pointer("/metadata/version")
            .map(plain)
            .unwrap_or_default()
    ));
    h.field(
        "holds",
        format!(
            "radiance probes of lmax {lmax} in three.js's basis (no Condon-Shortley phase), \
             from a volume of lmax {}; invalid probes filled from their neighbours",
            v.get("sourceLmax").map(plain).unwrap_or_default()
        ),
    );
    let resolution: Vec<u64> = v
        .get("resolution")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_u64).collect())
        .unwrap_or_default();
    let [nx, ny, nz] = resolution[..] else {
        return Err(FormatError::invalid(
            name,
            format!("{what}, but \"resolution\" is not [nx, ny, nz]"),
        ));
    };
    h.field(
        "grid",
        format!(
            "{nx} x {ny} x {nz} = {} probes at the cells' centres",
            nx * ny * nz
        ),
    );
    let corner = |k: &str| {
        v.get("boundingBox")
            .and_then(|b| b.get(k))
            .map(plain)
            .unwrap_or_default()
    };
    h.field(
        "bounds",
        format!("min {}, max {}", corner("min"), corner("max")),
    );
    let atlas = v.get("atlas").cloned().unwrap_or(Value::Null);
    let a = |k: &str| atlas.get(k).map(plain).unwrap_or_default();
    h.field(
        "atlas",
        format!(
            "{} x {} x {} {} texels of {} ({} bytes, {})",
            a("width"),
            a("height"),
            a("depth"),
            a("format"),
            a("type"),
            a("byteLength"),
            a("encoding")
        ),
    );
    if let Some(p) = v.pointer("/shlight/provenance").and_then(Value::as_object) {
        for (key, value) in p {
            h.field(key.as_str(), plain(value));
        }
    }
    for key in ["generator", "writer"] {
        if let Some(g) = v.pointer(&format!("/metadata/{key}")) {
            h.field(key, plain(g));
        }
    }
    for note in v
        .get("notes")
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
    {
        h.field("note", plain(note));
    }
    Ok(h)
}
