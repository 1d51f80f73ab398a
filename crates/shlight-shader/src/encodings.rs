//! The encodings' `shlight_irradiance(n)`: what a coefficient file that
//! holds an encoding other than plain SH adds to the code of its SH part
//! (`shlight_sh_irradiance`, [`crate::coefficients`] with the prefix
//! `shlight_sh_`), equal to the core's `Encoded::irradiance` of the file.
//!
//! | encoding | what the code adds |
//! |---|---|
//! | dominant lights + SH, Sloan's light + SH | `SHLIGHT_LIGHT_*`: each light a uniform cap, Snyder's exact irradiance |
//! | ZH3 | `SHLIGHT_ZH3_ZONAL` and the luminance axis computed from the lmax-1 part |
//! | hallucinated ZH3 | the zonal coefficient computed from the lmax-1 part |
//! | non-linear L1 | Hazel's non-linear reconstruction per channel |
//! | ambient cube | `SHLIGHT_CUBE`, six colours blended by `n^2` |
//!
//! The formulas are shlight-core's (`shlight_core::encoding`), statement
//! for statement: Snyder 1996 for a cap (including the case where it
//! crosses the horizon), ZH3 (Roughton et al. 2024), Hazel and Doran 2017,
//! Valve's ambient cube. The shading languages share one text up to
//! spelling; C, which has no vectors, writes the same formulas channel by
//! channel, in double precision (so a cap needs no series, below). Arrays
//! cannot be empty in these languages: with no light the light arrays hold
//! one zero light and `SHLIGHT_LIGHT_COUNT` is 0.

use core::f64::consts::PI;

use glam::DVec3;
use shlight_core::encoding::CapLight;

use crate::{Code, Language, Type, float_literal};

/// `(atan(u) - u) / u³` to `u^14` (error below 4e-12 for `u < 0.25`),
/// Horner form in `u2 = u²`.
const SERIES: &str = "-0.3333333333333333 + u2 * (0.2 + u2 * (-0.14285714285714285 + u2 * (0.1111111111111111 + u2 * (-0.09090909090909091 + u2 * (0.07692307692307693 + u2 * -0.06666666666666667)))))";

/// Rec.709 luminance weights, the core's (ZH3's luminance axis).
const LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// What an encoding adds to its SH part.
#[derive(Clone, Copy, Debug)]
pub enum EncodingTerm<'a> {
    /// Lights kept exactly (dominant lights, or Sloan's light when
    /// `sloan`), each a uniform cap.
    Lights {
        /// The lights, most powerful first; may be empty.
        lights: &'a [CapLight<DVec3>],
        /// Whether this is Sloan's light (the comment says which).
        sloan: bool,
    },
    /// ZH3 with its stored zonal coefficient per channel.
    Zh3Stored(DVec3),
    /// ZH3 with the zonal coefficient hallucinated from the lmax-1 part.
    Zh3Hallucinated,
    /// Hazel's non-linear reconstruction of the lmax-1 part.
    L1NonLinear,
    /// The ambient cube's colours, `+x, -x, +y, -y, +z, -z` (no SH part).
    AmbientCube(&'a [DVec3; 6]),
}

fn f(v: f64) -> String {
    float_literal(v)
}

