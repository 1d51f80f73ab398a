//! `unity`: Unity's `SphericalHarmonicsL2` (27 floats) and the seven shader
//! vectors `unity_SHAr, unity_SHAg, unity_SHAb, unity_SHBr, unity_SHBg,
//! unity_SHBb, unity_SHC` that Unity's `ShadeSH9` reads, as one JSON file.
//!
//! # Layout
//!
//! `"SphericalHarmonicsL2"`: the struct's fields in memory order
//! (`UnityCsReference`, `SphericalHarmonicsL2.bindings.cs`:
//! `shr0..shr8, shg0..shg8, shb0..shb8`), i.e. `sh[rgb, i]` at
//! `rgb * 9 + i`, `i = l(l+1)+m` (`0: L00, 1: L1-1, 2: L10, 3: L11, 4: L2-2,
//! 5: L2-1, 6: L20, 7: L21, 8: L22`). The shader vectors are packed from it as
//! Unity does (HDRP `SphericalHarmonicMath.PackCoefficients`, the same as the
//! built-in pipeline's `unity_SH*`):
//! `SHA{c} = (sh[c,3], sh[c,1], sh[c,2], sh[c,0] - sh[c,6])`,
//! `SHB{c} = (sh[c,4], sh[c,5], 3 sh[c,6], sh[c,7])`,
//! `SHC = (sh[0,8], sh[1,8], sh[2,8], 1)`.
//!
//! # What the numbers are
//!
//! `sh[c, i] = E_i k_i / pi`: irradiance coefficients `E_i = A_l L_i` (basis
//! with the Condon-Shortley phase) times the constant `k_i` of the basis
//! polynomial (with its CS sign, `Y_i = k_i p_i`) over `pi`. Sources:
//! HDRP's `SphericalHarmonicMath` (`Runtime/Lighting/SphericalHarmonics.cs`)
//! undoes this with `UndoCosineRescaling`, "coefficient rescaling due to the
//! convolution with the clamped cosine kernel", multiplying by
//! `invNormConsts = {1/c0, -1/c1, 1/c1, -1/c1, 1/c2, -1/c2, 1/c3, -1/c2, 1/c4}`
//! with `c0 = 1/(2 sqrt pi)`, `c1 = sqrt(3/pi)/3`, `c2 = sqrt(15/pi)/8`,
//! `c3 = sqrt(5/pi)/16`, `c4 = sqrt(15/pi)/16`, i.e. exactly `k_i A_l / pi`
//! (`A_l / pi = 1, 2/3, 1/4`), and `AddAmbientLight(c)` adds `c` to
//! `sh[., 0]` (uniform radiance `c` gives `E/pi = c`).
//!
//! `ShadeSH9(n)` (`UnityCG.cginc`: `SHEvalLinearL0L1` = `dot(unity_SHAr,
//! (n, 1))`..., `SHEvalLinearL2` = `dot(unity_SHBr, n.xyzz * n.yzzx)` +
//! `unity_SHC.rgb (x^2 - y^2)`) sums `sh[c,i] p_i(n)` and so returns
//! `E(n) / pi`, the radiance a white Lambertian surface reflects; Unity's
//! shaders multiply it by the diffuse colour only.
//!
//! - **Frame**: Unity's world is left-handed, +Y up, +Z forward. shlight's
//!   y-up direction `(x, y, z)` is Unity's `(x, y, -z)`: this is how Unity's
//!   `Skybox/Panoramic` shader (`ToRadialCoords`:
//!   `u = 0.5 - atan2(z, x) / 2pi`) shows the same equirect image that
//!   shlight reads. In coefficients the mirror multiplies `(l, m)` by
//!   `(-1)^(l+m)`. (Importers that negate x instead put the world a half
//!   turn about +Y away: set the skybox rotation to 180 to match.)
//! - **lmax 2** exactly.

use crate::{FormatError, Result};
use glam::DVec3;
use serde_json::{Value, json};
use shlight_core::sh::{Frame, ShCoeffs};

