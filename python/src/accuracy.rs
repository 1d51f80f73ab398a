//! `shlight.irradiance` (the exact irradiance of a map, `shlight
//! irradiance`) and `shlight.compare` (every encoding against it, `shlight
//! compare`): the same library calls as the command line's
//! (`shlight_pipeline::load_map`, `shlight_accuracy`).

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::prelude::*;
use shlight_accuracy::compare::{compare_map, rows_json};
use shlight_accuracy::map_irradiance::MapIrradiance;
use shlight_core::encoding::DominantLightOptions;
use shlight_core::map::{Layout, MapOrientation};
use shlight_io::ReadOptions;
use shlight_pipeline::{InputLayout, LoadedMap, load_map, output_grid};

use crate::errors::{pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::options::frame_of;

/// `layout=` of a map read from a file.
fn input_layout(layout: &str) -> PyResult<InputLayout> {
    layout
        .parse()
        .map_err(|e: String| shlight_error(format!("layout={layout:?}: {e}")))
}

/// Reads and checks a map as the command line does; its warnings are
/// returned for the caller to issue once the GIL is held again.
fn load(
    path: &std::path::Path,
    layout: InputLayout,
    read: &ReadOptions,
    sanitize: bool,
    warnings: &mut Vec<String>,
) -> PyResult<LoadedMap> {
    let loaded = load_map(path, layout, read, sanitize).map_err(pipeline_error)?;
    warnings.extend(loaded.warnings.iter().cloned());
    Ok(loaded)
}

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
    let read = ReadOptions {
        layer: None,
        max_pixels: max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
    };
    let mut warnings = Vec::new();
    let exact = py.detach(|| {
        guard(|| {
            let name = source.display().to_string();
            let loaded = load(&source, layout, &read, sanitize, &mut warnings)?;
            let map = loaded.map(orientation, &name).map_err(pipeline_error)?;
            MapIrradiance::on_equirect(&map, size, orientation, &|_| {})
                .map(|m| m.exact)
                .map_err(|e| shlight_error(format!("size=({w}, {h}): {e}")))
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
    let read = ReadOptions::default();
    let mut warnings = Vec::new();
    let text = py.detach(|| {
        guard(|| {
            let mut rows = Vec::new();
            for path in &paths {
                // The row's map is the file's stem, as `shlight compare` names it.
                let name = path.file_stem().map_or_else(
                    || path.display().to_string(),
                    |s| s.to_string_lossy().into_owned(),
                );
                let loaded = load(path, layout, &read, sanitize, &mut warnings)?;
                let map = loaded
                    .map(orientation, &path.display().to_string())
                    .map_err(pipeline_error)?;
                rows.extend(compare_map(
                    &name,
                    &map,
                    normals,
                    &DominantLightOptions::default(),
                ));
            }
            Ok(rows_json(&rows).to_string())
        })
    })?;
    warn_all(py, &warnings, 2)?;
    // The rows as compare.json holds them: the same keys, numbers read
    // back from the same shortest round-trip text.
    py.import("json")?.call_method1("loads", (text,))
}