/// The code that follows the SH part (or the header, for the ambient
/// cube): the term's constants and functions and `shlight_irradiance`.
#[must_use]
pub fn encoding_code(lang: Language, term: EncodingTerm<'_>) -> String {
    let mut c = Code::new();
    match term {
        EncodingTerm::Lights { lights, sloan } => {
            c.line(format!(
                "// The {} light(s) kept exactly ({}).",
                lights.len(),
                if sloan {
                    "Sloan's light"
                } else {
                    "dominant lights"
                }
            ));
            c.line(lang.constant(Type::Int, "SHLIGHT_LIGHT_COUNT", &lights.len().to_string()));
            let padded: Vec<CapLight<DVec3>> = if lights.is_empty() {
                vec![CapLight {
                    direction: DVec3::Z,
                    half_angle: 0.0,
                    power: DVec3::ZERO,
                }]
            } else {
                lights.to_vec()
            };
            let dirs: Vec<DVec3> = padded.iter().map(|l| l.direction).collect();
            let angles: Vec<DVec3> = padded.iter().map(|l| DVec3::splat(l.half_angle)).collect();
            let powers: Vec<DVec3> = padded.iter().map(|l| l.power).collect();
            array(lang, &mut c, "SHLIGHT_LIGHT_DIRECTION", true, &dirs);
            array(lang, &mut c, "SHLIGHT_LIGHT_HALF_ANGLE", false, &angles);
            array(lang, &mut c, "SHLIGHT_LIGHT_POWER", true, &powers);
            cap_per_power(lang, &mut c);
            lights_irradiance(lang, &mut c);
        }
        EncodingTerm::Zh3Stored(z) => {
            c.line("// The stored zonal degree-2 coefficient z per channel (RGB).");
            c.line(lang.constant(Type::Vec3, "SHLIGHT_ZH3_ZONAL", &vector(lang, z)));
            zh3(lang, &mut c, false);
        }
        EncodingTerm::Zh3Hallucinated => zh3(lang, &mut c, true),
        EncodingTerm::L1NonLinear => l1_nonlinear(lang, &mut c),
        EncodingTerm::AmbientCube(colours) => {
            c.line("// Irradiance at +x, -x, +y, -y, +z, -z (RGB).");
            array(lang, &mut c, "SHLIGHT_CUBE", true, colours);
            cube(lang, &mut c);
        }
    }
    c.finish()
}

/// `v` as a vector literal of `lang`.
fn vector(lang: Language, v: DVec3) -> String {
    lang.vector(Type::Vec3, &format!("{}, {}, {}", f(v.x), f(v.y), f(v.z)))
}

/// An array constant of `rows` (vectors when `vec`, else the scalars `x`),
/// one element a line.
fn array(lang: Language, c: &mut Code, name: &str, vec: bool, rows: &[DVec3]) {
    let t = if vec { Type::Vec3 } else { Type::Float };
    c.line(lang.array_open(t, name, &rows.len().to_string()));
    let items: Vec<String> = rows
        .iter()
        .map(|r| if vec { vector(lang, *r) } else { f(r.x) })
        .collect();
    c.line(format!("    {}", items.join(",\n    ")));
    c.line(lang.array_close());
}

/// `shlight_cap_per_power(alpha, cos_t)`: shlight-core's
/// `encoding::cap_irradiance_per_power`.
fn cap_per_power(lang: Language, c: &mut Code) {
    let fl = Type::Float;
    c.line("");
    c.line("// Irradiance per unit power of a uniform cap of half-angle alpha whose centre makes");
    c.line("// cosine cos_t with the normal (Snyder 1996, divided by the power 2 pi (1 - cos alpha) L):");
    c.line(
        "// (1 + cos alpha) / 2 max(cos_t, 0) while the cap is wholly above or below the horizon.",
    );
    c.open(format!(
        "{} {{",
        lang.signature(
            Some(fl),
            "shlight_cap_per_power",
            &[(fl, "alpha"), (fl, "cos_t_in")]
        )
    ));
    c.line(lang.let_(fl, "cos_t", &lang.clamp("cos_t_in", "-1.0", "1.0")));
    c.line(lang.let_(fl, "sin_a", "sin(alpha)"));
    c.line(lang.let_(fl, "sin2", "sin_a * sin_a"));
    c.open("if (alpha <= 0.0 || cos_t * cos_t >= sin2) {");
    c.line(format!(
        "return (1.0 + cos(alpha)) / 2.0 * {};",
        lang.max("cos_t", "0.0")
    ));
    c.close("}");
    c.line(lang.let_(fl, "sin_t", "sqrt(1.0 - cos_t * cos_t)"));
    c.line(lang.let_(fl, "x", "cos(alpha) / sin_a"));
    c.line(lang.let_(fl, "y", "-x * cos_t / sin_t"));
    c.line(lang.let_(
        fl,
        "s",
        &format!("sin_t * sqrt({})", lang.max("1.0 - y * y", "0.0")),
    ));
    let acos_y = format!("acos({})", lang.clamp("y", "-1.0", "1.0"));
    if lang.is_c() {
        // Doubles: the direct form loses nothing.
        c.line(lang.let_(
            fl,
            "e",
            &format!("(cos_t * {acos_y} - x * s) * sin2 + atan(s / x)"),
        ));
    } else {
        c.line("// atan(u) - x s sin2 = u sin2 + (atan(u) - u), u = s / x, the last by its series");
        c.line("// for small u: the two near-equal terms do not cancel in 32 bits.");
        c.line(lang.let_(fl, "u", "s / x"));
        c.line(lang.let_(fl, "u2", "u * u"));
        c.line(lang.var(fl, "d", "atan(u) - u"));
        c.open("if (u < 0.25) {");
        c.line(format!("d = u * u2 * ({SERIES});"));
        c.close("}");
        c.line(lang.let_(fl, "e", &format!("cos_t * {acos_y} * sin2 + u * sin2 + d")));
    }
    c.line(lang.let_(fl, "h", "sin(alpha / 2.0)"));
    c.line(format!("return e / ({} * h * h);", f(4.0 * PI)));
    c.close("}");
}