use super::{
    ExportFormat, ExportInput, Exported, basis_constant, engine_coeffs, engine_frame, transform,
};
use crate::{Imported, Quantity};

/// The `"format"` tag of the JSON this writes.
pub const FORMAT_TAG: &str = "shlight-unity-sh-l2";

/// `sh[c, i]` as the 27 floats of `SphericalHarmonicsL2`.
fn unity_floats(input: &ExportInput<'_>) -> Result<(Vec<f64>, Vec<String>)> {
    let (e, notes) = engine_coeffs(input, Quantity::Irradiance, ExportFormat::Unity)?;
    let mut sh = vec![0.0; 27];
    for (i, v) in e.as_slice().iter().enumerate() {
        let s = *v * (basis_constant(i) / std::f64::consts::PI);
        for c in 0..3 {
            sh[c * 9 + i] = s[c];
        }
    }
    Ok((sh, notes))
}

/// The seven packed vectors from the 27 floats.
fn pack(sh: &[f64]) -> [[f64; 4]; 7] {
    let s = |c: usize, i: usize| sh[c * 9 + i];
    let a = |c| [s(c, 3), s(c, 1), s(c, 2), s(c, 0) - s(c, 6)];
    let b = |c| [s(c, 4), s(c, 5), 3.0 * s(c, 6), s(c, 7)];
    [
        a(0),
        a(1),
        a(2),
        b(0),
        b(1),
        b(2),
        [s(0, 8), s(1, 8), s(2, 8), 1.0],
    ]
}

/// Renders the JSON.
pub fn render(input: &ExportInput<'_>) -> Result<Exported> {
    let (sh, notes) = unity_floats(input)?;
    let p = pack(&sh);
    let floats = sh
        .iter()
        .map(|v| format!("{}f", super::float_literal(*v)))
        .collect::<Vec<_>>();
    let csharp = format!(
        "var c = new float[] {{ {} }}; var sh = new UnityEngine.Rendering.SphericalHarmonicsL2(); \
         for (int rgb = 0; rgb < 3; rgb++) for (int i = 0; i < 9; i++) sh[rgb, i] = c[rgb * 9 + i]; \
         RenderSettings.ambientMode = UnityEngine.Rendering.AmbientMode.Custom; RenderSettings.ambientProbe = sh;",
        floats.join(", ")
    );
    let doc = json!({
        "format": FORMAT_TAG,
        "description": {
            "SphericalHarmonicsL2": "27 floats in field order shr0..shr8, shg0..shg8, shb0..shb8: sh[rgb, i] at rgb*9+i, i = l(l+1)+m (L00 L1-1 L10 L11 L2-2 L2-1 L20 L21 L22)",
            "meaning": "sh[c, i] = E_i k_i / pi: irradiance coefficients (basis with the Condon-Shortley phase) times the basis-polynomial constant, over pi; ShadeSH9(n) returns E(n)/pi (outgoing radiance of a white Lambertian surface), as HDRP's SphericalHarmonicMath.UndoCosineRescaling assumes",
            "frame": "Unity world: left-handed, +Y up, +Z forward; shlight y-up (x, y, z) is Unity (x, y, -z), as the Skybox/Panoramic shader maps the same equirect image",
            "shader": "unity_SHA{r,g,b} = (sh[c,3], sh[c,1], sh[c,2], sh[c,0] - sh[c,6]); unity_SHB{r,g,b} = (sh[c,4], sh[c,5], 3 sh[c,6], sh[c,7]); unity_SHC = (sh[0,8], sh[1,8], sh[2,8], 1)",
            "colour": "linear Rec.709 RGB",
        },
        "SphericalHarmonicsL2": sh,
        "unity_SHAr": p[0],
        "unity_SHAg": p[1],
        "unity_SHAb": p[2],
        "unity_SHBr": p[3],
        "unity_SHBg": p[4],
        "unity_SHBb": p[5],
        "unity_SHC": p[6],
        "csharp": csharp,
    });
    Ok(Exported {
        text: serde_json::to_string_pretty(&doc).expect("JSON values serialise") + "\n",
        notes,
    })
}

