//! `shlight accuracy`: the accuracy suite on demand (`shlight_accuracy`).
//!
//! Prints one row per case (oracle, method, resolution or samples, lmax,
//! mean / max relative irradiance error, bound, fitted slope, pass) as a
//! table, or with `--json` as a JSON array; `-o DIR` also writes the
//! pictures. The exit status is non-zero when any row fails. `--legendre`
//! prints the Legendre study instead (Rodrigues against the recurrence).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use shlight_accuracy::legendre_study::{DEGREES, legendre_study, legendre_table};
use shlight_accuracy::report_table::report_table;
use shlight_accuracy::suite::{self, Row, SuiteOptions};

use crate::progress::Ui;

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
    if args.legendre {
        let rows = legendre_study(&DEGREES);
        print!("{}", legendre_table(&rows));
        return Ok(());
    }
    if let Some(dir) = &args.output {
        if dir.exists() && !dir.is_dir() {
            bail!("{}: exists and is not a directory", dir.display());
        }
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
    }
    let bar = ui.spinner("accuracy suite");
    let report = suite::run(SuiteOptions { quick: args.quick }, &|what| {
        bar.set_message(what.to_string());
    });
    if let Some(dir) = &args.output {
        bar.set_message("pictures");
        for path in shlight_accuracy::plot::write_pictures(&report, dir)? {
            ui.note(format!("wrote {}", path.display()));
        }
    }
    bar.finish_and_clear();
    if args.json {
        let rows: Vec<serde_json::Value> = report.rows.iter().map(Row::to_json).collect();
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        print!("{}", report_table(&report));
    }
    let failed = report.rows.iter().filter(|r| !r.pass).count();
    if failed > 0 {
        bail!("{failed} of {} accuracy rows failed", report.rows.len());
    }
    Ok(())
}
