//! The environment-map inputs of `shlight project` and `shlight irradiance`:
//! `--up`, `--layout`, and [`load`], which reads and checks a map through
//! `shlight_pipeline::load_map` and shows its warnings.

use std::path::Path;

use anyhow::Result;
use shlight_core::sh::Frame;
use shlight_io::ReadOptions;
use shlight_pipeline::LoadedMap;

use crate::progress::Ui;

pub use shlight_pipeline::{FACE_PLACEHOLDER, InputLayout};

/// `--up y|z` as a frame.
pub fn frame_of(up: &str) -> Frame {
    if up == "z" { Frame::ZUp } else { Frame::YUp }
}

/// `--layout NAME`.
pub fn parse_input_layout(s: &str) -> std::result::Result<InputLayout, String> {
    s.parse()
}

/// Reads and checks an input ([`shlight_pipeline::load_map`]), showing its
/// warnings through `ui`.
pub fn load(
    path: &Path,
    input_layout: InputLayout,
    read: &ReadOptions,
    sanitize: bool,
    ui: &Ui,
) -> Result<LoadedMap> {
    let loaded = shlight_pipeline::load_map(path, input_layout, read, sanitize)?;
    for w in &loaded.warnings {
        ui.warn(w);
    }
    Ok(loaded)
}
