//! `shlight render`: a coefficient file back to an image.
//!
//! Each texel gets `sum c_l^m Y_l^m(d)` at its centre direction `d`, in the
//! coefficient file's frame (and mirroring), so that rendering a file made by
//! `shlight project` from an equirect map gives that map's band-limited
//! version texel for texel (`shlight_pipeline::render_map`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use shlight_core::map::{Layout, MapOrientation};
use shlight_core::sh::irradiance;
use shlight_io::{ToneMap, WriteOptions, write_image};
use shlight_pipeline::{default_output_size, output_grid, render_map};

use crate::progress::Ui;
use crate::values::parse_size;
use shlight_format::{CoeffFile, Quantity};

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
    /// for equirect; otherwise faces of 128 (cubes) or a 256x256 disc].
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(usize, usize)>,
    /// Layout of the image (equirect, cross-h, cross-v, strip, angular, mirror-ball; docs/conventions.md).
    #[arg(long, value_parser = crate::values::layout(), default_value = "equirect")]
    pub layout: Layout,
    /// Exposure in stops: values are multiplied by 2^EV before writing.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Tone map for PNG output: clamp, reinhard or aces.
    #[arg(long, default_value = "clamp")]
    pub tone_map: ToneMap,
}

/// Runs `shlight render`.
pub fn run(args: &RenderArgs, ui: &Ui) -> Result<()> {
    let name = args.input.display().to_string();
    crate::output_path::refuse_overwriting(&args.output, std::slice::from_ref(&args.input))?;
    let file = CoeffFile::read(&args.input)?;
    if file.encoding != shlight_format::FileEncoding::Sh {
        anyhow::bail!(
            "{name}: holds the {} encoding, whose coefficients are not the whole light; render draws plain SH (shlight irradiance --encoding draws an encoding's irradiance)",
            file.encoding.encoding()
        );
    }
    let coeffs = match (file.quantity, args.irradiance) {
        (Quantity::Radiance, true) => irradiance(&file.coeffs),
        (Quantity::Irradiance, false) => {
            ui.note(format!(
                "{name} holds irradiance; rendering irradiance (radiance cannot be recovered from it)"
            ));
            file.coeffs.clone()
        }
        _ => file.coeffs.clone(),
    };
    let size = args
        .size
        .unwrap_or_else(|| default_output_size(args.layout, 256));
    let orientation = MapOrientation {
        frame: file.frame,
        mirror: file.mirror,
    };
    output_grid(args.layout, size, orientation).context("--size")?;
    let bar = ui.bar(size.1 as u64, "rendering");
    let image = render_map(&coeffs, args.layout, size, orientation, &|| bar.inc(1))?;
    bar.finish_and_clear();
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
