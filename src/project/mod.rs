//! `shlight project`: environment maps in, SH coefficients out.
//!
//! One input goes to `-o FILE` (or stdout); several go to `-o DIR`, one
//! file per input, processed in parallel. Each input runs the same steps:
//! [`load`] (read, check, `--sanitize`), [`project_map`] (layout and method),
//! the window (per channel), `--preview`, then `--rotate` and the quantity
//! ([`shlight_pipeline::coefficient_file`]), and [`write_output`] (the one place that knows output formats: shlight's
//! JSON, or any exporter of `shlight_format`).
//!
//! Files: `args.rs` (the arguments), `settings.rs` (what the arguments
//! decide before any input is read), `plan.rs` (the batch: one job per
//! input), `projection.rs` (the projection step), `write.rs` (the output);
//! inputs are read by [`crate::input`].

mod args;
mod plan;
mod projection;
mod settings;
mod write;

use anyhow::{Context, Result, bail};
use indicatif::ProgressBar;
use rayon::prelude::*;
use shlight_core::sh::apply_channel_windows;
use shlight_pipeline::{MapInfo, choose_windows, coefficient_file, write_preview};

use crate::input::{is_faces, load};
use crate::progress::Ui;

pub use args::ProjectArgs;
use plan::{Job, plan};
use projection::project_map;
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

/// Projects one input and writes its results.
fn process(job: &Job, s: &Settings<'_>, ui: &Ui, bar: &ProgressBar) -> Result<()> {
    let args = s.args;
    let name = job.input.display().to_string();
    bar.set_message(format!("reading {name}"));
    let (image, layout, stats, sanitized) =
        load(&job.input, s.args.layout, &s.read, s.args.sanitize, ui)?;

    bar.set_message(format!(
        "projecting {name} ({}x{}, lmax {})",
        image.width(),
        image.height(),
        args.lmax
    ));
    let projection =
        project_map(&image, layout, s).with_context(|| format!("{name}: projecting"))?;

    if s.project.window.is_none() {
        bar.set_message(format!("choosing windows for {name}"));
    }
    let windows = choose_windows(&projection.coeffs, &s.project, &name)?;

    if let Some(path) = &job.preview {
        bar.set_message(format!("preview of {name}"));
        let radiance = apply_channel_windows(&windows, &projection.coeffs);
        write_preview(path, &image, layout, &radiance, s.orientation, &s.preview)
            .with_context(|| format!("{name}: preview"))?;
    }

    let info = MapInfo {
        name: name.clone(),
        width: image.width(),
        height: image.height(),
        layout: if is_faces(&job.input) {
            "faces".into()
        } else {
            layout.name().into()
        },
        stats,
        sanitized,
    };
    let mut file = coefficient_file(&projection, windows, &s.project, &info);
    if args.encoding != shlight_core::encoding::Encoding::Sh {
        bar.set_message(format!("encoding {name} as {}", args.encoding));
        let map = shlight_core::map::EnvMap::new(
            layout,
            s.orientation,
            image.width(),
            image.height(),
            image.pixels(),
        )
        .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        shlight_pipeline::encode_file(&mut file, &map, args.encoding, args.lmax);
    }
    if job.output == Dest::Stdout {
        // Nothing may draw on the terminal while the result is printed.
        bar.finish_and_clear();
    } else {
        bar.set_message(format!("writing {name}"));
    }
    write_output(&file, args.format, &job.output, ui)
}
