//! `shlight project`: environment map in, SH coefficients out.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use glam::DVec3;
use shlight_core::projection::{EquirectView, MapOrientation, project_equirect};
use shlight_core::rotation::Frame;
use shlight_core::window::{WindowFamily, WindowTarget, auto_window};
use shlight_core::{ShCoeffs, Window, irradiance};
use shlight_io::{ReadOptions, read_image};

use crate::coeff_file::{CoeffFile, Provenance, Quantity};

/// Arguments of `shlight project`.
#[derive(Args, Debug)]
pub struct ProjectArgs {
    /// The environment map (OpenEXR, Radiance .hdr, PNG, JPEG), equirect 2:1.
    pub input: PathBuf,
    /// Highest SH degree kept (lmax 2 = 9 coefficients).
    #[arg(long, default_value_t = 2)]
    pub lmax: usize,
    /// Which world axis the top row of the map faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// Read a map made for the mirrored pbrt / google mapping.
    #[arg(long)]
    pub mirror: bool,
    /// What the coefficients hold.
    #[arg(long, value_enum, default_value_t = Quantity::Radiance)]
    pub quantity: Quantity,
    /// Ringing window: none, hanning:W, lanczos:W, laplacian:LAMBDA, or auto
    /// (the weakest Hanning window that makes the result non-negative).
    #[arg(long, default_value = "none")]
    pub window: String,
    /// EXR layer to read (default: the first with R, G, B).
    #[arg(long)]
    pub layer: Option<String>,
    /// Output file; without it a readable table goes to stdout.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = OutFormat::Json)]
    pub format: OutFormat,
}

/// Output formats of `shlight project`.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum OutFormat {
    /// shlight's self-describing JSON coefficient file.
    Json,
    /// A readable table, one coefficient per line.
    Txt,
}

/// Runs `shlight project`.
pub fn run(args: &ProjectArgs) -> Result<()> {
    let image = read_image(
        &args.input,
        &ReadOptions {
            layer: args.layer.clone(),
            ..ReadOptions::default()
        },
    )?;
    let (w, h) = (image.width(), image.height());
    if w != 2 * h {
        bail!(
            "{}: a {w}x{h} image is not an equirect map (its width must be twice its height)",
            args.input.display()
        );
    }
    let stats = image.stats();
    if stats.non_finite > 0 {
        let (x, y) = stats.first_non_finite.unwrap_or((0, 0));
        bail!(
            "{}: {} texels are NaN or infinite (the first at x={x}, y={y})",
            args.input.display(),
            stats.non_finite
        );
    }
    if stats.negative > 0 {
        eprintln!(
            "warning: {}: {} negative texels (minimum {}), kept as data",
            args.input.display(),
            stats.negative,
            stats.min_value
        );
    }
    let orientation = MapOrientation {
        frame: if args.up == "z" {
            Frame::ZUp
        } else {
            Frame::YUp
        },
        mirror: args.mirror,
    };
    let view = EquirectView {
        width: w,
        height: h,
        pixels: image.pixels(),
    };
    let radiance = project_equirect(view, args.lmax, orientation);

    let target = match args.quantity {
        Quantity::Radiance => WindowTarget::Function,
        Quantity::Irradiance => WindowTarget::Irradiance,
    };
    let window = choose_window(&args.window, &radiance, target)?;
    let radiance = window.apply(&radiance);
    let coeffs = match args.quantity {
        Quantity::Radiance => radiance,
        Quantity::Irradiance => irradiance(&radiance),
    };

    let file = CoeffFile {
        coeffs,
        frame: orientation.frame,
        mirror: orientation.mirror,
        quantity: args.quantity,
        provenance: Provenance {
            input: args.input.display().to_string(),
            width: w,
            height: h,
            layout: "equirect".into(),
            method: "quadrature".into(),
            window: window.to_string(),
        },
        input_negative_texels: stats.negative,
        input_min_value: stats.min_value as f64,
    };
    match (&args.output, args.format) {
        (None, OutFormat::Txt) => print!("{}", file.to_table()),
        (None, OutFormat::Json) if std::io::IsTerminal::is_terminal(&std::io::stdout()) => {
            print!("{}", file.to_table())
        }
        (None, OutFormat::Json) => println!("{}", file.to_json_string()),
        (Some(path), format) => {
            let text = match format {
                OutFormat::Json => file.to_json_string() + "\n",
                OutFormat::Txt => file.to_table(),
            };
            shlight_io::write_atomically(path, |out| out.write_all(text.as_bytes()))
                .with_context(|| format!("writing {}", path.display()))?;
        }
    }
    Ok(())
}

/// Parses `--window`; `auto` picks, per colour channel, the weakest Hanning
/// window that makes the target non-negative, and keeps the strongest of the three.
fn choose_window(spec: &str, radiance: &ShCoeffs<DVec3>, target: WindowTarget) -> Result<Window> {
    if spec != "auto" {
        return spec
            .parse::<Window>()
            .map_err(|e| anyhow::anyhow!("--window {spec}: {e}"));
    }
    let mut best = Window::None;
    let strength = |w: &Window| -> f64 { (0..=radiance.lmax()).map(|l| 1.0 - w.factor(l)).sum() };
    for c in 0..3 {
        let chosen = auto_window(&radiance.channel(c), WindowFamily::Hanning, target)
            .map_err(|e| anyhow::anyhow!("--window auto: {e}"))?;
        if strength(&chosen.window) > strength(&best) {
            best = chosen.window;
        }
    }
    Ok(best)
}
