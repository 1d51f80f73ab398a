//! The guide (`docs/guide/`) runs as printed: every ```sh block of its
//! chapters runs, in page order, in one directory laid out like the
//! repository (the bundled `envmaps/` and `meshes/`, `docs/guide/basis.sh`
//! and `docs/guide/scenes/`, a fresh `docs/guide/img/`), with the built
//! `shlight` first on the `PATH` — what `docs/guide/make.sh --quick` does —
//! and
//! - every block exits 0;
//! - the ```text block under a `<!-- guide: output -->` comment equals the
//!   block's output line for line, text exactly, each number to the digits
//!   the page prints (half a unit in the last place) or to the tolerance
//!   the comment states (`<!-- guide: output, tolerance T -->`: relative
//!   above 1, absolute below);
//! - every figure a page shows (`](img/...)`) is in the repository and was
//!   written again by the commands.
//!
//! Blocks after `<!-- guide: slow -->` are skipped (make.sh runs them);
//! `make.sh --list` must list the same blocks as this test reads.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::util::temp_dir;

/// Relative (above 1) or absolute (below) tolerance of a printed number
/// when its block states none: printed digits beyond this are rounding
/// noise between machines (the AVX and portable kernels sum in another
/// order).
const DEFAULT_TOLERANCE: f64 = 1e-9;

/// One ```sh block of a page and the output the page prints for it.
#[derive(Debug, PartialEq)]
struct Block {
    /// The shell text, run by `bash -euo pipefail -c`.
    script: String,
    slow: bool,
    /// The page's ```text block under it, with its tolerance.
    expected: Option<(String, f64)>,
}

/// The ```sh blocks of a page, each with the output block that follows it.
fn blocks(page: &str) -> Vec<Block> {
    let mut out: Vec<Block> = Vec::new();
    let mut lines = page.lines();
    let mut slow = false;
    let mut tolerance: Option<f64> = None;
    while let Some(line) = lines.next() {
        let t = line.trim();
        if t == "<!-- guide: slow -->" {
            slow = true;
        } else if let Some(rest) = t.strip_prefix("<!-- guide: output") {
            let rest = rest.trim_end_matches("-->").trim();
            tolerance = Some(match rest.strip_prefix(", tolerance") {
                Some(v) => v.trim().parse().expect("guide: bad tolerance"),
                None => {
                    assert!(rest.is_empty(), "guide: unknown marker {t:?}");
                    DEFAULT_TOLERANCE
                }
            });
        } else if t == "```sh" || t == "```text" {
            let mut body = String::new();
            for l in lines.by_ref() {
                if l.trim() == "```" {
                    break;
                }
                body.push_str(l);
                body.push('\n');
            }
            if t == "```sh" {
                out.push(Block {
                    script: body,
                    slow: std::mem::take(&mut slow),
                    expected: None,
                });
            } else if let Some(tol) = tolerance.take() {
                let last = out
                    .last_mut()
                    .expect("guide: output block before any command");
                last.expected = Some((body, tol));
            }
        } else if t.starts_with("```") {
            slow = false;
        }
    }
    out
}

