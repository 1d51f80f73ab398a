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
//! a fixed 0-10% colour scale (shlight-accuracy's error maps). All of it is
//! shlight-pipeline's `irradiance` job; this prints its summary.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use shlight_pipeline::{IrradianceRequest, Spelling, irradiance};

use crate::input::MapInputArgs;
use crate::progress::{Reporter, Ui};
use crate::values::parse_size;

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

/// Runs `shlight irradiance`.
pub fn run(args: &IrradianceArgs, ui: &Ui) -> Result<()> {
    let plan = IrradianceRequest {
        input: &args.input,
        output: Some(&args.output),
        size: args.size,
        sh: args.sh,
        encoding: args.encoding,
        error_map: args.error_map.as_deref(),
        read: args.map.read_settings(),
        orientation: args.map.orientation(),
    }
    .check(Spelling::CommandLine)?;
    let reporter = Reporter::new(ui);
    let (_, summary) = irradiance(&plan, &reporter)?;
    reporter.finish();
    print!("{summary}");
    Ok(())
}
