//! Exporters: shlight coefficients to the formats engines and shaders read,
//! and back where the target keeps enough (docs/exporters.md).
//!
//! Every exporter starts from an [`ExportInput`]: coefficients in shlight's
//! basis (real orthonormal, Condon-Shortley phase, index `l(l+1)+m`), a
//! quantity (radiance or irradiance) and a frame (y-up or z-up). Each target
//! module states exactly what its numbers are and which source it follows
//! ([`ExportFormat`] tabulates them).

mod c;
mod encoded_snippet;
mod engine;
pub(crate) mod filament;
mod glsl;
pub mod gltf;
mod hlsl;
mod snippet;
pub(crate) mod threejs;
mod txt;
pub(crate) mod unity;
mod wgsl;

use std::path::Path;

use glam::DVec3;
use shlight_core::sh::{Frame, ShCoeffs, lm_from_index};

use crate::{CoeffFile, FormatError, Quantity, Result};

#[cfg(test)]
pub(crate) use engine::basis_polynomial;
pub use engine::engine_frame;
pub(crate) use engine::{basis_constant, engine_coeffs, frame_words, rgb_array, transform};
pub(crate) use shlight_shader::float_literal;
pub(crate) use snippet::{check_f32_range, snippet};

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

/// The formats coefficients can be written in (`--format`).
///
/// What each one holds (each exporter's file states its numbers and the
/// source it follows; docs/exporters.md):
///
/// | format | numbers | phase | frame | lmax |
/// |---|---|---|---|---|
/// | `txt` | the file's quantity | none (R&H tables) | the file's | any |
/// | `threejs` | radiance `L_lm` | none | y-up | 2 |
/// | [`gltf`](crate::gltf) | irradiance `E_lm = A_l L_lm` | CS | y-up (glTF) | 2 |
/// | `filament` | `E_lm k_lm / pi` (shader-prescaled) | folded in | y-up | 2 |
/// | `unity` | `E_lm k_lm / pi` (SphericalHarmonicsL2) | folded in | Unity: z flipped | 2 |
/// | `wgsl`, `glsl`, `hlsl`, `c` | the file's quantity + evaluator | CS | the file's | any |
///
/// (`k_lm` is the constant of the basis polynomial, `Y_lm(n) = k_lm p_lm(n)`.)
/// Formats limited to lmax 2 truncate a longer expansion (with a note on
/// stderr) and pad a shorter one with zeros, which is exact: a degree-1
/// expansion is the same function as the degree-2 one with zero band 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
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
    /// Every format, in the order `--format` lists them.
    pub const ALL: [ExportFormat; 10] = [
        ExportFormat::Json,
        ExportFormat::Txt,
        ExportFormat::Threejs,
        ExportFormat::Gltf,
        ExportFormat::Filament,
        ExportFormat::Unity,
        ExportFormat::Wgsl,
        ExportFormat::Glsl,
        ExportFormat::Hlsl,
        ExportFormat::C,
    ];

    /// The `--format` spelling.
    #[must_use]
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

    /// A one-line description, for `--help`.
    #[must_use]
    pub fn description(self) -> &'static str {
        match self {
            ExportFormat::Json => "shlight's self-describing JSON coefficient file",
            ExportFormat::Txt => "a Ramamoorthi-Hanrahan table (L00, L1-1, ...), no CS phase",
            ExportFormat::Threejs => "three.js LightProbe.toJSON() (radiance, no CS phase)",
            ExportFormat::Gltf => "a glTF 2.0 asset with an EXT_lights_image_based light",
            ExportFormat::Filament => {
                "Filament cmgen --sh-shader sh.txt (prescaled irradiance / pi)"
            }
            ExportFormat::Unity => "Unity SphericalHarmonicsL2 and unity_SHAr..SHC",
            ExportFormat::Wgsl => "WGSL coefficient array and evaluator, any lmax",
            ExportFormat::Glsl => "GLSL coefficient array and evaluator, any lmax",
            ExportFormat::Hlsl => "HLSL coefficient array and evaluator, any lmax",
            ExportFormat::C => "C coefficient array and evaluator, any lmax",
        }
    }

    /// Whether the format keeps every encoding (`shlight project
    /// --encoding`): shlight's JSON and the four code snippets, which get an
    /// evaluator of their own for each (docs/exporters.md).
    #[must_use]
    pub fn takes_encodings(self) -> bool {
        matches!(
            self,
            ExportFormat::Json
                | ExportFormat::Wgsl
                | ExportFormat::Glsl
                | ExportFormat::Hlsl
                | ExportFormat::C
        )
    }

    /// The file extension of this format's files (`-o DIR` batches name
    /// their outputs `NAME.ext`).
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            ExportFormat::Json | ExportFormat::Threejs | ExportFormat::Unity => "json",
            ExportFormat::Txt | ExportFormat::Filament => "txt",
            ExportFormat::Gltf => "gltf",
            ExportFormat::Wgsl => "wgsl",
            ExportFormat::Glsl => "glsl",
            ExportFormat::Hlsl => "hlsl",
            // Static arrays and static inline functions: a header.
            ExportFormat::C => "h",
        }
    }

    /// The format an output path's extension names, where only one does.
    ///
    /// # Errors
    /// `.json` (json, threejs, gltf, unity) and `.txt` (txt, filament) are
    /// ambiguous and give an error that says so, as do unknown extensions.
    pub fn from_path(path: &Path) -> Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        let name = path.display().to_string();
        let bad = |message: String| Err(FormatError::invalid(&name, message));
        Ok(match ext.as_str() {
            "wgsl" => ExportFormat::Wgsl,
            "glsl" | "frag" | "vert" | "comp" => ExportFormat::Glsl,
            "hlsl" | "hlsli" | "fx" => ExportFormat::Hlsl,
            "c" | "h" => ExportFormat::C,
            "gltf" => ExportFormat::Gltf,
            "json" => {
                return bad(
                    "cannot tell the format from the extension .json (json, threejs, \
                     gltf and unity all write JSON)"
                        .into(),
                );
            }
            "txt" => {
                return bad(
                    "cannot tell the format from the extension .txt (txt and filament \
                     both write text)"
                        .into(),
                );
            }
            "" => return bad("no extension to tell the format from".into()),
            other => {
                return bad(format!(
                    "no format writes .{other} files (the formats: json, txt, threejs, gltf, \
                     filament, unity, wgsl, glsl, hlsl, c)"
                ));
            }
        })
    }
}

