//! The SH sum `sum_{l <= lmax} sum_m w_l c_lm Y_lm(n)` as two loops to a
//! constant lmax, for any lmax and without a table: the evaluator of the
//! coefficient snippets ([`crate::coefficients`]) and of the volume
//! snippet ([`crate::volume`]).
//!
//! `Y_lm` by the normalised associated-Legendre recurrences of shlight-core
//! divided by `sin^m(theta)` and Sloan's trig-free azimuth recurrence
//! (Sloan 2008, "Stupid Spherical Harmonics (SH) Tricks"):
//!
//! ```text
//! C_0 = 1, S_0 = 0,   C_m = x C_(m-1) - y S_(m-1),   S_m = x S_(m-1) + y C_(m-1)
//! P_m^m = -sqrt((2m+1) / 2m) P_(m-1)^(m-1),   P_0^0 = 1 / sqrt(4 pi)
//! P_(m+1)^m = sqrt(2m+3) z P_m^m
//! P_l^m = a (z P_(l-1)^m - b P_(l-2)^m),
//!     a = sqrt((4l^2-1) / (l^2-m^2)),  b = sqrt(((l-1)^2-m^2) / (4(l-1)^2-1))
//! Y_l^0 = P_l^0,   Y_l^m = sqrt2 P_l^m C_m,   Y_l^-m = sqrt2 P_l^m S_m
//! ```
//!
//! (`P_l^m = Pbar_l^m(z) / sin^m(theta)`, `C_m + i S_m = (x + i y)^m`).

use crate::{Code, Language, Type};

/// What the loops read and write.
pub struct ShSum<'a> {
    /// The constant the loops run to (`SHLIGHT_LMAX`).
    pub lmax: &'a str,
    /// The direction's components: `[x, y, z]` or `[n.x, n.y, n.z]`.
    pub direction: [&'a str; 3],
    /// The name of the Legendre value `P_l^m` (`p`, or `pl` where `p` is
    /// taken).
    pub legendre: &'a str,
    /// Whether to say in comments what `pmm` starts at and what `p1`, `p2`
    /// hold.
    pub comments: bool,
    /// Statements that define the band's weight `w` from `l`.
    pub weight: &'a [String],
    /// Coefficient `i` (an index expression) as a vector (C: its channel
    /// `k`).
    pub coefficient: &'a dyn Fn(&str) -> String,
}

/// Writes the sum into `sum` (C: `out[0..3]`), from the recurrences'
/// first values to the end of the loops.
pub fn write_sh_sum(lang: Language, code: &mut Code, s: &ShSum<'_>) {
    let f = Type::Float;
    let [x, y, z] = s.direction;
    let p = s.legendre;
    let cast = |e: &str| lang.cast(f, e);
    code.line(format!(
        "{} // sin^m(theta) cos(m phi)",
        lang.var_typed(f, "c", "1.0")
    ));
    code.line(format!(
        "{} // sin^m(theta) sin(m phi)",
        lang.var_typed(f, "s", "0.0")
    ));
    code.line(format!(
        "{} // Pbar_m^m / sin^m(theta){}",
        lang.var_typed(f, "pmm", "0.28209479177387814"),
        if s.comments {
            ", m = 0: 1 / sqrt(4 pi)"
        } else {
            ""
        }
    ));
    let (sum, channel) = if lang.is_c() {
        code.line("out[0] = out[1] = out[2] = 0.0;");
        ("out[k]", true)
    } else {
        code.line(lang.var(Type::Vec3, "sum", &lang.vector(Type::Vec3, "0.0, 0.0, 0.0")));
        ("sum", false)
    };
    code.open(lang.for_open("m", "0", &format!("m <= {}", s.lmax), true));
    code.open("if (m > 0) {");
    code.line(lang.let_(f, "cn", &format!("{x} * c - {y} * s")));
    code.line(format!("s = {x} * s + {y} * c;"));
    code.line("c = cn;");
    code.line(format!(
        "pmm = pmm * -sqrt({} / {});",
        cast("2 * m + 1"),
        cast("2 * m")
    ));
    code.close("}");
    let (c1, c2) = if s.comments {
        (" // Pbar_(l-1)^m / sin^m", " // Pbar_(l-2)^m / sin^m")
    } else {
        ("", "")
    };
    code.line(format!("{}{c1}", lang.var_typed(f, "p1", "0.0")));
    code.line(format!("{}{c2}", lang.var_typed(f, "p2", "0.0")));
    code.open(lang.for_open("l", "m", &format!("l <= {}", s.lmax), true));
    code.line(lang.var_typed(f, p, "pmm"));
    code.open("if (l == m + 1) {");
    code.line(format!("{p} = sqrt({}) * {z} * pmm;", cast("2 * m + 3")));
    code.reopen("} else if (l > m + 1) {");
    code.line(lang.let_(
        f,
        "a",
        &format!(
            "sqrt({} / {})",
            cast("4 * l * l - 1"),
            cast("l * l - m * m")
        ),
    ));
    code.line(lang.let_(
        f,
        "b",
        &format!(
            "sqrt({} / {})",
            cast("(l - 1) * (l - 1) - m * m"),
            cast("4 * (l - 1) * (l - 1) - 1")
        ),
    ));
    code.line(format!("{p} = a * ({z} * p1 - b * p2);"));
    code.close("}");
    code.line("p2 = p1;");
    code.line(format!("p1 = {p};"));
    code.lines(s.weight);
    if channel {
        code.open("for (int k = 0; k < 3; k++) {");
    }
    let coefficient = s.coefficient;
    code.open("if (m == 0) {");
    code.line(format!(
        "{sum} += {} * (w * {p});",
        coefficient("l * l + l")
    ));
    code.reopen("} else {");
    code.line(lang.let_(f, "t", &format!("w * 1.4142135623730951 * {p}")));
    code.line(format!(
        "{sum} += {} * (t * c) + {} * (t * s);",
        coefficient("l * l + l + m"),
        coefficient("l * l + l - m")
    ));
    code.close("}");
    if channel {
        code.close("}");
    }
    code.close("}");
    code.close("}");
}
