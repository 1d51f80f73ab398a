//! Exporters: shlight coefficients to the formats engines and shaders read,
//! and back where the target keeps enough (docs/exporters.md).
//!
//! Every exporter starts from an [`ExportInput`]: coefficients in shlight's
//! basis (real orthonormal, Condon-Shortley phase, index `l(l+1)+m`), a
//! quantity (radiance or irradiance) and a frame (y-up or z-up). Each target
//! module states exactly what its numbers are and which source it follows:
//!
//! | format | numbers | phase | frame | lmax |
//! |---|---|---|---|---|
//! | [`txt`] | the file's quantity | none (R&H tables) | the file's | any |
//! | [`threejs`] | radiance `L_lm` | none | y-up | 2 |
//! | [`gltf`] | irradiance `E_lm = A_l L_lm` | CS | y-up (glTF) | 2 |
//! | [`filament`] | `E_lm k_lm / pi` (shader-prescaled) | folded in | y-up | 2 |
//! | [`unity`] | `E_lm k_lm / pi` (SphericalHarmonicsL2) | folded in | Unity: z flipped | 2 |
//! | [`wgsl`], [`glsl`], [`hlsl`], [`c`] | the file's quantity + evaluator | CS | the file's | any |
//!
//! (`k_lm` is the constant of the basis polynomial, `Y_lm(n) = k_lm p_lm(n)`.)
//! Formats limited to lmax 2 truncate a longer expansion (with a note on
//! stderr) and pad a shorter one with zeros, which is exact: a degree-1
//! expansion is the same function as the degree-2 one with zero band 2.

pub mod c;
pub mod filament;
pub mod glsl;
pub mod gltf;
pub mod hlsl;
pub mod threejs;
pub mod txt;
pub mod unity;
pub mod wgsl;

use std::path::Path;

use anyhow::{Result, anyhow, bail};
use clap::ValueEnum;
use glam::DVec3;
use serde_json::Value;
use shlight_core::rotation::{Frame, ShRotation};
use shlight_core::zonal::clamped_cosine_eigenvalue;
use shlight_core::{ShCoeffs, lm_from_index};

use crate::coeff_file::Quantity;

/// What an exporter needs to know about the coefficients it writes.
#[derive(Clone, Debug)]
pub struct ExportInput<'a> {
    /// shlight basis (CS phase included), linear Rec.709 RGB.
    pub coeffs: &'a ShCoeffs<DVec3>,
    /// What the coefficients hold.
    pub quantity: Quantity,
    /// Frame the coefficients are in.
    pub frame: Frame,
}

/// Target formats of `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// shlight's self-describing JSON coefficient file (written by the caller).
    Json,
    /// A Ramamoorthi-Hanrahan style table (L00, L1-1, ...), no CS phase.
    Txt,
    /// three.js `LightProbe.toJSON()` (radiance, no CS phase, y-up).
    Threejs,
    /// glTF `EXT_lights_image_based` light (irradiance coefficients, y-up).
    Gltf,
    /// Filament `cmgen --sh-shader` sh.txt (prescaled irradiance / pi, y-up).
    Filament,
    /// Unity `SphericalHarmonicsL2` and `unity_SHAr..SHC` (left-handed, y-up).
    Unity,
    /// WGSL coefficient array and evaluator, any lmax.
    Wgsl,
    /// GLSL coefficient array and evaluator, any lmax.
    Glsl,
    /// HLSL coefficient array and evaluator, any lmax.
    Hlsl,
    /// C coefficient array and evaluator, any lmax.
    C,
}

impl ExportFormat {
    /// The `--format` spelling.
    pub fn name(self) -> &'static str {
        match self {
            ExportFormat::Json => "json",
            ExportFormat::Txt => "txt",
            ExportFormat::Threejs => "threejs",
            ExportFormat::Gltf => "gltf",
            ExportFormat::Filament => "filament",
            ExportFormat::Unity => "unity",
            ExportFormat::Wgsl => "wgsl",
            ExportFormat::Glsl => "glsl",
            ExportFormat::Hlsl => "hlsl",
            ExportFormat::C => "c",
        }
    }

    /// The format an output path's extension names, where only one does.
    ///
    /// `.json` (json, threejs, gltf, unity) and `.txt` (txt, filament) are
    /// ambiguous and give an error that says so.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        Ok(match ext.as_str() {
            "wgsl" => ExportFormat::Wgsl,
            "glsl" | "frag" | "vert" | "comp" => ExportFormat::Glsl,
            "hlsl" | "hlsli" | "fx" => ExportFormat::Hlsl,
            "c" | "h" => ExportFormat::C,
            "gltf" => ExportFormat::Gltf,
            "json" => bail!(
                "{}: cannot tell the format from the extension .json (json, threejs, gltf and unity \
                 all write JSON); pass --format",
                path.display()
            ),
            "txt" => bail!(
                "{}: cannot tell the format from the extension .txt (txt and filament both write \
                 text); pass --format",
                path.display()
            ),
            "" => bail!(
                "{}: no extension to tell the format from; pass --format",
                path.display()
            ),
            other => bail!(
                "{}: no format writes .{other} files; pass --format (json, txt, threejs, gltf, \
                 filament, unity, wgsl, glsl, hlsl, c)",
                path.display()
            ),
        })
    }
}

