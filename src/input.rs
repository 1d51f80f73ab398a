//! The environment-map inputs of `shlight project`, `irradiance` and
//! `compare`: `--up` and `--layout` (the maps themselves are read by
//! shlight-pipeline's loader).

use clap::Args;
use shlight_core::map::MapOrientation;
use shlight_core::sh::Frame;
use shlight_io::ReadOptions;
use shlight_pipeline::{ReadSettings, Spelling};

pub use shlight_pipeline::InputLayout;

/// How a command that reads one environment map reads it: `--layout`,
/// `--up`, `--mirror`, `--sanitize`, `--max-pixels` (as `shlight project`
/// reads them).
#[derive(Args, Debug)]
pub struct MapInputArgs {
    /// Layout of the input (as for `shlight project`): auto, equirect,
    /// cross-h, cross-v, strip, angular, mirror-ball, faces.
    #[arg(long, default_value = "auto", value_parser = parse_input_layout)]
    pub layout: InputLayout,
    /// Which world axis the top row of the map faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// Read a map made for the mirrored pbrt / google mapping.
    #[arg(long)]
    pub mirror: bool,
    /// Replace NaN/inf and negative texels (as `shlight project --sanitize`).
    #[arg(long)]
    pub sanitize: bool,
    /// Refuse inputs with more pixels than this (judged from the header).
    #[arg(long, default_value_t = ReadOptions::DEFAULT_MAX_PIXELS)]
    pub max_pixels: usize,
}

impl MapInputArgs {
    /// The loader's settings: the layout, the pixel limit, `--sanitize`.
    pub fn read_settings(&self) -> ReadSettings {
        ReadSettings {
            layout: self.layout,
            read: ReadOptions {
                layer: None,
                max_pixels: self.max_pixels,
            },
            sanitize: self.sanitize,
            spelling: Spelling::CommandLine,
        }
    }

    /// The map's orientation: `--up` and `--mirror`.
    pub fn orientation(&self) -> MapOrientation {
        MapOrientation {
            frame: frame_of(&self.up),
            mirror: self.mirror,
        }
    }
}

/// `--up y|z` as a frame.
pub fn frame_of(up: &str) -> Frame {
    if up == "z" { Frame::ZUp } else { Frame::YUp }
}

/// `--layout NAME`.
pub fn parse_input_layout(s: &str) -> std::result::Result<InputLayout, String> {
    s.parse()
}
