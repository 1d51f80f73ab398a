//! `glsl`: a GLSL snippet (GLSL 3.30+ / GLSL ES 3.00+): the coefficients as
//! a `const vec3` array and functions that evaluate them at a normal.
//!
//! # What the numbers are
//!
//! `SHLIGHT_COEFFS[i]`, `i = l(l+1)+m`, are the file's own coefficients,
//! unchanged: shlight's basis (real orthonormal SH **with** the
//! Condon-Shortley phase, docs/conventions.md), the file's quantity
//! (radiance `L_lm` or irradiance `E_lm = A_l L_lm`) and frame (y-up or
//! z-up, named in the header), linear Rec.709 RGB, any lmax.
//!
//! - `shlight_irradiance(n)` returns irradiance `E(n)` (`A_l` applied from
//!   `SHLIGHT_A` when the file holds radiance).
//! - `shlight_radiance(w)` (radiance files only) returns `L(w)`.
//!
//! Both evaluate `Y_l^m` by the same recurrences as shlight-core
//! (`Pbar_m^m = -sqrt((2m+1)/2m) s Pbar_(m-1)^(m-1)`, ... divided by
//! `sin^m`, times the trig-free azimuth terms `C_m, S_m` of Sloan 2008),
//! in 32-bit floats. The header comment says all this in the file.

use shlight_shader::Language;

use super::{ExportInput, Exported, check_f32_range, snippet};
use crate::Result;

/// Renders the snippet.
pub fn render(input: &ExportInput<'_>) -> Result<Exported> {
    render_named(input, "shlight_")
}

/// The snippet with its public functions named `{prefix}irradiance` and
/// `{prefix}radiance`.
pub(crate) fn render_named(input: &ExportInput<'_>, prefix: &str) -> Result<Exported> {
    check_f32_range(input.coeffs, "GLSL")?;
    Ok(Exported {
        text: snippet(
            input,
            Language::Glsl,
            "SHLIGHT_COEFFS",
            "// GLSL 3.30 / GLSL ES 3.00 or later.\n",
            prefix,
        ),
        notes: Vec::new(),
    })
}
