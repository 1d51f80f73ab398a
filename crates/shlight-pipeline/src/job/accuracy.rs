//! `accuracy`: the accuracy suite of SH irradiance against analytic lights
//! (shlight-accuracy's `suite`), its table or JSON rows and its pictures;
//! or the Legendre study ([`AccuracyRequest`] → [`accuracy`]).

use std::path::Path;

use shlight_accuracy::legendre_study::{DEGREES, legendre_study, legendre_table};
use shlight_accuracy::report_table::report_table;
use shlight_accuracy::suite::{self, Row, SuiteOptions};

use crate::hooks::{Hooks, Progress};
use crate::{PipelineError, Result};

/// What `accuracy` runs and writes.
#[derive(Clone, Copy, Debug, Default)]
pub struct AccuracyRequest<'a> {
    /// The quick subset.
    pub quick: bool,
    /// The rows as a JSON array instead of the table.
    pub json: bool,
    /// A directory (made) for the pictures.
    pub output: Option<&'a Path>,
    /// The Legendre study instead of the suite.
    pub legendre: bool,
}

/// What `accuracy` found: the text for standard output, and how many of
/// how many rows failed.
#[derive(Clone, Debug)]
pub struct AccuracyOutcome {
    /// The table, the JSON rows, or the Legendre study's table.
    pub text: String,
    /// Rows that failed their bound.
    pub failed: usize,
    /// Rows in all.
    pub rows: usize,
}

/// `shlight accuracy`: runs the suite (progress: the case running) and
/// writes its pictures into the request's directory (each noted), or runs
/// the Legendre study.
///
/// # Errors
/// The directory cannot be made, or a picture cannot be written.
pub fn accuracy(request: &AccuracyRequest<'_>, hooks: &dyn Hooks) -> Result<AccuracyOutcome> {
    if request.legendre {
        let rows = legendre_study(&DEGREES);
        return Ok(AccuracyOutcome {
            text: legendre_table(&rows),
            failed: 0,
            rows: rows.len(),
        });
    }
    if let Some(dir) = request.output {
        if dir.exists() && !dir.is_dir() {
            return Err(PipelineError::new(format!(
                "{}: exists and is not a directory",
                dir.display()
            )));
        }
        std::fs::create_dir_all(dir).map_err(|e| {
            PipelineError::new(format!(
                "{}: cannot create the directory: {e}",
                dir.display()
            ))
        })?;
    }
    hooks.progress(Progress::Step("accuracy suite"));
    let report = suite::run(
        SuiteOptions {
            quick: request.quick,
        },
        &|what| hooks.progress(Progress::Step(what)),
    );
    if let Some(dir) = request.output {
        hooks.progress(Progress::Step("pictures"));
        let written = shlight_accuracy::plot::write_pictures(&report, dir)
            .map_err(|e| PipelineError::new(format!("{}: {e}", dir.display())))?;
        for path in written {
            hooks.note(&format!("wrote {}", path.display()));
        }
    }
    let text = if request.json {
        let rows: Vec<serde_json::Value> = report.rows.iter().map(Row::to_json).collect();
        serde_json::to_string_pretty(&rows).expect("rows are JSON values") + "\n"
    } else {
        report_table(&report)
    };
    Ok(AccuracyOutcome {
        text,
        failed: report.rows.iter().filter(|r| !r.pass).count(),
        rows: report.rows.len(),
    })
}
