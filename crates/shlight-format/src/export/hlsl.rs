//! `hlsl`: an HLSL snippet: the coefficients as a `static const float3`
//! array and functions that evaluate them at a normal.
//!
//! # What the numbers are
//!
//! `SHLIGHT_COEFFS[i]`, `i = l(l+1)+m`, are the file's own coefficients,
//! unchanged: shlight's basis (real orthonormal SH **with** the
//! Condon-Shortley phase, docs/conventions.md), the file's quantity
//! (radiance `L_lm` or irradiance `E_lm = A_l L_lm`) and frame (y-up or
//! z-up, named in the header; no handedness change: an engine with a
//! left-handed world, such as Unity, must mirror its normals into these
//! axes, e.g. `n.z = -n.z` for Unity and a y-up file), linear Rec.709 RGB,
//! any lmax.
//!
//! - `shlight_irradiance(n)` returns irradiance `E(n)` (`A_l` applied from
//!   `SHLIGHT_A` when the file holds radiance).
//! - `shlight_radiance(w)` (radiance files only) returns `L(w)`.
//!
//! The evaluator is the one of the GLSL snippet with HLSL spellings
//! (`float3`, `static const`, `{ ... }` initialisers; shlight-shader's
//! [`shlight_shader::coefficients`]); 32-bit floats.

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
    check_f32_range(input.coeffs, "HLSL")?;
    Ok(Exported {
        text: snippet(input, Language::Hlsl, "SHLIGHT_COEFFS", "", prefix),
        notes: Vec::new(),
    })
}
