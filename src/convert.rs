//! `shlight convert`: coefficient files to engine formats and back.

use anyhow::Result;
use clap::Args;

/// Arguments of `shlight convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input file.
    pub input: std::path::PathBuf,
}

/// Runs `shlight convert`.
pub fn run(_args: &ConvertArgs) -> Result<()> {
    anyhow::bail!("not written yet")
}
