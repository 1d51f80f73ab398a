//! `shlight irradiance`: the exact irradiance map of an environment, the
//! ground truth to compare SH against.
//!
//! Every texel of the output (an equirect map of `--size`, in the input's
//! frame) gets `E(n) = Σ L_k max(n · d_k, 0) Ω_k` over **every** texel `k`
//! of the input, for `n` the output texel's centre direction
//! (`shlight_core::map`): `O(input × output)` work, in parallel,
//! with a progress bar. `--sh LMAX` also writes the SH irradiance of the
//! same map (quadrature projection to LMAX, `E_l^m = A_l L_l^m`) as
//! `OUT-sh.EXT` and the difference SH minus exact as `OUT-diff.EXT`, and
//! prints the relative error of the SH irradiance's luminance over the
//! sphere (area-weighted mean, and maximum): pointwise `|ΔE| / E(n)` and,
//! as Ramamoorthi & Hanrahan measure it, `|ΔE| / max E`
//! (shlight-pipeline's `map_irradiance`, on shlight-accuracy). `--encoding E`
//! does the same for any encoding of `shlight_core::encoding` (dominant
//! lights + SH, ZH3, non-linear L1, the ambient cube), writing
//! `OUT-E.EXT` and `OUT-diff.EXT`; its SH part is `--sh LMAX` (default 2).
//! `--error-map FILE.png` draws the peak-relative error over the sphere on
//! a fixed 0-10% colour scale (shlight-accuracy's error maps).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use glam::DVec3;
use shlight_accuracy::plot::{error_map_values, write_error_map};
use shlight_core::map::{Layout, MapOrientation};
use shlight_io::{Image, WriteOptions, write_image};
use shlight_pipeline::{IrradianceSettings, map_irradiance, output_grid};

use crate::input::MapInputArgs;
use crate::output_path::refuse_overwriting;
use crate::progress::Ui;
use crate::values::parse_size;

/// Top of `--error-map`'s colour scale: 10% of the peak irradiance, about
/// the worst Ramamoorthi & Hanrahan allow for nine terms (9%).
const ERROR_MAP_TOP: f64 = 0.1;

/// Arguments of `shlight irradiance`.
#[derive(Args, Debug)]
pub struct IrradianceArgs {
    /// The environment map (OpenEXR, Radiance .hdr, PNG, JPEG), any layout.
    pub input: PathBuf,
    /// The irradiance map to write (equirect, the input's frame): .exr,
    /// .hdr or .png.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Output size WIDTHxHEIGHT (2:1). Work grows with input × output texels.
    #[arg(long, default_value = "256x128", value_parser = parse_size)]
    pub size: (usize, usize),
    /// Also write the SH irradiance to this lmax (OUT-sh.EXT) and SH minus
    /// exact (OUT-diff.EXT), and print the relative error.
    #[arg(long, value_name = "LMAX")]
    pub sh: Option<usize>,
    /// Compare this encoding instead of plain SH (sh, dominant+sh,
    /// sloan+sh, zh3, zh3-hallucinated, l1-nonlinear, ambient-cube): writes
    /// OUT-ENCODING.EXT and OUT-diff.EXT and prints its error. `--sh` is
    /// then the lmax of its SH part (default 2; the dominant lights'
    /// residual for dominant+sh).
    #[arg(long, value_parser = crate::values::encoding())]
    pub encoding: Option<shlight_core::encoding::Encoding>,
    /// With --sh or --encoding: also write an error map (PNG) of the
    /// estimate's luminance error relative to the peak irradiance,
    /// `|Ŷ(n) - Y(n)| / Y_peak` (what the `relative to max E` line
    /// summarises), on a fixed colour scale from 0 to 10% with its colour
    /// bar underneath, so the maps of different lights compare.
    #[arg(long, value_name = "FILE.png")]
    pub error_map: Option<PathBuf>,
    /// How the map is read.
    #[command(flatten)]
    pub map: MapInputArgs,
}

/// `OUT` with `suffix` added to its stem: `dir/name-sh.exr`.
fn beside(out: &Path, suffix: &str) -> PathBuf {
    let stem = out.file_stem().unwrap_or_default().to_string_lossy();
    let name = match out.extension() {
        Some(ext) => format!("{stem}{suffix}.{}", ext.to_string_lossy()),
        None => format!("{stem}{suffix}"),
    };
    out.with_file_name(name)
}

