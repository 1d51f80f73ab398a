//! `shlight`: spherical-harmonics lighting from the command line.
//!
//! The binary parses arguments, calls the library crates and maps errors to
//! messages and exit codes; all mathematics lives in `shlight-core` and all
//! file formats in `shlight-io`.

mod coeff_file;
mod convert;
mod export;
mod preview;
mod progress;
mod project;
mod prt;
mod render;
mod synth;
mod texels;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Spherical-harmonics lighting: HDR environment maps to SH coefficients.
#[derive(Parser, Debug)]
#[command(name = "shlight", version, about, long_about = None)]
struct Cli {
    /// No progress bars, warnings or notes on stderr (errors are still printed).
    #[arg(short, long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Project environment maps to SH coefficients.
    Project(project::ProjectArgs),
    /// Render a coefficient file to an image (radiance or irradiance).
    Render(render::RenderArgs),
    /// Write an analytic environment map (constant, hemisphere, cap, gradient, sun).
    Synth(synth::SynthArgs),
    /// Convert a coefficient file to an engine's format, or back.
    Convert(convert::ConvertArgs),
    /// Bake precomputed radiance transfer (PRT) for a mesh.
    Prt(prt::PrtArgs),
    /// Print a coefficient file (JSON) as a readable table.
    Show {
        /// A file written by `shlight project -o FILE.json`.
        file: std::path::PathBuf,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let ui = progress::Ui::new(cli.quiet);
    let result = match cli.command {
        Command::Project(args) => project::run(&args, &ui),
        Command::Render(args) => render::run(&args, &ui),
        Command::Synth(args) => synth::run(&args, &ui),
        Command::Show { file } => coeff_file::show(&file),
        Command::Convert(args) => convert::run(&args),
        Command::Prt(args) => prt::run(&args, &ui),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
