//! The WGSL function `sh_reconstruct` of the render passes, written out as
//! straight-line code for one lmax.
//!
//! ```text
//! sh_reconstruct(d, factors) = sum_{l <= lmax} f_l sum_m L_lm Y_lm(d),
//!     f_l = factors[l / 4][l % 4]   (A_l w_l for irradiance, w_l for radiance)
//! ```
//!
//! with `L_lm` the light's coefficients (`light[l(l+1)+m]`, `scene.wgsl`).
//! The basis is written as in `shaders/sh.wgsl`: with `z = cos(theta)` and
//! `C_m + i S_m = (x + i y)^m`,
//!
//! ```text
//! Y_l^0 = Q_l^0,   Y_l^m = sqrt2 Q_l^m C_m,   Y_l^-m = sqrt2 Q_l^m S_m   (m > 0),
//! Q_0^0 = 1/sqrt(4 pi),   Q_m^m = sectoral_m Q_{m-1}^{m-1},
//! Q_{m+1}^m = diagonal_m z Q_m^m,   Q_l^m = a z Q_{l-1}^m - (a b) Q_{l-2}^m,
//! ```
//!
//! `Q_l^m = Pbar_l^m(z) / sin(theta)^m`: the recurrences of shlight-core's
//! [`Legendre`] with the `sin(theta)` factor carried by `C_m, S_m`, so
//! nothing divides by `sin(theta)` at the poles. The recurrence factors are
//! [`Legendre`]'s own (f64, rounded to f32 literals).
//!
//! Why generated: a shader that loops over `l` and `m` to a run-time lmax
//! keeps `Y` in a local array (or a recurrence table) indexed by loop
//! variables, which CPU rasterisers such as Mesa's llvmpipe keep in memory,
//! lane by lane; written out for a fixed lmax, every value stays in
//! registers and every factor is a literal. The renderer builds one pipeline
//! per lmax (0..=[`LIGHT_MAX_LMAX`]) on first use.

use std::fmt::Write;

use shlight_core::sh::Legendre;

use shlight_baked::LIGHT_MAX_LMAX;

/// A WGSL float literal holding `x` rounded to f32 (shortest round trip).
pub(crate) fn literal(x: f64) -> String {
    format!("{:?}", x as f32)
}

/// The two WGSL lines that define `c{m}` and `s{m}`, `C_m + i S_m = (x + i y)^m`,
/// from `c{m-1}`, `s{m-1}` (`m >= 1`; at `m = 1`, `x` and `y` themselves):
/// `C_m + i S_m = (C_{m-1} + i S_{m-1}) (x + i y)`.
pub(crate) fn azimuth_power(m: usize, x: &str, y: &str) -> [String; 2] {
    assert!(m >= 1, "C_0 + i S_0 = 1 needs no line");
    if m == 1 {
        return [format!("let c1 = {x};"), format!("let s1 = {y};")];
    }
    let p = m - 1;
    [
        format!("let c{m} = c{p} * {x} - s{p} * {y};"),
        format!("let s{m} = c{p} * {y} + s{p} * {x};"),
    ]
}

/// The straight-line WGSL statements of the basis to `lmax` (the module
/// docs' recurrences), for the render passes and the volume pass alike:
/// `z`, `q0_0`, `g{l} = sqrt2 f_l` for `l >= 1`, then for each `m` the
/// azimuth's `c{m}`, `s{m}` and each `q{l}_{m}`, and for `m > 0` the pair's
/// weight `t{l}_{m} = g{l} q{l}_{m}`, so that `f_l Y_l^m = t{l}_{m} c{m}`
/// and `f_l Y_l^-m = t{l}_{m} s{m}` (`f_l Y_l^0 = factors[l / 4][l % 4]
/// q{l}_0`).
///
/// `term(l, m, lines)` adds the caller's statements for `(l, m)` (`m >= 0`)
/// as soon as those values are defined: `(0, 0)` right after `q0_0`,
/// before the `g{l}`; every other pair after its `q` (and `t`) line.
pub(crate) fn basis_statements(
    lmax: usize,
    mut term: impl FnMut(usize, usize, &mut Vec<String>),
) -> Vec<String> {
    let legendre = Legendre::<f64>::new(lmax);
    let mut lines = vec![
        "let z = d.z;".to_string(),
        format!("let q0_0 = {};", literal(0.5 / std::f64::consts::PI.sqrt())),
    ];
    term(0, 0, &mut lines);
    // g_l = sqrt2 f_l, the weight of the m != 0 terms of band l.
    for l in 1..=lmax {
        lines.push(format!(
            "let g{l} = SH_SQRT2 * factors[{}][{}];",
            l / 4,
            l % 4
        ));
    }
    for m in 0..=lmax {
        if m > 0 {
            lines.extend(azimuth_power(m, "d.x", "d.y"));
            lines.push(format!(
                "let q{m}_{m} = {} * q{p}_{p};",
                literal(legendre.sectoral_factor(m)),
                p = m - 1
            ));
        }
        for l in m.max(1)..=lmax {
            if l == m + 1 {
                lines.push(format!(
                    "let q{l}_{m} = {} * z * q{m}_{m};",
                    literal(legendre.diagonal_factor(m))
                ));
            } else if l > m + 1 {
                let [a, ab] = legendre.column_factors(m)[l - m - 2];
                lines.push(format!(
                    "let q{l}_{m} = {} * z * q{}_{m} - {} * q{}_{m};",
                    literal(a),
                    l - 1,
                    literal(ab),
                    l - 2
                ));
            }
            if m > 0 {
                lines.push(format!("let t{l}_{m} = g{l} * q{l}_{m};"));
            }
            term(l, m, &mut lines);
        }
    }
    lines
}

/// The WGSL text of `sh_reconstruct` for `lmax` (clamped to [`LIGHT_MAX_LMAX`]).
#[must_use]
pub(crate) fn sh_reconstruct_wgsl(lmax: usize) -> String {
    let lmax = lmax.min(LIGHT_MAX_LMAX);
    let body = basis_statements(lmax, |l, m, lines| {
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
    });
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

    #[test]
    fn literals_round_trip_to_the_f32_value() {
        for x in [0.282_094_791_773_878_14, -1.224_744_871_391_589, 3.0, 1e-9] {
            let text = literal(x);
            assert!(text.contains('.') || text.contains('e'), "{text}");
            assert_eq!(text.parse::<f32>().unwrap(), x as f32);
        }
    }
}
