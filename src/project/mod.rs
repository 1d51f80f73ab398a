//! `shlight project`: environment maps in, SH coefficients out.
//!
//! One input goes to `-o FILE` (or stdout); several go to `-o DIR`, one
//! file per input, processed in parallel. Each input runs the same steps:
//! [`load`] (read, check, `--sanitize`), [`project_map`] (layout and method),
//! the window (per channel), `--preview`, `--rotate`, the quantity, and
//! [`write_output`] (the one place that knows output formats: shlight's
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
use shlight_core::auto_window::WindowTarget;
use shlight_core::channel_windows::{apply_channel_windows, auto_windows};
use shlight_core::layout::Layout;
use shlight_core::rotation::rotate_once;
use shlight_core::std_error_rotation::rotate_std_error;
use shlight_core::window::WindowFamily;
use shlight_core::zonal::clamped_cosine_eigenvalue;
use shlight_core::{ShRotation, irradiance};
use shlight_format::{CoeffFile, Provenance, Quantity};

use crate::input::{is_faces, load};
use crate::preview::{equirect_panel, write_preview};
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

    let target = match args.quantity {
        Quantity::Radiance => WindowTarget::Function,
        Quantity::Irradiance => WindowTarget::Irradiance,
    };
    if s.window.is_none() {
        bar.set_message(format!("choosing windows for {name}"));
    }
    let windows = match s.window {
        Some(w) => [w; 3],
        None => auto_windows(&projection.coeffs, WindowFamily::Hanning, target)
            .with_context(|| format!("{name}: --window auto"))?,
    };
    let mut radiance = apply_channel_windows(&windows, &projection.coeffs);

    if let Some(path) = &job.preview {
        bar.set_message(format!("preview of {name}"));
        let equirect = match layout {
            Layout::Equirect => None,
            other => Some(equirect_panel(
                &image,
                other,
                s.orientation,
                s.preview.panel,
            )?),
        };
        let shown = equirect.as_ref().unwrap_or(&image);
        write_preview(path, shown, &radiance, s.orientation, &s.preview)
            .with_context(|| format!("{name}: preview"))?;
    }

    // Window factors lie in [0, 1], so errors scale by them as they are.
    let mut std_error = projection
        .std_error
        .map(|se| apply_channel_windows(&windows, &se));
    if let Some((_, matrix)) = &s.rotation {
        radiance = rotate_once(&radiance, *matrix);
        std_error =
            std_error.map(|se| rotate_std_error(&ShRotation::from_mat3(se.lmax(), *matrix), &se));
    }
    let coeffs = match args.quantity {
        Quantity::Radiance => radiance,
        Quantity::Irradiance => {
            std_error =
                std_error.map(|se| se.scaled_per_band(|l| clamped_cosine_eigenvalue(l).abs()));
            irradiance(&radiance)
        }
    };

    let mut file = CoeffFile::new(coeffs, s.orientation.frame, args.quantity);
    file.mirror = s.orientation.mirror;
    file.provenance = Provenance {
        input: name.clone(),
        width: image.width(),
        height: image.height(),
        layout: if is_faces(&job.input) {
            "faces".into()
        } else {
            layout.name().into()
        },
        method: args.method.name().into(),
        window: match s.window {
            Some(w) => w.to_string(),
            None => "auto".into(),
        },
        windows: windows.map(|w| w.to_string()),
        samples: projection.samples,
        seed: projection.seed,
        sampler: projection.sampler,
        rotate: s.rotation.as_ref().map(|(r, _)| r.clone()),
    };
    file.input_negative_texels = stats.negative;
    file.input_min_value = f64::from(stats.min_value);
    file.sanitized = sanitized;
    file.std_error = std_error;
    if args.encoding != shlight_core::Encoding::Sh {
        bar.set_message(format!("encoding {name} as {}", args.encoding));
        let map = shlight_core::layout::EnvMap::new(
            layout,
            s.orientation,
            image.width(),
            image.height(),
            image.pixels(),
        )
        .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        let encoded = shlight_core::encode_map(
            &map,
            args.encoding,
            args.lmax,
            &shlight_core::DominantLightOptions::default(),
        );
        let (encoding, coeffs) =
            shlight_format::FileEncoding::from_encoded(args.encoding, &encoded, &file.coeffs);
        file.coeffs = coeffs;
        file.encoding = encoding;
    }
    if job.output == Dest::Stdout {
        // Nothing may draw on the terminal while the result is printed.
        bar.finish_and_clear();
    } else {
        bar.set_message(format!("writing {name}"));
    }
    write_output(&file, args.format, &job.output, ui)
}