/// A line's text between its numbers, and each number with half a unit in
/// its last printed place.
fn split_numbers(line: &str) -> (Vec<String>, Vec<(f64, f64)>) {
    let b = line.as_bytes();
    let (mut texts, mut numbers) = (vec![String::new()], Vec::new());
    let mut i = 0;
    while i < b.len() {
        let sign = usize::from(b[i] == b'-' || b[i] == b'+');
        if i + sign < b.len() && b[i + sign].is_ascii_digit() {
            let start = i;
            let mut j = i + sign;
            while j < b.len() && b[j].is_ascii_digit() {
                j += 1;
            }
            let mut decimals = 0i32;
            if j + 1 < b.len() && b[j] == b'.' && b[j + 1].is_ascii_digit() {
                j += 1;
                while j < b.len() && b[j].is_ascii_digit() {
                    j += 1;
                    decimals += 1;
                }
            }
            let mut exponent = 0i32;
            if j < b.len() && (b[j] == b'e' || b[j] == b'E') {
                let mut k = j + 1;
                if k < b.len() && (b[k] == b'-' || b[k] == b'+') {
                    k += 1;
                }
                if k < b.len() && b[k].is_ascii_digit() {
                    while k < b.len() && b[k].is_ascii_digit() {
                        k += 1;
                    }
                    exponent = line[j + 1..k].parse().unwrap();
                    j = k;
                }
            }
            let value: f64 = line[start..j].parse().unwrap();
            numbers.push((value, 0.5 * 10f64.powi(exponent - decimals)));
            texts.push(String::new());
            i = j;
        } else {
            texts.last_mut().unwrap().push(b[i] as char);
            i += 1;
        }
    }
    for t in &mut texts {
        *t = t.split_whitespace().collect::<Vec<_>>().join(" ");
    }
    (texts, numbers)
}

/// Why the command's output line `got` does not match the page's `want`,
/// or `None` when it does.
fn mismatch(want: &str, got: &str, tolerance: f64) -> Option<String> {
    let (want_text, want_numbers) = split_numbers(want);
    let (got_text, got_numbers) = split_numbers(got);
    if want_text != got_text || want_numbers.len() != got_numbers.len() {
        return Some(format!("the text differs: page {want:?}, output {got:?}"));
    }
    for ((w, half_unit), (g, _)) in want_numbers.iter().zip(&got_numbers) {
        let allowed = half_unit.max(tolerance * w.abs().max(1.0));
        if (w - g).abs() > allowed * (1.0 + 1e-12) {
            return Some(format!(
                "{g} drifted from the page's {w} (allowed {allowed:e}): page {want:?}, output {got:?}"
            ));
        }
    }
    None
}

/// The figures a page shows: `img/NAME` in its Markdown image links.
fn figures(page: &str) -> Vec<String> {
    page.split("](img/")
        .skip(1)
        .map(|rest| rest[..rest.find(')').unwrap()].to_string())
        .collect()
}

/// The chapters, in order.
fn chapters(root: &Path) -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root.join("docs/guide"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let name = p.file_name().unwrap().to_string_lossy();
            name.starts_with('0') && name.ends_with(".md")
        })
        .collect();
    pages.sort();
    pages
}

#[test]
fn parsing_reads_blocks_markers_and_outputs() {
    let page = "text\n```sh\nshlight show a.json\n```\n\n<!-- guide: output, tolerance 1e-3 -->\n```text\n 0 0 1.5\n```\n<!-- guide: slow -->\n```sh\nshlight prt m.obj \\\n  --samples 9\n```\n```text\nnot checked\n```\n```sh\nls\n```\n";
    assert_eq!(
        blocks(page),
        [
            Block {
                script: "shlight show a.json\n".into(),
                slow: false,
                expected: Some((" 0 0 1.5\n".into(), 1e-3)),
            },
            Block {
                script: "shlight prt m.obj \\\n  --samples 9\n".into(),
                slow: true,
                expected: None,
            },
            Block {
                script: "ls\n".into(),
                slow: false,
                expected: None,
            },
        ]
    );
    assert_eq!(
        figures("a ![x](img/a.png) | ![](img/b-c.svg) ![y](../img/no.png)"),
        ["a.png", "b-c.svg"]
    );
}

