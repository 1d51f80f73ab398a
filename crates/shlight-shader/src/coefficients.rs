//! A coefficient file as code: its coefficients as a constant array and
//! functions that evaluate them at a direction, for any lmax, in every
//! language (what `shlight convert` and `shlight project --format
//! wgsl|glsl|hlsl|c` write below their header comment).
//!
//! - `SHLIGHT_COEFFS[i]` (C: `shlight_coeffs[i][k]`), `i = l(l+1)+m`: the
//!   coefficients as given (f32 in the shading languages, f64 in C).
//! - `{prefix}irradiance(n)`: irradiance `E(n)`; for radiance
//!   coefficients `A_l` is applied from `SHLIGHT_A` (C: `shlight_a`).
//! - `{prefix}radiance(w)` (radiance coefficients only): `L(w)`.
//!
//! Both call `shlight_expand`, the loops of [`crate::sh_sum`].

use glam::DVec3;
use shlight_core::sh::{ShCoeffs, clamped_cosine_eigenvalue, lm_from_index};

use crate::sh_sum::{ShSum, write_sh_sum};
use crate::{Code, Language, Type, float_literal};

/// `A_l`, `l = 0..=lmax`, as comma-separated literals.
#[must_use]
pub fn band_weight_list(lmax: usize) -> String {
    let a: Vec<String> = (0..=lmax)
        .map(|l| float_literal(clamped_cosine_eigenvalue(l)))
        .collect();
    a.join(", ")
}

/// The comment above the `A_l` arrays.
pub const BAND_WEIGHT_COMMENT: &str =
    "// A_l, the clamped-cosine eigenvalues: irradiance is A_l times radiance, band by band.";

/// The coefficient rows, one line each: `    vec3(r, g, b), // l=.. m=..`
/// (C: `{r, g, b}`), the comma left off the last row where the language's
/// initialiser refuses it (GLSL, HLSL).
fn coefficient_rows(lang: Language, coeffs: &ShCoeffs<DVec3>) -> String {
    let comma_after_last = matches!(lang, Language::Wgsl | Language::C);
    let n = coeffs.len();
    let mut s = String::new();
    for (i, v) in coeffs.as_slice().iter().enumerate() {
        let (l, m) = lm_from_index(i);
        let sep = if comma_after_last || i + 1 < n {
            ","
        } else {
            ""
        };
        let rgb = format!(
            "{}, {}, {}",
            float_literal(v.x),
            float_literal(v.y),
            float_literal(v.z)
        );
        s.push_str(&format!(
            "    {}{sep} // l={l} m={m}\n",
            lang.vector(Type::Vec3, &rgb)
        ));
    }
    s
}

