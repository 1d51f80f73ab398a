//! The SH basis as straight-line code for one lmax: no loop, no local
//! array, every recurrence factor a literal.
//!
//! With `z = cos(theta)` and `C_m + i S_m = (x + i y)^m`,
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
//! [`Legendre`]'s own (f64; rounded to f32 literals for the shading
//! languages, kept in full for C).
//!
//! Why straight-line: a shader that loops over `l` and `m` to a run-time
//! lmax keeps `Y` in a local array (or a recurrence table) indexed by loop
//! variables, which CPU rasterisers such as Mesa's llvmpipe keep in memory,
//! lane by lane; written out for a fixed lmax, every value stays in
//! registers and every factor is a literal. shlight's renderer builds one
//! pipeline per lmax.

use shlight_core::sh::Legendre;

use crate::literal::{f32_literal, float_literal};
use crate::{Language, Type};

/// The names the basis reads besides its own: every name it defines or
/// reads (`d`, `z`, `factors`, `g{l}`, `c{m}`, `s{m}`, `q{l}_{m}`,
/// `t{l}_{m}`) is prefixed by `prefix`, so two bases can share a function.
#[derive(Clone, Copy, Debug)]
pub struct BasisNames<'a> {
    /// Put before every name (`""`, or `n_` for a second basis).
    pub prefix: &'a str,
    /// The expression of `sqrt(2)` (a module constant).
    pub sqrt2: &'a str,
}

impl Default for BasisNames<'_> {
    /// No prefix; `sqrt(2)` is shlight's shaders' `SH_SQRT2`.
    fn default() -> Self {
        Self {
            prefix: "",
            sqrt2: "SH_SQRT2",
        }
    }
}

/// The two lines that define `{prefix}c{m}` and `{prefix}s{m}`,
/// `C_m + i S_m = (x + i y)^m`, from `c{m-1}`, `s{m-1}` (`m >= 1`; at
/// `m = 1`, `x` and `y` themselves): `C_m + i S_m = (C_{m-1} + i S_{m-1})
/// (x + i y)`.
///
/// # Panics
/// At `m = 0` (`C_0 + i S_0 = 1` needs no line).
#[must_use]
pub fn azimuth_power(lang: Language, m: usize, prefix: &str, x: &str, y: &str) -> [String; 2] {
    assert!(m >= 1, "C_0 + i S_0 = 1 needs no line");
    let (c, s) = (format!("{prefix}c{m}"), format!("{prefix}s{m}"));
    if m == 1 {
        return [lang.let_(Type::Float, &c, x), lang.let_(Type::Float, &s, y)];
    }
    let p = format!("{}", m - 1);
    [
        lang.let_(
            Type::Float,
            &c,
            &format!("{prefix}c{p} * {x} - {prefix}s{p} * {y}"),
        ),
        lang.let_(
            Type::Float,
            &s,
            &format!("{prefix}c{p} * {y} + {prefix}s{p} * {x}"),
        ),
    ]
}

/// The straight-line statements of the basis at the unit direction `d` to
/// `lmax` (the module docs' recurrences): `z`, `q0_0`, `g{l} = sqrt2 f_l`
/// for `l >= 1` (`f_l = factors[l / 4][l % 4]`, the caller's band
/// weights), then for each `m` the azimuth's `c{m}`, `s{m}` and each
/// `q{l}_{m}`, and for `m > 0` the pair's weight `t{l}_{m} = g{l}
/// q{l}_{m}`, so that `f_l Y_l^m = t{l}_{m} c{m}` and `f_l Y_l^-m =
/// t{l}_{m} s{m}` (`f_l Y_l^0 = factors[l / 4][l % 4] q{l}_0`). Every name
/// is prefixed as [`BasisNames`] says.
///
/// `term(l, m, lines)` adds the caller's statements for `(l, m)` (`m >= 0`)
/// as soon as those values are defined: `(0, 0)` right after `q0_0`,
/// before the `g{l}`; every other pair after its `q` (and `t`) line.
pub fn basis_statements(
    lang: Language,
    lmax: usize,
    names: BasisNames<'_>,
    mut term: impl FnMut(usize, usize, &mut Vec<String>),
) -> Vec<String> {
    let p = names.prefix;
    let lit = |x: f64| {
        if lang.is_c() {
            float_literal(x)
        } else {
            f32_literal(x)
        }
    };
    let f = Type::Float;
    let legendre = Legendre::<f64>::new(lmax);
    let mut lines = vec![
        lang.let_(f, &format!("{p}z"), &format!("{p}d.z")),
        lang.let_(
            f,
            &format!("{p}q0_0"),
            &lit(0.5 / std::f64::consts::PI.sqrt()),
        ),
    ];
    term(0, 0, &mut lines);
    // g_l = sqrt2 f_l, the weight of the m != 0 terms of band l.
    for l in 1..=lmax {
        lines.push(lang.let_(
            f,
            &format!("{p}g{l}"),
            &format!("{} * {p}factors[{}][{}]", names.sqrt2, l / 4, l % 4),
        ));
    }
    for m in 0..=lmax {
        if m > 0 {
            lines.extend(azimuth_power(
                lang,
                m,
                p,
                &format!("{p}d.x"),
                &format!("{p}d.y"),
            ));
            lines.push(lang.let_(
                f,
                &format!("{p}q{m}_{m}"),
                &format!(
                    "{} * {p}q{k}_{k}",
                    lit(legendre.sectoral_factor(m)),
                    k = m - 1
                ),
            ));
        }
        for l in m.max(1)..=lmax {
            let q = format!("{p}q{l}_{m}");
            if l == m + 1 {
                let value = format!("{} * {p}z * {p}q{m}_{m}", lit(legendre.diagonal_factor(m)));
                lines.push(lang.let_(f, &q, &value));
            } else if l > m + 1 {
                let [a, ab] = legendre.column_factors(m)[l - m - 2];
                let value = format!(
                    "{} * {p}z * {p}q{}_{m} - {} * {p}q{}_{m}",
                    lit(a),
                    l - 1,
                    lit(ab),
                    l - 2
                );
                lines.push(lang.let_(f, &q, &value));
            }
            if m > 0 {
                lines.push(lang.let_(f, &format!("{p}t{l}_{m}"), &format!("{p}g{l} * {q}")));
            }
            term(l, m, &mut lines);
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_prefixed_and_literals_kept() {
        let names = BasisNames {
            prefix: "n_",
            ..BasisNames::default()
        };
        let lines = basis_statements(Language::Wgsl, 3, names, |_, _, _| {});
        let q3_1 = lines
            .iter()
            .find(|l| l.starts_with("let n_q3_1 = "))
            .unwrap();
        let rest = q3_1.strip_prefix("let n_q3_1 = ").unwrap();
        let (a, rest) = rest.split_once(" * n_z * n_q2_1 - ").unwrap();
        let b = rest.strip_suffix(" * n_q1_1;").unwrap();
        let [want_a, want_ab] = Legendre::<f64>::new(3).column_factors(1)[0];
        assert_eq!(a.parse::<f32>().unwrap(), want_a as f32);
        assert_eq!(b.parse::<f32>().unwrap(), want_ab as f32);
        assert!(lines.contains(&"let n_g2 = SH_SQRT2 * n_factors[0][2];".to_string()));
        assert!(lines.contains(&"let n_c2 = n_c1 * n_d.x - n_s1 * n_d.y;".to_string()));
        assert_eq!(lines[0], "let n_z = n_d.z;");
    }
}