#[test]
fn numbers_match_to_the_digits_printed() {
    let (text, numbers) = split_numbers("x 0.25  trilinear 2.9461 cap30-el10 7.97e35 -1.2e-1 NaN");
    assert_eq!(text, ["x", "trilinear", "cap", "-el", "", "", "NaN"]);
    let values: Vec<f64> = numbers.iter().map(|n| n.0).collect();
    assert_eq!(values, [0.25, 2.9461, 30.0, 10.0, 7.97e35, -0.12]);
    assert!((numbers[1].1 - 5e-5).abs() < 1e-18);
    assert!((numbers[4].1 - 5e32).abs() < 1e20);
    // Within the last printed digit, and out of it.
    assert_eq!(mismatch("mean 0.1606", "mean 0.16064", 1e-9), None);
    assert!(mismatch("mean 0.1606", "mean 0.1607", 1e-9).is_some());
    assert!(mismatch("mean 0.1606", "max 0.1606", 1e-9).is_some());
    assert!(mismatch("A 1.0", "A 1.0 2.0", 1e-9).is_some());
    // A stated tolerance widens it.
    assert_eq!(mismatch("mean 0.1606", "mean 0.1609", 1e-3), None);
    assert_eq!(mismatch("p 2.500e3", "p 2.502e3", 1e-3), None);
    assert!(mismatch("p 2.500e3", "p 2.51e3", 1e-3).is_some());
}

/// make.sh runs the very blocks this test checks: its own parser (awk)
/// lists the same scripts, in the same order.
#[test]
fn make_sh_runs_the_blocks_this_test_reads() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new("bash")
        .args(["docs/guide/make.sh", "--list"])
        .current_dir(root)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let listed: Vec<String> = String::from_utf8(out.stdout)
        .unwrap()
        .split_terminator('\0')
        .map(str::to_string)
        .collect();
    let read: Vec<String> = chapters(root)
        .iter()
        .flat_map(|p| blocks(&std::fs::read_to_string(p).unwrap()))
        .map(|b| b.script)
        .collect();
    assert!(read.len() > 10, "blocks read: {}", read.len());
    assert_eq!(listed, read);
}

#[test]
fn every_guide_command_runs_and_prints_the_numbers_on_its_page() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let pages = chapters(root);
    assert!(pages.len() >= 8, "guide chapters found: {}", pages.len());
    let dir = temp_dir("guide");
    for bundled in ["envmaps", "meshes"] {
        std::os::unix::fs::symlink(root.join(bundled), dir.join(bundled)).unwrap();
    }
    let guide = dir.join("docs/guide");
    std::fs::create_dir_all(guide.join("img")).unwrap();
    for helper in ["basis.sh", "scenes"] {
        std::os::unix::fs::symlink(root.join("docs/guide").join(helper), guide.join(helper))
            .unwrap();
    }
    let exe = Path::new(env!("CARGO_BIN_EXE_shlight"));
    let path = format!(
        "{}:{}",
        exe.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut checked = 0;
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap();
        let name = page.file_name().unwrap().to_string_lossy().into_owned();
        for block in blocks(&text).iter().filter(|b| !b.slow) {
            let out = Command::new("bash")
                .args(["-euo", "pipefail", "-c", &block.script])
                .env("PATH", &path)
                .current_dir(&dir)
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{name}: block failed ({}):\n{}\n{}",
                out.status,
                block.script,
                String::from_utf8_lossy(&out.stderr)
            );
            let Some((want, tolerance)) = &block.expected else {
                continue;
            };
            let got = String::from_utf8_lossy(&out.stdout);
            let (want, got): (Vec<&str>, Vec<&str>) =
                (want.lines().collect(), got.lines().collect());
            assert_eq!(
                want.len(),
                got.len(),
                "{name}: the block\n{}prints {} lines, the page {}:\n{}",
                block.script,
                got.len(),
                want.len(),
                got.join("\n")
            );
            for (w, g) in want.iter().zip(&got) {
                if let Some(why) = mismatch(w, g, *tolerance) {
                    panic!("{name}: the block\n{}{why}", block.script);
                }
            }
            checked += want.len();
        }
        for figure in figures(&text) {
            assert!(
                root.join("docs/guide/img").join(&figure).is_file(),
                "{name}: img/{figure} is not in the repository"
            );
            assert!(
                guide.join("img").join(&figure).is_file(),
                "{name}: img/{figure} is not written by the page's commands"
            );
        }
    }
    assert!(checked > 100, "output lines checked: {checked}");
}
