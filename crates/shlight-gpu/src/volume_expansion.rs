//! The WGSL of the volume pass that depends on lmax, written out as
//! straight-line code: the weighted basis `ShBasis` and `probe_dot`.
//!
//! ```text
//! sh_basis(d, factors).y{i} = f_l Y_i(d),   f_l = factors[l / 4][l % 4]  (A_l w_l)
//! probe_dot(b, y)           = sum_i y{i} probes[b + i].rgb
//! ```
//!
//! so that `probe_dot(b, sh_basis(n, irradiance_band))` is the irradiance
//! `E(n) = sum_l A_l w_l sum_m L_lm Y_lm(n)` of the probe whose coefficients
//! start at `probes[b]` (`shaders/volume.wgsl` sums it over the eight probes
//! around a point). The basis is `sh_expansion.rs`'s: the recurrences of
//! shlight-core's [`Legendre`] with `sin(theta)^m` carried by
//! `C_m + i S_m = (x + i y)^m`, every factor an f32 literal, no loops and no
//! local array (a struct of named scalars stays in registers; an array
//! indexed at run time is what Mesa's llvmpipe keeps in memory lane by
//! lane, shaders/README.md).

use std::fmt::Write;

use shlight_core::legendre::Legendre;

use crate::sh_expansion::{azimuth_power, literal};
use crate::volume::VOLUME_MAX_LMAX;

/// The WGSL text of `ShBasis`, `sh_basis` and `probe_dot` for `lmax`
/// (clamped to [`VOLUME_MAX_LMAX`]).
#[must_use]
pub(crate) fn volume_wgsl(lmax: usize) -> String {
    let lmax = lmax.min(VOLUME_MAX_LMAX);
    let count = (lmax + 1) * (lmax + 1);
    let legendre = Legendre::<f64>::new(lmax);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "// Generated for lmax {lmax} (crates/shlight-gpu/src/volume_expansion.rs)."
    );
    let _ = writeln!(out, "// y{{i}} = f_l Y_i(d), i = l(l+1)+m.");
    out.push_str("struct ShBasis {\n");
    for i in 0..count {
        let _ = writeln!(out, "    y{i}: f32,");
    }
    out.push_str("}\n\n");
    out.push_str("fn sh_basis(d: vec3<f32>, factors: array<vec4<f32>, 3>) -> ShBasis {\n");
    let mut body = Vec::<String>::new();
    let mut fields = vec![String::new(); count];
    body.push("let z = d.z;".into());
    body.push(format!(
        "let q0_0 = {};",
        literal(0.5 / std::f64::consts::PI.sqrt())
    ));
    for l in 1..=lmax {
        body.push(format!(
            "let g{l} = SH_SQRT2 * factors[{}][{}];",
            l / 4,
            l % 4
        ));
    }
    for m in 0..=lmax {
        if m > 0 {
            body.extend(azimuth_power(m, "d.x", "d.y"));
            body.push(format!(
                "let q{m}_{m} = {} * q{p}_{p};",
                literal(legendre.sectoral_factor(m)),
                p = m - 1
            ));
        }
        for l in m..=lmax {
            if l == m + 1 {
                body.push(format!(
                    "let q{l}_{m} = {} * z * q{m}_{m};",
                    literal(legendre.diagonal_factor(m))
                ));
            } else if l > m + 1 {
                let [a, ab] = legendre.column_factors(m)[l - m - 2];
                body.push(format!(
                    "let q{l}_{m} = {} * z * q{}_{m} - {} * q{}_{m};",
                    literal(a),
                    l - 1,
                    literal(ab),
                    l - 2
                ));
            }
            let centre = l * (l + 1);
            if m == 0 {
                fields[centre] = format!("factors[{}][{}] * q{l}_0", l / 4, l % 4);
            } else {
                body.push(format!("let t{l}_{m} = g{l} * q{l}_{m};"));
                fields[centre + m] = format!("t{l}_{m} * c{m}");
                fields[centre - m] = format!("t{l}_{m} * s{m}");
            }
        }
    }
    for line in body {
        let _ = writeln!(out, "    {line}");
    }
    let _ = writeln!(out, "    return ShBasis({});", fields.join(", "));
    out.push_str("}\n\n");
    out.push_str("// sum_i y{i} probes[b + i].rgb.\n");
    out.push_str("fn probe_dot(b: u32, y: ShBasis) -> vec3<f32> {\n");
    let terms: Vec<String> = (0..count)
        .map(|i| format!("y.y{i} * probes[b + {i}u].rgb"))
        .collect();
    let _ = writeln!(out, "    return {};", terms.join("\n        + "));
    out.push_str("}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_coefficient_is_read_once_and_none_beyond() {
        for lmax in 0..=VOLUME_MAX_LMAX {
            let text = volume_wgsl(lmax);
            let count = (lmax + 1) * (lmax + 1);
            for i in 0..count {
                assert_eq!(
                    text.matches(&format!("probes[b + {i}u]")).count(),
                    1,
                    "lmax {lmax}: coefficient {i}\n{text}"
                );
                assert!(text.contains(&format!("    y{i}: f32,")), "{text}");
            }
            assert!(!text.contains(&format!("probes[b + {count}u]")), "{text}");
        }
        // Beyond the volume's highest degree the text is the clamped one's.
        assert_eq!(volume_wgsl(8), volume_wgsl(VOLUME_MAX_LMAX));
    }
}