/// An exporter's output: the file's text and notes for stderr (truncation,
/// padding, missing parts the target requires).
#[derive(Clone, Debug, Default)]
pub struct Exported {
    /// The file's content.
    pub text: String,
    /// Remarks for the user, one sentence each, without a `note:` prefix.
    pub notes: Vec<String>,
}

/// Renders `input` in `format` and returns the text and the notes.
pub fn render(input: &ExportInput<'_>, format: ExportFormat) -> Result<Exported> {
    check_finite(input.coeffs)?;
    match format {
        ExportFormat::Json => bail!(
            "the json format is shlight's coefficient file, written by CoeffFile::to_json_string"
        ),
        ExportFormat::Txt => Ok(txt::render(input)),
        ExportFormat::Threejs => threejs::render(input),
        ExportFormat::Gltf => gltf::render(input),
        ExportFormat::Filament => filament::render(input),
        ExportFormat::Unity => unity::render(input),
        ExportFormat::Wgsl => wgsl::render(input),
        ExportFormat::Glsl => glsl::render(input),
        ExportFormat::Hlsl => hlsl::render(input),
        ExportFormat::C => Ok(c::render(input)),
    }
}

/// Coefficients read back from a target format.
#[derive(Clone, Debug)]
pub struct Imported {
    /// shlight basis (CS phase), linear RGB.
    pub coeffs: ShCoeffs<DVec3>,
    /// What they hold.
    pub quantity: Quantity,
    /// The frame they are in (engines are y-up).
    pub frame: Frame,
    /// What was read, for the provenance (`layout`) of the coefficient file.
    pub source: &'static str,
}

fn check_finite(coeffs: &ShCoeffs<DVec3>) -> Result<()> {
    for (i, v) in coeffs.as_slice().iter().enumerate() {
        if !v.is_finite() {
            let (l, m) = lm_from_index(i);
            bail!("coefficient {i} (l={l}, m={m}) is not finite: {v}");
        }
    }
    Ok(())
}

/// `A_l` for `l = 0..=2`, the clamped-cosine eigenvalues
/// (Ramamoorthi & Hanrahan 2001): pi, 2 pi / 3, pi / 4.
pub(crate) fn a_l(l: usize) -> f64 {
    clamped_cosine_eigenvalue(l)
}

/// `k_i`, the constant of the basis polynomial in shlight's basis (CS
/// phase), `Y_i(n) = k_i p_i(n)` with
/// `p = (1, y, z, x, xy, yz, 3z^2 - 1, xz, x^2 - y^2)`, `i = 0..9`.
///
/// These are Filament's `preprocessSHForShader` factors `A[i]` and HDRP's
/// `SphericalHarmonicMath.ks` (both with the signs of the CS phase).
pub(crate) fn basis_constant(i: usize) -> f64 {
    let pi = std::f64::consts::PI;
    let k0 = 0.5 / pi.sqrt();
    let k1 = 3f64.sqrt() / (2.0 * pi.sqrt());
    let k2 = 15f64.sqrt() / (2.0 * pi.sqrt());
    let k20 = 5f64.sqrt() / (4.0 * pi.sqrt());
    let k22 = 15f64.sqrt() / (4.0 * pi.sqrt());
    [k0, -k1, k1, -k1, k2, -k2, k20, -k2, k22][i]
}

/// The polynomials `p_i(n)` of [`basis_constant`].
#[cfg(test)]
pub(crate) fn basis_polynomial(n: [f64; 3]) -> [f64; 9] {
    let [x, y, z] = n;
    [
        1.0,
        y,
        z,
        x,
        x * y,
        y * z,
        3.0 * z * z - 1.0,
        x * z,
        x * x - y * y,
    ]
}

