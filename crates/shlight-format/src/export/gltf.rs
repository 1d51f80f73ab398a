//! `gltf`: a complete glTF 2.0 asset holding one `EXT_lights_image_based`
//! light with `irradianceCoefficients`, referenced by its one scene; and
//! [`add_light`], which adds the same light to an existing asset (`.gltf`
//! or `.glb`) without changing anything else in it.
//!
//! # The asset
//!
//! `asset` (`version` 2.0, `generator`), `extensionsUsed`, the light under
//! `extensions.EXT_lights_image_based.lights`, and `scenes[0]` (the default
//! `scene`) with `extensions.EXT_lights_image_based.light` naming it, as the
//! extension's text asks. The Khronos glTF validator reports no errors for
//! it (it does not know the vendor extension, and says so as information).
//!
//! # What the numbers are
//!
//! `irradianceCoefficients` is a 9 x 3 array: 9 coefficients in the order
//! `L00, L1-1, L10, L11, L2-2, L2-1, L20, L21, L22`, each `[r, g, b]`.
//!
//! - **Irradiance** coefficients `E_lm = A_l L_lm` (Ramamoorthi & Hanrahan
//!   2001), `A = (pi, 2 pi / 3, pi / 4)`, in the orthonormal basis **with**
//!   the Condon-Shortley phase.
//! - Why: the extension's text (KhronosGroup/glTF
//!   `extensions/2.0/Vendor/EXT_lights_image_based/README.md`) says only
//!   "spherical harmonic coefficients for irradiance up to l=2 ... a 9x3
//!   array" and cites R&H 2001 and metashapes.com; it fixes neither phase
//!   nor normalisation. Its reference implementation, Babylon.js's loader
//!   (`packages/dev/loaders/src/glTF/2.0/Extensions/EXT_lights_image_based.ts`), does
//!   `SphericalHarmonics.FromArray(light.irradianceCoefficients)` (nested
//!   `[[r, g, b] x 9]`), `scaleInPlace(light.intensity)`,
//!   `convertIrradianceToLambertianRadiance()` (times `1/pi`) and evaluates
//!   with `SH3ylmBasisConstants` (`-sqrt(3/4pi)` for `l1_1` and `l11`,
//!   `-sqrt(15/4pi)` for `l2_1` and `l21`: the CS phase). So Babylon takes
//!   them as irradiance `E_lm` in the phase-carrying basis, which is what
//!   this writes; Babylon's own `CubeMapToSphericalPolynomialTools`
//!   computes its harmonics the same way (`convertIncidentRadianceToIrradiance`).
//! - **Frame**: the world Babylon.js looks the light up in. Babylon's
//!   loader puts the asset into its left-handed world through a root node
//!   that mirrors glTF's x, but evaluates `irradianceCoefficients` and
//!   looks `specularImages` up at its own world directions, undoing no
//!   mirror (tests/web.rs renders it). So shlight writes the light in
//!   Babylon's world: shlight's y-up `(x, y, z)` is `(z, y, x)`
//!   ([`super::engine_frame`]), where Babylon's own panorama mapping puts
//!   the map, and where the Khronos glTF Sample Viewer's picture of it
//!   (glTF `(-z, y, x)`) lands once the root node has mirrored it: the
//!   light sits around the asset as the Sample Viewer would show the map.
//!   A z-up file is turned to y-up first. `rotation` is the identity,
//!   `intensity` 1.
//! - **lmax 2** exactly.
//!
//! # The specular images
//!
//! The extension also requires `specularImageSize` and `specularImages`:
//! the environment prefiltered with the GGX lobe, `specularImages[k][f]`
//! the image of face `f` of mip `k`, faces in the order `+X -X +Y -Y +Z -Z`.
//! [`render`] writes them from [`SpecularImages`] (made by shlight-pipeline
//! from the map: shlight-specular's prefilter for Babylon.js, its
//! roughness per mip, each face RGBD-encoded, Babylon's `toRGBD`, as an
//! 8-bit RGBA PNG) as `images` with `data:image/png;base64,` URIs:
//! `specularImageSize` is the face size of mip 0 and the mips run down to
//! one pixel (`size >> k`). Faces are in the frame of the coefficients,
//! in the OpenGL cube-map convention, each PNG's rows bottom first
//! (Babylon puts a PNG's first row at the bottom of the face; the
//! extension's text asks for the images flipped).
//! Without them ([`render`] with `None`, `shlight convert
//! --irradiance-only`) the light lacks what the extension requires and a
//! note says so; [`super::export`] refuses to write such a light.