impl std::fmt::Display for ExportFormat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ExportFormat {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let s = s.trim();
        ExportFormat::ALL
            .into_iter()
            .find(|f| f.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = ExportFormat::ALL.iter().map(|f| f.name()).collect();
                format!("unknown format {s:?} ({})", names.join(", "))
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

/// The text of `file` in `format`, and the exporter's notes (truncation,
/// padding, missing parts): `json` is shlight's coefficient file
/// ([`CoeffFile::to_json_string`]); every other format goes through
/// [`export_coeffs`], and notes that it drops the Monte Carlo standard
/// errors when the file has them.
///
/// # Errors
/// As [`export_coeffs`], the message naming the file's input.
pub fn export(file: &CoeffFile, format: ExportFormat) -> Result<Exported> {
    export_with(file, format, None)
}

/// [`export`] as a glTF asset whose light carries `specular` (the map's
/// prefiltered cube; [`gltf`]), or, with `None`, the irradiance
/// coefficients alone (a light the extension's schema does not accept;
/// a note says so).
///
/// # Errors
/// As [`export`].
pub fn export_gltf(file: &CoeffFile, specular: Option<&gltf::SpecularImages>) -> Result<Exported> {
    export_with(file, ExportFormat::Gltf, Some(specular))
}

/// [`export`], and for glTF the specular images (`Some(None)`: knowingly
/// without them).
fn export_with(
    file: &CoeffFile,
    format: ExportFormat,
    gltf_specular: Option<Option<&gltf::SpecularImages>>,
) -> Result<Exported> {
    if format == ExportFormat::Json {
        return Ok(Exported {
            text: file.to_json_string() + "\n",
            notes: Vec::new(),
        });
    }
    if file.encoding != crate::FileEncoding::Sh {
        if !format.takes_encodings() {
            return Err(FormatError::Export(format!(
                "{}: {} cannot take the {} encoding (its coefficients are not the whole light); \
                 only shlight's JSON and the wgsl, glsl, hlsl and c snippets keep encodings",
                file.provenance.input,
                format.name(),
                file.encoding.encoding()
            )));
        }
        return encoded_snippet::render(file, format).map_err(|e| {
            FormatError::Export(format!(
                "{}: exporting as {}: {e}",
                file.provenance.input,
                format.name()
            ))
        });
    }
    let input = ExportInput {
        coeffs: &file.coeffs,
        quantity: file.quantity,
        frame: file.frame,
    };
    let rendered = match (format, gltf_specular) {
        (ExportFormat::Gltf, Some(specular)) => {
            check_finite(input.coeffs).and_then(|()| gltf::render(&input, specular))
        }
        _ => export_coeffs(&input, format),
    };
    let mut out = rendered.map_err(|e| {
        FormatError::Export(format!(
            "{}: exporting as {}: {e}",
            file.provenance.input,
            format.name()
        ))
    })?;
    if file.std_error.is_some() {
        out.notes.push(format!(
            "{} has no place for the Monte Carlo standard errors; they are kept only in \
             shlight's JSON (the json format)",
            format.name()
        ));
    }
    Ok(out)
}

/// Renders coefficients in `format` and returns the text and the notes.
///
/// # Errors
/// [`FormatError::Export`] for coefficients that are not finite, do not
/// fit the target's float type, or cannot be converted to the quantity the
/// target holds; `json` is refused here (it needs the whole [`CoeffFile`]:
/// use [`export`]).
pub fn export_coeffs(input: &ExportInput<'_>, format: ExportFormat) -> Result<Exported> {
    check_finite(input.coeffs)?;
    match format {
        ExportFormat::Json => Err(FormatError::Export(
            "the json format is shlight's coefficient file: export the CoeffFile".into(),
        )),
        ExportFormat::Txt => Ok(txt::render(input)),
        ExportFormat::Threejs => threejs::render(input),
        ExportFormat::Gltf => Err(FormatError::Export(gltf::MISSING_SPECULAR.to_owned())),
        ExportFormat::Filament => filament::render(input),
        ExportFormat::Unity => unity::render(input),
        ExportFormat::Wgsl => wgsl::render(input),
        ExportFormat::Glsl => glsl::render(input),
        ExportFormat::Hlsl => hlsl::render(input),
        ExportFormat::C => Ok(c::render(input)),
    }
}

fn check_finite(coeffs: &ShCoeffs<DVec3>) -> Result<()> {
    for (i, v) in coeffs.as_slice().iter().enumerate() {
        if !v.is_finite() {
            let (l, m) = lm_from_index(i);
            return Err(FormatError::Export(format!(
                "coefficient {i} (l={l}, m={m}) is not finite: {v}"
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_constants_times_polynomials_are_the_basis() {
        let basis = shlight_core::sh::ShBasis::<f64>::new(2);
        let mut y = [0.0; 9];
        for d in [[0.36, 0.48, 0.8], [-0.6, 0.0, -0.8], [0.0, -1.0, 0.0]] {
            basis.eval(DVec3::from(d), &mut y);
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
        // Which formats write the extension, and no front end's flag.
        assert!(
            err.contains("probe.json") && err.contains("threejs") && !err.contains("--"),
            "{err}"
        );
        assert!(f("sh.txt").unwrap_err().to_string().contains("filament"));
        assert!(f("sh.xyz").unwrap_err().to_string().contains(".xyz"));
    }

    #[test]
    fn batch_extensions_name_their_format_where_an_extension_can() {
        for f in ExportFormat::ALL {
            let ext = f.extension();
            match ExportFormat::from_path(Path::new(&format!("x.{ext}"))) {
                Ok(g) => assert_eq!(g, f, "{ext}"),
                // .json and .txt are shared; convert asks for --format.
                Err(_) => assert!(ext == "json" || ext == "txt", "{ext}"),
            }
        }
    }

    #[test]
    fn names_parse_back() {
        for f in ExportFormat::ALL {
            assert_eq!(f.name().parse::<ExportFormat>().unwrap(), f);
        }
        assert!("fbx".parse::<ExportFormat>().unwrap_err().contains("fbx"));
    }

    #[test]
    fn engine_coeffs_truncate_pad_and_turn_to_y_up() {
        // A directional light from +Z in a z-up file is a light from +Y in y-up.
        let light: ShCoeffs<DVec3> =
            shlight_core::sh::closed_form::directional(4, DVec3::new(0.0, 0.0, 1.0), DVec3::ONE);
        let input = ExportInput {
            coeffs: &light,
            quantity: Quantity::Radiance,
            frame: Frame::ZUp,
        };
        let (c, notes) = engine_coeffs(&input, Quantity::Radiance, ExportFormat::Threejs).unwrap();
        assert_eq!(c.lmax(), 2);
        assert!(notes[0].contains("dropped"), "{notes:?}");
        let want = shlight_core::sh::sh_eval(2, DVec3::new(0.0, 1.0, 0.0));
        for (g, w) in c.as_slice().iter().zip(&want) {
            assert!((g.x - w).abs() < 1e-14);
        }
        let short = light.resized(1);
        let input = ExportInput {
            coeffs: &short,
            quantity: Quantity::Radiance,
            frame: Frame::YUp,
        };
        let (c, notes) = engine_coeffs(&input, Quantity::Radiance, ExportFormat::Threejs).unwrap();
        assert_eq!(c.lmax(), 2);
        assert!(c.band(2).iter().all(|v| *v == DVec3::ZERO));
        assert!(notes[0].contains("zeros"), "{notes:?}");
    }
}
