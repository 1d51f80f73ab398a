//! The shader and C snippets (WGSL, GLSL, HLSL, C) of a coefficient file
//! that holds an encoding other than plain SH (docs/exporters.md,
//! "Encodings in the snippets"): each gets `shlight_irradiance(n)` equal to
//! the core's [`Encoded::irradiance`] of the file.
//!
//! | encoding | SH part (`shlight_sh_irradiance`) | what the snippet adds |
//! |---|---|---|
//! | `dominant+sh` | the residual's radiance SH | `SHLIGHT_LIGHT_*`: each light a uniform cap, Snyder's exact irradiance |
//! | `sloan+sh` | the residual once Sloan's light is taken out (at export) | the light, as for `dominant+sh` (half-angle 0) |
//! | `zh3` | the lmax-1 coefficients | `SHLIGHT_ZH3_ZONAL` and the luminance axis computed from the lmax-1 part |
//! | `zh3-hallucinated` | the lmax-1 coefficients | the zonal coefficient computed from the lmax-1 part |
//! | `l1-nonlinear` | the lmax-1 coefficients (the linear irradiance) | Hazel's non-linear reconstruction per channel |
//! | `ambient-cube` | none | `SHLIGHT_CUBE`, six colours blended by `n²` |
//!
//! This file chooses the parts and writes the header; the code is
//! shlight-shader's [`shlight_shader::encodings`], the core's formulas
//! ([`shlight_core::encoding`]) statement for statement in every language.

use glam::DVec3;
use shlight_core::encoding::{CapLight, Encoded, Encoding};
use shlight_core::sh::ShCoeffs;
use shlight_shader::Language;
use shlight_shader::encodings::{EncodingTerm, encoding_code};

use super::{ExportFormat, ExportInput, Exported};
use crate::{CoeffFile, FormatError, Quantity, Result};

/// The snippet of `file` in `format` (one of the four snippet formats),
/// whose encoding is not plain SH.
///
/// # Errors
/// An irradiance file (encodings keep radiance), coefficients too short
/// for the encoding, or values a 32-bit float cannot hold (shaders).
pub(crate) fn render(file: &CoeffFile, format: ExportFormat) -> Result<Exported> {
    let encoding = file.encoding.encoding();
    let encoded = file.encoded().ok_or_else(|| {
        FormatError::Export(if file.quantity != Quantity::Radiance {
            format!("the {encoding} encoding keeps radiance; this file holds irradiance")
        } else {
            format!("the coefficients are too short for the {encoding} encoding")
        })
    })?;
    let parts = Parts::of(&encoded, encoding);
    if format != ExportFormat::C {
        check_f32(&parts, format.name())?;
    }
    let lang = match format {
        ExportFormat::Wgsl => Language::Wgsl,
        ExportFormat::Hlsl => Language::Hlsl,
        ExportFormat::C => Language::C,
        _ => Language::Glsl,
    };
    let note = if lang.is_c() {
        "C99, double precision; link with -lm where needed."
    } else {
        "32-bit floats."
    };
    let mut text = header(encoding, &encoded, note);
    if let Some(sh) = &parts.sh {
        let input = ExportInput {
            coeffs: sh,
            quantity: Quantity::Radiance,
            frame: file.frame,
        };
        let sh_text = match format {
            ExportFormat::Wgsl => super::wgsl::render_named(&input, "shlight_sh_")?.text,
            ExportFormat::Glsl => super::glsl::render_named(&input, "shlight_sh_")?.text,
            ExportFormat::Hlsl => super::hlsl::render_named(&input, "shlight_sh_")?.text,
            _ => super::c::render_named(&input, "shlight_sh_").text,
        };
        text.push_str("//\n// The SH part:\n");
        text.push_str(&sh_text);
    } else {
        text.push_str(&format!(
            "// Frame: {}; n is a unit vector in those world axes.\n",
            super::frame_words(file.frame)
        ));
        if format == ExportFormat::C {
            text.push_str("// C99.\n");
        }
    }
    text.push('\n');
    text.push_str(&encoding_code(lang, parts.term(encoding)));
    Ok(Exported {
        text,
        notes: Vec::new(),
    })
}

/// What an encoding's snippet holds besides its SH part.
struct Parts {
    /// The SH part (radiance), when it has one.
    sh: Option<ShCoeffs<DVec3>>,
    /// What the snippet adds.
    extra: Extra,
}

enum Extra {
    Lights(Vec<CapLight<DVec3>>),
    Zh3Stored(DVec3),
    Zh3Hallucinated,
    L1NonLinear,
    Cube([DVec3; 6]),
}

