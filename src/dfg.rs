//! `shlight dfg`: the DFG (split-sum BRDF) table an engine reads beside its
//! prefiltered environment, by shlight-pipeline's `dfg` job.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use shlight_pipeline::{DfgRequest, Spelling, dfg};
use shlight_specular::{DfgTable, TargetEngine};

use crate::progress::{Reporter, Ui};

/// Arguments of `shlight dfg`.
#[derive(Args, Debug)]
pub struct DfgArgs {
    /// The table to write: .exr (float) or .png (8-bit values, not sRGB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The engine whose form to write: filament (multiscatter: bias, scale +
    /// bias), the others Karis' scale and bias.
    #[arg(long = "for", default_value = "filament", value_parser = crate::values::engine())]
    pub engine: TargetEngine,
    /// Texels per side.
    #[arg(long, default_value_t = DfgTable::DEFAULT_SIZE)]
    pub size: usize,
    /// Samples per texel.
    #[arg(long, default_value_t = DfgTable::DEFAULT_SAMPLES)]
    pub samples: u32,
}

/// Runs `shlight dfg`.
pub fn run(args: &DfgArgs, ui: &Ui) -> Result<()> {
    let plan = DfgRequest {
        engine: args.engine,
        size: args.size,
        samples: args.samples,
    }
    .check(Spelling::CommandLine)?;
    dfg(&args.output, &plan, &Reporter::new(ui))?;
    Ok(())
}
