//! One light in an engine's format (three.js, Unity, Filament; the glTF
//! light is in `gltf`), with its coefficients read back into shlight's
//! basis, and the Ramamoorthi-Hanrahan table (`--format txt`).

use serde_json::Value;

use super::{Header, plain};
use crate::coeff_file::coefficient_rows;
use crate::export::{filament, threejs, unity};
use crate::{Imported, Result};

/// The coefficients an engine file holds, read back as `shlight convert`
/// reads them: a line saying what they now are, then the rows of
/// [`crate::CoeffFile::to_table`].
pub(super) fn read_back(imported: &Imported) -> String {
    format!(
        "# as shlight convert reads it back: {}, lmax {} ({} coefficients), shlight's basis \
         (Condon-Shortley phase, index l*(l+1)+m), frame {}\n{}",
        imported.quantity.name(),
        imported.coeffs.lmax(),
        imported.coeffs.len(),
        imported.frame,
        coefficient_rows(&imported.coeffs, None)
    )
}

/// three.js `LightProbe.toJSON()` (`--format threejs`).
pub(super) fn describe_threejs(v: &Value, name: &str) -> Result<Header> {
    let imported = threejs::read(v, name)?;
    let mut h = Header::new("three.js LightProbe JSON (LightProbe.toJSON layout)");
    h.field(
        "holds",
        "radiance L_lm to lmax 2 (9 coefficients), three.js's basis (no Condon-Shortley phase)",
    );
    h.field("frame", "three.js's world (right-handed, +Y up)");
    let probe = v.get("object").unwrap_or(v);
    if let Some(i) = probe.get("intensity") {
        h.field("intensity", plain(i));
    }
    if let Some(g) = v.pointer("/metadata/generator") {
        h.field("generator", plain(g));
    }
    h.rows = read_back(&imported);
    Ok(h)
}

/// shlight's Unity JSON (`--format unity`).
pub(super) fn describe_unity(v: &Value, name: &str) -> Result<Header> {
    let imported = unity::read(v, name)?;
    let mut h = Header::new(format!(
        "Unity SphericalHarmonicsL2 ({})",
        v.get("format")
            .map_or_else(|| "SphericalHarmonicsL2".into(), plain)
    ));
    h.field(
        "holds",
        "27 floats sh[rgb, i] = E_i k_i / pi (irradiance times the basis polynomial's \
         constant over pi), lmax 2, and the unity_SHAr..SHC shader constants",
    );
    h.field(
        "frame",
        "Unity's world (left-handed, +Y up): shlight's y-up (x, y, z) is (x, y, -z)",
    );
    h.rows = read_back(&imported);
    Ok(h)
}

/// Filament's sh.txt (`--format filament`, cmgen `--sh-shader`).
pub(super) fn describe_filament(text: &str, name: &str) -> Result<Header> {
    let imported = filament::read(text, name)?;
    let rows = text.lines().filter(|l| !l.trim().is_empty()).count();
    let mut h = Header::new("Filament sh.txt (cmgen --sh-shader layout)");
    h.field(
        "holds",
        format!(
            "{rows} rows (r, g, b); {}",
            if imported.quantity == crate::Quantity::Irradiance {
                "E_lm k_lm / pi: irradiance pre-scaled for Filament's shader (the radiance \
                 a white Lambertian surface reflects)"
            } else {
                "radiance L_lm (cmgen --sh-output)"
            }
        ),
    );
    h.field(
        "frame",
        "Filament's world (right-handed, +Y up), as cmgen puts the map",
    );
    h.rows = read_back(&imported);
    Ok(h)
}

/// The Ramamoorthi-Hanrahan table (`--format txt`): its first line names
/// it; `None` for other text.
pub(super) fn describe_table(text: &str) -> Option<Header> {
    let first = text.lines().next()?;
    let what = first
        .strip_prefix("# shlight SH ")
        .and_then(|r| r.strip_suffix(", Ramamoorthi-Hanrahan table layout"))?;
    let mut h = Header::new("Ramamoorthi-Hanrahan table (shlight --format txt)");
    // "radiance, lmax 4 (25 coefficients)"
    let (quantity, lmax) = what.split_once(", ").unwrap_or((what, ""));
    h.field("holds", format!("{quantity}, {lmax}"));
    h.field(
        "basis",
        "real orthonormal SH without the Condon-Shortley phase (R&H 2001, three.js), \
         rows L00, L1-1, L10, ...",
    );
    let header_line = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(&format!("# {key}: ")))
            .map(str::to_string)
    };
    if let Some(frame) = header_line("frame") {
        h.field("frame", frame);
    }
    if let Some(colour) = header_line("colour") {
        h.field("colour", colour);
    }
    let rows = text.lines().filter(|l| l.starts_with('L')).count();
    h.field("rows", rows.to_string());
    Some(h)
}
