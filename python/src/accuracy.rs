//! `shlight.irradiance` (the exact irradiance of a map, and an encoding's
//! against it, `shlight irradiance`), `shlight.compare` (every encoding
//! against it, `shlight compare`) and `shlight.accuracy` (the accuracy
//! suite, `shlight accuracy`): shlight-pipeline's `irradiance`, `compare`
//! and `accuracy` jobs, as the command line runs them.

use std::path::PathBuf;

use glam::DVec3;
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use shlight_accuracy::compare::rows_json;
use shlight_core::encoding::Encoding;
use shlight_core::map::MapOrientation;
use shlight_io::ReadOptions;
use shlight_pipeline::{
    AccuracyRequest, CompareRequest, IrradianceRequest, ReadSettings, Spelling, accuracy,
    compare as compare_job, irradiance as irradiance_job,
};

use crate::errors::{pipeline_error, warn_all};
use crate::guard::guard;
use crate::hooks::PyHooks;
use crate::options::{frame_of, input_layout};

/// `(h, w, 3)` float64 array of values on a `w x h` grid.
fn grid_array<'py>(
    py: Python<'py>,
    (w, h): (usize, usize),
    values: &[DVec3],
) -> Bound<'py, PyArray3<f64>> {
    let flat: Vec<f64> = values.iter().flat_map(|v| v.to_array()).collect();
    Array3::from_shape_vec((h, w, 3), flat)
        .expect("h x w x 3 values")
        .into_pyarray(py)
}

/// How a map is read, from Python's keywords.
fn read_settings(
    layout: &str,
    sanitize: bool,
    max_pixels: Option<usize>,
) -> PyResult<ReadSettings> {
    Ok(ReadSettings {
        layout: input_layout(layout)?,
        read: ReadOptions {
            layer: None,
            max_pixels: max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
        },
        sanitize,
        spelling: Spelling::Python,
    })
}

/// irradiance(source, size=(64, 32), *, up="y", layout="auto", mirror=False,
/// sanitize=False, max_pixels=None, sh=None, encoding=None, output=None,
/// error_map=None)
/// --
///
/// See the package documentation (`help(shlight.irradiance)`).
#[pyfunction]
#[pyo3(signature = (source, size=(64, 32), *, up="y".to_string(), layout="auto".to_string(),
    mirror=false, sanitize=false, max_pixels=None, sh=None, encoding=None, output=None,
    error_map=None))]
pub fn irradiance<'py>(
    py: Python<'py>,
    source: PathBuf,
    size: (usize, usize),
    up: String,
    layout: String,
    mirror: bool,
    sanitize: bool,
    max_pixels: Option<usize>,
    sh: Option<usize>,
    encoding: Option<String>,
    output: Option<PathBuf>,
    error_map: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let encoding: Option<Encoding> = encoding
        .map(|e| Spelling::Python.parse("encoding", &e))
        .transpose()
        .map_err(pipeline_error)?;
    let plan = IrradianceRequest {
        input: &source,
        output: output.as_deref(),
        size,
        sh,
        encoding,
        error_map: error_map.as_deref(),
        read: read_settings(&layout, sanitize, max_pixels)?,
        orientation: MapOrientation {
            frame: frame_of(&up)?,
            mirror,
        },
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let hooks = PyHooks::new(false);
    let done = py.detach(|| guard(|| irradiance_job(&plan, &hooks).map_err(pipeline_error)));
    warn_all(py, &hooks.warnings(), 2)?;
    let (report, summary) = done?;
    let exact = grid_array(py, size, &report.exact.exact);
    let Some(measured) = &report.encoded else {
        return Ok(exact.into_any());
    };
    let errors = measured
        .errors
        .expect("the job refuses a map without light");
    let dict = PyDict::new(py);
    dict.set_item("exact", exact)?;
    dict.set_item("estimate", grid_array(py, size, &measured.estimate))?;
    dict.set_item("encoding", measured.encoding.name())?;
    dict.set_item("lmax", measured.lmax)?;
    dict.set_item("floats", measured.light.floats(measured.encoding))?;
    dict.set_item("mean_relative", errors.pointwise.mean)?;
    dict.set_item("max_relative", errors.pointwise.max)?;
    dict.set_item("mean_peak_relative", errors.peak_relative.mean)?;
    dict.set_item("max_peak_relative", errors.peak_relative.max)?;
    dict.set_item("summary", summary)?;
    Ok(dict.into_any())
}

/// compare(paths, normals=(128, 64), *, up="y", layout="auto",
/// sanitize=False, output=None) -> list[dict]
/// --
///
/// See the package documentation (`help(shlight.compare)`).
#[pyfunction]
#[pyo3(signature = (paths, normals=(128, 64), *, up="y".to_string(), layout="auto".to_string(),
    sanitize=false, output=None))]
pub fn compare<'py>(
    py: Python<'py>,
    paths: Vec<PathBuf>,
    normals: (usize, usize),
    up: String,
    layout: String,
    sanitize: bool,
    output: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let plan = CompareRequest {
        inputs: &paths,
        output: output.as_deref(),
        normals,
        read: read_settings(&layout, sanitize, None)?,
        orientation: MapOrientation {
            frame: frame_of(&up)?,
            mirror: false,
        },
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let hooks = PyHooks::new(false);
    let done = py.detach(|| guard(|| compare_job(&plan, &hooks).map_err(pipeline_error)));
    warn_all(py, &hooks.warnings(), 2)?;
    let (rows, _) = done?;
    // The rows as compare.json holds them: the same keys, numbers read
    // back from the same shortest round-trip text.
    py.import("json")?
        .call_method1("loads", (rows_json(&rows).to_string(),))
}

/// accuracy(quick=False, *, output=None) -> list[dict]
/// --
///
/// See the package documentation (`help(shlight.accuracy)`).
#[pyfunction]
#[pyo3(signature = (quick=false, *, output=None))]
pub fn accuracy_suite<'py>(
    py: Python<'py>,
    quick: bool,
    output: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let request = AccuracyRequest {
        quick,
        json: true,
        output: output.as_deref(),
        legendre: false,
    };
    let hooks = PyHooks::new(false);
    let outcome = py.detach(|| guard(|| accuracy(&request, &hooks).map_err(pipeline_error)))?;
    py.import("json")?.call_method1("loads", (outcome.text,))
}
