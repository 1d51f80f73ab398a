//! `gltf`: an `EXT_lights_image_based` light with `irradianceCoefficients`,
//! as a glTF JSON fragment (`extensionsUsed` and `extensions`) to merge into
//! a glTF document.
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
//! - **Frame**: glTF's world, right-handed, +Y up (glTF 2.0 spec, "Coordinate
//!   System and Units"), the axes of shlight's y-up frame. A z-up file is
//!   rotated first. `rotation` is the identity, `intensity` 1.
//! - **lmax 2** exactly.
//!
//! The extension also requires `specularImages` and `specularImageSize`
//! (the prefiltered cube map), which shlight does not make: the light is
//! written without them and a note says so.

use anyhow::{Result, anyhow, bail};
use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::ShCoeffs;
use shlight_core::rotation::Frame;

use super::{ExportInput, Exported, Imported, engine_coeffs, rgb_array};
use crate::coeff_file::Quantity;

/// Renders the glTF fragment.
pub fn render(input: &ExportInput<'_>) -> Result<Exported> {
    let (e, mut notes) = engine_coeffs(input, Quantity::Irradiance, "gltf")?;
    notes.push(
        "EXT_lights_image_based also requires specularImages and specularImageSize (the \
         prefiltered cube map); shlight writes only the irradiance coefficients"
            .into(),
    );
    let coeffs: Vec<[f64; 3]> = e.as_slice().iter().map(|v| rgb_array(*v)).collect();
    let doc = json!({
        "extensionsUsed": ["EXT_lights_image_based"],
        "extensions": {
            "EXT_lights_image_based": {
                "lights": [{
                    "name": "shlight",
                    "intensity": 1.0,
                    "rotation": [0.0, 0.0, 0.0, 1.0],
                    "irradianceCoefficients": coeffs,
                    "extras": {
                        "shlight": {
                            "irradianceCoefficients": "irradiance E_lm = A_l L_lm (A = pi, 2pi/3, pi/4), order L00 L1-1 L10 L11 L2-2 L2-1 L20 L21 L22, [r, g, b] linear Rec.709",
                            "basis": "real orthonormal SH with the Condon-Shortley phase (as Babylon.js's SH3ylmBasisConstants)",
                            "frame": "glTF world: right-handed, +Y up",
                            "missing": "specularImages and specularImageSize (required by the extension) are not written",
                        }
                    },
                }]
            }
        },
    });
    Ok(Exported {
        text: serde_json::to_string_pretty(&doc).expect("JSON values serialise") + "\n",
        notes,
    })
}

/// Reads the light of a glTF (or fragment) with `EXT_lights_image_based`:
/// irradiance times `intensity`, y-up, lmax 2. A light with a rotation other
/// than the identity is refused (its direction convention is not pinned
/// down by the extension).
pub fn read(v: &Value, name: &str) -> Result<Imported> {
    let lights = v
        .pointer("/extensions/EXT_lights_image_based/lights")
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("{name}: EXT_lights_image_based has no \"lights\" array"))?;
    let light = match lights.as_slice() {
        [l] => l,
        [] => bail!("{name}: EXT_lights_image_based has no lights"),
        more => bail!(
            "{name}: EXT_lights_image_based has {} lights; shlight reads files with one",
            more.len()
        ),
    };
    let rows = light
        .get("irradianceCoefficients")
        .and_then(Value::as_array)
        .ok_or_else(|| anyhow!("{name}: the light has no \"irradianceCoefficients\" array"))?;
    if rows.len() != 9 {
        bail!(
            "{name}: \"irradianceCoefficients\" must hold 9 [r, g, b] rows, found {}",
            rows.len()
        );
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
            bail!(
                "{name}: the light's \"rotation\" {q:?} is not the identity; shlight reads only \
                 unrotated lights"
            );
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
            _ => bail!("{name}: irradianceCoefficients[{i}] is not three numbers"),
        }
    }
    Ok(Imported {
        coeffs: ShCoeffs::from_vec(coeffs).expect("9 coefficients"),
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
        let radiance = &shlight_core::analytic::directional(2, [0.0, 0.6, 0.8], DVec3::ONE)
            + &shlight_core::analytic::constant(2, DVec3::splat(0.3));
        let out = render(&ExportInput {
            coeffs: &radiance,
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
        })
        .unwrap();
        let v: Value = serde_json::from_str(&out.text).unwrap();
        let e = shlight_core::irradiance(&radiance);
        for n in [[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, -0.8, 0.6]] {
            let got = babylon_lambertian_radiance(&v, n);
            let want = e.eval(n).x / std::f64::consts::PI;
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
