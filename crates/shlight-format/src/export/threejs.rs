//! `threejs`: a three.js `LightProbe` as `LightProbe.toJSON()` writes it,
//! loadable with `new THREE.ObjectLoader().parse(json)` or
//! `new THREE.LightProbe().fromJSON(json.object)`.
//!
//! # What the numbers are
//!
//! `object.sh` is `SphericalHarmonics3.toArray()`: 27 floats, coefficient
//! `i` (three.js order `0: L00, 1: L1-1, 2: L10, 3: L11, 4: L2-2, 5: L2-1,
//! 6: L20, 7: L21, 8: L22`) at `3i..3i+3` as red, green, blue.
//!
//! - **Radiance** coefficients `L_lm = int L(w) Y_lm(w) dw`, orthonormal
//!   basis **without** the Condon-Shortley phase. Source: three.js
//!   `src/math/SphericalHarmonics3.js`: `getBasisAt` is `0.282095`,
//!   `0.488603 y`, `0.488603 z`, `0.488603 x`, `1.092548 xy`, `1.092548 yz`,
//!   `0.315392 (3z^2 - 1)`, `1.092548 xz`, `0.546274 (x^2 - y^2)`; `getAt`
//!   sums `c_i` times these (radiance); `getIrradianceAt` and the shader's
//!   `shGetIrradianceAt` (`ShaderChunk/lights_pars_begin.glsl.js`) use
//!   `0.886227 = pi * 0.282095`, `2 * 0.511664 = (2 pi / 3) * 0.488603`,
//!   `2 * 0.429043 = (pi / 4) * 1.092548`, ... i.e. they apply `A_l` to
//!   radiance coefficients. `LightProbeGenerator.fromCubeTexture` computes
//!   `sum c(d) getBasisAt(d) dw` normalised to `4 pi` total weight: the
//!   radiance projection, no phase.
//! - The shader's result is irradiance `E(n)` in world space; three.js then
//!   multiplies by `BRDF_Lambert = diffuseColor / pi` (`RE_IndirectDiffuse`),
//!   and by the probe's `intensity` (1 here).
//! - **Frame**: three.js world, right-handed, +Y up, the same axes as
//!   shlight's y-up frame (three.js `equirectUv` maps an equirect image the
//!   way shlight's y-up frame does). A z-up file is rotated to y-up first.
//! - **lmax 2** exactly (`SphericalHarmonics3` has 9 coefficients).
//!
//! The object's `userData.shlight` says the same in words; `ObjectLoader`
//! copies `userData` onto the LightProbe and ignores it otherwise.

use std::hash::{DefaultHasher, Hash, Hasher};

use crate::{FormatError, Result};
use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::sh::{Frame, ShCoeffs};

use super::{ExportFormat, ExportInput, Exported, engine_coeffs};
use crate::{Imported, Quantity};

/// Renders the `LightProbe.toJSON()` document.
pub fn render(input: &ExportInput<'_>) -> Result<Exported> {
    let (radiance, notes) = engine_coeffs(input, Quantity::Radiance, ExportFormat::Threejs)?;
    let no_phase = radiance.toggled_cs_phase();
    let sh: Vec<f64> = no_phase
        .as_slice()
        .iter()
        .flat_map(|v| [v.x, v.y, v.z])
        .collect();
    let doc = json!({
        "metadata": {
            "version": 4.6,
            "type": "Object",
            "generator": concat!("shlight ", env!("CARGO_PKG_VERSION"), " (LightProbe.toJSON layout)"),
        },
        "object": {
            "uuid": uuid_of(&sh),
            "type": "LightProbe",
            "name": "shlight",
            "layers": 1,
            "matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0],
            "up": [0.0, 1.0, 0.0],
            "color": 0xffffff,
            "intensity": 1.0,
            "sh": sh,
            "userData": {
                "shlight": {
                    "sh": "SphericalHarmonics3.toArray(): coefficient i (L00, L1-1, L10, L11, L2-2, L2-1, L20, L21, L22) at 3i..3i+3 as linear Rec.709 RGB",
                    "quantity": "radiance L_lm = integral of L(w) Y_lm(w) dw; getIrradianceAt / shGetIrradianceAt give irradiance E(n)",
                    "basis": "real orthonormal SH without the Condon-Shortley phase (three.js getBasisAt)",
                    "frame": "three.js world, right-handed, +Y up",
                }
            },
        },
    });
    Ok(Exported {
        text: serde_json::to_string_pretty(&doc).expect("JSON values serialise") + "\n",
        notes,
    })
}

/// A UUID-shaped id derived from the numbers, so the same input always
/// gives the same file.
fn uuid_of(sh: &[f64]) -> String {
    let mut words = [0u64; 2];
    for (k, w) in words.iter_mut().enumerate() {
        let mut h = DefaultHasher::new();
        k.hash(&mut h);
        for v in sh {
            v.to_bits().hash(&mut h);
        }
        *w = h.finish();
    }
    let hex = format!("{:016X}{:016X}", words[0], words[1]);
    format!(
        "{}-{}-4{}-8{}-{}",
        &hex[0..8],
        &hex[8..12],
        &hex[13..16],
        &hex[17..20],
        &hex[20..32]
    )
}

