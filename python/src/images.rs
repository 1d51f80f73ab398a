//! `shlight.read_image`, `shlight.write_image`, `shlight.render` and
//! `shlight.synth` (shlight-pipeline's `render` and `synth` jobs).

use std::path::PathBuf;

use glam::DVec3;
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3, PyUntypedArray};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use shlight_core::map::Layout;
use shlight_core::map::MapOrientation;
use shlight_io::{Image, ReadOptions, ToneMap, WriteOptions};
use shlight_pipeline::{
    Collected, RenderLayout, RenderRequest, Spelling, SynthRequest, render_light,
    synth as synth_job, synth_map,
};

use crate::errors::{chained, pipeline_error, shlight_error, warn_all};
use crate::guard::guard;
use crate::hooks::PyHooks;
use crate::options::frame_of;
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

/// render(sh, size=None, *, layout="equirect", irradiance=False, view=None) -> ndarray
/// --
///
/// See the package documentation (`help(shlight.render)`).
#[pyfunction]
#[pyo3(signature = (sh, size=None, *, layout="equirect".to_string(), irradiance=false, view=None))]
pub fn render<'py>(
    py: Python<'py>,
    sh: &Sh,
    size: Option<&Bound<'py, PyAny>>,
    layout: String,
    irradiance: bool,
    view: Option<[f64; 3]>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let layout: RenderLayout = Spelling::Python
        .parse("layout", &layout)
        .map_err(pipeline_error)?;
    let size = match size {
        None => None,
        Some(s) => Some(if let Ok(n) = s.extract::<usize>() {
            match layout {
                RenderLayout::Map(l) => l.dimensions(n),
                RenderLayout::Lobe => (n, n),
            }
        } else {
            s.extract::<(usize, usize)>().map_err(|_| {
                PyTypeError::new_err(
                    "size is (width, height) or one number (see help(shlight.render))",
                )
            })?
        }),
    };
    let plan = RenderRequest {
        irradiance,
        size,
        layout,
        view: view.map(DVec3::from_array),
        ..RenderRequest::default()
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    sh.plain("render")?;
    let hooks = Collected::new();
    let image = py.detach(|| {
        guard(|| render_light(sh.file(), "this SH", &plan, &hooks).map_err(pipeline_error))
    })?;
    warn_all(py, &hooks.notes(), 1)?;
    Ok(to_array(py, image))
}

/// synth(kind, size=None, *, layout="equirect", up="y", mirror=False,
/// color=(1, 1, 1), value=1.0, slope=0.5, direction=None, half_angle=None,
/// supersample=4, output=None, exposure=0.0, tone_map="clamp") -> ndarray
/// --
///
/// See the package documentation (`help(shlight.synth)`).
#[pyfunction]
#[pyo3(signature = (kind, size=None, *, layout="equirect".to_string(), up="y".to_string(),
    mirror=false, color=[1.0, 1.0, 1.0], value=1.0, slope=0.5, direction=None, half_angle=None,
    supersample=4, output=None, exposure=0.0, tone_map="clamp".to_string()))]
pub fn synth<'py>(
    py: Python<'py>,
    kind: String,
    size: Option<(usize, usize)>,
    layout: String,
    up: String,
    mirror: bool,
    color: [f64; 3],
    value: f64,
    slope: f64,
    direction: Option<[f64; 3]>,
    half_angle: Option<f64>,
    supersample: u32,
    output: Option<PathBuf>,
    exposure: f32,
    tone_map: String,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let plan = SynthRequest {
        kind: Spelling::Python
            .parse("kind", &kind)
            .map_err(pipeline_error)?,
        size,
        layout: Spelling::Python
            .parse("layout", &layout)
            .map_err(pipeline_error)?,
        orientation: MapOrientation {
            frame: frame_of(&up)?,
            mirror,
        },
        color: DVec3::from_array(color),
        value,
        slope,
        direction: direction.map(DVec3::from_array),
        half_angle,
        supersample,
        exposure,
        tone_map: Spelling::Python
            .parse("tone_map", &tone_map)
            .map_err(pipeline_error)?,
    }
    .check(Spelling::Python)
    .map_err(pipeline_error)?;
    let hooks = PyHooks::new(false);
    let image = py.detach(|| {
        guard(|| {
            match &output {
                Some(path) => synth_job(path, &plan, &hooks),
                None => synth_map(&plan, &hooks),
            }
            .map_err(pipeline_error)
        })
    });
    warn_all(py, &hooks.warnings(), 1)?;
    Ok(to_array(py, image?))
}
