//! `shlight dfg`: the DFG (split-sum BRDF) table an engine reads beside its
//! prefiltered environment (shlight-specular's `DfgTable`, written by
//! shlight-pipeline's `write_dfg`).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use shlight_pipeline::write_dfg;
use shlight_specular::{DfgForm, DfgTable, Engine};

use crate::progress::Ui;

/// Arguments of `shlight dfg`.
#[derive(Args, Debug)]
pub struct DfgArgs {
    /// The table to write: .exr (float) or .png (8-bit values, not sRGB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The engine whose form to write: filament (multiscatter: bias, scale +
    /// bias), the others Karis' scale and bias.
    #[arg(long = "for", default_value = "filament", value_parser = crate::values::engine())]
    pub engine: Engine,
    /// Texels per side.
    #[arg(long, default_value_t = DfgTable::DEFAULT_SIZE)]
    pub size: usize,
    /// Samples per texel.
    #[arg(long, default_value_t = DfgTable::DEFAULT_SAMPLES)]
    pub samples: u32,
}

/// Runs `shlight dfg`.
pub fn run(args: &DfgArgs, ui: &Ui) -> Result<()> {
    if args.size == 0 || args.size > 4096 {
        bail!("--size {} must be from 1 to 4096", args.size);
    }
    if args.samples == 0 {
        bail!("--samples must be at least 1");
    }
    let spinner = ui.spinner("DFG table");
    let table = DfgTable::for_engine(args.engine, args.size, args.samples);
    spinner.finish_and_clear();
    write_dfg(&table, &args.output)?;
    ui.note(match table.form {
        DfgForm::Multiscatter => "red: bias of F0 (B), green: scale + bias (A + B); x = n.v, y = perceptual roughness (top row 1)",
        DfgForm::ScaleBias => "red: scale of F0 (A), green: bias (B); x = n.v, y = perceptual roughness (top row 1)",
    });
    Ok(())
}