/// Reads the 27 floats back: irradiance, y-up (z mirrored back), lmax 2.
pub fn read(v: &Value, name: &str) -> Result<Imported> {
    let sh: Vec<f64> = v
        .get("SphericalHarmonicsL2")
        .and_then(Value::as_array)
        .ok_or_else(|| FormatError::invalid(name, "no \"SphericalHarmonicsL2\" array".to_string()))?
        .iter()
        .map(|x| x.as_f64())
        .collect::<Option<_>>()
        .ok_or_else(|| {
            FormatError::invalid(
                name,
                "\"SphericalHarmonicsL2\" holds something not a number".to_string(),
            )
        })?;
    if sh.len() != 27 {
        return Err(FormatError::invalid(
            name,
            format!(
                "\"SphericalHarmonicsL2\" must be 27 numbers (shr0..shb8), found {}",
                sh.len()
            ),
        ));
    }
    let pi = std::f64::consts::PI;
    let e = ShCoeffs::from_vec(
        (0..9)
            .map(|i| DVec3::new(sh[i], sh[9 + i], sh[18 + i]) * (pi / basis_constant(i)))
            .collect(),
    )
    .expect("9 coefficients");
    Ok(Imported {
        // The mirror is its own inverse.
        coeffs: transform(&e, engine_frame(ExportFormat::Unity).expect("an engine")),
        quantity: Quantity::Irradiance,
        frame: Frame::YUp,
        source: "Unity SphericalHarmonicsL2",
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `ShadeSH9` (UnityCG.cginc) on the packed vectors, red channel.
    fn shade_sh9_red(p: &[[f64; 4]; 7], n: [f64; 3]) -> f64 {
        let dot = |a: [f64; 4], b: [f64; 4]| a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>();
        let [x, y, z] = n;
        let l0l1 = dot(p[0], [x, y, z, 1.0]);
        let vb = [x * y, y * z, z * z, z * x];
        let l2 = dot(p[3], vb) + p[6][0] * (x * x - y * y);
        l0l1 + l2
    }

    #[test]
    fn shade_sh9_gives_irradiance_over_pi_in_unity_axes() {
        // A light from shlight's +Z is Unity's -Z.
        let radiance =
            &shlight_core::sh::closed_form::directional(2, DVec3::new(0.0, 0.6, 0.8), DVec3::ONE)
                + &shlight_core::sh::closed_form::constant(2, DVec3::splat(0.1));
        let (sh, _) = unity_floats(&ExportInput {
            coeffs: &radiance,
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
        })
        .unwrap();
        let p = pack(&sh);
        let e = shlight_core::sh::irradiance(&radiance);
        for nu in [
            [0.0, 0.6, -0.8],
            [0.0, 0.6, 0.8],
            [0.8, 0.0, 0.6],
            [-0.36, -0.48, 0.8],
        ] {
            let got = shade_sh9_red(&p, nu);
            let want = e.eval(DVec3::from([nu[0], nu[1], -nu[2]])).x / std::f64::consts::PI;
            assert!((got - want).abs() < 1e-13, "{nu:?}: {got} vs {want}");
        }
        // Uniform radiance c: AddAmbientLight(c) puts c in sh[., 0], ShadeSH9 = c.
        let c = shlight_core::sh::closed_form::constant(2, DVec3::new(0.5, 0.25, 2.0));
        let (sh, _) = unity_floats(&ExportInput {
            coeffs: &c,
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
        })
        .unwrap();
        assert!((sh[0] - 0.5).abs() < 1e-15 && (sh[9] - 0.25).abs() < 1e-15);
        assert!((sh[18] - 2.0).abs() < 1e-15);
    }
}
