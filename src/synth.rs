//! `shlight synth`: analytic environment maps, the test inputs whose SH
//! coefficients are known in closed form, by shlight-pipeline's `synth`
//! job.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};
use glam::DVec3;
use shlight_core::map::{Layout, MapOrientation};
use shlight_io::ToneMap;
use shlight_pipeline::{Spelling, SynthKind, SynthRequest, synth};

use crate::progress::{Reporter, Ui};
use crate::values::{parse_size, parse_vec3};

/// The lights `shlight synth` can draw (shlight-pipeline's `SynthKind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SynthKindArg {
    /// Radiance `value * color` in every direction.
    Constant,
    /// Radiance `value * color` over the hemisphere about `--direction`
    /// (default: the frame's up axis), 0 below.
    Hemisphere,
    /// Radiance `value * color` inside a cap of `--half-angle` degrees about
    /// `--direction` (default up), 0 outside.
    Cap,
    /// Sky gradient `(value + slope (d . direction)) * color`, direction
    /// defaulting to up.
    Gradient,
    /// A sun: irradiance `value * color` facing `--direction` (default up);
    /// see `--half-angle`.
    Directional,
}

impl From<SynthKindArg> for SynthKind {
    fn from(k: SynthKindArg) -> Self {
        match k {
            SynthKindArg::Constant => SynthKind::Constant,
            SynthKindArg::Hemisphere => SynthKind::Hemisphere,
            SynthKindArg::Cap => SynthKind::Cap,
            SynthKindArg::Gradient => SynthKind::Gradient,
            SynthKindArg::Directional => SynthKind::Directional,
        }
    }
}

/// Arguments of `shlight synth`.
#[derive(Args, Debug)]
pub struct SynthArgs {
    /// Which light.
    #[arg(value_enum)]
    pub kind: SynthKindArg,
    /// The map to write: .exr (exact), .hdr (RGBE, ~1% precision) or .png
    /// (8-bit, tone mapped; not for projecting).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Full image size, WIDTHxHEIGHT, fitting --layout [default: 1024x512
    /// for equirect; otherwise faces of 256 (cubes) or a 512x512 disc].
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(usize, usize)>,
    /// Which world axis the top row of the map faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// Write the mirrored pbrt / google mapping.
    #[arg(long)]
    pub mirror: bool,
    /// Layout of the map (equirect, cross-h, cross-v, strip, angular, mirror-ball; docs/conventions.md).
    #[arg(long, value_parser = crate::values::layout(), default_value = "equirect")]
    pub layout: Layout,
    /// Linear Rec.709 colour R,G,B multiplying the light.
    #[arg(long, default_value = "1,1,1", value_parser = parse_vec3, allow_negative_numbers = true)]
    pub color: DVec3,
    /// Strength: radiance (constant, hemisphere, cap; the gradient's mean
    /// `a`) or, for directional, the irradiance facing the light.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub value: f64,
    /// The gradient's `b` in `a + b (d . direction)`.
    #[arg(long, default_value_t = 0.5, allow_negative_numbers = true)]
    pub slope: f64,
    /// Axis X,Y,Z of the light in world coordinates (normalised); default:
    /// the frame's up axis.
    #[arg(long, value_parser = parse_vec3, allow_negative_numbers = true)]
    pub direction: Option<DVec3>,
    /// Half-angle in degrees: cap (default 30), directional (default 0 =
    /// one texel; up to 90 a small cap of the same irradiance).
    #[arg(long)]
    pub half_angle: Option<f64>,
    /// Points per texel side for the texel means (N x N per texel).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub supersample: u32,
    /// Exposure in stops applied when writing (2^EV).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Tone map for PNG output: clamp, reinhard or aces.
    #[arg(long, default_value = "clamp")]
    pub tone_map: ToneMap,
}

/// Runs `shlight synth`.
pub fn run(args: &SynthArgs, ui: &Ui) -> Result<()> {
    let plan = SynthRequest {
        kind: args.kind.into(),
        size: args.size,
        layout: args.layout,
        orientation: MapOrientation {
            frame: crate::input::frame_of(&args.up),
            mirror: args.mirror,
        },
        color: args.color,
        value: args.value,
        slope: args.slope,
        direction: args.direction,
        half_angle: args.half_angle,
        supersample: args.supersample,
        exposure: args.exposure,
        tone_map: args.tone_map,
    }
    .check(Spelling::CommandLine)?;
    synth(&args.output, &plan, &Reporter::new(ui))?;
    Ok(())
}
