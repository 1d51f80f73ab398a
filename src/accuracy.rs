//! `shlight accuracy`: the accuracy suite on demand (`shlight_accuracy`).
//!
//! Prints one row per case (oracle, method, resolution or samples, lmax,
//! mean / max relative irradiance error, bound, fitted slope, pass) as a
//! table, or with `--json` as a JSON array; `-o DIR` also writes the
//! pictures. The exit status is non-zero when any row fails. `--legendre`
//! prints the Legendre study instead (Rodrigues against the recurrence).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use shlight_pipeline::{AccuracyRequest, accuracy};

use crate::progress::{Reporter, Ui};

/// Arguments of `shlight accuracy`.
#[derive(Args, Debug)]
pub struct AccuracyArgs {
    /// A subset that runs in a few seconds (resolutions to 512x256, cube
    /// faces to 64, Monte Carlo to 2^16 samples, lmax to 4).
    #[arg(long)]
    pub quick: bool,
    /// Write the rows as a JSON array instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Directory for the pictures (created): error-vs-samples and
    /// error-vs-lmax plots (SVG), error maps over the sphere (PNG).
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Instead of the suite: Legendre polynomials by Rodrigues' formula
    /// against the recurrence shlight uses, degrees 1 to 2800, and the
    /// addition theorem's check near a pole.
    #[arg(long, conflicts_with_all = ["quick", "json", "output"])]
    pub legendre: bool,
}

/// Runs `shlight accuracy`.
pub fn run(args: &AccuracyArgs, ui: &Ui) -> Result<()> {
    let request = AccuracyRequest {
        quick: args.quick,
        json: args.json,
        output: args.output.as_deref(),
        legendre: args.legendre,
    };
    let reporter = Reporter::new(ui);
    let outcome = accuracy(&request, &reporter)?;
    reporter.finish();
    print!("{}", outcome.text);
    if outcome.failed > 0 {
        bail!(
            "{} of {} accuracy rows failed",
            outcome.failed,
            outcome.rows
        );
    }
    Ok(())
}