impl Parts {
    fn of(encoded: &Encoded, encoding: Encoding) -> Self {
        let l1 = |c: &[DVec3; 4]| Some(ShCoeffs::from_vec(c.to_vec()).expect("4 coefficients"));
        match encoded {
            Encoded::Sh(f) => Self {
                sh: Some(f.clone()),
                extra: Extra::Lights(Vec::new()),
            },
            Encoded::Lights { lights, residual } => Self {
                sh: Some(residual.clone()),
                extra: Extra::Lights(lights.clone()),
            },
            Encoded::Zh3(z) => Self {
                sh: l1(&z.l1),
                // The hallucinated zonal coefficient is a function of the
                // lmax-1 part: the snippet computes it as the core does.
                extra: if encoding == Encoding::Zh3Hallucinated {
                    Extra::Zh3Hallucinated
                } else {
                    Extra::Zh3Stored(z.zonal)
                },
            },
            Encoded::L1NonLinear(l) => Self {
                sh: l1(&l.l1),
                extra: Extra::L1NonLinear,
            },
            Encoded::AmbientCube(c) => Self {
                sh: None,
                extra: Extra::Cube(c.colours),
            },
        }
    }

    /// What the snippet adds, for shlight-shader.
    fn term(&self, encoding: Encoding) -> EncodingTerm<'_> {
        match &self.extra {
            Extra::Lights(lights) => EncodingTerm::Lights {
                lights,
                sloan: encoding == Encoding::SloanSh,
            },
            Extra::Zh3Stored(z) => EncodingTerm::Zh3Stored(*z),
            Extra::Zh3Hallucinated => EncodingTerm::Zh3Hallucinated,
            Extra::L1NonLinear => EncodingTerm::L1NonLinear,
            Extra::Cube(c) => EncodingTerm::AmbientCube(c),
        }
    }

    /// The numbers besides the SH part, for the range check.
    fn numbers(&self) -> Vec<(String, DVec3)> {
        match &self.extra {
            Extra::Lights(lights) => lights
                .iter()
                .enumerate()
                .map(|(i, l)| (format!("light {i} power"), l.power))
                .collect(),
            Extra::Zh3Stored(z) => vec![("the zonal coefficient".into(), *z)],
            Extra::Cube(c) => c
                .iter()
                .zip(crate::file_encoding::CUBE_KEYS)
                .map(|(v, k)| (format!("ambient cube colour {k}"), *v))
                .collect(),
            Extra::Zh3Hallucinated | Extra::L1NonLinear => Vec::new(),
        }
    }
}

fn check_f32(parts: &Parts, format: &str) -> Result<()> {
    if let Some(sh) = &parts.sh {
        super::check_f32_range(sh, format)?;
    }
    for (what, v) in parts.numbers() {
        if !v.is_finite() || v.abs().max_element() > f32::MAX as f64 {
            return Err(FormatError::Export(format!(
                "{what} = {v} does not fit a 32-bit float, which {format} uses"
            )));
        }
    }
    Ok(())
}

