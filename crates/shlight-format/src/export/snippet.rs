//! What the shader and C snippets (WGSL, GLSL, HLSL, C) share: the header
//! comment and the range check; their code is shlight-shader's
//! ([`shlight_shader::coefficients`]).

use glam::DVec3;
use shlight_core::sh::{ShCoeffs, lm_from_index};

use shlight_shader::Language;
use shlight_shader::coefficients::coefficient_code;

use super::ExportInput;
use super::engine::frame_words;
use crate::{FormatError, Quantity, Result};

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

/// A snippet in `lang`: the header comment (`comment`, `array`, `prefix`
/// as [`code_header`] takes them), `note` (the language's line, if any)
/// and a blank line, then shlight-shader's code of the coefficients.
pub(crate) fn snippet(
    input: &ExportInput<'_>,
    lang: Language,
    array: &str,
    note: &str,
    prefix: &str,
) -> String {
    let mut text = code_header(input, "//", array, prefix);
    text.push_str(note);
    text.push('\n');
    text.push_str(&coefficient_code(
        lang,
        input.coeffs,
        input.quantity == Quantity::Radiance,
        prefix,
    ));
    text
}
