//! `shlight render`: a coefficient file back to an image, by
//! shlight-pipeline's `render` job (its `RenderRequest`, checked, then run).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use glam::DVec3;
use shlight_io::ToneMap;
use shlight_pipeline::{RenderLayout, RenderRequest, Spelling, render};

use crate::progress::{Reporter, Ui};
use crate::values::{parse_size, parse_vec3};

/// Arguments of `shlight render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// A coefficient file (`shlight project -o FILE.json`).
    pub input: PathBuf,
    /// The image to write: .exr, .hdr or .png (tone mapped).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Render irradiance `E = A_l L_l^m` (what a white Lambertian surface
    /// facing each direction receives; its radiance is E/π) instead of
    /// radiance. A file that holds irradiance is rendered as it is.
    #[arg(long)]
    pub irradiance: bool,
    /// Full image size, WIDTHxHEIGHT, fitting --layout [default: 512x256
    /// for equirect; otherwise faces of 128 (cubes) or 256x256 (a disc, a
    /// lobe)].
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(usize, usize)>,
    /// Layout of the image (equirect, cross-h, cross-v, strip, angular,
    /// mirror-ball; docs/conventions.md), or lobe: the luminance
    /// f = 0.2126 R + 0.7152 G + 0.0722 B as the 3D surface r(w) = |f(w)|,
    /// red where f > 0 and blue where f < 0, on white.
    #[arg(long, value_parser = crate::values::render_layout(), default_value = "equirect")]
    pub layout: RenderLayout,
    /// Where --layout lobe is seen from: the direction X,Y,Z from the lobe
    /// toward the eye, in the file's frame (an orthographic camera looking
    /// along -X,-Y,-Z, the frame's up axis up) [default: 2,1,1 for a z-up
    /// file, the same view 2,1,-1 for a y-up file].
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub view: Option<DVec3>,
    /// Exposure in stops: values are multiplied by 2^EV before writing.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Tone map for PNG output: clamp, reinhard or aces.
    #[arg(long, default_value = "clamp")]
    pub tone_map: ToneMap,
}

/// Runs `shlight render`.
pub fn run(args: &RenderArgs, ui: &Ui) -> Result<()> {
    let plan = RenderRequest {
        irradiance: args.irradiance,
        size: args.size,
        layout: args.layout,
        view: args.view,
        exposure: args.exposure,
        tone_map: args.tone_map,
    }
    .check(Spelling::CommandLine)?;
    render(&args.input, &args.output, &plan, &Reporter::new(ui))?;
    Ok(())
}
