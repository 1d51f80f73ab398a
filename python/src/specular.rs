//! `shlight.prefilter` (a map GGX-prefiltered into cube mips, `shlight
//! prefilter`) and `shlight.dfg` (the DFG table, `shlight dfg`): the same
//! library calls as the command line's (shlight-pipeline's
//! `prefilter_map`, `write_prefiltered_faces` and `write_dfg`).

use std::path::PathBuf;

use pyo3::prelude::*;
use shlight_core::map::MapOrientation;
use shlight_io::ReadOptions;
use shlight_pipeline::{
    PrefilterRequest, ReadSettings, prefilter_map, write_dfg, write_prefiltered_faces,
};
use shlight_specular::{DfgTable, Engine, PrefilterSettings};

use crate::errors::{pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::options::{frame_of, input_layout};

fn engine_of(name: &str) -> PyResult<Engine> {
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
    let request = PrefilterRequest {
        read: ReadSettings {
            layout: input_layout(&layout)?,
            read: ReadOptions {
                layer: None,
                max_pixels: max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
            },
            sanitize,
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
    };
    let warnings = std::sync::Mutex::new(Vec::new());
    let written = py.detach(|| {
        guard(|| {
            let cube = prefilter_map(
                &source,
                &request,
                &|w| warnings.lock().unwrap().push(w.to_string()),
                &|_| {},
            )
            .map_err(pipeline_error)?;
            write_prefiltered_faces(&cube, &output).map_err(pipeline_error)
        })
    });
    warn_all(py, &warnings.into_inner().unwrap(), 1)?;
    Ok(written?.iter().map(|p| p.display().to_string()).collect())
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
    let engine = engine_of(&engine)?;
    if size == 0 || size > 4096 || samples == 0 {
        return Err(shlight_error(format!(
            "size={size}, samples={samples}: size must be from 1 to 4096 and samples at least 1"
        )));
    }
    py.detach(|| {
        guard(|| {
            let table = DfgTable::for_engine(engine, size, samples);
            write_dfg(&table, &output).map_err(pipeline_error)
        })
    })
}
