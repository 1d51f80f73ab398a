//! `shlight compare`: every encoding on every map against the map's exact
//! irradiance (shlight-pipeline's `compare_encodings`, on
//! `shlight_accuracy::compare`): the table on stdout; with
//! `-o DIR`, `compare.json` and one plot of error against floats stored
//! per map (`compare-MAP.svg`).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use shlight_accuracy::compare::{self, CompareRow};
use shlight_core::map::MapOrientation;
use shlight_io::ReadOptions;
use shlight_pipeline::{ReadSettings, compare_encodings, compare_name};

use crate::input::{InputLayout, parse_input_layout};
use crate::progress::Ui;
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
    if let Some(dir) = &args.output {
        if dir.exists() && !dir.is_dir() {
            bail!("{}: exists and is not a directory", dir.display());
        }
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
    }
    let orientation = MapOrientation {
        frame: crate::input::frame_of(&args.up),
        mirror: false,
    };
    let read = ReadSettings {
        layout: args.layout,
        read: ReadOptions::default(),
        sanitize: args.sanitize,
    };
    let mut rows: Vec<CompareRow> = Vec::new();
    let mut names = Vec::new();
    for input in &args.inputs {
        let name = compare_name(input);
        let bar = ui.spinner(&format!("comparing {name}"));
        rows.extend(compare_encodings(
            input,
            &read,
            orientation,
            args.normals,
            &|m| ui.warn(m),
        )?);
        bar.finish_and_clear();
        names.push(name);
    }
    print!("{}", compare::table(&rows));
    if let Some(dir) = &args.output {
        let json = dir.join("compare.json");
        let text = serde_json::to_string_pretty(&compare::rows_json(&rows))? + "\n";
        shlight_io::write_atomically(&json, |w| w.write_all(text.as_bytes()))?;
        ui.note(format!("wrote {}", json.display()));
        for name in &names {
            let svg = compare::floats_plot(name, &rows)?;
            let path = dir.join(format!("compare-{name}.svg"));
            shlight_accuracy::plot::write_svg(&path, &svg)?;
            ui.note(format!("wrote {}", path.display()));
        }
    }
    Ok(())
}
