//! `shlight compare`: every encoding on every map against the map's exact
//! irradiance (shlight-pipeline's `compare_encodings`, on
//! `shlight_accuracy::compare`): the table on stdout; with
//! `-o DIR`, `compare.json` and one plot of error against floats stored
//! per map (`compare-MAP.svg`).

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use shlight_core::map::MapOrientation;
use shlight_io::ReadOptions;
use shlight_pipeline::{CompareRequest, ReadSettings, Spelling, compare};

use crate::input::{InputLayout, parse_input_layout};
use crate::progress::{Reporter, Ui};
use crate::values::parse_size;

/// Arguments of `shlight compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The environment maps (any layout `shlight project` reads).
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Directory (created) for compare.json and the plots.
    #[arg(short, long, value_name = "DIR")]
    pub output: Option<PathBuf>,
    /// Normals the errors are measured at: an equirect grid WIDTHxHEIGHT.
    #[arg(long, default_value = "128x64", value_parser = parse_size)]
    pub normals: (usize, usize),
    /// Layout of the inputs: auto, equirect, cross-h, cross-v, strip,
    /// angular, mirror-ball, faces.
    #[arg(long, default_value = "auto", value_parser = parse_input_layout)]
    pub layout: InputLayout,
    /// Which world axis the top row of the maps faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// Replace NaN/inf and negative texels (as `shlight project --sanitize`).
    #[arg(long)]
    pub sanitize: bool,
}

/// Runs `shlight compare`.
pub fn run(args: &CompareArgs, ui: &Ui) -> Result<()> {
    let plan = CompareRequest {
        inputs: &args.inputs,
        output: args.output.as_deref(),
        normals: args.normals,
        read: ReadSettings {
            layout: args.layout,
            read: ReadOptions::default(),
            sanitize: args.sanitize,
            spelling: Spelling::CommandLine,
        },
        orientation: MapOrientation {
            frame: crate::input::frame_of(&args.up),
            mirror: false,
        },
    }
    .check(Spelling::CommandLine)?;
    let reporter = Reporter::new(ui);
    let (_, table) = compare(&plan, &reporter)?;
    reporter.finish();
    print!("{table}");
    Ok(())
}
