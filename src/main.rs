//! `shlight`: spherical-harmonics lighting from the command line.
//!
//! The binary parses arguments, calls the library crates and maps errors to
//! messages and exit codes; all mathematics lives in `shlight-core`, image
//! files in `shlight-io`, and shlight's own files and engine formats in
//! `shlight-format`.

mod accuracy;
#[cfg(feature = "gpu")]
mod bundled;
mod compare;
mod convert;
mod dfg;
#[cfg(not(feature = "gpu"))]
mod gpu_feature;
mod heap;
mod input;
mod irradiance;
mod lightmap;
mod prefilter;
mod progress;
mod project;
mod prt;
mod render;
mod render_mesh;
#[cfg(feature = "gpu")]
mod runtime_dir;
mod sample;
mod synth;
mod values;
mod view;
mod volume;
mod volume_shading;

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
    /// Irradiance of an environment map by brute force (every texel), and
    /// its SH version with --sh.
    Irradiance(irradiance::IrradianceArgs),
    /// Every encoding (SH, dominant lights + SH, ZH3, non-linear L1, ambient
    /// cube) of maps against their exact irradiance: table, JSON, plots.
    Compare(compare::CompareArgs),
    /// Accuracy of SH irradiance against analytic lights: table, JSON, pictures.
    Accuracy(accuracy::AccuracyArgs),
    /// Render a mesh lit by SH coefficients on the GPU, without a window.
    RenderMesh(render_mesh::RenderMeshArgs),
    /// Show a mesh lit by SH coefficients in a window (GPU).
    View(view::ViewArgs),
    /// Bake precomputed radiance transfer (PRT) for a mesh.
    Prt(prt::PrtArgs),
    /// Bake an irradiance volume: relightable SH probes on a grid through a scene.
    Volume(volume::VolumeArgs),
    /// Bake a glTF scene's lightmap on its second UV set (irradiance, L1
    /// SH or MonoSH) for three.js, Bevy, Godot or Unity.
    Lightmap(lightmap::LightmapArgs),
    /// What a baked file shades with: a volume's irradiance at points, a
    /// PRT file's exit radiance per vertex.
    Sample(sample::SampleArgs),
    /// GGX-prefilter an environment map into cube mips for an engine's
    /// specular lighting (cmgen's --ibl-ld files).
    Prefilter(prefilter::PrefilterArgs),
    /// Write the DFG (split-sum BRDF) table an engine reads.
    Dfg(dfg::DfgArgs),
    /// Print any file shlight writes as a readable table: a coefficient
    /// file's coefficients; any other file's header (what it holds, lmax,
    /// grid, provenance).
    Show {
        /// A file shlight writes: a coefficient file; an engine export of a
        /// light (three.js, Unity, Filament, glTF/GLB, txt) or a code
        /// snippet; a .shprt or .shvol file, a volume's JSON, three.js or
        /// Bevy export; a PRT glTF/GLB; a KTX2 or KTX texture; `sample`'s
        /// answer or points (JSON, CSV); an image (its size and channels).
        /// The kind is read from the content, not the extension.
        file: std::path::PathBuf,
    },
}

/// `shlight show FILE`: any file shlight writes as a readable table
/// (shlight-format's `describe`).
fn show(path: &std::path::Path) -> anyhow::Result<()> {
    print!("{}", shlight_format::describe(path)?.to_table());
    Ok(())
}

/// Runs one command.
fn run(command: Command, ui: &progress::Ui) -> anyhow::Result<()> {
    match command {
        Command::Project(args) => project::run(&args, ui),
        Command::Render(args) => render::run(&args, ui),
        Command::Synth(args) => synth::run(&args, ui),
        Command::Show { file } => show(&file),
        Command::Convert(args) => convert::run(&args, ui),
        Command::Irradiance(args) => irradiance::run(&args, ui),
        Command::Accuracy(args) => accuracy::run(&args, ui),
        Command::Compare(args) => compare::run(&args, ui),
        Command::RenderMesh(args) => render_mesh::run(&args, ui),
        Command::View(args) => view::run(&args, ui),
        Command::Prt(args) => prt::run(&args, ui),
        Command::Volume(args) => volume::run(&args, ui),
        Command::Lightmap(args) => lightmap::run(&args, ui),
        Command::Sample(args) => sample::run(&args, ui),
        Command::Prefilter(args) => prefilter::run(&args, ui),
        Command::Dfg(args) => dfg::run(&args, ui),
    }
}

/// Large buffers on huge pages (see heap.rs).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[global_allocator]
static HEAP: heap::Heap = heap::Heap;

/// Output piped into a reader that stops early (`shlight show F | head`)
/// ends the process quietly, as other command-line tools do, instead of a
/// panic in `print!`: the default action of `SIGPIPE`, which Rust's runtime
/// sets to ignored.
fn default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: sets a signal's disposition to its default before any thread
    // exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    default_sigpipe();
    heap::keep_freed_memory();
    let cli = Cli::parse();
    let ui = progress::Ui::new(cli.quiet);
    // Only the GPU commands load the Vulkan stack (see runtime_dir.rs).
    #[cfg(feature = "gpu")]
    let _runtime_dir = match &cli.command {
        Command::RenderMesh(_) | Command::View(_) => runtime_dir::ensure_runtime_dir(),
        Command::Project(args) if args.gpu => runtime_dir::ensure_runtime_dir(),
        _ => None,
    };
    match run(cli.command, &ui) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
