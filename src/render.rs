//! `shlight render`: a coefficient file back to an image.
//!
//! Each texel gets `sum c_l^m Y_l^m(d)` at its centre direction `d`, in the
//! coefficient file's frame (and mirroring), so that rendering a file made by
//! `shlight project` from an equirect map gives that map's band-limited
//! version texel for texel (`shlight_pipeline::render_map`). `--layout
//! lobe` draws the luminance's lobe instead (`shlight_pipeline::render_lobe`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use glam::DVec3;
use shlight_core::map::{MapOrientation, luminance};
use shlight_core::sh::irradiance;
use shlight_io::{ToneMap, WriteOptions, write_image};
use shlight_pipeline::{
    default_lobe_view, default_output_size, output_grid, render_lobe, render_map,
};

use crate::progress::Ui;
use crate::values::{RenderLayout, parse_size, parse_vec3};
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
    let image = match args.layout {
        RenderLayout::Map(layout) => {
            if args.view.is_some() {
                anyhow::bail!(
                    "--view is where --layout lobe is seen from; a map (--layout {}) shows every direction",
                    layout.name()
                );
            }
            let size = args
                .size
                .unwrap_or_else(|| default_output_size(layout, 256));
            let orientation = MapOrientation {
                frame: file.frame,
                mirror: file.mirror,
            };
            output_grid(layout, size, orientation).context("--size")?;
            let bar = ui.bar(size.1 as u64, "rendering");
            let image = render_map(&coeffs, layout, size, orientation, &|| bar.inc(1))?;
            bar.finish_and_clear();
            image
        }
        RenderLayout::Lobe => {
            let size = args.size.unwrap_or((256, 256));
            let view = args.view.unwrap_or_else(|| default_lobe_view(file.frame));
            if view.length_squared() == 0.0 {
                anyhow::bail!(
                    "--view 0,0,0 has no direction: give the direction from the lobe toward the eye (e.g. 2,1,1)"
                );
            }
            let bar = ui.bar(size.1 as u64, "drawing the lobe");
            let image = render_lobe(&coeffs.map(luminance), file.frame, view, size, &|| {
                bar.inc(1);
            })
            .with_context(|| format!("{name}: --layout lobe"))?;
            bar.finish_and_clear();
            image
        }
    };
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