use std::path::Path;

use base64::Engine as _;
use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::sh::{Frame, ShCoeffs};

use super::{
    ExportFormat, ExportInput, Exported, engine_coeffs, engine_frame, rgb_array, transform,
};
use crate::{FormatError, Imported, Quantity, Result};

/// The extension's name.
pub const EXTENSION: &str = "EXT_lights_image_based";

/// The note every export carries: what the extension requires that
/// shlight does not write.
const SPECULAR_NOTE: &str = "EXT_lights_image_based also requires specularImages and \
     specularImageSize (the prefiltered cube map); shlight writes only the irradiance \
     coefficients, so a loader lights diffuse surfaces from them and needs its own \
     specular environment";

/// The prefiltered specular cube of an `EXT_lights_image_based` light:
/// per mip, six PNG files (RGBD, faces `+X -X +Y -Y +Z -Z`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpecularImages {
    /// Face size of mip 0 (`specularImageSize`).
    pub size: usize,
    /// Mip 0 first, each `size >> k` pixels a side; the PNG bytes of each
    /// face.
    pub mips: Vec<[Vec<u8>; 6]>,
}

/// Why a glTF light cannot be written from coefficients alone.
pub const MISSING_SPECULAR: &str = "a glTF EXT_lights_image_based light requires \
     specularImages and specularImageSize (the environment prefiltered into cube mips), \
     which coefficients cannot give: project the map itself to a glTF light, or write the \
     light from its coefficients alone, irradiance only, without them";

/// The light object: `irradianceCoefficients` of `input`, and what they
/// are in words under `extras.shlight`.
fn light(input: &ExportInput<'_>) -> Result<(Value, Vec<String>)> {
    let (e, mut notes) = engine_coeffs(input, Quantity::Irradiance, ExportFormat::Gltf)?;
    notes.push(SPECULAR_NOTE.into());
    let coeffs: Vec<[f64; 3]> = e.as_slice().iter().map(|v| rgb_array(*v)).collect();
    let light = json!({
        "name": "shlight",
        "intensity": 1.0,
        "rotation": [0.0, 0.0, 0.0, 1.0],
        "irradianceCoefficients": coeffs,
        "extras": {
            "shlight": {
                "irradianceCoefficients": "irradiance E_lm = A_l L_lm (A = pi, 2pi/3, pi/4), order L00 L1-1 L10 L11 L2-2 L2-1 L20 L21 L22, [r, g, b] linear Rec.709",
                "basis": "real orthonormal SH with the Condon-Shortley phase (as Babylon.js's SH3ylmBasisConstants)",
                "frame": "Babylon.js's world, as its glTF loader reads the light (left-handed, +Y up: the glTF world with x mirrored); the map's centre at +Z",
                "missing": "specularImages and specularImageSize (required by the extension) are not written",
            }
        },
    });
    Ok((light, notes))
}

