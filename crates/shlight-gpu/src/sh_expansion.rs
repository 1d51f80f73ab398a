//! The WGSL function `sh_reconstruct` of the render passes, written out as
//! straight-line code for one lmax.
//!
//! ```text
//! sh_reconstruct(d, factors) = sum_{l <= lmax} f_l sum_m L_lm Y_lm(d),
//!     f_l = factors[l / 4][l % 4]   (A_l w_l for irradiance, w_l for radiance)
//! ```
//!
//! with `L_lm` the light's coefficients (`light[l(l+1)+m]`, `scene.wgsl`).
//! The basis is shlight-shader's [`basis_statements`] (the recurrences of
//! shlight-core's `Legendre`, every factor an f32 literal, `sin(theta)^m`
//! carried by `C_m + i S_m = (x + i y)^m`): a loop to a run-time lmax would
//! keep `Y` in a local array, which CPU rasterisers such as Mesa's llvmpipe
//! keep in memory, lane by lane. The renderer builds one pipeline per lmax
//! (0..=[`LIGHT_MAX_LMAX`]) on first use.

use std::fmt::Write;

use shlight_baked::LIGHT_MAX_LMAX;
use shlight_shader::Language;
use shlight_shader::basis::{BasisNames, basis_statements};
/// The WGSL text of `sh_reconstruct` for `lmax` (clamped to [`LIGHT_MAX_LMAX`]).
#[must_use]
pub(crate) fn sh_reconstruct_wgsl(lmax: usize) -> String {
    let lmax = lmax.min(LIGHT_MAX_LMAX);
    let body = basis_statements(
        Language::Wgsl,
        lmax,
        BasisNames::default(),
        |l, m, lines| {
            let centre = l * (l + 1);
            if l == 0 {
                lines.push("var sum = (factors[0][0] * q0_0) * light[0].rgb;".into());
            } else if m == 0 {
                lines.push(format!(
                    "sum += (factors[{}][{}] * q{l}_0) * light[{centre}].rgb;",
                    l / 4,
                    l % 4
                ));
            } else {
                // One multiply-add per colour channel for each of the pair's
                // coefficients.
                lines.push(format!(
                    "sum += (t{l}_{m} * c{m}) * light[{}].rgb + (t{l}_{m} * s{m}) * light[{}].rgb;",
                    centre + m,
                    centre - m
                ));
            }
        },
    );
    summing_function(
        &format!(
            "sum_l factors_l sum_m L_lm Y_lm(d) to lmax {lmax}, factors_l = factors[l / 4][l % 4]."
        ),
        "fn sh_reconstruct(d: vec3<f32>, factors: array<vec4<f32>, 3>) -> vec3<f32>",
        &format!("lmax {lmax} (crates/shlight-gpu/src/sh_expansion.rs)"),
        &body,
    )
}

/// A generated WGSL function that returns `sum`: a `// doc` line, then
/// `signature {`, a `// Generated for ...` line naming `generated_for`,
/// `body` (which declares and adds to `sum`) indented, and `return sum;`.
pub(crate) fn summing_function(
    doc: &str,
    signature: &str,
    generated_for: &str,
    body: &[String],
) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "// {doc}");
    let _ = writeln!(out, "{signature} {{");
    let _ = writeln!(out, "    // Generated for {generated_for}.");
    for line in body {
        let _ = writeln!(out, "    {line}");
    }
    out.push_str("    return sum;\n}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_coefficient_is_summed_once() {
        for lmax in 0..=LIGHT_MAX_LMAX {
            let text = sh_reconstruct_wgsl(lmax);
            for i in 0..(lmax + 1) * (lmax + 1) {
                assert_eq!(
                    text.matches(&format!("light[{i}]")).count(),
                    1,
                    "lmax {lmax}: coefficient {i}\n{text}"
                );
            }
            let beyond = (lmax + 1) * (lmax + 1);
            assert!(!text.contains(&format!("light[{beyond}]")), "{text}");
        }
    }
}
