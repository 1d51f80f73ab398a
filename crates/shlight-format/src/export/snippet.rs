//! What the shader and C snippets (WGSL, GLSL, HLSL, C) share: the header
//! comment, float literals, the coefficient rows and the evaluator's text.

use glam::DVec3;
use shlight_core::sh::{ShCoeffs, clamped_cosine_eigenvalue, lm_from_index};

use super::ExportInput;
use super::engine::frame_words;
use crate::{FormatError, Quantity, Result};

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
            return Err(FormatError::Export(format!(
                "coefficient {i} (l={l}, m={m}) = {v} does not fit a 32-bit float, which {format} uses"
            )));
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
    pub(crate) fn body(&self, input: &ExportInput<'_>, prefix: &str) -> String {
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
                "\n// Radiance L(w) arriving from direction w.\n{v3} {prefix}radiance({v3} w) {{\n    return shlight_expand(w, false);\n}}\n"
            ));
            s.push_str(&format!(
                "\n// Irradiance E(n) at a surface with normal n.\n{v3} {prefix}irradiance({v3} n) {{\n    return shlight_expand(n, true);\n}}\n"
            ));
        } else {
            s.push_str(&format!(
                "\n// Irradiance E(n) at a surface with normal n.\n{v3} {prefix}irradiance({v3} n) {{\n    return shlight_expand(n);\n}}\n"
            ));
        }
        s
    }
}