/// Renders the glTF asset, with `specular`'s images when given (module
/// docs), else the irradiance coefficients alone with a note.
///
/// # Errors
/// As [`super::export_coeffs`].
pub fn render(input: &ExportInput<'_>, specular: Option<&SpecularImages>) -> Result<Exported> {
    let (mut light, mut notes) = light(input)?;
    let mut images = Vec::new();
    if let Some(spec) = specular {
        notes.retain(|n| n != SPECULAR_NOTE);
        let extras = &mut light["extras"]["shlight"];
        if let Some(o) = extras.as_object_mut() {
            o.remove("missing");
            o.insert(
                "specularImages".into(),
                json!(format!(
                    "the environment GGX-prefiltered for Babylon.js (mip k at alphaG = {}^(k/{} - 1), mip 0 a mirror), {} mips of {}x{} down to 1x1, faces +X -X +Y -Y +Z -Z in the frame of the coefficients (OpenGL cube-map convention, each PNG's rows bottom first, as Babylon's loader reads them), RGBD as Babylon's toRGBD (rgb = (c D)^(1/2.2), alpha = D), 8-bit RGBA PNG",
                    spec.size,
                    spec.mips.len().saturating_sub(1).max(1),
                    spec.mips.len(),
                    spec.size,
                    spec.size
                )),
            );
        }
        let mut mips = Vec::new();
        for faces in &spec.mips {
            let mut row = Vec::new();
            for png in faces {
                row.push(images.len());
                images.push(json!({
                    "uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(png)),
                }));
            }
            mips.push(row);
        }
        light["specularImageSize"] = json!(spec.size);
        light["specularImages"] = json!(mips);
    }
    let mut doc = json!({
        "asset": {
            "version": "2.0",
            "generator": concat!("shlight ", env!("CARGO_PKG_VERSION")),
        },
        "extensionsUsed": [EXTENSION],
        "extensions": { EXTENSION: { "lights": [light] } },
        "scene": 0,
        "scenes": [{
            "name": "shlight",
            "extensions": { EXTENSION: { "light": 0 } },
        }],
    });
    if !images.is_empty() {
        doc["images"] = json!(images);
    }
    Ok(Exported {
        text: serde_json::to_string_pretty(&doc).expect("JSON values serialise") + "\n",
        notes,
    })
}

/// `glTF`, the first four bytes of a GLB file.
const GLB_MAGIC: u32 = 0x4654_6C67;
/// The JSON chunk's type, `JSON`.
const CHUNK_JSON: u32 = 0x4E4F_534A;
/// The binary chunk's type, `BIN\0`.
const CHUNK_BIN: u32 = 0x004E_4942;

/// Whether `bytes` start like a GLB (binary glTF) file.
#[must_use]
pub fn is_glb(bytes: &[u8]) -> bool {
    bytes.len() >= 4 && u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) == GLB_MAGIC
}

/// A GLB file's parts: the JSON document and every chunk after it
/// (type and bytes, kept as they are).
struct Glb {
    json: Value,
    rest: Vec<(u32, Vec<u8>)>,
}

fn read_glb(bytes: &[u8], name: &str) -> Result<Glb> {
    let bad = |message: String| FormatError::invalid(name, message);
    let word = |at: usize| -> Result<u32> {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .ok_or_else(|| bad(format!("truncated GLB (ends at byte {})", bytes.len())))
    };
    let version = word(4)?;
    if version != 2 {
        return Err(bad(format!(
            "GLB version {version} (shlight reads version 2)"
        )));
    }
    let length = word(8)? as usize;
    if length != bytes.len() {
        return Err(bad(format!(
            "the GLB header says {length} bytes, the file has {}",
            bytes.len()
        )));
    }
    let mut at = 12;
    let mut chunks = Vec::new();
    while at < length {
        let size = word(at)? as usize;
        let kind = word(at + 4)?;
        let data = bytes
            .get(at + 8..)
            .and_then(|b| b.get(..size))
            .ok_or_else(|| bad(format!("truncated GLB chunk at byte {at}")))?;
        chunks.push((kind, data.to_vec()));
        at += 8 + size;
    }
    let mut chunks = chunks.into_iter();
    let json = match chunks.next() {
        Some((CHUNK_JSON, data)) => serde_json::from_slice(&data)
            .map_err(|e| bad(format!("the GLB's JSON chunk is not valid JSON ({e})")))?,
        _ => return Err(bad("a GLB whose first chunk is not JSON".into())),
    };
    Ok(Glb {
        json,
        rest: chunks.collect(),
    })
}

fn write_glb(glb: &Glb) -> Vec<u8> {
    let mut json = serde_json::to_vec(&glb.json).expect("JSON values serialise");
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut chunks = vec![(CHUNK_JSON, json)];
    for (kind, data) in &glb.rest {
        let mut data = data.clone();
        // Chunks are 4-byte aligned; BIN pads with zeros.
        while data.len() % 4 != 0 {
            data.push(if *kind == CHUNK_BIN { 0 } else { b' ' });
        }
        chunks.push((*kind, data));
    }
    let length = 12 + chunks.iter().map(|(_, d)| 8 + d.len()).sum::<usize>();
    let mut out = Vec::with_capacity(length);
    out.extend(GLB_MAGIC.to_le_bytes());
    out.extend(2u32.to_le_bytes());
    out.extend((length as u32).to_le_bytes());
    for (kind, data) in chunks {
        out.extend((data.len() as u32).to_le_bytes());
        out.extend(kind.to_le_bytes());
        out.extend(data);
    }
    out
}

