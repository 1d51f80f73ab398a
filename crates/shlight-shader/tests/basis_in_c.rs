//! The straight-line basis written in C (double precision, every factor a
//! full f64 literal), compiled with `cc` and run, against shlight-core's
//! basis (`sh_eval`, its own recurrences) at every lmax to 8, at random
//! directions and the poles, each band weighted by its own factor. A
//! missing `cc` skips the test (a line on stderr), or fails it under
//! `SHLIGHT_REQUIRE_ALL=1`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Command;

use glam::DVec3;
use shlight_core::sh::sh_eval;
use shlight_shader::Language;
use shlight_shader::basis::{BasisNames, basis_statements};

/// The core in f64 against the same recurrences in C doubles (factors
/// rounded alike, sums in another order): a few ulps; a wrong factor,
/// sign or index is off by far more.
const TOL: f64 = 1e-13;

/// A fixed linear congruential sequence (Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

fn directions() -> Vec<DVec3> {
    let mut rng = Lcg(9);
    let mut dirs: Vec<DVec3> = (0..200)
        .filter_map(|_| {
            let v = DVec3::new(rng.next(), rng.next(), rng.next());
            (v.length() > 0.1 && v.length() < 1.0).then(|| v.normalize())
        })
        .collect();
    dirs.extend([DVec3::Z, DVec3::NEG_Z, DVec3::X, DVec3::NEG_Y]);
    dirs
}

/// Band weight `f_l` of the test: distinct per band, so a slip between
/// bands shows.
fn factor(l: usize) -> f64 {
    1.0 + 0.25 * l as f64
}

fn have_cc(test: &str) -> bool {
    let ok = Command::new("cc")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        let why = format!("{test}: `cc` is not installed");
        assert!(
            std::env::var("SHLIGHT_REQUIRE_ALL").as_deref() != Ok("1"),
            "SHLIGHT_REQUIRE_ALL=1 but it would be skipped: {why}"
        );
        eprintln!("SKIPPED {why}");
    }
    ok
}

/// A C program that prints `f_l Y_i(d)` for every `i` to `lmax`, a line
/// per direction.
fn program(lmax: usize, dirs: &[DVec3]) -> String {
    let count = (lmax + 1) * (lmax + 1);
    let body = basis_statements(Language::C, lmax, BasisNames::default(), |l, m, lines| {
        let centre = l * (l + 1);
        if m == 0 {
            lines.push(format!(
                "y[{centre}] = factors[{}][{}] * q{l}_0;",
                l / 4,
                l % 4
            ));
        } else {
            lines.push(format!("y[{}] = t{l}_{m} * c{m};", centre + m));
            lines.push(format!("y[{}] = t{l}_{m} * s{m};", centre - m));
        }
    });
    let mut s = String::from(
        "#include <math.h>\n#include <stdio.h>\n\n#define SH_SQRT2 1.4142135623730951\n\n\
         struct direction { double x, y, z; };\n\n",
    );
    let _ = writeln!(
        s,
        "static void basis(struct direction d, const double factors[3][4], double y[{count}]) {{"
    );
    for line in body {
        let _ = writeln!(s, "    {line}");
    }
    // At lmax 0 nothing reads z.
    s.push_str("    (void)z;\n}\n\nint main(void) {\n");
    let f: Vec<String> = (0..12).map(|l| format!("{:?}", factor(l))).collect();
    let _ = writeln!(
        s,
        "    static const double factors[3][4] = {{{{{}}}, {{{}}}, {{{}}}}};",
        f[0..4].join(", "),
        f[4..8].join(", "),
        f[8..12].join(", ")
    );
    let _ = writeln!(
        s,
        "    static const struct direction dirs[{}] = {{",
        dirs.len()
    );
    for d in dirs {
        let _ = writeln!(s, "        {{{:?}, {:?}, {:?}}},", d.x, d.y, d.z);
    }
    s.push_str("    };\n");
    let _ = writeln!(
        s,
        "    for (unsigned k = 0; k < {}; k++) {{\n        double y[{count}];\n        basis(dirs[k], factors, y);\n        \
         for (int i = 0; i < {count}; i++) {{\n            printf(\"%.17g \", y[i]);\n        }}\n        \
         printf(\"\\n\");\n    }}\n    return 0;\n}}",
        dirs.len()
    );
    s
}

#[test]
fn the_basis_in_c_equals_the_cores_at_every_lmax() {
    let test = "the_basis_in_c_equals_the_cores_at_every_lmax";
    if !have_cc(test) {
        return;
    }
    let dir: PathBuf =
        std::env::temp_dir().join(format!("shlight-shader-basis-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let dirs = directions();
    for lmax in 0..=8 {
        let (src, exe) = (
            dir.join(format!("basis{lmax}.c")),
            dir.join(format!("basis{lmax}")),
        );
        std::fs::write(&src, program(lmax, &dirs)).unwrap();
        let out = Command::new("cc")
            .args([
                "-std=c99",
                "-pedantic",
                "-O1",
                "-Wall",
                "-Wextra",
                "-Werror",
                "-o",
            ])
            .arg(&exe)
            .arg(&src)
            .arg("-lm")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "cc rejects {}:\n{}",
            src.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        let run = Command::new(&exe).output().unwrap();
        assert!(run.status.success());
        let text = String::from_utf8(run.stdout).unwrap();
        let rows: Vec<Vec<f64>> = text
            .lines()
            .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), dirs.len());
        for (d, row) in dirs.iter().zip(&rows) {
            let want = sh_eval(lmax, *d);
            assert_eq!(row.len(), want.len());
            for (i, (g, w)) in row.iter().zip(&want).enumerate() {
                let l = (i as f64).sqrt() as usize;
                let w = factor(l) * w;
                assert!(
                    (g - w).abs() <= TOL,
                    "lmax {lmax}, coefficient {i} at {d}: C {g}, core {w}"
                );
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
