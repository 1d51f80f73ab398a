//! Exporters: shlight coefficients to the formats engines and shaders read.

use anyhow::Result;
use clap::ValueEnum;
use glam::DVec3;
use shlight_core::ShCoeffs;
use shlight_core::rotation::Frame;

use crate::coeff_file::Quantity;

/// What an exporter needs to know about the coefficients it writes.
#[derive(Clone, Debug)]
pub struct ExportInput<'a> {
    /// shlight basis (CS phase included), linear Rec.709 RGB.
    pub coeffs: &'a ShCoeffs<DVec3>,
    /// What the coefficients hold.
    pub quantity: Quantity,
    /// Frame the coefficients are in.
    pub frame: Frame,
}

/// Target formats of `--format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ExportFormat {
    /// shlight's self-describing JSON coefficient file.
    Json,
    /// A readable table, one coefficient per line.
    Txt,
}

/// Renders `input` in `format` (not `Json`, which the coefficient file writes).
pub fn export(_input: &ExportInput<'_>, format: ExportFormat) -> Result<String> {
    anyhow::bail!("exporter {format:?} not written yet")
}