/// The encoding's header comment: what it is, its source, what the
/// snippet's names hold.
fn header(encoding: Encoding, encoded: &Encoded, lang_note: &str) -> String {
    let mut lines = vec![format!(
        "shlight {} -- the {encoding} encoding; shlight_irradiance(n) is its irradiance E(n)",
        env!("CARGO_PKG_VERSION")
    )];
    let more: &[&str] = match encoding {
        Encoding::DominantSh => &[
            "  (its lights, kept exactly, plus the residual's SH: shlight_sh_irradiance).",
            "Each light is a uniform cap (a small disc of directions): SHLIGHT_LIGHT_DIRECTION (unit,",
            "  towards its centre), SHLIGHT_LIGHT_HALF_ANGLE (radians) and SHLIGHT_LIGHT_POWER (its",
            "  radiance integrated over the cap, RGB). Its irradiance is Snyder's exact formula, the cap",
            "  crossing the horizon included (J. Snyder, Area light sources for real-time graphics,",
            "  MSR-TR-96-11, 1996; Lagarde & de Rousiers, Moving Frostbite to PBR, 2014, 4.7.2).",
        ],
        Encoding::SloanSh => &[
            "  (Sloan's directional light, found from the coefficients when this was written and kept",
            "  exactly, plus the residual's SH: shlight_sh_irradiance; P.-P. Sloan, Stupid Spherical",
            "  Harmonics (SH) Tricks, GDC 2008). The light is a cap of half-angle 0 (SHLIGHT_LIGHT_*).",
        ],
        Encoding::Zh3 | Encoding::Zh3Hallucinated => &[
            "  ZH3 (Roughton, Sloan, Silvennoinen, Iwanicki and Shirley, ZH3: Quadratic Zonal Harmonics,",
            "  i3D 2024): the lmax-1 SH (shlight_sh_irradiance) plus one zonal degree-2 coefficient per",
            "  channel about the luminance axis a, the unit Rec.709-luminance degree-1 vector:",
            "  E(n) = E_1(n) + (pi/4) z sqrt(5/(16 pi)) (3 (a.n)^2 - 1).",
        ],
        Encoding::L1NonLinear => &[
            "  the non-linear reconstruction of lmax-1 radiance (G. Hazel and C. Doran, Converting SH",
            "  Radiance to Irradiance, 2017; the Geomerics model Frostbite and Godot use), per channel:",
            "  R0 = f00 / (2 sqrt(pi)), R1 = (-f11, -f1-1, f10) / (2 sqrt(3 pi)), r = min(|R1| / R0, 1),",
            "  p = 1 + 2r, a = (1 - r) / (1 + r), q = (1 + R1.n / |R1|) / 2,",
            "  E(n) = pi R0 (a + (1 - a) (p + 1) q^p). shlight_sh_irradiance is the linear one.",
        ],
        Encoding::AmbientCube => &[
            "  the ambient cube (Mitchell, McTaggart and Green, Shading in Valve's Source Engine,",
            "  SIGGRAPH 2006; the lookup of Bevy's irradiance volumes): SHLIGHT_CUBE holds the",
            "  irradiance at +x, -x, +y, -y, +z, -z, and",
            "  E(n) = n.x^2 C[x] + n.y^2 C[y] + n.z^2 C[z], C[x] = C[+x] if n.x >= 0 else C[-x] (so y, z).",
        ],
        Encoding::Sh => &[],
    };
    lines.extend(more.iter().map(|s| s.to_string()));
    if let (Encoding::Zh3, Encoded::Zh3(z)) = (encoding, encoded) {
        lines.push(
            "  SHLIGHT_ZH3_ZONAL is the stored z (the band-2 projection onto the zonal harmonic about a);"
                .into(),
        );
        lines.push(format!(
            "  a = ({:.6}, {:.6}, {:.6}) is computed from the lmax-1 part.",
            z.axis.x, z.axis.y, z.axis.z
        ));
    }
    if encoding == Encoding::Zh3Hallucinated {
        lines.push(
            "  z is hallucinated from the lmax-1 part (the paper's 3.4.3 fit): r = |v.a| / f00,"
                .into(),
        );
        lines.push("  z = f00 (0.08 r + 0.6 r^2), v the channel's degree-1 vector.".into());
    }
    if !lang_note.is_empty() {
        lines.push(lang_note.to_string());
    }
    lines.iter().map(|l| format!("// {l}\n")).collect()
}

#[cfg(test)]
mod tests {
    use shlight_core::sh::Frame;

    use super::*;
    use crate::FileEncoding;

    fn file(encoding: FileEncoding, quantity: Quantity) -> CoeffFile {
        let l1 = ShCoeffs::from_vec(vec![
            DVec3::ONE,
            DVec3::ZERO,
            DVec3::splat(0.3),
            DVec3::ZERO,
        ])
        .unwrap();
        let mut f = CoeffFile::new(l1, Frame::YUp, quantity);
        f.provenance.input = "enc.exr".into();
        f.encoding = encoding;
        f
    }

    #[test]
    fn an_irradiance_file_or_a_colour_beyond_f32_is_refused_naming_the_file() {
        let f = file(FileEncoding::L1NonLinear, Quantity::Irradiance);
        let err = crate::export(&f, ExportFormat::Wgsl)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("enc.exr") && err.contains("irradiance"),
            "{err}"
        );
        let mut colours = [DVec3::ONE; 6];
        colours[3] = DVec3::splat(1e39);
        let f = file(FileEncoding::AmbientCube { colours }, Quantity::Radiance);
        let err = crate::export(&f, ExportFormat::Hlsl)
            .unwrap_err()
            .to_string();
        assert!(err.contains("-y") && err.contains("32-bit"), "{err}");
        // C keeps doubles.
        let c = crate::export(&f, ExportFormat::C).unwrap().text;
        assert!(c.contains("1e39"), "{c}");
    }

    #[test]
    fn no_light_is_one_zero_light_and_a_count_of_zero() {
        let f = file(
            FileEncoding::DominantSh { lights: Vec::new() },
            Quantity::Radiance,
        );
        let glsl = crate::export(&f, ExportFormat::Glsl).unwrap().text;
        assert!(
            glsl.contains("const int SHLIGHT_LIGHT_COUNT = 0;"),
            "{glsl}"
        );
        assert!(glsl.contains("SHLIGHT_LIGHT_POWER[1]"), "{glsl}");
        assert!(
            glsl.contains("vec3 shlight_sh_irradiance(vec3 n)"),
            "{glsl}"
        );
    }
}
