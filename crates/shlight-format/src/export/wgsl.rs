//! `wgsl`: a WGSL snippet: the coefficients as a module-scope array and
//! functions that evaluate them at a normal, for any lmax.
//!
//! # What the numbers are
//!
//! `SHLIGHT_COEFFS[i]`, `i = l(l+1)+m`, are the file's own coefficients,
//! unchanged: shlight's basis (real orthonormal SH **with** the
//! Condon-Shortley phase, docs/conventions.md), the file's quantity
//! (radiance `L_lm` or irradiance `E_lm = A_l L_lm`) and frame (y-up or
//! z-up, named in the header), linear Rec.709 RGB, as `f32`.
//!
//! - `shlight_irradiance(n)` returns irradiance `E(n)` (`A_l` applied from
//!   `SHLIGHT_A` when the file holds radiance).
//! - `shlight_radiance(w)` (radiance files only) returns `L(w)`.
//!
//! The evaluator loops over `m` and `l` with the normalised Legendre
//! recurrences and Sloan's trig-free azimuth recurrence, statement for
//! statement the GLSL/HLSL/C evaluator (which the tests compile and run).
//! The arrays are `var<private>` so that they can be indexed by loop
//! variables (a `const` array may only be indexed by constants in some
//! implementations).

use crate::Result;

use super::{
    BAND_WEIGHT_COMMENT, ExportInput, Exported, band_weight_list, check_f32_range, code_header,
    coefficient_rows,
};
use crate::Quantity;

/// Renders the snippet.
pub fn render(input: &ExportInput<'_>) -> Result<Exported> {
    render_named(input, "shlight_")
}

/// The snippet with its public functions named `{prefix}irradiance` and
/// `{prefix}radiance`.
pub(crate) fn render_named(input: &ExportInput<'_>, prefix: &str) -> Result<Exported> {
    check_f32_range(input.coeffs, "WGSL")?;
    let c = input.coeffs;
    let (lmax, n) = (c.lmax(), c.len());
    let mut s = code_header(input, "//", "SHLIGHT_COEFFS", prefix);
    s.push('\n');
    s.push_str(&format!("const SHLIGHT_LMAX: i32 = {lmax};\n"));
    s.push_str(&format!(
        "var<private> SHLIGHT_COEFFS: array<vec3<f32>, {n}> = array<vec3<f32>, {n}>(\n"
    ));
    s.push_str(&coefficient_rows(c, "vec3<f32>(", ")", true));
    s.push_str(");\n");
    let radiance = input.quantity == Quantity::Radiance;
    if radiance {
        s.push_str(&format!(
            "{BAND_WEIGHT_COMMENT}\nvar<private> SHLIGHT_A: array<f32, {k}> = array<f32, {k}>({});\n",
            band_weight_list(lmax),
            k = lmax + 1
        ));
    }
    let (param, weight) = if radiance {
        (
            ", irradiance: bool",
            "if (irradiance) {\n                w = SHLIGHT_A[l];\n            }",
        )
    } else {
        ("", "// irradiance coefficients: no weight")
    };
    s.push_str(&format!(
        r#"
// sum over l, m of w_l SHLIGHT_COEFFS[l*(l+1)+m] Y_l^m(n), w_l = A_l for irradiance from radiance, else 1.
fn shlight_expand(n: vec3<f32>{param}) -> vec3<f32> {{
    let x = n.x;
    let y = n.y;
    let z = n.z;
    var c: f32 = 1.0; // sin^m(theta) cos(m phi)
    var s: f32 = 0.0; // sin^m(theta) sin(m phi)
    var pmm: f32 = 0.28209479177387814; // Pbar_m^m / sin^m(theta), m = 0: 1 / sqrt(4 pi)
    var sum = vec3<f32>(0.0, 0.0, 0.0);
    for (var m: i32 = 0; m <= SHLIGHT_LMAX; m++) {{
        if (m > 0) {{
            let cn = x * c - y * s;
            s = x * s + y * c;
            c = cn;
            pmm = pmm * -sqrt(f32(2 * m + 1) / f32(2 * m));
        }}
        var p1: f32 = 0.0; // Pbar_(l-1)^m / sin^m
        var p2: f32 = 0.0; // Pbar_(l-2)^m / sin^m
        for (var l: i32 = m; l <= SHLIGHT_LMAX; l++) {{
            var p: f32 = pmm;
            if (l == m + 1) {{
                p = sqrt(f32(2 * m + 3)) * z * pmm;
            }} else if (l > m + 1) {{
                let a = sqrt(f32(4 * l * l - 1) / f32(l * l - m * m));
                let b = sqrt(f32((l - 1) * (l - 1) - m * m) / f32(4 * (l - 1) * (l - 1) - 1));
                p = a * (z * p1 - b * p2);
            }}
            p2 = p1;
            p1 = p;
            var w: f32 = 1.0;
            {weight}
            if (m == 0) {{
                sum += SHLIGHT_COEFFS[l * l + l] * (w * p);
            }} else {{
                let t = w * 1.4142135623730951 * p;
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
            "\n// Radiance L(w) arriving from direction w.\nfn {prefix}radiance(w: vec3<f32>) -> vec3<f32> {{\n    return shlight_expand(w, false);\n}}\n",
        ));
        s.push_str(&format!(
            "\n// Irradiance E(n) at a surface with normal n.\nfn {prefix}irradiance(n: vec3<f32>) -> vec3<f32> {{\n    return shlight_expand(n, true);\n}}\n",
        ));
    } else {
        s.push_str(&format!(
            "\n// Irradiance E(n) at a surface with normal n.\nfn {prefix}irradiance(n: vec3<f32>) -> vec3<f32> {{\n    return shlight_expand(n);\n}}\n",
        ));
    }
    Ok(Exported {
        text: s,
        notes: Vec::new(),
    })
}