/// The lights' irradiance and `shlight_irradiance`, the SH part's plus it.
fn lights_irradiance(lang: Language, c: &mut Code) {
    let v3 = Type::Vec3;
    let doc = "// Irradiance E(n) at a surface with normal n: the SH part plus the lights.";
    c.line("");
    if lang.is_c() {
        c.line(doc);
        c.open(format!(
            "{} {{",
            lang.signature(Some(v3), "shlight_irradiance", &[(v3, "n")])
        ));
        c.line("shlight_sh_irradiance(n, out);");
        c.open(lang.for_open("k", "0", "k < SHLIGHT_LIGHT_COUNT", true));
        c.line("const double *d = shlight_light_direction[k];");
        c.line(lang.let_(
            Type::Float,
            "w",
            "shlight_cap_per_power(shlight_light_half_angle[k], n[0] * d[0] + n[1] * d[1] + n[2] * d[2])",
        ));
        c.open("for (int c = 0; c < 3; c++) {");
        c.line("out[c] += shlight_light_power[k][c] * w;");
        c.close("}");
        c.close("}");
        c.close("}");
        return;
    }
    c.line("// The lights' irradiance at normal n.");
    c.open(format!(
        "{} {{",
        lang.signature(Some(v3), "shlight_lights_irradiance", &[(v3, "n")])
    ));
    c.line(lang.var(v3, "e", &lang.vector(v3, "0.0, 0.0, 0.0")));
    c.open(lang.for_open("k", "0", "k < SHLIGHT_LIGHT_COUNT", true));
    c.line("e += SHLIGHT_LIGHT_POWER[k] * shlight_cap_per_power(SHLIGHT_LIGHT_HALF_ANGLE[k], dot(n, SHLIGHT_LIGHT_DIRECTION[k]));");
    c.close("}");
    c.line("return e;");
    c.close("}");
    c.line("");
    c.line(doc);
    c.open(format!(
        "{} {{",
        lang.signature(Some(v3), "shlight_irradiance", &[(v3, "n")])
    ));
    c.line("return shlight_sh_irradiance(n) + shlight_lights_irradiance(n);");
    c.close("}");
}

