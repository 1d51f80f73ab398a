//! [`guard`]: Rust work run so that a panic becomes a Python exception.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::PyResult;

use crate::errors::shlight_error;

/// Runs `f`, turning a panic into a `ShlightError` that says so (a bug in
/// shlight, never a crash of the interpreter).
pub fn guard<T>(f: impl FnOnce() -> PyResult<T>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => Err(shlight_error(format!(
            "internal error (please report it): {}",
            panic_text(payload.as_ref())
        ))),
    }
}

/// The text of a panic payload.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic".to_string()
    }
}
