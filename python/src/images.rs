//! `shlight.read_image`, `shlight.write_image` and `shlight.render`.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3, PyUntypedArray};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use shlight_core::map::{Layout, MapOrientation};
use shlight_format::Quantity;
use shlight_io::{Image, ReadOptions, ToneMap, WriteOptions};

use crate::errors::{chained, pipeline_error, shlight_error};
use crate::guard::guard;
use crate::sh::Sh;
use crate::source::{ArrayMap, Data};

/// `(H, W, 3)` float32 array of an image.
fn to_array<'py>(py: Python<'py>, image: Image) -> Bound<'py, PyArray3<f32>> {
    let (w, h) = (image.width(), image.height());
    let flat: Vec<f32> = image.into_pixels().into_iter().flatten().collect();
    Array3::from_shape_vec((h, w, 3), flat)
        .expect("h x w x 3 values")
        .into_pyarray(py)
}

/// read_image(path, *, layer=None, max_pixels=None) -> ndarray
/// --
///
/// Reads an OpenEXR, Radiance .hdr, PNG or JPEG file as linear RGB.
#[pyfunction]
#[pyo3(signature = (path, *, layer=None, max_pixels=None))]
pub fn read_image<'py>(
    py: Python<'py>,
    path: PathBuf,
    layer: Option<String>,
    max_pixels: Option<usize>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let options = ReadOptions {
        layer,
        max_pixels: max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
    };
    let image =
        py.detach(|| guard(|| shlight_io::read_image(&path, &options).map_err(|e| chained(&e))))?;
    Ok(to_array(py, image))
}

/// write_image(path, array, *, exposure=0.0, tone_map="clamp")
/// --
///
/// Writes an (H, W, 3) linear RGB array as .exr, .hdr or .png, atomically.
#[pyfunction]
#[pyo3(signature = (path, array, *, exposure=0.0, tone_map="clamp".to_string()))]
pub fn write_image(
    py: Python<'_>,
    path: PathBuf,
    array: &Bound<'_, PyAny>,
    exposure: f32,
    tone_map: String,
) -> PyResult<()> {
    let untyped = array
        .cast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err("array must be a numpy array of shape (H, W, 3)"))?;
    let map = ArrayMap::from_array(untyped, "array")?;
    let tone_map: ToneMap = tone_map
        .parse()
        .map_err(|e| shlight_error(format!("tone_map={tone_map:?}: {e}")))?;
    let view = map.view(Layout::Equirect);
    let pixels: Vec<[f32; 3]> = match view.data {
        Data::F32(p) => p.to_vec(),
        Data::F64(p) => p.iter().map(|t| t.map(|v| v as f32)).collect(),
    };
    let image = Image::new(map.width, map.height, pixels).map_err(shlight_error)?;
    let options = WriteOptions {
        exposure_ev: exposure,
        tone_map,
        ..WriteOptions::default()
    };
    py.detach(|| {
        guard(|| shlight_io::write_image(&path, &image, &options).map_err(|e| chained(&e)))
    })
}

/// render(sh, size=None, *, layout="equirect", irradiance=False) -> ndarray
/// --
///
/// See the package documentation (`help(shlight.render)`).
#[pyfunction]
#[pyo3(signature = (sh, size=None, *, layout="equirect".to_string(), irradiance=false))]
pub fn render<'py>(
    py: Python<'py>,
    sh: &Sh,
    size: Option<&Bound<'py, PyAny>>,
    layout: String,
    irradiance: bool,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let layout: Layout = layout
        .parse()
        .map_err(|e| shlight_error(format!("layout={layout:?}: {e}")))?;
    let (w, h) = match size {
        None => {
            let n = 256;
            layout.dimensions(if layout.is_cube() { n / 2 } else { n })
        }
        Some(s) => {
            if let Ok(n) = s.extract::<usize>() {
                layout.dimensions(n)
            } else {
                s.extract::<(usize, usize)>().map_err(|_| {
                    PyTypeError::new_err(
                        "size is (width, height) or one number (see help(shlight.render))",
                    )
                })?
            }
        }
    };
    if layout == Layout::Equirect && (w == 0 || w != 2 * h) {
        return Err(shlight_error(format!(
            "a {w}x{h} image is not an equirect map (its width must be twice its height)"
        )));
    }
    if w.checked_mul(h)
        .is_none_or(|n| n > ReadOptions::DEFAULT_MAX_PIXELS)
    {
        return Err(shlight_error(format!(
            "{w}x{h}: more than {} pixels",
            ReadOptions::DEFAULT_MAX_PIXELS
        )));
    }
    sh.plain("render")?;
    let file = sh.file();
    let coeffs = match (file.quantity, irradiance) {
        (Quantity::Radiance, true) => shlight_core::sh::irradiance(&file.coeffs),
        _ => file.coeffs.clone(),
    };
    let orientation = MapOrientation {
        frame: file.frame,
        mirror: file.mirror,
    };
    let image = py.detach(|| {
        guard(|| {
            shlight_pipeline::render_map(&coeffs, layout, (w, h), orientation, &|| {})
                .map_err(pipeline_error)
        })
    })?;
    Ok(to_array(py, image))
}
