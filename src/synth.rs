//! `shlight synth`: analytic environment maps, the test inputs whose SH
//! coefficients are known in closed form (`shlight_core::analytic`).
//!
//! Every texel holds the light's **mean over the texel**: the average of the
//! radiance at `N x N` points spread over equal solid angles of the texel
//! (`--supersample N`). Constant and band-limited lights are then exact up
//! to `f32`, and the projection of a light with an edge (hemisphere, cap)
//! errs only in the texels the edge crosses. A hemisphere about the map's
//! own up axis has its edge on a row boundary (even heights) and is exact.
//!
//! A directional light (a delta) cannot be stored in texels. `directional`
//! approximates it in one of two ways, both keeping its irradiance `E`:
//!
//! - `--half-angle 0` (default): all of it in the single texel that the
//!   direction falls in, with radiance `E / Ω_texel`. shlight's projection
//!   (texel centres) then gives exactly the delta at that texel's centre,
//!   `E Y_l^m(d_texel)`; the centre is at most half a texel from the
//!   direction asked for, and is reported.
//! - `--half-angle A > 0`: a uniform cap of half-angle `A` whose radiance
//!   `L = E / (π sin² A)` gives irradiance `E` facing it; its coefficients
//!   are `analytic::cap` and differ from the delta's by about
//!   `l(l+1) A² / 4` relatively in degree `l`. The texels are then scaled so
//!   that their total `Σ L_texel Ω_texel` is the cap's exact `2π(1 - cos A) L`.

use std::f64::consts::PI;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use glam::DVec3;
use rayon::prelude::*;
use shlight_core::projection::MapOrientation;
use shlight_io::{Image, ToneMap, WriteOptions, write_image};

use crate::progress::Ui;
use crate::texels::{LayoutArg, TexelGrid, default_size, parse_size};

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
    #[arg(long, value_enum, default_value_t)]
    pub layout: LayoutArg,
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
    /// one texel; > 0 a small cap of the same irradiance).
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

/// `X,Y,Z` (or `R,G,B`): three finite numbers.
pub fn parse_vec3(s: &str) -> std::result::Result<DVec3, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|e| format!("{s:?}: {e}"))?;
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(DVec3::new(*x, *y, *z)),
        _ => Err(format!("{s:?} is not three finite numbers X,Y,Z")),
    }
}

/// What to draw, resolved from the arguments.
#[derive(Clone, Copy, Debug)]
enum Light {
    Constant(DVec3),
    /// Radiance inside `d . axis >= cos_half`.
    Cap {
        axis: DVec3,
        cos_half: f64,
        radiance: DVec3,
    },
    Gradient {
        axis: DVec3,
        a: DVec3,
        b: DVec3,
    },
}

impl Light {
    fn radiance(&self, d: DVec3) -> DVec3 {
        match *self {
            Light::Constant(v) => v,
            Light::Cap {
                axis,
                cos_half,
                radiance,
            } => {
                if d.dot(axis) >= cos_half {
                    radiance
                } else {
                    DVec3::ZERO
                }
            }
            Light::Gradient { axis, a, b } => a + b * d.dot(axis),
        }
    }
}

