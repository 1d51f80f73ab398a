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
//! The formulas are the core's, statement for statement:
//! [`shlight_core::encoding`] (Snyder 1996, including the case where the
//! cap crosses the horizon), [`shlight_core::encoding`], [`shlight_core::encoding`],
//! [`shlight_core::encoding`]. Arrays cannot be empty in these
//! languages: with no light the light arrays hold one zero light and
//! `SHLIGHT_LIGHT_COUNT` is 0.

use core::f64::consts::PI;

use glam::DVec3;
use shlight_core::encoding::{CapLight, Encoded, Encoding};
use shlight_core::sh::ShCoeffs;

use super::{ExportFormat, ExportInput, Exported, float_literal};
use crate::{CoeffFile, FormatError, Quantity, Result};

/// `(atan(u) - u) / u³` to `u^14` (error below 4e-12 for `u < 0.25`),
/// Horner form in `u2 = u²`.
const SERIES: &str = "-0.3333333333333333 + u2 * (0.2 + u2 * (-0.14285714285714285 + u2 * (0.1111111111111111 + u2 * (-0.09090909090909091 + u2 * (0.07692307692307693 + u2 * -0.06666666666666667)))))";

/// Rec.709 luminance weights, the core's (ZH3's luminance axis).
const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

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
    let lang = Lang::of(format);
    let mut text = header(encoding, &encoded, lang.comment_note());
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
    text.push_str(&lang.body(encoding, &parts));
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

/// The three code dialects: GLSL/HLSL share one text.
enum Lang {
    Wgsl,
    CLike {
        vec3: &'static str,
        konst: &'static str,
        hlsl: bool,
    },
    C,
}

fn f(v: f64) -> String {
    float_literal(v)
}

impl Lang {
    fn of(format: ExportFormat) -> Self {
        match format {
            ExportFormat::Wgsl => Lang::Wgsl,
            ExportFormat::Hlsl => Lang::CLike {
                vec3: "float3",
                konst: "static const",
                hlsl: true,
            },
            ExportFormat::C => Lang::C,
            _ => Lang::CLike {
                vec3: "vec3",
                konst: "const",
                hlsl: false,
            },
        }
    }

