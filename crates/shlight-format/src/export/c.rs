//! `c`: a C99 snippet: the coefficients as a `static const double` array
//! and functions that evaluate them at a normal, for any lmax.
//!
//! # What the numbers are
//!
//! `shlight_coeffs[i][k]`, `i = l(l+1)+m`, `k` = red, green, blue, are the
//! file's own coefficients, unchanged and in double precision: shlight's
//! basis (real orthonormal SH **with** the Condon-Shortley phase,
//! docs/conventions.md), the file's quantity (radiance `L_lm` or irradiance
//! `E_lm = A_l L_lm`) and frame (y-up or z-up, named in the header), linear
//! Rec.709 RGB.
//!
//! - `shlight_irradiance(n, out)` writes irradiance `E(n)` (`A_l` applied
//!   from `shlight_a` when the file holds radiance).
//! - `shlight_radiance(w, out)` (radiance files only) writes `L(w)`.
//!
//! The evaluator is the GLSL/HLSL/WGSL one in C (`static inline`, so that
//! unused functions do not warn); it needs `<math.h>` (`-lm` on some
//! systems).

use super::{
    BAND_WEIGHT_COMMENT, ExportInput, Exported, band_weight_list, code_header, coefficient_rows,
};
use crate::Quantity;

/// Renders the snippet.
pub fn render(input: &ExportInput<'_>) -> Exported {
    render_named(input, "shlight_")
}

/// The snippet with its public functions named `{prefix}irradiance` and
/// `{prefix}radiance`.
pub(crate) fn render_named(input: &ExportInput<'_>, prefix: &str) -> Exported {
    let c = input.coeffs;
    let (lmax, n) = (c.lmax(), c.len());
    let mut s = code_header(input, "//", "shlight_coeffs", prefix);
    s.push_str("// C99; link with -lm where needed.\n\n#include <math.h>\n\n");
    s.push_str(&format!(
        "#define SHLIGHT_LMAX {lmax}\n#define SHLIGHT_COUNT {n}\n\n"
    ));
    s.push_str("static const double shlight_coeffs[SHLIGHT_COUNT][3] = {\n");
    s.push_str(&coefficient_rows(c, "{", "}", true));
    s.push_str("};\n");
    let radiance = input.quantity == Quantity::Radiance;
    if radiance {
        s.push_str(&format!(
            "{BAND_WEIGHT_COMMENT}\nstatic const double shlight_a[SHLIGHT_LMAX + 1] = {{{}}};\n",
            band_weight_list(lmax)
        ));
    }
    s.push_str(
        r#"
// out = sum over l, m of w_l shlight_coeffs[l*(l+1)+m] Y_l^m(n), w_l = band_weight[l] or 1 if NULL.
static inline void shlight_expand(const double n[3], const double *band_weight, double out[3]) {
    const double x = n[0], y = n[1], z = n[2];
    double c = 1.0; // sin^m(theta) cos(m phi)
    double s = 0.0; // sin^m(theta) sin(m phi)
    double pmm = 0.28209479177387814; // Pbar_m^m / sin^m(theta), m = 0: 1 / sqrt(4 pi)
    out[0] = out[1] = out[2] = 0.0;
    for (int m = 0; m <= SHLIGHT_LMAX; m++) {
        if (m > 0) {
            const double cn = x * c - y * s;
            s = x * s + y * c;
            c = cn;
            pmm = pmm * -sqrt((double)(2 * m + 1) / (double)(2 * m));
        }
        double p1 = 0.0; // Pbar_(l-1)^m / sin^m
        double p2 = 0.0; // Pbar_(l-2)^m / sin^m
        for (int l = m; l <= SHLIGHT_LMAX; l++) {
            double p = pmm;
            if (l == m + 1) {
                p = sqrt((double)(2 * m + 3)) * z * pmm;
            } else if (l > m + 1) {
                const double a = sqrt((double)(4 * l * l - 1) / (double)(l * l - m * m));
                const double b = sqrt((double)((l - 1) * (l - 1) - m * m) / (double)(4 * (l - 1) * (l - 1) - 1));
                p = a * (z * p1 - b * p2);
            }
            p2 = p1;
            p1 = p;
            const double w = band_weight ? band_weight[l] : 1.0;
            for (int k = 0; k < 3; k++) {
                if (m == 0) {
                    out[k] += shlight_coeffs[l * l + l][k] * (w * p);
                } else {
                    const double t = w * 1.4142135623730951 * p;
                    out[k] += shlight_coeffs[l * l + l + m][k] * (t * c) + shlight_coeffs[l * l + l - m][k] * (t * s);
                }
            }
        }
    }
}
"#,
    );
    if radiance {
        s.push_str(&format!(
            "\n// Radiance L(w) arriving from direction w.\nstatic inline void {prefix}radiance(const double w[3], double out[3]) {{\n    shlight_expand(w, 0, out);\n}}\n",
        ));
        s.push_str(&format!(
            "\n// Irradiance E(n) at a surface with normal n.\nstatic inline void {prefix}irradiance(const double n[3], double out[3]) {{\n    shlight_expand(n, shlight_a, out);\n}}\n",
        ));
    } else {
        s.push_str(&format!(
            "\n// Irradiance E(n) at a surface with normal n.\nstatic inline void {prefix}irradiance(const double n[3], double out[3]) {{\n    shlight_expand(n, 0, out);\n}}\n",
        ));
    }
    Exported {
        text: s,
        notes: Vec::new(),
    }
}