/// ZH3's axis, zonal coefficient and irradiance.
fn zh3(lang: Language, c: &mut Code, hallucinated: bool) {
    let (v3, fl) = (Type::Vec3, Type::Float);
    let [lr, lg, lb] = LUMA.map(f);
    let zh = f(PI / 4.0 * (5.0 / (16.0 * PI)).sqrt());
    c.line("");
    c.line("// The luminance axis a: the unit Rec.709-luminance degree-1 vector (-f11, -f1-1, f10); +z if zero.");
    if lang.is_c() {
        c.open("static inline void shlight_zh3_axis(double a[3]) {");
        c.line(format!("static const double w[3] = {{{lr}, {lg}, {lb}}};"));
        c.line("double v[3] = {0.0, 0.0, 0.0};");
        c.open("for (int c = 0; c < 3; c++) {");
        c.line("v[0] -= shlight_coeffs[3][c] * w[c];");
        c.line("v[1] -= shlight_coeffs[1][c] * w[c];");
        c.line("v[2] += shlight_coeffs[2][c] * w[c];");
        c.close("}");
        c.line(lang.let_(fl, "len", "sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])"));
        c.open("if (len > 0.0) {");
        c.lines([
            "a[0] = v[0] / len;",
            "a[1] = v[1] / len;",
            "a[2] = v[2] / len;",
        ]);
        c.reopen("} else {");
        c.lines(["a[0] = 0.0;", "a[1] = 0.0;", "a[2] = 1.0;"]);
        c.close("}");
        c.close("}");
    } else {
        c.open(format!(
            "{} {{",
            lang.signature(Some(v3), "shlight_zh3_axis", &[])
        ));
        c.line(lang.let_(v3, "w", &lang.vector(v3, &format!("{lr}, {lg}, {lb}"))));
        c.line(lang.let_(
            v3,
            "v",
            &lang.vector(
                v3,
                "-dot(SHLIGHT_COEFFS[3], w), -dot(SHLIGHT_COEFFS[1], w), dot(SHLIGHT_COEFFS[2], w)",
            ),
        ));
        c.line(lang.let_(fl, "len", "length(v)"));
        c.open("if (len > 0.0) {");
        c.line("return v / len;");
        c.close("}");
        c.line(format!("return {};", lang.vector(v3, "0.0, 0.0, 1.0")));
        c.close("}");
    }
    c.line("");
    let a_in = [(v3, "a")];
    match (hallucinated, lang.is_c()) {
        (true, true) => {
            c.line("// z per channel, hallucinated from the lmax-1 part: f00 (0.08 r + 0.6 r^2), r = |v.a| / f00.");
            c.open("static inline void shlight_zh3_z(const double a[3], double z[3]) {");
            c.open("for (int c = 0; c < 3; c++) {");
            c.line(lang.let_(fl, "f00", "shlight_coeffs[0][c]"));
            c.line(lang.let_(fl, "va", "-shlight_coeffs[3][c] * a[0] - shlight_coeffs[1][c] * a[1] + shlight_coeffs[2][c] * a[2]"));
            c.line(lang.let_(fl, "r", "f00 > 0.0 ? fabs(va) / f00 : 0.0"));
            c.line("z[c] = f00 > 0.0 ? f00 * (0.08 * r + 0.6 * r * r) : 0.0;");
            c.close("}");
            c.close("}");
        }
        (true, false) => {
            c.line("// The hallucinated zonal coefficient of one channel: f00 (0.08 r + 0.6 r^2), r = |v.a| / f00.");
            c.open(format!(
                "{} {{",
                lang.signature(
                    Some(fl),
                    "shlight_zh3_hallucinate",
                    &[(fl, "f00"), (fl, "va")]
                )
            ));
            c.open("if (f00 <= 0.0) {");
            c.line("return 0.0;");
            c.close("}");
            c.line(lang.let_(fl, "r", "abs(va) / f00"));
            c.line("return f00 * (0.08 * r + 0.6 * r * r);");
            c.close("}");
            c.line("");
            c.line("// z per channel, from the lmax-1 part.");
            c.open(format!(
                "{} {{",
                lang.signature(Some(v3), "shlight_zh3_z", &a_in)
            ));
            c.line(lang.let_(
                v3,
                "va",
                "-SHLIGHT_COEFFS[3] * a.x - SHLIGHT_COEFFS[1] * a.y + SHLIGHT_COEFFS[2] * a.z",
            ));
            c.line(lang.let_(v3, "f00", "SHLIGHT_COEFFS[0]"));
            c.line(format!(
                "return {};",
                lang.vector(
                    v3,
                    "shlight_zh3_hallucinate(f00.x, va.x), shlight_zh3_hallucinate(f00.y, va.y), shlight_zh3_hallucinate(f00.z, va.z)"
                )
            ));
            c.close("}");
        }
        (false, true) => {
            c.line("// z per channel: the stored coefficient.");
            c.open("static inline void shlight_zh3_z(const double a[3], double z[3]) {");
            c.line("(void)a;");
            c.open("for (int c = 0; c < 3; c++) {");
            c.line("z[c] = shlight_zh3_zonal[c];");
            c.close("}");
            c.close("}");
        }
        (false, false) => {
            c.line("// z per channel: the stored coefficient.");
            c.open(format!(
                "{} {{",
                lang.signature(Some(v3), "shlight_zh3_z", &a_in)
            ));
            c.line("return SHLIGHT_ZH3_ZONAL;");
            c.close("}");
        }
    }
    c.line("");
    c.line("// Irradiance E(n) at a surface with normal n: E_1(n) + (pi/4) z sqrt(5/(16 pi)) (3 (a.n)^2 - 1).");
    c.open(format!(
        "{} {{",
        lang.signature(Some(v3), "shlight_irradiance", &[(v3, "n")])
    ));
    let band = format!("({zh} * (3.0 * t * t - 1.0))");
    if lang.is_c() {
        c.line("double a[3], z[3];");
        c.line("shlight_zh3_axis(a);");
        c.line("shlight_zh3_z(a, z);");
        c.line(lang.let_(fl, "t", "a[0] * n[0] + a[1] * n[1] + a[2] * n[2]"));
        c.line("shlight_sh_irradiance(n, out);");
        c.open("for (int c = 0; c < 3; c++) {");
        c.line(format!("out[c] += z[c] * {band};"));
        c.close("}");
    } else {
        c.line(lang.let_(v3, "a", "shlight_zh3_axis()"));
        c.line(lang.let_(fl, "t", "dot(a, n)"));
        c.line(format!(
            "return shlight_sh_irradiance(n) + shlight_zh3_z(a) * {band};"
        ));
    }
    c.close("}");
}

