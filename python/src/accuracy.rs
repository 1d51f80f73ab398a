//! `shlight.irradiance` (the exact irradiance of a map, `shlight
//! irradiance`) and `shlight.compare` (every encoding against it, `shlight
//! compare`): the same library calls as the command line's
//! (shlight-pipeline's `map_irradiance` and `compare_encodings`).

use std::cell::RefCell;
use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use shlight_accuracy::compare::rows_json;
use shlight_core::map::{Layout, MapOrientation};
use shlight_io::ReadOptions;
use shlight_pipeline::{
    IrradianceSettings, ReadSettings, compare_encodings, map_irradiance, output_grid,
};

use crate::errors::{pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::options::{frame_of, input_layout};

/// irradiance(source, size=(64, 32), *, up="y", layout="auto", mirror=False,
/// sanitize=False, max_pixels=None) -> ndarray
/// --
///
/// See the package documentation (`help(shlight.irradiance)`).
#[pyfunction]
#[pyo3(signature = (source, size=(64, 32), *, up="y".to_string(), layout="auto".to_string(),
    mirror=false, sanitize=false, max_pixels=None))]
pub fn irradiance<'py>(
    py: Python<'py>,
    source: PathBuf,
    size: (usize, usize),
    up: String,
    layout: String,
    mirror: bool,
    sanitize: bool,
    max_pixels: Option<usize>,
) -> PyResult<Bound<'py, PyArray3<f64>>> {
    let orientation = MapOrientation {
        frame: frame_of(&up)?,
        mirror,
    };
    let layout = input_layout(&layout)?;
    let (w, h) = size;
    output_grid(Layout::Equirect, size, MapOrientation::default())
        .map_err(|e| shlight_error(format!("size=({w}, {h}): {e}")))?;
    let settings = IrradianceSettings {
        read: ReadSettings {
            layout,
            read: ReadOptions {
                layer: None,
                max_pixels: max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
            },
            sanitize,
        },
        orientation,
        size,
        encoding: None,
    };
    let (exact, warnings) = py.detach(|| {
        guard(|| {
            let warnings = RefCell::new(Vec::new());
            let warn = |m: &str| warnings.borrow_mut().push(m.to_string());
            let report =
                map_irradiance(&source, &settings, &warn, &|_| {}).map_err(pipeline_error)?;
            Ok((report.exact.exact, warnings.into_inner()))
        })
    })?;
    warn_all(py, &warnings, 2)?;
    let flat: Vec<f64> = exact.iter().flat_map(|v| v.to_array()).collect();
    Ok(Array3::from_shape_vec((h, w, 3), flat)
        .expect("h x w x 3 values")
        .into_pyarray(py))
}

/// compare(paths, normals=(128, 64), *, up="y", layout="auto",
/// sanitize=False) -> list[dict]
/// --
///
/// See the package documentation (`help(shlight.compare)`).
#[pyfunction]
#[pyo3(signature = (paths, normals=(128, 64), *, up="y".to_string(), layout="auto".to_string(),
    sanitize=false))]
pub fn compare<'py>(
    py: Python<'py>,
    paths: Vec<PathBuf>,
    normals: (usize, usize),
    up: String,
    layout: String,
    sanitize: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let orientation = MapOrientation {
        frame: frame_of(&up)?,
        mirror: false,
    };
    let layout = input_layout(&layout)?;
    let (w, h) = normals;
    if w == 0 || h == 0 {
        return Err(shlight_error(format!(
            "normals=({w}, {h}): the grid of normals needs at least one texel"
        )));
    }
    let read = ReadSettings {
        layout,
        read: ReadOptions::default(),
        sanitize,
    };
    let (text, warnings) = py.detach(|| {
        guard(|| {
            let warnings = RefCell::new(Vec::new());
            let warn = |m: &str| warnings.borrow_mut().push(m.to_string());
            let mut rows = Vec::new();
            for path in &paths {
                rows.extend(
                    compare_encodings(path, &read, orientation, normals, &warn)
                        .map_err(pipeline_error)?,
                );
            }
            Ok((rows_json(&rows).to_string(), warnings.into_inner()))
        })
    })?;
    warn_all(py, &warnings, 2)?;
    // The rows as compare.json holds them: the same keys, numbers read
    // back from the same shortest round-trip text.
    py.import("json")?.call_method1("loads", (text,))
}
