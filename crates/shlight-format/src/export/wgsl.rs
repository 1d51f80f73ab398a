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
//! recurrences and Sloan's trig-free azimuth recurrence: shlight-shader's
//! [`shlight_shader::coefficients`], one description spelled for WGSL,
//! GLSL, HLSL and C alike (which the tests compile and run). The arrays are
//! `var<private>` so that they can be indexed by loop variables (a `const`
//! array may only be indexed by constants in some implementations).

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
    check_f32_range(input.coeffs, "WGSL")?;
    Ok(Exported {
        text: snippet(input, Language::Wgsl, "SHLIGHT_COEFFS", "", prefix),
        notes: Vec::new(),
    })
}
