//! `shlight`: spherical-harmonics lighting from the command line.
//!
//! The binary parses arguments, calls the library crates and maps errors to
//! messages and exit codes; all mathematics lives in `shlight-core` and all
//! file formats in `shlight-io`.

mod coeff_file;
mod convert;
mod export;
mod project;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Spherical-harmonics lighting: HDR environment maps to SH coefficients.
#[derive(Parser, Debug)]
#[command(name = "shlight", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Project an environment map to SH coefficients.
    Project(project::ProjectArgs),
    /// Convert a coefficient file to an engine's format, or back.
    Convert(convert::ConvertArgs),
    /// Print a coefficient file (JSON) as a readable table.
    Show {
        /// A file written by `shlight project -o FILE.json`.
        file: std::path::PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Project(args) => project::run(&args),
        Command::Show { file } => coeff_file::show(&file),
        Command::Convert(args) => convert::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
