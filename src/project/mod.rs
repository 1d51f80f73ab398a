//! `shlight project`: environment maps in, SH coefficients out.
//!
//! One input goes to `-o FILE` (or stdout); several go to `-o DIR`, one
//! file per input, processed in parallel. Each input is one call of
//! [`shlight_pipeline::project`] (read, check, project, window, preview,
//! rotate, quantity, encoding: the pipeline sequences every step), with
//! the GPU's projector for `--gpu`, then [`write_output`] (the one place
//! that knows output formats: shlight's JSON, or any exporter of
//! `shlight_format`).
//!
//! Files: `args.rs` (the arguments), `settings.rs` (what the arguments
//! decide before any input is read), `plan.rs` (the batch: one job per
//! input), `gpu.rs` (`--gpu`'s projector), `write.rs` (the output).

mod args;
#[cfg(feature = "gpu")]
mod gpu;
mod plan;
mod settings;
mod write;

use anyhow::{Result, bail};
use indicatif::ProgressBar;
use rayon::prelude::*;
use shlight_format::ExportFormat;
use shlight_pipeline::{Hooks, Preview, Source, project};

use crate::progress::Ui;

pub use args::ProjectArgs;
use plan::{Job, plan};
use settings::Settings;
use write::{Dest, write_output};

/// Runs `shlight project`.
pub fn run(args: &ProjectArgs, ui: &Ui) -> Result<()> {
    let settings = Settings::new(args)?;
    let jobs = plan(args)?;
    if let [job] = jobs.as_slice() {
        let bar = ui.spinner("starting");
        let result = process(job, &settings, ui, &bar);
        bar.finish_and_clear();
        return result;
    }
    let bar = ui.bar(jobs.len() as u64, "projecting");
    let failed: usize = jobs
        .par_iter()
        .map(|job| {
            let result = process(job, &settings, ui, &ProgressBar::hidden());
            bar.inc(1);
            match result {
                Ok(()) => 0,
                Err(e) => {
                    let msg = format!("{e:#}");
                    let input = job.input.display().to_string();
                    if msg.contains(&input) {
                        ui.error(msg);
                    } else {
                        ui.error(format!("{input}: {msg}"));
                    }
                    1
                }
            }
        })
        .sum();
    bar.finish_and_clear();
    if failed > 0 {
        bail!("{failed} of {} inputs failed", jobs.len());
    }
    Ok(())
}

/// Projects one input ([`shlight_pipeline::project`]) and writes its
/// results.
fn process(job: &Job, s: &Settings<'_>, ui: &Ui, bar: &ProgressBar) -> Result<()> {
    let settings = shlight_pipeline::Settings {
        preview: job.preview.clone().map(|path| Preview {
            path,
            options: s.preview,
        }),
        ..s.pipeline.clone()
    };
    let progress = |m: &str| bar.set_message(m.to_string());
    let warn = |w: &str| ui.warn(w);
    let hooks = Hooks {
        projector: s.projector(),
        progress: &progress,
        warn: &warn,
    };
    let file = project(Source::Path(&job.input), &settings, &hooks)?;
    if job.output == Dest::Stdout {
        // Nothing may draw on the terminal while the result is printed.
        bar.finish_and_clear();
    } else {
        bar.set_message(format!("writing {}", job.input.display()));
    }
    let specular = if s.args.format == Some(ExportFormat::Gltf) {
        bar.set_message(format!("specular images of {}", job.input.display()));
        Some(shlight_pipeline::gltf_specular_images(
            &job.input,
            &s.pipeline.read,
            s.pipeline.project.orientation,
            s.pipeline.project.rotation.as_ref().map(|(_, m)| *m),
            s.args.specular_size,
            s.args.specular_samples,
            &|_| {},
        )?)
    } else {
        None
    };
    write_output(&file, s.args.format, specular.as_ref(), &job.output, ui)
}
