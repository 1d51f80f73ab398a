//! `shlight.convert`: a coefficient file or volume to another format, or a
//! light into a glTF asset, as `shlight convert` does it (shlight-pipeline's
//! `convert` job).

use std::path::PathBuf;

use pyo3::IntoPyObjectExt;
use pyo3::prelude::*;
use shlight_format::ExportFormat;
use shlight_format::threejs_volume::Precision;
use shlight_pipeline::{ConvertRequest, Spelling, convert as convert_job};

use crate::errors::{pipeline_error, warn_all};
use crate::guard::guard;
use crate::hooks::PyHooks;

/// convert(input, output=None, *, format=None, into=None,
/// precision="half", irradiance_only=False) -> str | list[str] | None
/// --
///
/// See the package documentation (`help(shlight.convert)`).
#[pyfunction]
#[pyo3(signature = (input, output=None, *, format=None, into=None,
    precision="half".to_string(), irradiance_only=false))]
pub fn convert(
    py: Python<'_>,
    input: PathBuf,
    output: Option<PathBuf>,
    format: Option<String>,
    into: Option<PathBuf>,
    precision: String,
    irradiance_only: bool,
) -> PyResult<Py<PyAny>> {
    let format: Option<ExportFormat> = format
        .map(|f| Spelling::Python.parse("format", &f))
        .transpose()
        .map_err(pipeline_error)?;
    let precision: Precision = Spelling::Python
        .parse("precision", &precision)
        .map_err(pipeline_error)?;
    let plan = ConvertRequest {
        input: &input,
        output: output.as_deref(),
        format,
        into: into.as_deref(),
        precision,
        irradiance_only,
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let hooks = PyHooks::new(false);
    let done = py.detach(|| guard(|| convert_job(&plan, &hooks).map_err(pipeline_error)));
    warn_all(py, &hooks.notes(), 1)?;
    let done = done?;
    if let Some(text) = done.stdout {
        return text.into_py_any(py);
    }
    if done.written.is_empty() {
        return Ok(py.None());
    }
    let paths: Vec<String> = done
        .written
        .iter()
        .map(|p| p.display().to_string())
        .collect();
    paths.into_py_any(py)
}
