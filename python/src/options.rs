//! The keyword options of `project` and `project_many`, turned into the
//! pipeline's [`Settings`] by the checks the command line makes too
//! ([`ProjectOptions::check`]).

use pyo3::prelude::*;
use shlight_core::encoding::Encoding;
use shlight_core::map::MapOrientation;
use shlight_core::map::montecarlo::SamplerKind;
use shlight_core::sh::Frame;
use shlight_format::Quantity;
use shlight_io::ReadOptions;
use shlight_pipeline::{InputLayout, ProjectOptions, ReadSettings, Settings, Spelling};

use crate::errors::{pipeline_error, shlight_error};

/// Every option of a projection, as given from Python.
#[derive(Clone, Debug)]
pub struct RawOptions {
    pub lmax: usize,
    pub up: String,
    pub layout: String,
    pub method: String,
    pub samples: Option<usize>,
    pub sampler: Option<String>,
    pub seed: Option<u64>,
    pub window: Option<String>,
    pub quantity: String,
    pub mirror: bool,
    pub sanitize: bool,
    pub rotate: Option<String>,
    pub layer: Option<String>,
    pub max_pixels: Option<usize>,
    pub encoding: String,
}

/// `layout=` of a map read from a file.
pub fn input_layout(layout: &str) -> PyResult<InputLayout> {
    layout
        .parse()
        .map_err(|e: String| shlight_error(format!("layout={layout:?}: {e}")))
}

/// `up="y"` or `"z"` as a frame.
pub fn frame_of(up: &str) -> PyResult<Frame> {
    match up.trim() {
        "y" | "y-up" => Ok(Frame::YUp),
        "z" | "z-up" => Ok(Frame::ZUp),
        other => Err(shlight_error(format!(
            "up={other:?}: expected \"y\" (the top row faces +Y) or \"z\" (+Z)"
        ))),
    }
}

impl RawOptions {
    /// Parses the options given as strings and makes the pipeline's
    /// settings through the checks every front end makes
    /// ([`ProjectOptions::check`], in Python's spelling): the same defaults
    /// and refusals as `shlight project` (Monte Carlo options only with
    /// `method="montecarlo"`; an encoding other than `sh` only for radiance
    /// by quadrature, without a window or rotation).
    pub fn resolve(&self) -> PyResult<Settings> {
        self.options()?
            .check(Spelling::Python)
            .map_err(pipeline_error)
    }

    /// The options, parsed, before [`ProjectOptions::check`].
    pub fn options(&self) -> PyResult<ProjectOptions<'_>> {
        let frame = frame_of(&self.up)?;
        let layout = input_layout(&self.layout)?;
        let quantity: Quantity = Spelling::Python
            .parse("quantity", &self.quantity)
            .map_err(pipeline_error)?;
        let monte_carlo = monte_carlo(&self.method)?;
        let sampler = sampler_of(self.sampler.as_deref(), monte_carlo)?;
        let encoding: Encoding = Spelling::Python
            .parse("encoding", &self.encoding)
            .map_err(pipeline_error)?;
        Ok(ProjectOptions {
            read: ReadSettings {
                layout,
                read: ReadOptions {
                    layer: self.layer.clone(),
                    max_pixels: self.max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
                },
                sanitize: self.sanitize,
                spelling: Spelling::Python,
            },
            lmax: self.lmax,
            orientation: MapOrientation {
                frame,
                mirror: self.mirror,
            },
            monte_carlo,
            samples: self.samples,
            sampler,
            seed: self.seed,
            window: self.window.as_deref().unwrap_or("none"),
            rotate: self.rotate.as_deref(),
            quantity,
            encoding,
            gpu: false,
            format: None,
        })
    }
}

/// `method=`: whether it is Monte Carlo (else quadrature).
fn monte_carlo(method: &str) -> PyResult<bool> {
    match method.trim() {
        "montecarlo" => Ok(true),
        "quadrature" => Ok(false),
        other => Err(shlight_error(format!(
            "method={other:?}: expected \"quadrature\" or \"montecarlo\""
        ))),
    }
}

/// `sampler=`, parsed only for Monte Carlo; with quadrature it is kept as
/// given (any name), for the check to refuse.
fn sampler_of(sampler: Option<&str>, monte_carlo: bool) -> PyResult<Option<SamplerKind>> {
    match sampler {
        None => Ok(None),
        Some(_) if !monte_carlo => Ok(Some(SamplerKind::default())),
        Some(name) => Spelling::Python
            .parse("sampler", name)
            .map(Some)
            .map_err(pipeline_error),
    }
}

/// An albedo from Python: one value or (R, G, B) (`bake_transfer`'s and
/// `bake_volume`'s).
pub fn albedo_of(albedo: &Bound<'_, PyAny>) -> PyResult<[f32; 3]> {
    let rgb = if let Ok(v) = albedo.extract::<f32>() {
        [v; 3]
    } else {
        albedo.extract::<[f32; 3]>().map_err(|_| {
            shlight_error("albedo is one value or (R, G, B), linear, each in [0, 1]")
        })?
    };
    if !rgb.iter().all(|v| (0.0..=1.0).contains(v)) {
        return Err(shlight_error(format!(
            "albedo={rgb:?}: each value must lie in [0, 1]"
        )));
    }
    Ok(rgb)
}
