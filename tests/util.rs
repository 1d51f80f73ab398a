//! Shared helpers: temporary directories, running the binary, writing maps.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use shlight_io::{Image, WriteOptions, write_image};

/// A fresh directory under the target dir, removed and recreated per test.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `shlight ARGS` and returns its output.
pub fn shlight(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shlight"))
        .args(args)
        .output()
        .expect("the shlight binary runs")
}

/// Writes an equirect map of `w x h` texels, `f(x, y)` each, as EXR.
pub fn write_map(path: &Path, w: usize, h: usize, f: impl Fn(usize, usize) -> [f32; 3]) {
    let img = Image::from_fn(w, h, f);
    write_image(path, &img, &WriteOptions::default()).unwrap();
}

/// Parses stdout as JSON, with the output shown on failure.
pub fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

/// The coefficients of a coefficient file as `[r, g, b]` rows.
pub fn coefficients(v: &serde_json::Value) -> Vec<[f64; 3]> {
    v["coefficients"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            [
                c[0].as_f64().unwrap(),
                c[1].as_f64().unwrap(),
                c[2].as_f64().unwrap(),
            ]
        })
        .collect()
}