/// Converts between quantities: irradiance is `A_l` times radiance. The
/// way back divides by `A_l`, impossible where `A_l = 0` (odd `l > 1`)
/// unless the band is zero too (it is then left zero, and said so).
pub(crate) fn convert_quantity(
    coeffs: &ShCoeffs<DVec3>,
    from: Quantity,
    to: Quantity,
) -> Result<ShCoeffs<DVec3>> {
    Ok(match (from, to) {
        (Quantity::Radiance, Quantity::Irradiance) => coeffs.scaled_per_band(a_l),
        (Quantity::Irradiance, Quantity::Radiance) => {
            for l in 0..=coeffs.lmax() {
                if a_l(l) == 0.0 && coeffs.band(l).iter().any(|c| *c != DVec3::ZERO) {
                    bail!(
                        "radiance cannot be recovered from irradiance at degree {l}: A_{l} = 0 \
                         but the irradiance band is not zero"
                    );
                }
            }
            coeffs.scaled_per_band(|l| {
                let a = a_l(l);
                if a == 0.0 { 0.0 } else { 1.0 / a }
            })
        }
        _ => coeffs.clone(),
    })
}

/// The coefficients an lmax-2, y-up engine format starts from: truncated or
/// zero-padded to lmax 2 (with a note), turned to the y-up frame, converted
/// to `want`.
pub(crate) fn engine_coeffs(
    input: &ExportInput<'_>,
    want: Quantity,
    format: &str,
) -> Result<(ShCoeffs<DVec3>, Vec<String>)> {
    let mut notes = Vec::new();
    let lmax = input.coeffs.lmax();
    if lmax > 2 {
        notes.push(format!(
            "{format} holds lmax 2 (9 coefficients): degrees 3..={lmax} of the input are dropped"
        ));
    } else if lmax < 2 {
        notes.push(format!(
            "{format} holds lmax 2: the input has lmax {lmax}, the missing degrees are written as \
             zeros (the same function)"
        ));
    }
    let c = input.coeffs.resized(2);
    let c = to_frame(&c, input.frame, Frame::YUp);
    let c = convert_quantity(&c, input.quantity, want)?;
    Ok((c, notes))
}

/// The same function in another frame's world axes.
pub(crate) fn to_frame(coeffs: &ShCoeffs<DVec3>, from: Frame, to: Frame) -> ShCoeffs<DVec3> {
    if from == to {
        coeffs.clone()
    } else {
        ShRotation::between_frames(coeffs.lmax(), from, to).apply(coeffs)
    }
}

/// `"y-up"` / `"z-up"` with the axis the map's top row faces.
pub(crate) fn frame_words(frame: Frame) -> &'static str {
    match frame {
        Frame::YUp => "y-up (world +Y up; three.js / glTF equirect mapping)",
        Frame::ZUp => "z-up (world +Z up; Blender equirect mapping)",
    }
}

/// A float literal every target language reads (C, GLSL, HLSL, WGSL):
/// the shortest round-trip decimal, always with a `.` or an exponent.
pub(crate) fn float_literal(v: f64) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e', 'E']) {
        s
    } else {
        format!("{s}.0")
    }
}