/// Runs `shlight synth`.
pub fn run(args: &SynthArgs, ui: &Ui) -> Result<()> {
    let orientation = MapOrientation {
        frame: crate::input::frame_of(&args.up),
        mirror: args.mirror,
    };
    let grid = TexelGrid::new(
        args.layout,
        args.size.unwrap_or_else(|| default_size(args.layout, 512)),
        orientation,
    )
    .context("--size")?;
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
    let alpha = half_angle.to_radians();
    let n = args.supersample as usize;
    let bar = ui.bar(grid.height as u64, "synthesising");
    let image = match args.kind {
        SynthKind::Constant => fill(&grid, 1, &Light::Constant(colour), &bar),
        SynthKind::Hemisphere => fill(
            &grid,
            n,
            &Light::Cap {
                axis,
                cos_half: 0.0,
                radiance: colour,
            },
            &bar,
        ),
        SynthKind::Cap => fill(
            &grid,
            n,
            &Light::Cap {
                axis,
                cos_half: alpha.cos(),
                radiance: colour,
            },
            &bar,
        ),
        SynthKind::Gradient => fill(
            &grid,
            n,
            &Light::Gradient {
                axis,
                a: colour,
                b: args.color * args.slope,
            },
            &bar,
        ),
        SynthKind::Directional => directional(&grid, axis, colour, alpha, n, ui, &bar),
    };
    bar.finish_and_clear();
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

/// Each texel the mean of `light` over `n x n` equal-area points of it.
fn fill(grid: &TexelGrid, n: usize, light: &Light, bar: &indicatif::ProgressBar) -> Image {
    // Only equirect texels are sub-sampled (TexelGrid::sample); the other
    // layouts take each texel's centre direction.
    let n = if grid.layout == LayoutArg::Equirect {
        n
    } else {
        1
    };
    let w = grid.width;
    let mut pixels = vec![[0.0f32; 3]; w * grid.height];
    pixels.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, px) in row.iter_mut().enumerate() {
            let mut sum = DVec3::ZERO;
            let mut used = 0usize;
            for i in 0..n {
                for j in 0..n {
                    let (s, t) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                    if let Some(d) = grid.sample(x, y, s, t) {
                        sum += light.radiance(d);
                        used += 1;
                    }
                }
            }
            let mean = if used > 0 {
                sum / used as f64
            } else {
                DVec3::ZERO
            };
            *px = mean.as_vec3().to_array();
        }
        bar.inc(1);
    });
    Image::new(w, grid.height, pixels).expect("w * h pixels")
}

/// A directional light of irradiance `e` from `axis`: one texel when
/// `alpha == 0` (or when a cap would miss every sample point), else a cap
/// normalised to its exact power (module docs).
fn directional(
    grid: &TexelGrid,
    axis: DVec3,
    e: DVec3,
    alpha: f64,
    n: usize,
    ui: &Ui,
    bar: &indicatif::ProgressBar,
) -> Image {
    if alpha > 0.0 {
        let sin2 = alpha.sin().powi(2);
        let radiance = e / (PI * sin2);
        let cap = Light::Cap {
            axis,
            cos_half: alpha.cos(),
            radiance: DVec3::ONE,
        };
        let coverage = fill(grid, n.max(8), &cap, bar);
        let mut power = 0.0;
        for y in 0..grid.height {
            for x in 0..grid.width {
                power += f64::from(coverage.get(x, y)[0]) * grid.solid_angle(x, y);
            }
        }
        if power > 0.0 {
            // The cap's solid angle 2π(1 - cos a), written without cancellation.
            let exact = 4.0 * PI * (alpha / 2.0).sin().powi(2);
            let scale = exact / power;
            let mut image = coverage;
            for px in image.pixels_mut() {
                let c = f64::from(px[0]) * scale;
                *px = (radiance * c).as_vec3().to_array();
            }
            return image;
        }
        ui.warn(format!(
            "a cap of half-angle {}° is smaller than the texels can resolve; drawn as one texel",
            alpha.to_degrees()
        ));
    }
    let (x, y) = grid.texel_of(axis);
    let centre = grid.direction(x, y).expect("texel_of gives a used texel");
    if centre.angle_between(axis) > 1e-9 {
        ui.note(format!(
            "the light lands in texel x={x}, y={y}, centred at direction {:.6},{:.6},{:.6} ({:.3}° from the one asked for)",
            centre.x,
            centre.y,
            centre.z,
            centre.angle_between(axis).to_degrees()
        ));
    }
    let radiance = e / grid.solid_angle(x, y);
    let mut image = Image::from_fn(grid.width, grid.height, |_, _| [0.0; 3]);
    image.set(x, y, radiance.as_vec3().to_array());
    bar.inc(grid.height as u64);
    image
}