    fn comment_note(&self) -> &'static str {
        match self {
            Lang::C => "C99, double precision; link with -lm where needed.",
            _ => "32-bit floats.",
        }
    }

    fn v3(&self, v: DVec3) -> String {
        let (x, y, z) = (f(v.x), f(v.y), f(v.z));
        match self {
            Lang::Wgsl => format!("vec3<f32>({x}, {y}, {z})"),
            Lang::CLike { vec3, .. } => format!("{vec3}({x}, {y}, {z})"),
            Lang::C => format!("{{{x}, {y}, {z}}}"),
        }
    }

    /// An array constant of `rows` (vec3 when `vec`, else scalars `x`).
    fn array(&self, name: &str, vec: bool, rows: &[DVec3]) -> String {
        let n = rows.len();
        let items: Vec<String> = rows
            .iter()
            .map(|r| if vec { self.v3(*r) } else { f(r.x) })
            .collect();
        let body = items
            .iter()
            .map(|i| format!("    {i}"))
            .collect::<Vec<_>>()
            .join(",\n");
        match self {
            Lang::Wgsl => {
                let ty = if vec { "vec3<f32>" } else { "f32" };
                format!("var<private> {name}: array<{ty}, {n}> = array<{ty}, {n}>(\n{body}\n);\n")
            }
            Lang::CLike { vec3, konst, hlsl } => {
                let ty = if vec { *vec3 } else { "float" };
                if *hlsl {
                    format!("{konst} {ty} {name}[{n}] = {{\n{body}\n}};\n")
                } else {
                    format!("{konst} {ty} {name}[{n}] = {ty}[{n}](\n{body}\n);\n")
                }
            }
            Lang::C => {
                let dims = if vec { "[3]" } else { "" };
                let lower = name.to_ascii_lowercase();
                format!("static const double {lower}[{n}]{dims} = {{\n{body}\n}};\n")
            }
        }
    }

    fn int_const(&self, name: &str, v: usize) -> String {
        match self {
            Lang::Wgsl => format!("const {name}: i32 = {v};\n"),
            Lang::CLike { konst, .. } => format!("{konst} int {name} = {v};\n"),
            Lang::C => format!("#define {name} {v}\n"),
        }
    }

    fn vec_const(&self, name: &str, v: DVec3) -> String {
        match self {
            Lang::Wgsl => format!("const {name}: vec3<f32> = {};\n", self.v3(v)),
            Lang::CLike { vec3, konst, .. } => format!("{konst} {vec3} {name} = {};\n", self.v3(v)),
            Lang::C => format!(
                "static const double {}[3] = {};\n",
                name.to_ascii_lowercase(),
                self.v3(v)
            ),
        }
    }

    /// The text below the SH part.
    fn body(&self, encoding: Encoding, parts: &Parts) -> String {
        let mut s = String::new();
        match &parts.extra {
            Extra::Lights(lights) => {
                s.push_str(&format!(
                    "// The {} light(s) kept exactly ({}).\n",
                    lights.len(),
                    if encoding == Encoding::SloanSh {
                        "Sloan's light"
                    } else {
                        "dominant lights"
                    }
                ));
                s.push_str(&self.int_const("SHLIGHT_LIGHT_COUNT", lights.len()));
                let padded: Vec<CapLight<DVec3>> = if lights.is_empty() {
                    vec![CapLight {
                        direction: DVec3::Z,
                        half_angle: 0.0,
                        power: DVec3::ZERO,
                    }]
                } else {
                    lights.clone()
                };
                let dirs: Vec<DVec3> = padded.iter().map(|l| l.direction).collect();
                let angles: Vec<DVec3> =
                    padded.iter().map(|l| DVec3::splat(l.half_angle)).collect();
                let powers: Vec<DVec3> = padded.iter().map(|l| l.power).collect();
                s.push_str(&self.array("SHLIGHT_LIGHT_DIRECTION", true, &dirs));
                s.push_str(&self.array("SHLIGHT_LIGHT_HALF_ANGLE", false, &angles));
                s.push_str(&self.array("SHLIGHT_LIGHT_POWER", true, &powers));
                s.push_str(&self.cap_function());
                s.push_str(&self.lights_irradiance());
            }
            Extra::Zh3Stored(z) => {
                s.push_str("// The stored zonal degree-2 coefficient z per channel (RGB).\n");
                s.push_str(&self.vec_const("SHLIGHT_ZH3_ZONAL", *z));
                s.push_str(&self.zh3(false));
            }
            Extra::Zh3Hallucinated => s.push_str(&self.zh3(true)),
            Extra::L1NonLinear => s.push_str(&self.l1_nonlinear()),
            Extra::Cube(c) => {
                s.push_str("// Irradiance at +x, -x, +y, -y, +z, -z (RGB).\n");
                s.push_str(&self.array("SHLIGHT_CUBE", true, c));
                s.push_str(&self.cube());
            }
        }
        s
    }

    /// `shlight_cap_per_power(alpha, cos_t)`: [`shlight_core::encoding::cap_irradiance_per_power`].
    fn cap_function(&self) -> String {
        let four_pi = f(4.0 * PI);
        let doc = "\n// Irradiance per unit power of a uniform cap of half-angle alpha whose centre makes\n\
                   // cosine cos_t with the normal (Snyder 1996, divided by the power 2 pi (1 - cos alpha) L):\n\
                   // (1 + cos alpha) / 2 max(cos_t, 0) while the cap is wholly above or below the horizon.\n";
        let body = match self {
            Lang::Wgsl => format!(
                "fn shlight_cap_per_power(alpha: f32, cos_t_in: f32) -> f32 {{\n\
                 \x20   let cos_t = clamp(cos_t_in, -1.0, 1.0);\n\
                 \x20   let sin_a = sin(alpha);\n\
                 \x20   let sin2 = sin_a * sin_a;\n\
                 \x20   if (alpha <= 0.0 || cos_t * cos_t >= sin2) {{\n\
                 \x20       return (1.0 + cos(alpha)) / 2.0 * max(cos_t, 0.0);\n\
                 \x20   }}\n\
                 \x20   let sin_t = sqrt(1.0 - cos_t * cos_t);\n\
                 \x20   let x = cos(alpha) / sin_a;\n\
                 \x20   let y = -x * cos_t / sin_t;\n\
                 \x20   let s = sin_t * sqrt(max(1.0 - y * y, 0.0));\n\
                 \x20   // atan(u) - x s sin2 = u sin2 + (atan(u) - u), u = s / x, the last by its series\n\
                 \x20   // for small u: the two near-equal terms do not cancel in 32 bits.\n\
                 \x20   let u = s / x;\n\
                 \x20   let u2 = u * u;\n\
                 \x20   var d = atan(u) - u;\n\
                 \x20   if (u < 0.25) {{\n\
                 \x20       d = u * u2 * ({SERIES});\n\
                 \x20   }}\n\
                 \x20   let e = cos_t * acos(clamp(y, -1.0, 1.0)) * sin2 + u * sin2 + d;\n\
                 \x20   let h = sin(alpha / 2.0);\n\
                 \x20   return e / ({four_pi} * h * h);\n\
                 }}\n"
            ),
            Lang::CLike { .. } | Lang::C => {
                let (ty, cst, lc) = match self {
                    Lang::C => ("double", "static inline double", "const "),
                    _ => ("float", "float", ""),
                };
                let fmax = if matches!(self, Lang::C) {
                    "fmax"
                } else {
                    "max"
                };
                let clamp = |v: &str| {
                    if matches!(self, Lang::C) {
                        format!("fmin(fmax({v}, -1.0), 1.0)")
                    } else {
                        format!("clamp({v}, -1.0, 1.0)")
                    }
                };
                format!(
                    "{cst} shlight_cap_per_power({ty} alpha, {ty} cos_t_in) {{\n\
                     \x20   {lc}{ty} cos_t = {};\n\
                     \x20   {lc}{ty} sin_a = sin(alpha);\n\
                     \x20   {lc}{ty} sin2 = sin_a * sin_a;\n\
                     \x20   if (alpha <= 0.0 || cos_t * cos_t >= sin2) {{\n\
                     \x20       return (1.0 + cos(alpha)) / 2.0 * {fmax}(cos_t, 0.0);\n\
                     \x20   }}\n\
                     \x20   {lc}{ty} sin_t = sqrt(1.0 - cos_t * cos_t);\n\
                     \x20   {lc}{ty} x = cos(alpha) / sin_a;\n\
                     \x20   {lc}{ty} y = -x * cos_t / sin_t;\n\
                     \x20   {lc}{ty} s = sin_t * sqrt({fmax}(1.0 - y * y, 0.0));\n\
                     {tail}\
                     \x20   {lc}{ty} h = sin(alpha / 2.0);\n\
                     \x20   return e / ({four_pi} * h * h);\n\
                     }}\n",
                    clamp("cos_t_in"),
                    tail = if matches!(self, Lang::C) {
                        format!(
                            "    const double e = (cos_t * acos({}) - x * s) * sin2 + atan(s / x);\n",
                            clamp("y")
                        )
                    } else {
                        format!(
                            "    // atan(u) - x s sin2 = u sin2 + (atan(u) - u), u = s / x, the last by its series\n\
                             \x20   // for small u: the two near-equal terms do not cancel in 32 bits.\n\
                             \x20   float u = s / x;\n\
                             \x20   float u2 = u * u;\n\
                             \x20   float d = atan(u) - u;\n\
                             \x20   if (u < 0.25) {{\n\
                             \x20       d = u * u2 * ({SERIES});\n\
                             \x20   }}\n\
                             \x20   float e = cos_t * acos({}) * sin2 + u * sin2 + d;\n",
                            clamp("y")
                        )
                    }
                )
            }
        };
        format!("{doc}{body}")
    }

    fn lights_irradiance(&self) -> String {
        match self {
            Lang::Wgsl => "\n// The lights' irradiance at normal n.\n\
                fn shlight_lights_irradiance(n: vec3<f32>) -> vec3<f32> {\n\
                \x20   var e = vec3<f32>(0.0, 0.0, 0.0);\n\
                \x20   for (var k: i32 = 0; k < SHLIGHT_LIGHT_COUNT; k++) {\n\
                \x20       e += SHLIGHT_LIGHT_POWER[k] * shlight_cap_per_power(SHLIGHT_LIGHT_HALF_ANGLE[k], dot(n, SHLIGHT_LIGHT_DIRECTION[k]));\n\
                \x20   }\n\
                \x20   return e;\n\
                }\n\n\
                // Irradiance E(n) at a surface with normal n: the SH part plus the lights.\n\
                fn shlight_irradiance(n: vec3<f32>) -> vec3<f32> {\n\
                \x20   return shlight_sh_irradiance(n) + shlight_lights_irradiance(n);\n\
                }\n"
                .to_string(),
            Lang::CLike { vec3: v3, .. } => format!(
                "\n// The lights' irradiance at normal n.\n\
                 {v3} shlight_lights_irradiance({v3} n) {{\n\
                 \x20   {v3} e = {v3}(0.0, 0.0, 0.0);\n\
                 \x20   for (int k = 0; k < SHLIGHT_LIGHT_COUNT; k++) {{\n\
                 \x20       e += SHLIGHT_LIGHT_POWER[k] * shlight_cap_per_power(SHLIGHT_LIGHT_HALF_ANGLE[k], dot(n, SHLIGHT_LIGHT_DIRECTION[k]));\n\
                 \x20   }}\n\
                 \x20   return e;\n\
                 }}\n\n\
                 // Irradiance E(n) at a surface with normal n: the SH part plus the lights.\n\
                 {v3} shlight_irradiance({v3} n) {{\n\
                 \x20   return shlight_sh_irradiance(n) + shlight_lights_irradiance(n);\n\
                 }}\n"
            ),
            Lang::C => "\n// Irradiance E(n) at a surface with normal n: the SH part plus the lights.\n\
                static inline void shlight_irradiance(const double n[3], double out[3]) {\n\
                \x20   shlight_sh_irradiance(n, out);\n\
                \x20   for (int k = 0; k < SHLIGHT_LIGHT_COUNT; k++) {\n\
                \x20       const double *d = shlight_light_direction[k];\n\
                \x20       const double w = shlight_cap_per_power(shlight_light_half_angle[k], n[0] * d[0] + n[1] * d[1] + n[2] * d[2]);\n\
                \x20       for (int c = 0; c < 3; c++) {\n\
                \x20           out[c] += shlight_light_power[k][c] * w;\n\
                \x20       }\n\
                \x20   }\n\
                }\n"
            .to_string(),
        }
    }

    /// ZH3's axis, zonal coefficient and irradiance.
    fn zh3(&self, hallucinated: bool) -> String {
        let [lr, lg, lb] = LUMA.map(f);
        let zh = f(PI / 4.0 * (5.0 / (16.0 * PI)).sqrt());
        let mut s = String::new();
        match self {
            Lang::Wgsl => {
                s.push_str(&format!(
                    "\n// The luminance axis a: the unit Rec.709-luminance degree-1 vector (-f11, -f1-1, f10); +z if zero.\n\
                     fn shlight_zh3_axis() -> vec3<f32> {{\n\
                     \x20   let w = vec3<f32>({lr}, {lg}, {lb});\n\
                     \x20   let v = vec3<f32>(-dot(SHLIGHT_COEFFS[3], w), -dot(SHLIGHT_COEFFS[1], w), dot(SHLIGHT_COEFFS[2], w));\n\
                     \x20   let len = length(v);\n\
                     \x20   if (len > 0.0) {{\n\
                     \x20       return v / len;\n\
                     \x20   }}\n\
                     \x20   return vec3<f32>(0.0, 0.0, 1.0);\n\
                     }}\n"
                ));
                if hallucinated {
                    s.push_str(
                        "\n// The hallucinated zonal coefficient of one channel: f00 (0.08 r + 0.6 r^2), r = |v.a| / f00.\n\
                         fn shlight_zh3_hallucinate(f00: f32, va: f32) -> f32 {\n\
                         \x20   if (f00 <= 0.0) {\n\
                         \x20       return 0.0;\n\
                         \x20   }\n\
                         \x20   let r = abs(va) / f00;\n\
                         \x20   return f00 * (0.08 * r + 0.6 * r * r);\n\
                         }\n\n\
                         // z per channel, from the lmax-1 part.\n\
                         fn shlight_zh3_z(a: vec3<f32>) -> vec3<f32> {\n\
                         \x20   let va = -SHLIGHT_COEFFS[3] * a.x - SHLIGHT_COEFFS[1] * a.y + SHLIGHT_COEFFS[2] * a.z;\n\
                         \x20   let f00 = SHLIGHT_COEFFS[0];\n\
                         \x20   return vec3<f32>(shlight_zh3_hallucinate(f00.x, va.x), shlight_zh3_hallucinate(f00.y, va.y), shlight_zh3_hallucinate(f00.z, va.z));\n\
                         }\n",
                    );
                } else {
                    s.push_str(
                        "\n// z per channel: the stored coefficient.\n\
                         fn shlight_zh3_z(a: vec3<f32>) -> vec3<f32> {\n\
                         \x20   return SHLIGHT_ZH3_ZONAL;\n\
                         }\n",
                    );
                }
                s.push_str(&format!(
                    "\n// Irradiance E(n) at a surface with normal n: E_1(n) + (pi/4) z sqrt(5/(16 pi)) (3 (a.n)^2 - 1).\n\
                     fn shlight_irradiance(n: vec3<f32>) -> vec3<f32> {{\n\
                     \x20   let a = shlight_zh3_axis();\n\
                     \x20   let t = dot(a, n);\n\
                     \x20   return shlight_sh_irradiance(n) + shlight_zh3_z(a) * ({zh} * (3.0 * t * t - 1.0));\n\
                     }}\n"
                ));
            }
            Lang::CLike { vec3: v3, .. } => {
                s.push_str(&format!(
                    "\n// The luminance axis a: the unit Rec.709-luminance degree-1 vector (-f11, -f1-1, f10); +z if zero.\n\
                     {v3} shlight_zh3_axis() {{\n\
                     \x20   {v3} w = {v3}({lr}, {lg}, {lb});\n\
                     \x20   {v3} v = {v3}(-dot(SHLIGHT_COEFFS[3], w), -dot(SHLIGHT_COEFFS[1], w), dot(SHLIGHT_COEFFS[2], w));\n\
                     \x20   float len = length(v);\n\
                     \x20   if (len > 0.0) {{\n\
                     \x20       return v / len;\n\
                     \x20   }}\n\
                     \x20   return {v3}(0.0, 0.0, 1.0);\n\
                     }}\n"
                ));
                if hallucinated {
                    s.push_str(&format!(
                        "\n// The hallucinated zonal coefficient of one channel: f00 (0.08 r + 0.6 r^2), r = |v.a| / f00.\n\
                         float shlight_zh3_hallucinate(float f00, float va) {{\n\
                         \x20   if (f00 <= 0.0) {{\n\
                         \x20       return 0.0;\n\
                         \x20   }}\n\
                         \x20   float r = abs(va) / f00;\n\
                         \x20   return f00 * (0.08 * r + 0.6 * r * r);\n\
                         }}\n\n\
                         // z per channel, from the lmax-1 part.\n\
                         {v3} shlight_zh3_z({v3} a) {{\n\
                         \x20   {v3} va = -SHLIGHT_COEFFS[3] * a.x - SHLIGHT_COEFFS[1] * a.y + SHLIGHT_COEFFS[2] * a.z;\n\
                         \x20   {v3} f00 = SHLIGHT_COEFFS[0];\n\
                         \x20   return {v3}(shlight_zh3_hallucinate(f00.x, va.x), shlight_zh3_hallucinate(f00.y, va.y), shlight_zh3_hallucinate(f00.z, va.z));\n\
                         }}\n"
                    ));
                } else {
                    s.push_str(&format!(
                        "\n// z per channel: the stored coefficient.\n\
                         {v3} shlight_zh3_z({v3} a) {{\n\
                         \x20   return SHLIGHT_ZH3_ZONAL;\n\
                         }}\n"
                    ));
                }
                s.push_str(&format!(
                    "\n// Irradiance E(n) at a surface with normal n: E_1(n) + (pi/4) z sqrt(5/(16 pi)) (3 (a.n)^2 - 1).\n\
                     {v3} shlight_irradiance({v3} n) {{\n\
                     \x20   {v3} a = shlight_zh3_axis();\n\
                     \x20   float t = dot(a, n);\n\
                     \x20   return shlight_sh_irradiance(n) + shlight_zh3_z(a) * ({zh} * (3.0 * t * t - 1.0));\n\
                     }}\n"
                ));
            }
            Lang::C => {
                s.push_str(&format!(
                    "\n// The luminance axis a: the unit Rec.709-luminance degree-1 vector (-f11, -f1-1, f10); +z if zero.\n\
                     static inline void shlight_zh3_axis(double a[3]) {{\n\
                     \x20   static const double w[3] = {{{lr}, {lg}, {lb}}};\n\
                     \x20   double v[3] = {{0.0, 0.0, 0.0}};\n\
                     \x20   for (int c = 0; c < 3; c++) {{\n\
                     \x20       v[0] -= shlight_coeffs[3][c] * w[c];\n\
                     \x20       v[1] -= shlight_coeffs[1][c] * w[c];\n\
                     \x20       v[2] += shlight_coeffs[2][c] * w[c];\n\
                     \x20   }}\n\
                     \x20   const double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);\n\
                     \x20   if (len > 0.0) {{\n\
                     \x20       a[0] = v[0] / len;\n\
                     \x20       a[1] = v[1] / len;\n\
                     \x20       a[2] = v[2] / len;\n\
                     \x20   }} else {{\n\
                     \x20       a[0] = 0.0;\n\
                     \x20       a[1] = 0.0;\n\
                     \x20       a[2] = 1.0;\n\
                     \x20   }}\n\
                     }}\n"
                ));
                if hallucinated {
                    s.push_str(
                        "\n// z per channel, hallucinated from the lmax-1 part: f00 (0.08 r + 0.6 r^2), r = |v.a| / f00.\n\
                         static inline void shlight_zh3_z(const double a[3], double z[3]) {\n\
                         \x20   for (int c = 0; c < 3; c++) {\n\
                         \x20       const double f00 = shlight_coeffs[0][c];\n\
                         \x20       const double va = -shlight_coeffs[3][c] * a[0] - shlight_coeffs[1][c] * a[1] + shlight_coeffs[2][c] * a[2];\n\
                         \x20       const double r = f00 > 0.0 ? fabs(va) / f00 : 0.0;\n\
                         \x20       z[c] = f00 > 0.0 ? f00 * (0.08 * r + 0.6 * r * r) : 0.0;\n\
                         \x20   }\n\
                         }\n",
                    );
                } else {
                    s.push_str(
                        "\n// z per channel: the stored coefficient.\n\
                         static inline void shlight_zh3_z(const double a[3], double z[3]) {\n\
                         \x20   (void)a;\n\
                         \x20   for (int c = 0; c < 3; c++) {\n\
                         \x20       z[c] = shlight_zh3_zonal[c];\n\
                         \x20   }\n\
                         }\n",
                    );
                }
                s.push_str(&format!(
                    "\n// Irradiance E(n) at a surface with normal n: E_1(n) + (pi/4) z sqrt(5/(16 pi)) (3 (a.n)^2 - 1).\n\
                     static inline void shlight_irradiance(const double n[3], double out[3]) {{\n\
                     \x20   double a[3], z[3];\n\
                     \x20   shlight_zh3_axis(a);\n\
                     \x20   shlight_zh3_z(a, z);\n\
                     \x20   const double t = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];\n\
                     \x20   shlight_sh_irradiance(n, out);\n\
                     \x20   for (int c = 0; c < 3; c++) {{\n\
                     \x20       out[c] += z[c] * ({zh} * (3.0 * t * t - 1.0));\n\
                     \x20   }}\n\
                     }}\n"
                ));
            }
        }
        s
    }

    fn l1_nonlinear(&self) -> String {
        let (k0, k1, pi) = (
            f(1.0 / (2.0 * PI.sqrt())),
            f(1.0 / (2.0 * (3.0 * PI).sqrt())),
            f(PI),
        );
        let doc = "\n// Hazel's non-linear irradiance of one channel from its lmax-1 radiance f00, f1-1, f10, f11 (header).\n";
        match self {
            Lang::Wgsl => format!(
                "{doc}fn shlight_l1_channel(f00: f32, f1m1: f32, f10: f32, f11: f32, n: vec3<f32>) -> f32 {{\n\
                 \x20   let r0 = f00 * {k0};\n\
                 \x20   if (r0 <= 0.0) {{\n\
                 \x20       return 0.0;\n\
                 \x20   }}\n\
                 \x20   let r1 = vec3<f32>(-f11, -f1m1, f10) * {k1};\n\
                 \x20   let len = length(r1);\n\
                 \x20   if (len == 0.0) {{\n\
                 \x20       return {pi} * r0;\n\
                 \x20   }}\n\
                 \x20   let r = min(len / r0, 1.0);\n\
                 \x20   let p = 1.0 + 2.0 * r;\n\
                 \x20   let a = (1.0 - r) / (1.0 + r);\n\
                 \x20   let q = max(0.5 * (1.0 + dot(r1, n) / len), 0.0);\n\
                 \x20   return {pi} * r0 * (a + (1.0 - a) * (p + 1.0) * pow(q, p));\n\
                 }}\n\n\
                 // Irradiance E(n) at a surface with normal n, channel by channel.\n\
                 fn shlight_irradiance(n: vec3<f32>) -> vec3<f32> {{\n\
                 \x20   let c0 = SHLIGHT_COEFFS[0];\n\
                 \x20   let c1 = SHLIGHT_COEFFS[1];\n\
                 \x20   let c2 = SHLIGHT_COEFFS[2];\n\
                 \x20   let c3 = SHLIGHT_COEFFS[3];\n\
                 \x20   return vec3<f32>(\n\
                 \x20       shlight_l1_channel(c0.x, c1.x, c2.x, c3.x, n),\n\
                 \x20       shlight_l1_channel(c0.y, c1.y, c2.y, c3.y, n),\n\
                 \x20       shlight_l1_channel(c0.z, c1.z, c2.z, c3.z, n),\n\
                 \x20   );\n\
                 }}\n"
            ),
            Lang::CLike { vec3: v3, .. } => format!(
                "{doc}float shlight_l1_channel(float f00, float f1m1, float f10, float f11, {v3} n) {{\n\
                 \x20   float r0 = f00 * {k0};\n\
                 \x20   if (r0 <= 0.0) {{\n\
                 \x20       return 0.0;\n\
                 \x20   }}\n\
                 \x20   {v3} r1 = {v3}(-f11, -f1m1, f10) * {k1};\n\
                 \x20   float len = length(r1);\n\
                 \x20   if (len == 0.0) {{\n\
                 \x20       return {pi} * r0;\n\
                 \x20   }}\n\
                 \x20   float r = min(len / r0, 1.0);\n\
                 \x20   float p = 1.0 + 2.0 * r;\n\
                 \x20   float a = (1.0 - r) / (1.0 + r);\n\
                 \x20   float q = max(0.5 * (1.0 + dot(r1, n) / len), 0.0);\n\
                 \x20   return {pi} * r0 * (a + (1.0 - a) * (p + 1.0) * pow(q, p));\n\
                 }}\n\n\
                 // Irradiance E(n) at a surface with normal n, channel by channel.\n\
                 {v3} shlight_irradiance({v3} n) {{\n\
                 \x20   {v3} c0 = SHLIGHT_COEFFS[0];\n\
                 \x20   {v3} c1 = SHLIGHT_COEFFS[1];\n\
                 \x20   {v3} c2 = SHLIGHT_COEFFS[2];\n\
                 \x20   {v3} c3 = SHLIGHT_COEFFS[3];\n\
                 \x20   return {v3}(\n\
                 \x20       shlight_l1_channel(c0.x, c1.x, c2.x, c3.x, n),\n\
                 \x20       shlight_l1_channel(c0.y, c1.y, c2.y, c3.y, n),\n\
                 \x20       shlight_l1_channel(c0.z, c1.z, c2.z, c3.z, n));\n\
                 }}\n"
            ),
            Lang::C => format!(
                "{doc}static inline double shlight_l1_channel(int c, const double n[3]) {{\n\
                 \x20   const double r0 = shlight_coeffs[0][c] * {k0};\n\
                 \x20   if (r0 <= 0.0) {{\n\
                 \x20       return 0.0;\n\
                 \x20   }}\n\
                 \x20   const double r1[3] = {{-shlight_coeffs[3][c] * {k1}, -shlight_coeffs[1][c] * {k1}, shlight_coeffs[2][c] * {k1}}};\n\
                 \x20   const double len = sqrt(r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2]);\n\
                 \x20   if (len == 0.0) {{\n\
                 \x20       return {pi} * r0;\n\
                 \x20   }}\n\
                 \x20   const double r = fmin(len / r0, 1.0);\n\
                 \x20   const double p = 1.0 + 2.0 * r;\n\
                 \x20   const double a = (1.0 - r) / (1.0 + r);\n\
                 \x20   const double q = fmax(0.5 * (1.0 + (r1[0] * n[0] + r1[1] * n[1] + r1[2] * n[2]) / len), 0.0);\n\
                 \x20   return {pi} * r0 * (a + (1.0 - a) * (p + 1.0) * pow(q, p));\n\
                 }}\n\n\
                 // Irradiance E(n) at a surface with normal n, channel by channel.\n\
                 static inline void shlight_irradiance(const double n[3], double out[3]) {{\n\
                 \x20   for (int c = 0; c < 3; c++) {{\n\
                 \x20       out[c] = shlight_l1_channel(c, n);\n\
                 \x20   }}\n\
                 }}\n"
            ),
        }
    }

    fn cube(&self) -> String {
        match self {
            Lang::Wgsl => "\n// Irradiance E(n) at a surface with normal n: the colours blended by n^2.\n\
                fn shlight_irradiance(n: vec3<f32>) -> vec3<f32> {\n\
                \x20   let nn = n * n;\n\
                \x20   let cx = select(SHLIGHT_CUBE[0], SHLIGHT_CUBE[1], n.x < 0.0);\n\
                \x20   let cy = select(SHLIGHT_CUBE[2], SHLIGHT_CUBE[3], n.y < 0.0);\n\
                \x20   let cz = select(SHLIGHT_CUBE[4], SHLIGHT_CUBE[5], n.z < 0.0);\n\
                \x20   return nn.x * cx + nn.y * cy + nn.z * cz;\n\
                }\n"
            .to_string(),
            Lang::CLike { vec3: v3, .. } => format!(
                "\n// Irradiance E(n) at a surface with normal n: the colours blended by n^2.\n\
                 {v3} shlight_irradiance({v3} n) {{\n\
                 \x20   {v3} nn = n * n;\n\
                 \x20   {v3} cx = n.x < 0.0 ? SHLIGHT_CUBE[1] : SHLIGHT_CUBE[0];\n\
                 \x20   {v3} cy = n.y < 0.0 ? SHLIGHT_CUBE[3] : SHLIGHT_CUBE[2];\n\
                 \x20   {v3} cz = n.z < 0.0 ? SHLIGHT_CUBE[5] : SHLIGHT_CUBE[4];\n\
                 \x20   return nn.x * cx + nn.y * cy + nn.z * cz;\n\
                 }}\n"
            ),
            Lang::C => "\n// Irradiance E(n) at a surface with normal n: the colours blended by n^2.\n\
                static inline void shlight_irradiance(const double n[3], double out[3]) {\n\
                \x20   const double *cx = shlight_cube[n[0] < 0.0 ? 1 : 0];\n\
                \x20   const double *cy = shlight_cube[n[1] < 0.0 ? 3 : 2];\n\
                \x20   const double *cz = shlight_cube[n[2] < 0.0 ? 5 : 4];\n\
                \x20   for (int c = 0; c < 3; c++) {\n\
                \x20       out[c] = n[0] * n[0] * cx[c] + n[1] * n[1] * cy[c] + n[2] * n[2] * cz[c];\n\
                \x20   }\n\
                }\n"
            .to_string(),
        }
    }
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