/// The JSON document of a GLB file.
///
/// # Errors
/// [`FormatError::Invalid`] naming `name` for a broken container.
pub fn glb_json(bytes: &[u8], name: &str) -> Result<Value> {
    read_glb(bytes, name).map(|glb| glb.json)
}

/// Adds the light of `input` to the glTF asset `scene` (the bytes of a
/// `.gltf` or `.glb` file, told apart by content; `name` names it in
/// errors) and returns the new file's bytes in the same container.
///
/// The light is appended to `extensions.EXT_lights_image_based.lights`
/// (a light named `shlight` already there is replaced instead, so running
/// it twice gives one light), the extension is added to `extensionsUsed`,
/// and the default scene (`scene`, else scene 0) is pointed at the light.
/// Nothing else changes: every other property, and a GLB's binary chunk
/// byte for byte, stays as it was.
///
/// # Errors
/// [`FormatError::Invalid`] when `scene` is not a glTF 2.0 asset;
/// as [`super::export_coeffs`] for the coefficients.
pub fn add_light(
    input: &ExportInput<'_>,
    scene: &[u8],
    name: &str,
) -> Result<(Vec<u8>, Vec<String>)> {
    let bad = |message: &str| FormatError::invalid(name, message.to_string());
    let glb = is_glb(scene);
    let mut file = if glb {
        read_glb(scene, name)?
    } else {
        let json = serde_json::from_slice(scene)
            .map_err(|e| FormatError::invalid(name, format!("not a glTF file (not JSON: {e})")))?;
        Glb {
            json,
            rest: Vec::new(),
        }
    };
    let doc = file
        .json
        .as_object_mut()
        .ok_or_else(|| bad("not a glTF file (the document is not a JSON object)"))?;
    match doc
        .get("asset")
        .and_then(|a| a.get("version"))
        .and_then(Value::as_str)
    {
        Some(v) if v.starts_with("2.") => {}
        Some(v) => {
            return Err(FormatError::invalid(
                name,
                format!("glTF version {v}; shlight writes into glTF 2.0 assets"),
            ));
        }
        None => return Err(bad("not a glTF 2.0 asset (no asset.version)")),
    }
    let (light, mut notes) = light(input)?;
    let used = doc
        .entry("extensionsUsed")
        .or_insert_with(|| json!([]))
        .as_array_mut()
        .ok_or_else(|| bad("\"extensionsUsed\" is not an array"))?;
    if !used.iter().any(|e| e.as_str() == Some(EXTENSION)) {
        used.push(json!(EXTENSION));
    }
    let lights = doc
        .entry("extensions")
        .or_insert_with(|| json!({}))
        .as_object_mut()
        .ok_or_else(|| bad("\"extensions\" is not an object"))?
        .entry(EXTENSION)
        .or_insert_with(|| json!({}))
        .as_object_mut()
        .ok_or_else(|| bad("\"extensions.EXT_lights_image_based\" is not an object"))?
        .entry("lights")
        .or_insert_with(|| json!([]))
        .as_array_mut()
        .ok_or_else(|| bad("\"EXT_lights_image_based.lights\" is not an array"))?;
    let index = match lights
        .iter()
        .position(|l| l.get("name").and_then(Value::as_str) == Some("shlight"))
    {
        Some(i) => {
            notes.push(format!(
                "{name}: replaced the light named shlight (light {i})"
            ));
            lights[i] = light;
            i
        }
        None => {
            lights.push(light);
            lights.len() - 1
        }
    };
    let default_scene = doc.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
    match doc
        .get_mut("scenes")
        .and_then(Value::as_array_mut)
        .and_then(|s| s.get_mut(default_scene))
        .and_then(Value::as_object_mut)
    {
        Some(scene) => {
            let ext = scene
                .entry("extensions")
                .or_insert_with(|| json!({}))
                .as_object_mut()
                .ok_or_else(|| bad("the scene's \"extensions\" is not an object"))?;
            ext.insert(EXTENSION.into(), json!({ "light": index }));
        }
        None => notes.push(format!(
            "{name}: the asset has no scene {default_scene} to point at the light; the light \
             is added to the extension's list only"
        )),
    }
    let bytes = if glb {
        write_glb(&file)
    } else {
        let mut text = serde_json::to_vec_pretty(&file.json).expect("JSON values serialise");
        text.push(b'\n');
        text
    };
    Ok((bytes, notes))
}

