//! The WGSL function `glossy_radiance` of the mesh pass's glossy PRT
//! shading, written out as straight-line code for one lmax (the transfer's):
//!
//! ```text
//! glossy_radiance(n, r) = sum_{l <= lmax} sum_m (rho/pi A_l Y_lm(n) + Lambda_l Y_lm(r)) T_lm
//! ```
//!
//! `rho` the diffuse base's albedo (`frame.albedo`), `A_l` the clamped
//! cosine's zonal coefficients (literals), `Lambda_l` the lobe's
//! (`frame.glossy_band`), `T_lm = glossy_t(l(l+1)+m)` the vertex's
//! transferred radiance (`mesh.wgsl`). The basis at `n` and at `r` is
//! shlight-shader's [`basis_statements`] (the renderer's `sh_reconstruct`
//! basis), the one at `n` with its names prefixed `n_`.

use shlight_baked::LIGHT_MAX_LMAX;
use shlight_core::sh::clamped_cosine_eigenvalue;
use shlight_shader::basis::{BasisNames, basis_statements};
use shlight_shader::{Language, f32_literal as literal};

use crate::sh_expansion::summing_function;

/// The WGSL text of `glossy_radiance` for `lmax` (clamped to
/// [`LIGHT_MAX_LMAX`]).
#[must_use]
pub(crate) fn glossy_radiance_wgsl(lmax: usize) -> String {
    let lmax = lmax.min(LIGHT_MAX_LMAX);
    let band = |f: &dyn Fn(usize) -> f64| {
        (0..3)
            .map(|e| {
                let lanes: Vec<String> = (0..4)
                    .map(|lane| {
                        literal(if 4 * e + lane <= lmax {
                            f(4 * e + lane)
                        } else {
                            0.0
                        })
                    })
                    .collect();
                format!("vec4<f32>({})", lanes.join(", "))
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut body = vec![
        "let base = frame.albedo.rgb / SH_PI;".to_string(),
        "let n_d = n;".to_string(),
        format!(
            "let n_factors = array<vec4<f32>, 3>({});",
            band(&clamped_cosine_eigenvalue)
        ),
    ];
    let n_names = BasisNames {
        prefix: "n_",
        ..BasisNames::default()
    };
    body.extend(basis_statements(
        Language::Wgsl,
        lmax,
        n_names,
        |_, _, _| {},
    ));
    body.push("let d = r;".into());
    body.push("let factors = frame.glossy_band;".into());
    body.extend(basis_statements(Language::Wgsl, lmax, BasisNames::default(), |l, m, lines| {
        let centre = l * (l + 1);
        let (e, lane) = (l / 4, l % 4);
        if m == 0 {
            let term = format!(
                "(factors[{e}][{lane}] * q{l}_0 + base * (n_factors[{e}][{lane}] * n_q{l}_0)) * glossy_t({centre}u)"
            );
            lines.push(if l == 0 {
                format!("var sum = {term};")
            } else {
                format!("sum += {term};")
            });
        } else {
            lines.push(format!(
                "sum += (t{l}_{m} * c{m} + base * (n_t{l}_{m} * n_c{m})) * glossy_t({}u) \
                 + (t{l}_{m} * s{m} + base * (n_t{l}_{m} * n_s{m})) * glossy_t({}u);",
                centre + m,
                centre - m
            ));
        }
    }));
    summing_function(
        &format!("sum_i (rho/pi A_l Y_i(n) + Lambda_l Y_i(r)) T_i to lmax {lmax}."),
        "fn glossy_radiance(n: vec3<f32>, r: vec3<f32>) -> vec3<f32>",
        &format!("lmax {lmax} (crates/shlight-gpu/src/glossy_expansion.rs)"),
        &body,
    )
}

/// The WGSL text of `ggx_band_sums` for `lmax` (clamped to
/// [`LIGHT_MAX_LMAX`]): band `l`'s part of the vertex's transferred
/// radiance at the unit direction `d`, `sum_m Y_lm(d) T_lm` with
/// `T_lm = ggx_t[l(l+1)+m]` (filled by `mesh.wgsl`'s `ggx_layer`), for
/// every `l <= lmax`; the GGX layer weighs them per direction.
#[must_use]
pub(crate) fn ggx_band_sums_wgsl(lmax: usize) -> String {
    let lmax = lmax.min(LIGHT_MAX_LMAX);
    let mut body = vec![
        "let factors = array<vec4<f32>, 3>(vec4<f32>(1.0), vec4<f32>(1.0), vec4<f32>(1.0));"
            .to_string(),
        format!("var sum = array<vec3<f32>, {}>();", LIGHT_MAX_LMAX + 1),
    ];
    body.extend(basis_statements(
        Language::Wgsl,
        lmax,
        BasisNames::default(),
        |l, m, lines| {
            let centre = l * (l + 1);
            lines.push(if m == 0 {
                format!("sum[{l}] += q{l}_0 * ggx_t[{centre}];")
            } else {
                format!(
                    "sum[{l}] += (t{l}_{m} * c{m}) * ggx_t[{}] + (t{l}_{m} * s{m}) * ggx_t[{}];",
                    centre + m,
                    centre - m
                )
            });
        },
    ));
    summing_function(
        &format!("Per band l, sum_m Y_lm(d) T_lm, to lmax {lmax}."),
        &format!(
            "fn ggx_band_sums(d: vec3<f32>) -> array<vec3<f32>, {}>",
            LIGHT_MAX_LMAX + 1
        ),
        &format!("lmax {lmax} (crates/shlight-gpu/src/glossy_expansion.rs)"),
        &body,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn band_sums_take_each_coefficient_once() {
        for lmax in 0..=LIGHT_MAX_LMAX {
            let text = ggx_band_sums_wgsl(lmax);
            for i in 0..(lmax + 1) * (lmax + 1) {
                assert_eq!(
                    text.matches(&format!("ggx_t[{i}]")).count(),
                    1,
                    "lmax {lmax}: coefficient {i}"
                );
            }
        }
    }

    #[test]
    fn every_coefficient_is_read_once() {
        for lmax in 0..=LIGHT_MAX_LMAX {
            let text = glossy_radiance_wgsl(lmax);
            let count = (lmax + 1) * (lmax + 1);
            for i in 0..count {
                assert_eq!(
                    text.matches(&format!("glossy_t({i}u)")).count(),
                    1,
                    "lmax {lmax}: coefficient {i}\n{text}"
                );
            }
            assert!(!text.contains(&format!("glossy_t({count}u)")), "{text}");
        }
    }
}