/// Hazel's non-linear irradiance per channel and `shlight_irradiance`.
fn l1_nonlinear(lang: Language, c: &mut Code) {
    let (v3, fl) = (Type::Vec3, Type::Float);
    let (k0, k1, pi) = (
        f(1.0 / (2.0 * PI.sqrt())),
        f(1.0 / (2.0 * (3.0 * PI).sqrt())),
        f(PI),
    );
    c.line("");
    c.line("// Hazel's non-linear irradiance of one channel from its lmax-1 radiance f00, f1-1, f10, f11 (header).");
    // C reads a channel's four coefficients by its index; the others are
    // handed them.
    let (params, f00, r1, length, dot): (&[(Type, &str)], _, _, _, _) = if lang.is_c() {
        (
            &[(Type::Int, "c"), (v3, "n")],
            "shlight_coeffs[0][c]",
            format!(
                "{{-shlight_coeffs[3][c] * {k1}, -shlight_coeffs[1][c] * {k1}, shlight_coeffs[2][c] * {k1}}}"
            ),
            "sqrt(r1[0] * r1[0] + r1[1] * r1[1] + r1[2] * r1[2])",
            "(r1[0] * n[0] + r1[1] * n[1] + r1[2] * n[2])",
        )
    } else {
        (
            &[
                (fl, "f00"),
                (fl, "f1m1"),
                (fl, "f10"),
                (fl, "f11"),
                (v3, "n"),
            ],
            "f00",
            format!("{} * {k1}", lang.vector(v3, "-f11, -f1m1, f10")),
            "length(r1)",
            "dot(r1, n)",
        )
    };
    c.open(format!(
        "{} {{",
        lang.signature(Some(fl), "shlight_l1_channel", params)
    ));
    c.line(lang.let_(fl, "r0", &format!("{f00} * {k0}")));
    c.open("if (r0 <= 0.0) {");
    c.line("return 0.0;");
    c.close("}");
    if lang.is_c() {
        c.line(format!("const double r1[3] = {r1};"));
    } else {
        c.line(lang.let_(v3, "r1", &r1));
    }
    c.line(lang.let_(fl, "len", length));
    c.open("if (len == 0.0) {");
    c.line(format!("return {pi} * r0;"));
    c.close("}");
    c.line(lang.let_(fl, "r", &lang.min("len / r0", "1.0")));
    c.line(lang.let_(fl, "p", "1.0 + 2.0 * r"));
    c.line(lang.let_(fl, "a", "(1.0 - r) / (1.0 + r)"));
    c.line(lang.let_(
        fl,
        "q",
        &lang.max(&format!("0.5 * (1.0 + {dot} / len)"), "0.0"),
    ));
    c.line(format!(
        "return {pi} * r0 * (a + (1.0 - a) * (p + 1.0) * pow(q, p));"
    ));
    c.close("}");
    c.line("");
    c.line("// Irradiance E(n) at a surface with normal n, channel by channel.");
    c.open(format!(
        "{} {{",
        lang.signature(Some(v3), "shlight_irradiance", &[(v3, "n")])
    ));
    if lang.is_c() {
        c.open("for (int c = 0; c < 3; c++) {");
        c.line("out[c] = shlight_l1_channel(c, n);");
        c.close("}");
    } else {
        for k in 0..4 {
            c.line(lang.let_(v3, &format!("c{k}"), &format!("SHLIGHT_COEFFS[{k}]")));
        }
        c.line(format!("return {}(", lang.ty(v3)));
        let channels: Vec<String> = ["x", "y", "z"]
            .iter()
            .map(|ch| format!("    shlight_l1_channel(c0.{ch}, c1.{ch}, c2.{ch}, c3.{ch}, n)"))
            .collect();
        // WGSL takes a trailing comma; GLSL and HLSL do not.
        if lang == Language::Wgsl {
            c.line(format!("{},", channels.join(",\n    ")));
            c.line(");");
        } else {
            c.line(format!("{});", channels.join(",\n    ")));
        }
    }
    c.close("}");
}

