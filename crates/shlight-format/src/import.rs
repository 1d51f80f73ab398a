//! Reading coefficients back from the engine formats that keep enough of
//! them: three.js LightProbe JSON, glTF / GLB with `EXT_lights_image_based`,
//! shlight's Unity JSON and Filament's sh.txt (docs/exporters.md).

use std::path::Path;

use serde_json::Value;

use crate::export::{filament, gltf, threejs, unity};
use crate::imported::Imported;
use crate::{CoeffFile, FormatError, Result};

/// What `read_back` recognised in a file.
enum Recognised {
    /// A shlight coefficient file (JSON).
    Shlight,
    /// An engine format, already read.
    EngineFormat(Imported),
}

/// Reads the file at `path` as coefficients: a shlight coefficient file,
/// or any engine format shlight reads back (three.js LightProbe JSON, a glTF
/// or GLB with `EXT_lights_image_based`, shlight's Unity JSON, Filament
/// sh.txt), told apart by content, not by extension.
///
/// # Errors
/// [`FormatError::Read`] when the file cannot be read,
/// [`FormatError::Invalid`] naming it when it is none of these or is broken.
pub fn read_coefficients(path: &Path) -> Result<CoeffFile> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| FormatError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    read_coefficients_from_bytes(&bytes, &name)
}

/// [`read_coefficients`] of a file held in memory; `name` names it in errors.
///
/// # Errors
/// As [`read_coefficients`].
pub fn read_coefficients_from_bytes(bytes: &[u8], name: &str) -> Result<CoeffFile> {
    if gltf::is_glb(bytes) {
        let json = gltf::glb_json(bytes, name)?;
        return Ok(gltf::read(&json, name)?.into_coeff_file(name));
    }
    let text = std::str::from_utf8(bytes)
        .map_err(|_| FormatError::invalid(name, "not a text file (not UTF-8)"))?;
    match recognise(text, name)? {
        Recognised::Shlight => CoeffFile::from_json_str(text, name),
        Recognised::EngineFormat(imported) => Ok(imported.into_coeff_file(name)),
    }
}

fn recognise(text: &str, name: &str) -> Result<Recognised> {
    let trimmed = text.trim_start();
    if trimmed.starts_with('{') {
        let v: Value = serde_json::from_str(text)
            .map_err(|e| FormatError::invalid(name, format!("not valid JSON ({e})")))?;
        if v.get("format").and_then(Value::as_str) == Some(crate::coeff_file::FORMAT) {
            return Ok(Recognised::Shlight);
        }
        if v.get("format").and_then(Value::as_str) == Some(unity::FORMAT_TAG)
            || v.get("SphericalHarmonicsL2").is_some()
        {
            return unity::read(&v, name).map(Recognised::EngineFormat);
        }
        if v.pointer("/extensions/EXT_lights_image_based").is_some() {
            return gltf::read(&v, name).map(Recognised::EngineFormat);
        }
        if threejs::is_light_probe_json(&v) {
            return threejs::read(&v, name).map(Recognised::EngineFormat);
        }
        return Err(FormatError::invalid(
            name,
            "JSON, but not a file shlight reads (a shlight coefficient file, three.js \
             LightProbe JSON, a glTF with EXT_lights_image_based, or shlight's Unity export)",
        ));
    }
    if trimmed.starts_with('(') {
        return filament::read(text, name).map(Recognised::EngineFormat);
    }
    Err(FormatError::invalid(
        name,
        "not a file shlight reads (a shlight coefficient file, three.js LightProbe JSON, \
         glTF EXT_lights_image_based, shlight's Unity JSON, or Filament sh.txt)",
    ))
}