/// Whether `v` is a three.js object JSON with a LightProbe in it.
pub fn is_light_probe_json(v: &Value) -> bool {
    let mut found = Vec::new();
    find_probes(v.get("object").unwrap_or(v), &mut found);
    !found.is_empty()
}

fn find_probes<'a>(v: &'a Value, out: &mut Vec<&'a Value>) {
    if v.get("type").and_then(Value::as_str) == Some("LightProbe") {
        out.push(v);
    }
    if let Some(children) = v.get("children").and_then(Value::as_array) {
        for c in children {
            find_probes(c, out);
        }
    }
}

/// Reads a LightProbe back: `sh` times `intensity`, to shlight's basis.
/// The result is radiance in the y-up frame, lmax 2.
pub fn read(v: &Value, name: &str) -> Result<Imported> {
    let mut probes = Vec::new();
    find_probes(v.get("object").unwrap_or(v), &mut probes);
    let probe = match probes.as_slice() {
        [p] => *p,
        [] => {
            return Err(FormatError::invalid(
                name,
                "no LightProbe object".to_string(),
            ));
        }
        more => {
            return Err(FormatError::invalid(
                name,
                format!(
                    "{} LightProbe objects; shlight reads files with one",
                    more.len()
                ),
            ));
        }
    };
    let sh: Vec<f64> = probe
        .get("sh")
        .and_then(Value::as_array)
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    if sh.len() != 27 {
        return Err(FormatError::invalid(
            name,
            format!(
                "the LightProbe's \"sh\" must be 27 numbers (9 RGB coefficients), found {}",
                sh.len()
            ),
        ));
    }
    let intensity = match probe.get("intensity") {
        None => 1.0,
        Some(i) => i.as_f64().ok_or_else(|| {
            FormatError::invalid(
                name,
                "the LightProbe's \"intensity\" is not a number".to_string(),
            )
        })?,
    };
    let coeffs: Vec<DVec3> = sh
        .chunks(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]) * intensity)
        .collect();
    let no_phase = ShCoeffs::from_vec(coeffs).expect("9 coefficients");
    Ok(Imported {
        coeffs: no_phase.toggled_cs_phase(),
        quantity: Quantity::Radiance,
        frame: Frame::YUp,
        source: "three.js LightProbe",
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::basis_polynomial;
    use shlight_core::sh::clamped_cosine_eigenvalue as a_l;

    /// three.js `SphericalHarmonics3.getIrradianceAt`, constants as in its source.
    fn get_irradiance_at(c: &[[f64; 3]], n: [f64; 3]) -> [f64; 3] {
        let [x, y, z] = n;
        let w = [
            0.886227,
            2.0 * 0.511664 * y,
            2.0 * 0.511664 * z,
            2.0 * 0.511664 * x,
            2.0 * 0.429043 * x * y,
            2.0 * 0.429043 * y * z,
            0.743125 * z * z - 0.247708,
            2.0 * 0.429043 * x * z,
            0.429043 * (x * x - y * y),
        ];
        let mut out = [0.0; 3];
        for i in 0..9 {
            for k in 0..3 {
                out[k] += c[i][k] * w[i];
            }
        }
        out
    }

    #[test]
    fn get_irradiance_at_of_the_export_is_shlight_irradiance() {
        let light = shlight_core::sh::closed_form::directional(
            2,
            DVec3::new(0.48, 0.6, 0.64),
            DVec3::new(1.0, 0.5, 0.25),
        );
        let out = render(&ExportInput {
            coeffs: &light,
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
        })
        .unwrap();
        let v: Value = serde_json::from_str(&out.text).unwrap();
        let sh: Vec<f64> = v["object"]["sh"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let c: Vec<[f64; 3]> = sh.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        let e = shlight_core::sh::irradiance(&light);
        for n in [[0.0, 1.0, 0.0], [0.6, 0.0, 0.8], [-0.36, 0.48, -0.8]] {
            let got = get_irradiance_at(&c, n);
            let want = e.eval(DVec3::from(n));
            assert!((got[0] - want.x).abs() < 2e-6, "{got:?} vs {want}");
        }
        // The identity behind it: three.js constants are A_l times its basis constants.
        let p = basis_polynomial([0.0, 0.0, 1.0]);
        assert!((0.886227 - a_l(0) * 0.282095).abs() < 1e-6 && p[0] == 1.0);
    }

    #[test]
    fn uuids_are_uuid_shaped_and_stable() {
        let a = uuid_of(&[1.0, 2.0]);
        assert_eq!(a, uuid_of(&[1.0, 2.0]));
        assert_ne!(a, uuid_of(&[1.0, 2.5]));
        let parts: Vec<usize> = a.split('-').map(str::len).collect();
        assert_eq!(parts, [8, 4, 4, 4, 12]);
    }
}