/// The ambient cube's `shlight_irradiance`: the colours blended by `n²`.
fn cube(lang: Language, c: &mut Code) {
    let v3 = Type::Vec3;
    c.line("");
    c.line("// Irradiance E(n) at a surface with normal n: the colours blended by n^2.");
    c.open(format!(
        "{} {{",
        lang.signature(Some(v3), "shlight_irradiance", &[(v3, "n")])
    ));
    let axes = ["x", "y", "z"];
    if lang.is_c() {
        for (k, axis) in axes.iter().enumerate() {
            c.line(format!(
                "const double *c{axis} = shlight_cube[n[{k}] < 0.0 ? {} : {}];",
                2 * k + 1,
                2 * k
            ));
        }
        c.open("for (int c = 0; c < 3; c++) {");
        c.line("out[c] = n[0] * n[0] * cx[c] + n[1] * n[1] * cy[c] + n[2] * n[2] * cz[c];");
        c.close("}");
    } else {
        c.line(lang.let_(v3, "nn", "n * n"));
        for (k, axis) in axes.iter().enumerate() {
            c.line(lang.let_(
                v3,
                &format!("c{axis}"),
                &lang.select(
                    &format!("SHLIGHT_CUBE[{}]", 2 * k),
                    &format!("SHLIGHT_CUBE[{}]", 2 * k + 1),
                    &format!("n.{axis} < 0.0"),
                ),
            ));
        }
        c.line("return nn.x * cx + nn.y * cy + nn.z * cz;");
    }
    c.close("}");
}