/// Runs `shlight irradiance`.
pub fn run(args: &IrradianceArgs, ui: &Ui) -> Result<()> {
    let name = args.input.display().to_string();
    let (w, h) = args.size;
    output_grid(Layout::Equirect, (w, h), MapOrientation::default())
        .map_err(|e| anyhow!("--size: {e}"))?;
    let encoding = match (args.encoding, args.sh) {
        (Some(e), lmax) => Some((e, lmax.unwrap_or(2))),
        (None, Some(lmax)) => Some((shlight_core::encoding::Encoding::Sh, lmax)),
        (None, None) => None,
    };
    let outputs: Vec<PathBuf> = match (args.encoding, encoding) {
        (_, None) => vec![args.output.clone()],
        (None, Some(_)) => vec![
            args.output.clone(),
            beside(&args.output, "-sh"),
            beside(&args.output, "-diff"),
        ],
        (Some(e), Some(_)) => vec![
            args.output.clone(),
            beside(&args.output, &format!("-{e}")),
            beside(&args.output, "-diff"),
        ],
    };
    if let Some(map) = &args.error_map {
        if encoding.is_none() {
            bail!("--error-map needs --sh or --encoding: it maps an estimate's error");
        }
        if map.extension().and_then(|e| e.to_str()) != Some("png") {
            bail!("{}: --error-map writes a PNG (.png)", map.display());
        }
    }
    for out in outputs.iter().chain(&args.error_map) {
        refuse_overwriting(out, std::slice::from_ref(&args.input))?;
    }
    let settings = IrradianceSettings {
        read: args.map.read_settings(),
        orientation: args.map.orientation(),
        size: (w, h),
        encoding,
    };
    let bar = ui.bar((w * h) as u64, "irradiance");
    let report = map_irradiance(&args.input, &settings, &|m| ui.warn(m), &|n| {
        bar.inc(n as u64);
    });
    bar.finish_and_clear();
    let report = report?;
    let to_image = |values: &[DVec3]| {
        Image::new(
            w,
            h,
            values.iter().map(|v| v.as_vec3().to_array()).collect(),
        )
        .expect("w * h values")
    };
    let write = |path: &Path, values: &[DVec3]| {
        write_image(path, &to_image(values), &WriteOptions::default())
            .with_context(|| format!("{name}: writing"))
    };
    write(&args.output, &report.exact.exact)?;

    let Some(measured) = &report.encoded else {
        return Ok(());
    };
    let (encoding, lmax) = (measured.encoding, measured.lmax);
    write(&outputs[1], &measured.estimate)?;
    write(&outputs[2], &measured.difference)?;
    let Some(errors) = measured.errors else {
        bail!("{name}: the map has no light (its irradiance is 0 everywhere)");
    };
    if let Some(path) = &args.error_map {
        let values = report
            .exact
            .peak_relative_map(&measured.estimate)
            .expect("the map has light: its errors exist");
        let (image, _) = error_map_values(w, h, Some(ERROR_MAP_TOP), &values);
        write_error_map(path, &image).with_context(|| format!("{name}: writing"))?;
    }
    let (p, q) = (errors.pointwise, errors.peak_relative);
    let what = match (args.encoding, encoding.takes_lmax()) {
        (None, _) => format!("SH irradiance (lmax {lmax})"),
        (Some(_), true) => format!("{encoding} irradiance (SH lmax {lmax})"),
        (Some(_), false) => format!("{encoding} irradiance"),
    };
    println!(
        "{name}: {what} against brute force over {} normals ({}x{} texels of input):",
        report.exact.normals.len(),
        report.map_size.0,
        report.map_size.1
    );
    if args.encoding.is_some() {
        println!("  floats stored:      {}", measured.light.floats(encoding));
        for (i, l) in measured.light.lights().iter().enumerate() {
            println!(
                "  light {i}: direction {:.4},{:.4},{:.4}  half-angle {:.3}°  power {:.4},{:.4},{:.4}",
                l.direction.x,
                l.direction.y,
                l.direction.z,
                l.half_angle.to_degrees(),
                l.power.x,
                l.power.y,
                l.power.z
            );
        }
    }
    println!(
        "  relative to E(n):   mean {:.3}%  max {:.3}%",
        100.0 * p.mean,
        100.0 * p.max
    );
    println!(
        "  relative to max E:  mean {:.3}%  max {:.3}%",
        100.0 * q.mean,
        100.0 * q.max
    );
    Ok(())
}
