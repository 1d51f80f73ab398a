//! The keyword options of `project` and `project_many`, turned into the
//! library's [`ProjectSettings`] and [`ReadSettings`] with the command
//! line's defaults and checks.

use pyo3::prelude::*;
use shlight_core::encoding::Encoding;
use shlight_core::map::MapOrientation;
use shlight_core::map::montecarlo::{DEFAULT_SEED, McOptions, SamplerKind};
use shlight_core::sh::{Frame, Window};
use shlight_format::{Quantity, RotationRecord};
use shlight_io::ReadOptions;
use shlight_pipeline::{DEFAULT_SAMPLES, InputLayout, Method, ProjectSettings, ReadSettings};

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

/// The settings of a projection and how its inputs are read.
#[derive(Clone, Debug)]
pub struct Options {
    pub settings: ProjectSettings,
    pub read: ReadSettings,
    /// The light kept: plain SH or an encoding of the map.
    pub encoding: Encoding,
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
    /// Checks the options and makes the library's settings: the same
    /// defaults and refusals as `shlight project` (Monte Carlo options only
    /// with `method="montecarlo"`; an encoding other than `sh` only for
    /// radiance by quadrature, without a window or rotation).
    pub fn resolve(&self) -> PyResult<Options> {
        let frame = frame_of(&self.up)?;
        let layout: InputLayout = self
            .layout
            .parse()
            .map_err(|e: String| shlight_error(format!("layout={:?}: {e}", self.layout)))?;
        let quantity: Quantity = self
            .quantity
            .parse()
            .map_err(|e| shlight_error(format!("quantity={:?}: {e}", self.quantity)))?;
        let window = match self.window.as_deref().map(str::trim) {
            None => Some(Window::None),
            Some("auto") => None,
            Some(spec) => Some(
                spec.parse::<Window>()
                    .map_err(|e| shlight_error(format!("--window {spec}: {e}")))?,
            ),
        };
        let method = match self.method.trim() {
            "montecarlo" => {
                let sampler = match &self.sampler {
                    None => SamplerKind::default(),
                    Some(name) => name
                        .parse::<SamplerKind>()
                        .map_err(|e| shlight_error(format!("sampler={name:?}: {e}")))?,
                };
                let samples = self.samples.unwrap_or(DEFAULT_SAMPLES);
                if samples == 0 {
                    return Err(shlight_error("the sample count must be at least 1"));
                }
                Method::MonteCarlo {
                    options: McOptions {
                        lmax: self.lmax,
                        samples,
                        seed: self.seed.unwrap_or(DEFAULT_SEED),
                        ..McOptions::default()
                    },
                    sampler,
                }
            }
            "quadrature" => {
                let given: Vec<&str> = [
                    ("samples", self.samples.is_some()),
                    ("sampler", self.sampler.is_some()),
                    ("seed", self.seed.is_some()),
                ]
                .into_iter()
                .filter_map(|(name, given)| given.then_some(name))
                .collect();
                if !given.is_empty() {
                    return Err(shlight_error(format!(
                        "{} only apply to method=\"montecarlo\" (the method is quadrature)",
                        given.join(", ")
                    )));
                }
                Method::Quadrature
            }
            other => {
                return Err(shlight_error(format!(
                    "method={other:?}: expected \"quadrature\" or \"montecarlo\""
                )));
            }
        };
        let rotation = match &self.rotate {
            None => None,
            Some(spec) => {
                let matrix =
                    shlight_pipeline::parse_rotation(spec, frame).map_err(pipeline_error)?;
                let record = RotationRecord {
                    spec: spec.trim().to_string(),
                    matrix: matrix.transpose().to_cols_array_2d(),
                };
                Some((record, matrix))
            }
        };
        let orientation = MapOrientation {
            frame,
            mirror: self.mirror,
        };
        // After the other options are known to be valid.
        let encoding = self.encoding()?;
        Ok(Options {
            settings: ProjectSettings {
                lmax: self.lmax,
                orientation,
                method,
                window,
                rotation,
                quantity,
            },
            read: ReadSettings {
                layout,
                read: ReadOptions {
                    layer: self.layer.clone(),
                    max_pixels: self.max_pixels.unwrap_or(ReadOptions::DEFAULT_MAX_PIXELS),
                },
                sanitize: self.sanitize,
            },
            encoding,
        })
    }

    /// `encoding=`, refused with the options `shlight project --encoding`
    /// refuses it with (src/project/settings.rs), in Python's spelling.
    fn encoding(&self) -> PyResult<Encoding> {
        let e: Encoding = self
            .encoding
            .trim()
            .parse()
            .map_err(|err| shlight_error(format!("encoding={:?}: {err}", self.encoding)))?;
        if e == Encoding::Sh {
            return Ok(e);
        }
        let window = self.window.as_deref().map(str::trim);
        let clash = [
            (
                self.quantity.trim() != Quantity::Radiance.name(),
                "quantity=\"irradiance\"",
            ),
            (self.rotate.is_some(), "rotate"),
            (self.method.trim() != "quadrature", "method=\"montecarlo\""),
            (window.is_some_and(|w| w != "none"), "window"),
        ];
        if let Some((_, what)) = clash.iter().find(|(c, _)| *c) {
            return Err(shlight_error(format!(
                "encoding=\"{e}\" keeps radiance projected by quadrature in shlight's JSON file; it cannot be combined with {what}"
            )));
        }
        Ok(e)
    }
}
