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
//! The evaluator is the GLSL/HLSL/WGSL one in C (shlight-shader's
//! [`shlight_shader::coefficients`]; `static inline`, so that unused
//! functions do not warn); it needs `<math.h>` (`-lm` on some systems).

use shlight_shader::Language;

use super::{ExportInput, Exported, snippet};

/// Renders the snippet.
pub fn render(input: &ExportInput<'_>) -> Exported {
    render_named(input, "shlight_")
}

/// The snippet with its public functions named `{prefix}irradiance` and
/// `{prefix}radiance`.
pub(crate) fn render_named(input: &ExportInput<'_>, prefix: &str) -> Exported {
    Exported {
        text: snippet(
            input,
            Language::C,
            "shlight_coeffs",
            "// C99; link with -lm where needed.\n",
            prefix,
        ),
        notes: Vec::new(),
    }
}
