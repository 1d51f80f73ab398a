//! `shlight.ShlightError` and the conversions of library errors into it;
//! warnings for the user as Python `UserWarning`s.

use std::ffi::CString;

use pyo3::create_exception;
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;

create_exception!(
    shlight,
    ShlightError,
    PyValueError,
    "A map, file or option shlight cannot use; the message names the input and the problem, as the shlight command line prints it."
);

/// A `ShlightError` with this message.
pub fn shlight_error(msg: impl std::fmt::Display) -> PyErr {
    ShlightError::new_err(msg.to_string())
}

/// A `ShlightError` from a pipeline error (its message as the CLI prints it).
pub fn pipeline_error(e: shlight_pipeline::PipelineError) -> PyErr {
    shlight_error(e)
}

/// A `ShlightError` from any error and its causes, joined as the CLI
/// prints them.
pub fn chained(e: &(dyn std::error::Error + 'static)) -> PyErr {
    shlight_error(shlight_pipeline::error_chain(e))
}

/// Issues each message as a `UserWarning`, attributed `stacklevel` frames
/// up (2 from the package's Python wrappers: the user's call).
pub fn warn_all(py: Python<'_>, messages: &[String], stacklevel: i32) -> PyResult<()> {
    let category = py.get_type::<PyUserWarning>();
    for m in messages {
        let text = CString::new(m.replace('\0', " ")).expect("NUL bytes replaced");
        PyErr::warn(py, &category, &text, stacklevel)?;
    }
    Ok(())
}
