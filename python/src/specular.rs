//! `shlight.prefilter` (a map GGX-prefiltered into cube mips: faces, KTX or
//! KTX2, `shlight prefilter`) and `shlight.dfg` (the DFG table, `shlight
//! dfg`): shlight-pipeline's `prefilter` and `dfg` jobs, as the command
//! line runs them.

use std::path::PathBuf;

use pyo3::prelude::*;
use shlight_core::map::MapOrientation;
use shlight_io::ReadOptions;
use shlight_pipeline::{
    DfgRequest, PrefilterRequest, ReadSettings, Silent, Spelling, dfg as dfg_job,
    prefilter as prefilter_job,
};
use shlight_specular::{PrefilterSettings, TargetEngine};

use crate::errors::{pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::hooks::PyHooks;
use crate::options::{frame_of, input_layout};

fn engine_of(name: &str) -> PyResult<TargetEngine> {
    name.parse()
        .map_err(|e| shlight_error(format!("engine={name:?}: {e}")))
}

/// prefilter(source, output, engine="filament", size=256, mips=None,
/// samples=1024, *, up="y", layout="auto", mirror=False, sanitize=False,
/// max_pixels=None) -> list[str]
/// --
///
/// See the package documentation (`help(shlight.prefilter)`).
#[pyfunction]
#[pyo3(signature = (source, output, engine="filament".to_string(), size=256, mips=None,
    samples=1024, *, up="y".to_string(), layout="auto".to_string(), mirror=false,
    sanitize=false, max_pixels=None))]
pub fn prefilter(
    py: Python<'_>,
    source: PathBuf,
    output: PathBuf,
    engine: String,
    size: usize,
    mips: Option<usize>,
    samples: u32,
    up: String,
    layout: String,
    mirror: bool,
    sanitize: bool,
    max_pixels: Option<usize>,
) -> PyResult<Vec<String>> {
    let plan = PrefilterRequest {
        input: &source,
        output: &output,
        read: ReadSettings {
            layout: input_layout(&layout)?,
            read: ReadOptions {
                layer: None,
                max_pixels: max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
            },
            sanitize,
            spelling: Spelling::Python,
        },
        orientation: MapOrientation {
            frame: frame_of(&up)?,
            mirror,
        },
        settings: PrefilterSettings {
            engine: engine_of(&engine)?,
            size,
            mips,
            samples,
        },
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let hooks = PyHooks::new(false);
    let written = py.detach(|| guard(|| prefilter_job(&plan, &hooks).map_err(pipeline_error)));
    warn_all(py, &hooks.warnings(), 1)?;
    Ok(written?.1.iter().map(|p| p.display().to_string()).collect())
}

/// dfg(output, engine="filament", size=128, samples=1024) -> None
/// --
///
/// See the package documentation (`help(shlight.dfg)`).
#[pyfunction]
#[pyo3(signature = (output, engine="filament".to_string(), size=128, samples=1024))]
pub fn dfg(
    py: Python<'_>,
    output: PathBuf,
    engine: String,
    size: usize,
    samples: u32,
) -> PyResult<()> {
    let plan = DfgRequest {
        engine: engine_of(&engine)?,
        size,
        samples,
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    py.detach(|| {
        guard(|| {
            dfg_job(&output, &plan, &Silent)
                .map(|_| ())
                .map_err(pipeline_error)
        })
    })
}
