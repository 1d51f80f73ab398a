//! The environment-map inputs of `shlight project`, `irradiance` and
//! `compare`: `--up` and `--layout` (the maps themselves are read by
//! shlight-pipeline's loader).

use shlight_core::sh::Frame;

pub use shlight_pipeline::{FACE_PLACEHOLDER, InputLayout};

/// `--up y|z` as a frame.
pub fn frame_of(up: &str) -> Frame {
    if up == "z" { Frame::ZUp } else { Frame::YUp }
}

/// `--layout NAME`.
pub fn parse_input_layout(s: &str) -> std::result::Result<InputLayout, String> {
    s.parse()
}