/// The code of `coeffs` (radiance when `radiance`, else irradiance): the
/// constants, `shlight_expand` and the public functions, named
/// `{prefix}irradiance` and `{prefix}radiance`. C's starts with its
/// `#include <math.h>`.
#[must_use]
pub fn coefficient_code(
    lang: Language,
    coeffs: &ShCoeffs<DVec3>,
    radiance: bool,
    prefix: &str,
) -> String {
    let (lmax, n) = (coeffs.lmax(), coeffs.len());
    let mut c = Code::new();
    if lang.is_c() {
        c.line("#include <math.h>");
        c.line("");
        c.line(lang.constant(Type::Int, "SHLIGHT_LMAX", &lmax.to_string()));
        c.line(lang.constant(Type::Int, "SHLIGHT_COUNT", &n.to_string()));
        c.line("");
        c.line(lang.array_open(Type::Vec3, "SHLIGHT_COEFFS", "SHLIGHT_COUNT"));
    } else {
        c.line(lang.constant(Type::Int, "SHLIGHT_LMAX", &lmax.to_string()));
        c.line(lang.array_open(Type::Vec3, "SHLIGHT_COEFFS", &n.to_string()));
    }
    c.raw(coefficient_rows(lang, coeffs));
    c.line(lang.array_close());
    if radiance {
        let count = if lang.is_c() {
            "SHLIGHT_LMAX + 1".to_string()
        } else {
            (lmax + 1).to_string()
        };
        c.line(BAND_WEIGHT_COMMENT);
        c.line(format!(
            "{}{}{}",
            lang.array_open(Type::Float, "SHLIGHT_A", &count),
            band_weight_list(lmax),
            lang.array_close()
        ));
    }
    c.line("");
    let v3 = Type::Vec3;
    if lang.is_c() {
        c.line("// out = sum over l, m of w_l shlight_coeffs[l*(l+1)+m] Y_l^m(n), w_l = band_weight[l] or 1 if NULL.");
        c.open("static inline void shlight_expand(const double n[3], const double *band_weight, double out[3]) {");
        c.line("const double x = n[0], y = n[1], z = n[2];");
    } else {
        c.line("// sum over l, m of w_l SHLIGHT_COEFFS[l*(l+1)+m] Y_l^m(n), w_l = A_l for irradiance from radiance, else 1.");
        let mut params = vec![(v3, "n")];
        if radiance {
            params.push((Type::Bool, "irradiance"));
        }
        c.open(format!(
            "{} {{",
            lang.signature(Some(v3), "shlight_expand", &params)
        ));
        for axis in ["x", "y", "z"] {
            c.line(lang.let_(Type::Float, axis, &format!("n.{axis}")));
        }
    }
    // The band weight: A_l for the irradiance of radiance, else 1 (WGSL
    // has no conditional expression of its own but `select`, which would
    // read SHLIGHT_A for every band; an `if` reads it only when asked).
    let weight: Vec<String> = match (lang, radiance) {
        (Language::C, _) => vec!["const double w = band_weight ? band_weight[l] : 1.0;".into()],
        (Language::Wgsl, true) => vec![
            "var w: f32 = 1.0;".into(),
            "if (irradiance) {".into(),
            "    w = SHLIGHT_A[l];".into(),
            "}".into(),
        ],
        (Language::Wgsl, false) => vec![
            "var w: f32 = 1.0;".into(),
            "// irradiance coefficients: no weight".into(),
        ],
        (_, true) => vec![lang.let_(Type::Float, "w", "irradiance ? SHLIGHT_A[l] : 1.0")],
        (_, false) => vec![lang.let_(Type::Float, "w", "1.0")],
    };
    let coefficient = |i: &str| {
        if lang.is_c() {
            format!("shlight_coeffs[{i}][k]")
        } else {
            format!("SHLIGHT_COEFFS[{i}]")
        }
    };
    write_sh_sum(
        lang,
        &mut c,
        &ShSum {
            lmax: "SHLIGHT_LMAX",
            direction: ["x", "y", "z"],
            legendre: "p",
            comments: true,
            weight: &weight,
            coefficient: &coefficient,
        },
    );
    if !lang.is_c() {
        c.line("return sum;");
    }
    c.close("}");
    // The public functions: shlight_expand with or without A_l.
    let public = |c: &mut Code, doc: &str, name: &str, arg: &str, weights: Option<bool>| {
        c.line("");
        c.line(doc);
        c.open(format!(
            "{} {{",
            lang.signature(Some(v3), &format!("{prefix}{name}"), &[(v3, arg)])
        ));
        c.line(match (lang, weights) {
            (Language::C, Some(true)) => format!("shlight_expand({arg}, shlight_a, out);"),
            (Language::C, _) => format!("shlight_expand({arg}, 0, out);"),
            (_, Some(w)) => format!("return shlight_expand({arg}, {});", lang.boolean(w)),
            (_, None) => format!("return shlight_expand({arg});"),
        });
        c.close("}");
    };
    let irradiance_doc = "// Irradiance E(n) at a surface with normal n.";
    if radiance {
        public(
            &mut c,
            "// Radiance L(w) arriving from direction w.",
            "radiance",
            "w",
            Some(false),
        );
        public(&mut c, irradiance_doc, "irradiance", "n", Some(true));
    } else {
        public(&mut c, irradiance_doc, "irradiance", "n", None);
    }
    c.finish()
}