/// [`add_light`] on the file at `scene`, written back in place atomically
/// (a temporary file renamed over it, so a failure leaves it as it was).
///
/// # Errors
/// [`FormatError::Read`] / [`FormatError::Write`] naming the file, and as
/// [`add_light`].
pub fn add_light_to_file(input: &ExportInput<'_>, scene: &Path) -> Result<Vec<String>> {
    let name = scene.display().to_string();
    let bytes = std::fs::read(scene).map_err(|source| FormatError::Read {
        path: scene.to_path_buf(),
        source,
    })?;
    let (out, notes) = add_light(input, &bytes, &name)?;
    shlight_io::write_atomically(scene, |w| std::io::Write::write_all(w, &out))?;
    Ok(notes)
}

/// Reads the light of a glTF (or fragment) with `EXT_lights_image_based`:
/// irradiance times `intensity`, y-up, lmax 2. With several lights, the one
/// the default scene names (else the only one). A light with a rotation
/// other than the identity is refused (its direction convention is not
/// pinned down by the extension).
///
/// # Errors
/// [`FormatError::Invalid`] naming `name` and what is missing or wrong.
pub fn read(v: &Value, name: &str) -> Result<Imported> {
    let lights = v
        .pointer("/extensions/EXT_lights_image_based/lights")
        .and_then(Value::as_array)
        .ok_or_else(|| {
            FormatError::invalid(name, "EXT_lights_image_based has no \"lights\" array")
        })?;
    let default_scene = v.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
    let named = v
        .get("scenes")
        .and_then(|s| s.get(default_scene))
        .and_then(|s| s.pointer("/extensions/EXT_lights_image_based/light"))
        .and_then(Value::as_u64);
    let light = match (lights.as_slice(), named) {
        (_, Some(i)) => lights.get(i as usize).ok_or_else(|| {
            FormatError::invalid(
                name,
                format!(
                    "scene {default_scene} names light {i}, but there are {} lights",
                    lights.len()
                ),
            )
        })?,
        ([l], None) => l,
        ([], None) => {
            return Err(FormatError::invalid(
                name,
                "EXT_lights_image_based has no lights",
            ));
        }
        (more, None) => {
            return Err(FormatError::invalid(
                name,
                format!(
                    "EXT_lights_image_based has {} lights and no scene names one",
                    more.len()
                ),
            ));
        }
    };
    let rows = light
        .get("irradianceCoefficients")
        .and_then(Value::as_array)
        .ok_or_else(|| {
            FormatError::invalid(
                name,
                "the light has no \"irradianceCoefficients\" array".to_string(),
            )
        })?;
    if rows.len() != 9 {
        return Err(FormatError::invalid(
            name,
            format!(
                "\"irradianceCoefficients\" must hold 9 [r, g, b] rows, found {}",
                rows.len()
            ),
        ));
    }
    let intensity = light
        .get("intensity")
        .and_then(Value::as_f64)
        .unwrap_or(1.0);
    if let Some(q) = light.get("rotation") {
        let q: Vec<f64> = q
            .as_array()
            .map(|a| a.iter().filter_map(Value::as_f64).collect())
            .unwrap_or_default();
        let identity =
            q.len() == 4 && q[0].abs() + q[1].abs() + q[2].abs() < 1e-12 && q[3].abs() > 0.0;
        if !identity {
            return Err(FormatError::invalid(
                name,
                format!(
                    "the light's \"rotation\" {q:?} is not the identity; shlight reads only \
                 unrotated lights"
                ),
            ));
        }
    }
    let mut coeffs = Vec::with_capacity(9);
    for (i, row) in rows.iter().enumerate() {
        let c: Vec<f64> = row
            .as_array()
            .map(|a| a.iter().filter_map(Value::as_f64).collect())
            .unwrap_or_default();
        match c.as_slice() {
            [r, g, b] => coeffs.push(DVec3::new(*r, *g, *b) * intensity),
            _ => {
                return Err(FormatError::invalid(
                    name,
                    format!("irradianceCoefficients[{i}] is not three numbers"),
                ));
            }
        }
    }
    // Back from Babylon's world, the light's frame.
    let m = engine_frame(ExportFormat::Gltf).expect("an engine");
    let coeffs = ShCoeffs::from_vec(coeffs).expect("9 coefficients");
    Ok(Imported {
        coeffs: transform(&coeffs, m.transpose()),
        quantity: Quantity::Irradiance,
        frame: Frame::YUp,
        source: "glTF EXT_lights_image_based",
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Babylon.js: `FromArray`, `scaleInPlace(intensity)`,
    /// `convertIrradianceToLambertianRadiance`, then the SH3 basis
    /// (`SH3ylmBasisConstants` times `SH3ylmBasisTrigonometricTerms`).
    fn babylon_lambertian_radiance(v: &Value, n: [f64; 3]) -> f64 {
        let pi = std::f64::consts::PI;
        let k = [
            (1.0 / (4.0 * pi)).sqrt(),
            -(3.0 / (4.0 * pi)).sqrt(),
            (3.0 / (4.0 * pi)).sqrt(),
            -(3.0 / (4.0 * pi)).sqrt(),
            (15.0 / (4.0 * pi)).sqrt(),
            -(15.0 / (4.0 * pi)).sqrt(),
            (5.0 / (16.0 * pi)).sqrt(),
            -(15.0 / (4.0 * pi)).sqrt(),
            (15.0 / (16.0 * pi)).sqrt(),
        ];
        let [x, y, z] = n;
        let t = [
            1.0,
            y,
            z,
            x,
            x * y,
            y * z,
            3.0 * z * z - 1.0,
            x * z,
            x * x - y * y,
        ];
        let light = &v["extensions"]["EXT_lights_image_based"]["lights"][0];
        let intensity = light["intensity"].as_f64().unwrap();
        (0..9)
            .map(|i| {
                light["irradianceCoefficients"][i][0].as_f64().unwrap() * intensity / pi
                    * k[i]
                    * t[i]
            })
            .sum()
    }

    #[test]
    fn babylon_reads_irradiance_over_pi() {
        let radiance =
            &shlight_core::sh::closed_form::directional(2, DVec3::new(0.0, 0.6, 0.8), DVec3::ONE)
                + &shlight_core::sh::closed_form::constant(2, DVec3::splat(0.3));
        let out = render(
            &ExportInput {
                coeffs: &radiance,
                quantity: Quantity::Radiance,
                frame: Frame::YUp,
            },
            None,
        )
        .unwrap();
        let v: Value = serde_json::from_str(&out.text).unwrap();
        let e = shlight_core::sh::irradiance(&radiance);
        for n in [[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, -0.8, 0.6]] {
            // Babylon looks the texel shlight reads at (x, y, z) up at
            // (z, y, x) of its world.
            let [x, y, z] = n;
            let got = babylon_lambertian_radiance(&v, [z, y, x]);
            let want = e.eval(DVec3::from(n)).x / std::f64::consts::PI;
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        assert!(out.notes.iter().any(|n| n.contains("specularImages")));
    }

    #[test]
    fn rotated_lights_are_refused() {
        let v = json!({"extensions": {"EXT_lights_image_based": {"lights": [{
            "rotation": [0.0, 0.6, 0.0, 0.8],
            "irradianceCoefficients": vec![[0.0, 0.0, 0.0]; 9],
        }]}}});
        let err = read(&v, "x.gltf").unwrap_err().to_string();
        assert!(err.contains("x.gltf") && err.contains("rotation"), "{err}");
    }
}
