//! `shlight accuracy`: the accuracy suite on demand (`shlight_accuracy`).
//!
//! Prints one row per case (oracle, method, resolution or samples, lmax,
//! mean / max relative irradiance error, bound, fitted slope, pass) as a
//! table, or with `--json` as a JSON array; `-o DIR` also writes the
//! pictures. The exit status is non-zero when any row fails.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use shlight_accuracy::suite::{self, Report, Row, SuiteOptions};

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
}

/// Runs `shlight accuracy`.
pub fn run(args: &AccuracyArgs, ui: &Ui) -> Result<()> {
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
        print!("{}", table(&report));
    }
    let failed = report.rows.iter().filter(|r| !r.pass).count();
    if failed > 0 {
        bail!("{failed} of {} accuracy rows failed", report.rows.len());
    }
    Ok(())
}

/// A number in a short scientific form, or `-`.
fn sci(v: Option<f64>) -> String {
    v.map_or_else(|| "-".into(), |v| format!("{v:.2e}"))
}

/// The report as a plain-text table with a legend.
pub fn table(report: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<13} {:<20} {:>10} {:>4} {:>9} {:>9} {:>9} {:>6}  pass",
        "case", "method", "res/N", "lmax", "mean", "max", "bound", "slope"
    );
    for r in &report.rows {
        let _ = writeln!(
            out,
            "{:<13} {:<20} {:>10} {:>4} {:>9} {:>9} {:>9} {:>6}  {}",
            r.case,
            r.method,
            r.setting(),
            r.lmax,
            sci(Some(r.mean_rel_err)),
            sci(Some(r.max_rel_err)),
            sci(r.bound),
            r.slope.map_or_else(|| "-".into(), |s| format!("{s:.2}")),
            if r.pass { "pass" } else { "FAIL" }
        );
    }
    let passed = report.rows.iter().filter(|r| r.pass).count();
    let _ = writeln!(
        out,
        "\n{passed} of {} rows pass. Errors are |E_est(n) - E_ref(n)| / max E over {} \
         Fibonacci normals:\ntruncation against the closed-form E; quadrature and mc-* \
         against the SH irradiance truncated at the same lmax.\nslope: fitted to the RMS \
         error against map width or samples (accepted: smooth / edges {:?} / {:?}, \
         mc uniform, importance {:?}, stratified, sobol {:?}).",
        report.rows.len(),
        suite::NORMALS,
        suite::SMOOTH_RATE,
        suite::EDGE_RATE,
        suite::IID_RATE,
        suite::QMC_RATE,
    );
    out
}
