//! Every `cargo run --release -- ...` line of README.md's `sh` blocks runs,
//! in order, in one directory holding the bundled `envmaps/` and `meshes/`
//! and the Blender scenes of `tests/scenes/` (as a fresh clone has them),
//! against the built binary.
//!
//! Lines ending in `# needs: gpu` run when a Vulkan adapter exists (and
//! fail the test under `SHLIGHT_REQUIRE_GPU=1` when none does); lines
//! ending in `# needs: window` open an interactive window and are skipped.
//! Skipped lines are printed as SKIPPED.

use std::path::Path;
use std::process::Command;

use crate::util::{skip_gpu, skip_interactive, temp_dir};

/// What runs a README command.
const PREFIX: &str = "cargo run --release -- ";

/// A README command line and what it needs.
#[derive(Debug)]
struct Line {
    /// The words after [`PREFIX`], marker comment removed.
    command: String,
    needs: Needs,
}

#[derive(Debug, PartialEq, Eq)]
enum Needs {
    Nothing,
    Gpu,
    Window,
}

/// The `cargo run` lines of the ```sh blocks of `readme`, continuation
/// lines (`\` at the end) joined.
fn commands(readme: &str) -> Vec<Line> {
    let mut out = Vec::new();
    let mut in_sh = false;
    let mut pending = String::new();
    for raw in readme.lines() {
        let trimmed = raw.trim();
        if trimmed.starts_with("```") {
            in_sh = !in_sh && trimmed == "```sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        if let Some(head) = trimmed.strip_suffix('\\') {
            pending.push_str(head.trim_end());
            pending.push(' ');
            continue;
        }
        pending.push_str(trimmed);
        let full = std::mem::take(&mut pending);
        let Some(rest) = full.strip_prefix(PREFIX) else {
            continue;
        };
        let (command, needs) = match rest.split_once("# needs:") {
            Some((c, need)) => (
                c,
                match need.trim() {
                    "gpu" => Needs::Gpu,
                    "window" => Needs::Window,
                    other => panic!("README: unknown marker `# needs: {other}` in {full:?}"),
                },
            ),
            None => (rest, Needs::Nothing),
        };
        out.push(Line {
            command: command.trim().to_string(),
            needs,
        });
    }
    out
}

/// Whether a Vulkan adapter exists; `None` in a build without the `gpu`
/// feature, where GPU lines cannot run at all.
fn adapter() -> Result<(), String> {
    #[cfg(feature = "gpu")]
    return shlight_gpu::GpuContext::headless()
        .map(|_| ())
        .map_err(|e| e.to_string());
    #[cfg(not(feature = "gpu"))]
    Err("built without the gpu feature".into())
}

#[test]
fn parsing_joins_continuations_and_reads_markers() {
    let text = "```sh\n# a comment\ncargo run --release -- show a.json\ncargo run --release -- prt m.obj \\\n    --light l.json\ncargo test\ncargo run --release -- view  # needs: window\n```\n```rust\ncargo run --release -- not sh\n```\n";
    let lines = commands(text);
    let got: Vec<(&str, &Needs)> = lines
        .iter()
        .map(|l| (l.command.as_str(), &l.needs))
        .collect();
    assert_eq!(
        got,
        [
            ("show a.json", &Needs::Nothing),
            ("prt m.obj --light l.json", &Needs::Nothing),
            ("view", &Needs::Window),
        ]
    );
}

#[test]
fn every_readme_command_runs_in_order_from_a_fresh_clone() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = commands(&readme);
    assert!(lines.len() > 20, "README commands found: {}", lines.len());
    let dir = temp_dir("readme");
    for bundled in ["envmaps", "meshes"] {
        std::os::unix::fs::symlink(root.join(bundled), dir.join(bundled)).unwrap();
    }
    // The Blender test scenes, which the README's lightmap commands bake.
    std::fs::create_dir_all(dir.join("tests")).unwrap();
    std::os::unix::fs::symlink(root.join("tests/scenes"), dir.join("tests/scenes")).unwrap();
    let gpu = adapter();
    let exe = env!("CARGO_BIN_EXE_shlight");
    for line in &lines {
        match (&line.needs, &gpu) {
            (Needs::Window, _) => {
                skip_interactive("README", &format!("`{}` needs a window", line.command));
                continue;
            }
            (Needs::Gpu, Err(why)) => {
                skip_gpu("README", &format!("`{}` needs a GPU: {why}", line.command));
                continue;
            }
            _ => {}
        }
        // Through the shell, as a reader would type it: globs, quotes and
        // redirections work as they do there.
        let out = Command::new("sh")
            .arg("-c")
            .arg(format!("\"$SHLIGHT\" {}", line.command))
            .env("SHLIGHT", exe)
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "README line `{PREFIX}{}` failed ({}): {}",
            line.command,
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
