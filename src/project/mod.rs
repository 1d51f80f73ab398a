//! `shlight project`: environment maps in, SH coefficients out, by
//! shlight-pipeline's `project_files` job (one file per input, in
//! parallel), with the GPU's projector for `--gpu`.
//!
//! Files: `args.rs` (the arguments), `gpu.rs` (`--gpu`'s projector).

mod args;
#[cfg(feature = "gpu")]
mod gpu;

use std::io::{IsTerminal, Write};

use anyhow::{Context, Result, bail};
use shlight_core::map::MapOrientation;
use shlight_io::ReadOptions;
use shlight_pipeline::{
    CpuProjector, PreviewOptions, ProjectOptions, ProjectRequest, Projected, Projector,
    ReadSettings, Spelling, StdoutForm, project_files,
};

use crate::progress::{Reporter, Ui};

use args::Method;
pub use args::ProjectArgs;

/// Runs `shlight project`.
pub fn run(args: &ProjectArgs, ui: &Ui) -> Result<()> {
    let plan = request(args).check(Spelling::CommandLine)?;
    #[cfg(not(feature = "gpu"))]
    if args.gpu {
        return Err(crate::gpu_feature::needs_gpu("project --gpu"));
    }
    #[cfg(feature = "gpu")]
    let gpu = args.gpu.then(gpu::GpuProjection::new).transpose()?;
    #[cfg(feature = "gpu")]
    let projector: &dyn Projector = gpu.as_ref().map_or(&CpuProjector, |g| g);
    #[cfg(not(feature = "gpu"))]
    let projector: &dyn Projector = &CpuProjector;
    let reporter = Reporter::new(ui);
    let results = project_files(&plan, projector, &reporter)?;
    reporter.finish();
    report(results, ui)
}

/// One input's error as the command's, its text on stdout; several
/// inputs' errors each on its line, then a count.
fn report(results: Vec<shlight_pipeline::Result<Projected>>, ui: &Ui) -> Result<()> {
    let total = results.len();
    if let [result] = results.as_slice() {
        if let Some(text) = &result.as_ref().map_err(Clone::clone)?.stdout {
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(text.as_bytes())
                .and_then(|()| stdout.flush())
                .context("writing to stdout")?;
        }
        return Ok(());
    }
    let failed: Vec<_> = results.into_iter().filter_map(Result::err).collect();
    failed.iter().for_each(|e| ui.error(e));
    if !failed.is_empty() {
        bail!("{} of {total} inputs failed", failed.len());
    }
    Ok(())
}

/// The job's request from the arguments.
fn request(args: &ProjectArgs) -> ProjectRequest<'_> {
    ProjectRequest {
        options: ProjectOptions {
            read: ReadSettings {
                layout: args.layout,
                read: ReadOptions {
                    layer: args.layer.clone(),
                    max_pixels: args.max_pixels,
                },
                sanitize: args.sanitize,
                spelling: Spelling::CommandLine,
            },
            lmax: args.lmax,
            orientation: MapOrientation {
                frame: crate::input::frame_of(&args.up),
                mirror: args.mirror,
            },
            monte_carlo: args.method == Method::MonteCarlo,
            samples: args.samples,
            sampler: args.sampler,
            seed: args.seed,
            window: &args.window,
            rotate: args.rotate.as_deref(),
            quantity: args.quantity,
            encoding: args.encoding,
            gpu: args.gpu,
            format: args.format,
        },
        inputs: &args.inputs,
        output: args.output.as_deref(),
        preview: args.preview.as_deref(),
        preview_options: PreviewOptions {
            panel: args.preview_size,
            exposure: args.preview_exposure,
            tone_map: args.preview_tone_map,
        },
        specular_size: args.specular_size,
        specular_samples: args.specular_samples,
        stdout: if std::io::stdout().is_terminal() {
            StdoutForm::Table
        } else {
            StdoutForm::Json
        },
    }
}
