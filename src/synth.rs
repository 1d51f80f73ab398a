//! `shlight synth`: analytic environment maps, the test inputs whose SH
//! coefficients are known in closed form (`shlight_core::sh::closed_form`).
//!
//! Every texel holds the light's mean over the texel
//! (`shlight_core::map::texel_means`, `--supersample N` points a side); a
//! directional light is one texel or a cap of exact power
//! (`shlight_core::map::directional_texels`, `--half-angle`). This module
//! resolves the arguments into a `shlight_core::map::AnalyticLight`, reports
//! where a one-texel sun landed, and writes the map.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use glam::DVec3;
use shlight_core::map::{
    AnalyticLight, DirectionalDrawing, Layout, MapOrientation, directional_texels, texel_means,
};
use shlight_io::{Image, ToneMap, WriteOptions, write_image};
use shlight_pipeline::{default_output_size, output_grid};

use crate::progress::Ui;
use crate::values::{parse_size, parse_vec3};

/// The lights `shlight synth` can draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SynthKind {
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

/// Arguments of `shlight synth`.
#[derive(Args, Debug)]
pub struct SynthArgs {
    /// Which light.
    #[arg(value_enum)]
    pub kind: SynthKind,
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
    let orientation = MapOrientation {
        frame: crate::input::frame_of(&args.up),
        mirror: args.mirror,
    };
    let size = args
        .size
        .unwrap_or_else(|| default_output_size(args.layout, 512));
    let grid = output_grid(args.layout, size, orientation).context("--size")?;
    let axis = match args.direction {
        None => grid.up(),
        Some(d) if d.length() > 0.0 => d.normalize(),
        Some(_) => bail!("--direction 0,0,0 has no direction"),
    };
    let colour = args.color * args.value;
    let half_angle = args.half_angle.unwrap_or(if args.kind == SynthKind::Cap {
        30.0
    } else {
        0.0
    });
    if !(0.0..=180.0).contains(&half_angle) {
        bail!("--half-angle {half_angle}: must be between 0 and 180 degrees");
    }
    if args.kind == SynthKind::Directional && half_angle > 90.0 {
        bail!(
            "--half-angle {half_angle}: a directional light's cap must be at most 90 degrees \
             (a wider cap cannot give the light's irradiance facing it)"
        );
    }
    let alpha = half_angle.to_radians();
    let n = args.supersample as usize;
    let bar = ui.bar(grid.height() as u64, "synthesising");
    let on_rows = |rows: usize| bar.inc(rows as u64);
    let means =
        |light: AnalyticLight, n: usize| texel_means(&grid, n, |d| light.radiance(d), &on_rows);
    let pixels = match args.kind {
        SynthKind::Constant => means(AnalyticLight::Constant(colour), 1),
        SynthKind::Hemisphere => means(
            AnalyticLight::Cap {
                axis,
                cos_half: 0.0,
                radiance: colour,
            },
            n,
        ),
        SynthKind::Cap => means(
            AnalyticLight::Cap {
                axis,
                cos_half: alpha.cos(),
                radiance: colour,
            },
            n,
        ),
        SynthKind::Gradient => means(
            AnalyticLight::Gradient {
                axis,
                a: colour,
                b: args.color * args.slope,
            },
            n,
        ),
        SynthKind::Directional => {
            let drawn = directional_texels(&grid, axis, colour, alpha, n, &on_rows);
            if let DirectionalDrawing::Texel {
                x,
                y,
                centre,
                offset,
                unresolved_cap,
            } = drawn.drawing
            {
                if unresolved_cap {
                    ui.warn(format!(
                        "a cap of half-angle {}° is smaller than the texels can resolve; drawn as one texel",
                        alpha.to_degrees()
                    ));
                }
                if offset > 1e-9 {
                    ui.note(format!(
                        "the light lands in texel x={x}, y={y}, centred at direction {:.6},{:.6},{:.6} ({:.3}° from the one asked for)",
                        centre.x,
                        centre.y,
                        centre.z,
                        offset.to_degrees()
                    ));
                }
            }
            drawn.pixels
        }
    };
    bar.finish_and_clear();
    let image = Image::new(grid.width(), grid.height(), pixels)?;
    let stats = image.stats();
    if stats.negative > 0 {
        ui.warn(format!(
            "{}: {} negative values (minimum {}); radiance cannot be negative",
            args.output.display(),
            stats.negative,
            stats.min_value
        ));
    }
    write_image(
        &args.output,
        &image,
        &WriteOptions {
            exposure_ev: args.exposure,
            tone_map: args.tone_map,
            ..WriteOptions::default()
        },
    )?;
    Ok(())
}