/// A float array literal for JSON and messages.
pub(crate) fn rgb_array(v: DVec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The header comment of the code snippets: what the array holds, in which
/// basis, quantity and frame, and what each function returns.
pub(crate) fn code_header(
    input: &ExportInput<'_>,
    comment: &str,
    array: &str,
    prefix: &str,
) -> String {
    let c = input.coeffs;
    let (what, definition) = match input.quantity {
        Quantity::Radiance => ("radiance", "L_lm = integral of L(w) Y_lm(w) dw"),
        Quantity::Irradiance => (
            "irradiance",
            "E_lm = A_l L_lm (Ramamoorthi & Hanrahan 2001)",
        ),
    };
    let mut lines = vec![
        format!(
            "shlight {} -- SH {what}, lmax {} ({} RGB coefficients)",
            env!("CARGO_PKG_VERSION"),
            c.lmax(),
            c.len()
        ),
        format!("{array}[i], i = l*(l+1)+m: {what} coefficients {definition},"),
        "  linear Rec.709 RGB, real orthonormal SH WITH the Condon-Shortley phase:".into(),
        "  Y_1^-1 = -0.488603 y, Y_1^0 = 0.488603 z, Y_1^1 = -0.488603 x (shlight docs/conventions.md).".into(),
        format!(
            "Frame: {}; w and n are unit vectors in those world axes.",
            frame_words(input.frame)
        ),
    ];
    if input.quantity == Quantity::Radiance {
        lines.push(format!(
            "{prefix}radiance(w): radiance L(w) arriving from direction w (the band-limited sum)."
        ));
    }
    lines.push(format!(
        "{prefix}irradiance(n): irradiance E(n) = integral of L(w) max(n.w, 0) dw at normal n"
    ));
    lines.push("  (times albedo / pi: the radiance a Lambertian surface reflects).".into());
    lines.push(
        "Y_l^m by the normalised associated-Legendre recurrences and the azimuth recurrence".into(),
    );
    lines.push(
        "  C_m = x C_(m-1) - y S_(m-1), S_m = x S_(m-1) + y C_(m-1) (Sloan 2008): any lmax.".into(),
    );
    lines.iter().map(|l| format!("{comment} {l}\n")).collect()
}

/// `A_l`, `l = 0..=lmax`, for the snippets' irradiance of radiance files,
/// as comma-separated literals.
pub(crate) fn band_weight_list(lmax: usize) -> String {
    let a: Vec<String> = (0..=lmax)
        .map(|l| float_literal(clamped_cosine_eigenvalue(l)))
        .collect();
    a.join(", ")
}

/// The comment above the snippets' `A_l` arrays.
pub(crate) const BAND_WEIGHT_COMMENT: &str =
    "// A_l, the clamped-cosine eigenvalues: irradiance is A_l times radiance, band by band.";

/// The snippets' coefficient rows, one line each:
/// `    {open}r, g, b{close}, // l=.. m=..`, the comma left off the last row
/// unless `comma_after_last`.
pub(crate) fn coefficient_rows(
    coeffs: &ShCoeffs<DVec3>,
    open: &str,
    close: &str,
    comma_after_last: bool,
) -> String {
    let n = coeffs.len();
    let mut s = String::new();
    for (i, v) in coeffs.as_slice().iter().enumerate() {
        let (l, m) = lm_from_index(i);
        let sep = if comma_after_last || i + 1 < n {
            ","
        } else {
            ""
        };
        s.push_str(&format!(
            "    {open}{}, {}, {}{close}{sep} // l={l} m={m}\n",
            float_literal(v.x),
            float_literal(v.y),
            float_literal(v.z)
        ));
    }
    s
}

/// Refuses values a 32-bit float cannot hold (the shader targets).
pub(crate) fn check_f32_range(coeffs: &ShCoeffs<DVec3>, format: &str) -> Result<()> {
    for (i, v) in coeffs.as_slice().iter().enumerate() {
        if v.abs().max_element() > f32::MAX as f64 {
            let (l, m) = lm_from_index(i);
            bail!(
                "coefficient {i} (l={l}, m={m}) = {v} does not fit a 32-bit float, which {format} uses"
            );
        }
    }
    Ok(())
}

/// GLSL and HLSL share the evaluator's text up to a few spellings.
pub(crate) struct CLikeShader {
    /// `vec3` / `float3`.
    pub vec3: &'static str,
    /// Qualifier of constants: `const` / `static const`.
    pub konst: &'static str,
    /// Opening of an array initialiser of `n` elements of type `ty`:
    /// GLSL `ty[n](`, HLSL `{`.
    pub array_open: fn(ty: &str, n: usize) -> String,
    /// Its closing, on a line of its own: `);` / `};`.
    pub array_close: &'static str,
}

impl CLikeShader {
    /// The snippet below the header: arrays, evaluator, public functions.
    pub(crate) fn body(&self, input: &ExportInput<'_>) -> String {
        let c = input.coeffs;
        let (lmax, n, v3) = (c.lmax(), c.len(), self.vec3);
        let mut s = format!("{} int SHLIGHT_LMAX = {lmax};\n", self.konst);
        s.push_str(&format!(
            "{} {v3} SHLIGHT_COEFFS[{n}] = {}\n",
            self.konst,
            (self.array_open)(v3, n)
        ));
        s.push_str(&coefficient_rows(c, &format!("{v3}("), ")", false));
        s.push_str(self.array_close);
        s.push('\n');
        let radiance = input.quantity == Quantity::Radiance;
        if radiance {
            s.push_str(&format!(
                "{BAND_WEIGHT_COMMENT}\n{} float SHLIGHT_A[{}] = {}{}{}\n",
                self.konst,
                lmax + 1,
                (self.array_open)("float", lmax + 1),
                band_weight_list(lmax),
                self.array_close
            ));
        }
        let (param, weight) = if radiance {
            (
                ", bool irradiance",
                "float w = irradiance ? SHLIGHT_A[l] : 1.0;",
            )
        } else {
            ("", "float w = 1.0;")
        };
        s.push_str(&format!(
            r#"
// sum over l, m of w_l SHLIGHT_COEFFS[l*(l+1)+m] Y_l^m(n), w_l = A_l for irradiance from radiance, else 1.
{v3} shlight_expand({v3} n{param}) {{
    float x = n.x;
    float y = n.y;
    float z = n.z;
    float c = 1.0; // sin^m(theta) cos(m phi)
    float s = 0.0; // sin^m(theta) sin(m phi)
    float pmm = 0.28209479177387814; // Pbar_m^m / sin^m(theta), m = 0: 1 / sqrt(4 pi)
    {v3} sum = {v3}(0.0, 0.0, 0.0);
    for (int m = 0; m <= SHLIGHT_LMAX; m++) {{
        if (m > 0) {{
            float cn = x * c - y * s;
            s = x * s + y * c;
            c = cn;
            pmm = pmm * -sqrt(float(2 * m + 1) / float(2 * m));
        }}
        float p1 = 0.0; // Pbar_(l-1)^m / sin^m
        float p2 = 0.0; // Pbar_(l-2)^m / sin^m
        for (int l = m; l <= SHLIGHT_LMAX; l++) {{
            float p = pmm;
            if (l == m + 1) {{
                p = sqrt(float(2 * m + 3)) * z * pmm;
            }} else if (l > m + 1) {{
                float a = sqrt(float(4 * l * l - 1) / float(l * l - m * m));
                float b = sqrt(float((l - 1) * (l - 1) - m * m) / float(4 * (l - 1) * (l - 1) - 1));
                p = a * (z * p1 - b * p2);
            }}
            p2 = p1;
            p1 = p;
            {weight}
            if (m == 0) {{
                sum += SHLIGHT_COEFFS[l * l + l] * (w * p);
            }} else {{
                float t = w * 1.4142135623730951 * p;
                sum += SHLIGHT_COEFFS[l * l + l + m] * (t * c) + SHLIGHT_COEFFS[l * l + l - m] * (t * s);
            }}
        }}
    }}
    return sum;
}}
"#
        ));
        if radiance {
            s.push_str(&format!(
                "\n// Radiance L(w) arriving from direction w.\n{v3} shlight_radiance({v3} w) {{\n    return shlight_expand(w, false);\n}}\n"
            ));
            s.push_str(&format!(
                "\n// Irradiance E(n) at a surface with normal n.\n{v3} shlight_irradiance({v3} n) {{\n    return shlight_expand(n, true);\n}}\n"
            ));
        } else {
            s.push_str(&format!(
                "\n// Irradiance E(n) at a surface with normal n.\n{v3} shlight_irradiance({v3} n) {{\n    return shlight_expand(n);\n}}\n"
            ));
        }
        s
    }
}

/// Reads `text` (from the file `name`) written by one of the exporters
/// that keep enough information: three.js LightProbe JSON, a glTF with
/// `EXT_lights_image_based`, shlight's Unity JSON, Filament sh.txt.
/// Returns `Ok(None)` for a shlight coefficient file (the caller reads it
/// with `CoeffFile::from_json_str`).
pub fn read_back(text: &str, name: &str) -> Result<Option<Imported>> {
    let trimmed = text.trim_start();
    if trimmed.starts_with('{') {
        let v: Value =
            serde_json::from_str(text).map_err(|e| anyhow!("{name}: not valid JSON: {e}"))?;
        if v.get("format").and_then(Value::as_str) == Some("shlight-sh") {
            return Ok(None);
        }
        if v.get("format").and_then(Value::as_str) == Some(unity::FORMAT_TAG)
            || v.get("SphericalHarmonicsL2").is_some()
        {
            return unity::read(&v, name).map(Some);
        }
        if v.pointer("/extensions/EXT_lights_image_based").is_some() {
            return gltf::read(&v, name).map(Some);
        }
        if threejs::is_light_probe_json(&v) {
            return threejs::read(&v, name).map(Some);
        }
        bail!(
            "{name}: JSON, but not a file shlight reads (a shlight coefficient file, three.js \
             LightProbe JSON, a glTF with EXT_lights_image_based, or shlight's Unity export)"
        );
    }
    if trimmed.starts_with('(') {
        return filament::read(text, name).map(Some);
    }
    bail!(
        "{name}: not a file shlight reads (a shlight coefficient file, three.js LightProbe JSON, \
         glTF EXT_lights_image_based, shlight's Unity JSON, or Filament sh.txt)"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_constants_times_polynomials_are_the_basis() {
        let basis = shlight_core::ShBasis::<f64>::new(2);
        let mut y = [0.0; 9];
        for d in [[0.36, 0.48, 0.8], [-0.6, 0.0, -0.8], [0.0, -1.0, 0.0]] {
            basis.eval(d, &mut y);
            let p = basis_polynomial(d);
            for i in 0..9 {
                assert!((basis_constant(i) * p[i] - y[i]).abs() < 1e-15, "i={i}");
            }
        }
    }

    #[test]
    fn float_literals_parse_back_exactly() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -2.5,
            1e-300,
            1e20,
            0.1,
            0.28209479177387814,
            -7e-9,
        ] {
            let s = float_literal(v);
            assert!(s.contains(['.', 'e']), "{s}");
            assert_eq!(s.parse::<f64>().unwrap(), v, "{s}");
        }
    }

    #[test]
    fn extensions_name_formats_or_say_why_not() {
        let f = |p: &str| ExportFormat::from_path(Path::new(p));
        assert_eq!(f("a/sh.wgsl").unwrap(), ExportFormat::Wgsl);
        assert_eq!(f("sh.FRAG").unwrap(), ExportFormat::Glsl);
        assert_eq!(f("sh.hlsl").unwrap(), ExportFormat::Hlsl);
        assert_eq!(f("sh.h").unwrap(), ExportFormat::C);
        assert_eq!(f("scene.gltf").unwrap(), ExportFormat::Gltf);
        let err = f("probe.json").unwrap_err().to_string();
        assert!(
            err.contains("probe.json") && err.contains("--format"),
            "{err}"
        );
        assert!(f("sh.txt").unwrap_err().to_string().contains("filament"));
        assert!(f("sh.xyz").unwrap_err().to_string().contains(".xyz"));
    }

    #[test]
    fn irradiance_to_radiance_refuses_what_cannot_be_undone() {
        let mut e = ShCoeffs::<DVec3>::zeros(3);
        e[(3, 1)] = DVec3::ONE;
        let err = convert_quantity(&e, Quantity::Irradiance, Quantity::Radiance).unwrap_err();
        assert!(err.to_string().contains("degree 3"), "{err}");
        let l = ShCoeffs::from_fn(2, |l, m| DVec3::splat(1.0 + l as f64 + m as f64 * 0.1));
        let e = convert_quantity(&l, Quantity::Radiance, Quantity::Irradiance).unwrap();
        let back = convert_quantity(&e, Quantity::Irradiance, Quantity::Radiance).unwrap();
        for (a, b) in back.as_slice().iter().zip(l.as_slice()) {
            assert!((*a - *b).abs().max_element() < 1e-15);
        }
    }

    #[test]
    fn engine_coeffs_truncate_pad_and_turn_to_y_up() {
        // A directional light from +Z in a z-up file is a light from +Y in y-up.
        let light: ShCoeffs<DVec3> =
            shlight_core::analytic::directional(4, [0.0, 0.0, 1.0], DVec3::ONE);
        let input = ExportInput {
            coeffs: &light,
            quantity: Quantity::Radiance,
            frame: Frame::ZUp,
        };
        let (c, notes) = engine_coeffs(&input, Quantity::Radiance, "x").unwrap();
        assert_eq!(c.lmax(), 2);
        assert!(notes[0].contains("dropped"), "{notes:?}");
        let want = shlight_core::sh_eval(2, [0.0, 1.0, 0.0]);
        for (g, w) in c.as_slice().iter().zip(&want) {
            assert!((g.x - w).abs() < 1e-14);
        }
        let short = light.resized(1);
        let input = ExportInput {
            coeffs: &short,
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
        };
        let (c, notes) = engine_coeffs(&input, Quantity::Radiance, "x").unwrap();
        assert_eq!(c.lmax(), 2);
        assert!(c.band(2).iter().all(|v| *v == DVec3::ZERO));
        assert!(notes[0].contains("zeros"), "{notes:?}");
    }
}
