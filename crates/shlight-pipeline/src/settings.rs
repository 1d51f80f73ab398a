//! [`Settings`]: everything [`crate::project`] does with a map, decided
//! before it is read: [`ProjectSettings`] (lmax, orientation, method,
//! window, rotation, quantity), [`ReadSettings`] (how input files are
//! read), the encoding kept and the [`Preview`] written.

use std::path::PathBuf;

use crate::preview::PreviewOptions;
use crate::read_settings::ReadSettings;
use glam::DMat3;
use shlight_core::encoding::Encoding;
use shlight_core::map::MapOrientation;
use shlight_core::map::montecarlo::{McOptions, SamplerKind};
use shlight_core::sh::Window;
use shlight_format::{Quantity, RotationRecord};

/// Monte Carlo directions drawn when no count is given.
pub const DEFAULT_SAMPLES: usize = 1 << 16;

/// How the coefficients are computed.
#[derive(Clone, Debug, PartialEq)]
pub enum Method {
    /// Exact texel-solid-angle quadrature over every texel
    /// ([`shlight_core::map::project`]).
    Quadrature,
    /// Monte Carlo integration of the bilinearly interpolated map
    /// ([`shlight_core::map::montecarlo::project_montecarlo`]), with standard
    /// errors. `options.sampler` is replaced per map by `sampler`'s
    /// sampler (importance sampling needs the map).
    MonteCarlo {
        /// lmax, samples and seed (the sampler is set per map).
        options: McOptions,
        /// How directions are drawn.
        sampler: SamplerKind,
    },
}

impl Method {
    /// The method's name in files and on the command line
    /// (`quadrature`, `montecarlo`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Method::Quadrature => "quadrature",
            Method::MonteCarlo { .. } => "montecarlo",
        }
    }
}

/// Everything a projection decides before any input is read.
#[derive(Clone, Debug)]
pub struct ProjectSettings {
    /// Highest SH degree kept.
    pub lmax: usize,
    /// How the map's texels meet world directions (frame, mirroring).
    pub orientation: MapOrientation,
    /// Quadrature or Monte Carlo.
    pub method: Method,
    /// The ringing window for all three channels; `None` chooses one per
    /// channel (`auto`: [`crate::choose_windows`]).
    pub window: Option<Window>,
    /// A rotation of the result: the record for the file and the matrix
    /// `R` (a light from `a` comes from `R a` afterwards).
    pub rotation: Option<(RotationRecord, DMat3)>,
    /// What the coefficients hold.
    pub quantity: Quantity,
}

impl ProjectSettings {
    /// Settings with no window ([`Window::None`]) and no rotation.
    #[must_use]
    pub fn new(
        lmax: usize,
        orientation: MapOrientation,
        method: Method,
        quantity: Quantity,
    ) -> Self {
        Self {
            lmax,
            orientation,
            method,
            window: Some(Window::None),
            rotation: None,
            quantity,
        }
    }
}

/// `--preview`: the three-panel picture of a projection, and where it goes.
#[derive(Clone, Debug)]
pub struct Preview {
    /// The image file written.
    pub path: PathBuf,
    /// Panel size, exposure, tone map.
    pub options: PreviewOptions,
}

/// Everything [`crate::project`] does with a map, decided before it is read.
#[derive(Clone, Debug)]
pub struct Settings {
    /// How files are read (layout, reader options, `--sanitize`); texels in
    /// memory use only `sanitize`.
    pub read: ReadSettings,
    /// lmax, orientation, method, window, rotation, quantity.
    pub project: ProjectSettings,
    /// The light kept as this encoding of the map's texels
    /// ([`Encoding::Sh`]: plain SH, the coefficients as projected).
    pub encoding: Encoding,
    /// A preview to write, if any.
    pub preview: Option<Preview>,
}

impl Settings {
    /// Plain SH by `project`'s settings, files read with the defaults, no
    /// preview.
    #[must_use]
    pub fn new(project: ProjectSettings) -> Self {
        Self {
            read: ReadSettings::default(),
            project,
            encoding: Encoding::Sh,
            preview: None,
        }
    }
}
