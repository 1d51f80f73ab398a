//! [`Projector`]: the projection step as [`crate::project`] calls it, and
//! [`Projection`], what it gives.

use glam::DVec3;
use shlight_core::map::TexelSource;
use shlight_core::sh::ShCoeffs;

use crate::Result;
use crate::settings::ProjectSettings;

/// The projection step, injected: the library's own on the CPU
/// ([`crate::CpuProjector`]), or another (the command line's GPU projector) that
/// the pipeline need not know.
pub trait Projector: Sync {
    /// Radiance coefficients of `texels`, read in `s.orientation`, to
    /// `s.lmax` by `s.method`.
    ///
    /// # Errors
    /// The projector cannot project this map (its layout, size or method).
    fn project(&self, texels: &dyn TexelSource, s: &ProjectSettings) -> Result<Projection>;

    /// Whether [`crate::project`] may compute this projection itself from
    /// an equirect map file's rows as they are decoded, with no image
    /// buffer, instead of calling [`Projector::project`] on the whole map:
    /// true only where that gives this projector's result bit for bit.
    /// `false` by default.
    fn projects_rows(&self, s: &ProjectSettings) -> bool {
        let _ = s;
        false
    }
}

/// Radiance coefficients of a map, and what the method reports about them.
#[derive(Clone, Debug, PartialEq)]
pub struct Projection {
    /// Radiance coefficients to the settings' lmax, in the map's frame.
    pub coeffs: ShCoeffs<DVec3>,
    /// Standard error per coefficient (Monte Carlo).
    pub std_error: Option<ShCoeffs<DVec3>>,
    /// Monte Carlo directions used.
    pub samples: Option<u64>,
    /// Monte Carlo seed.
    pub seed: Option<u64>,
    /// Monte Carlo sampler name.
    pub sampler: Option<String>,
}

impl Projection {
    /// The coefficients of an exact method (quadrature): no standard
    /// errors, no samples.
    #[must_use]
    pub fn exact(coeffs: ShCoeffs<DVec3>) -> Self {
        Self {
            coeffs,
            std_error: None,
            samples: None,
            seed: None,
            sampler: None,
        }
    }
}
