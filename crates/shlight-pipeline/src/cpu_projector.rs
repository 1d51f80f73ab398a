//! [`CpuProjector`]: the library's projection step on the CPU, the place
//! where layouts and methods meet ([`project_radiance`],
//! [`project_radiance_texels`]).

use shlight_core::map::montecarlo::{ImportanceGrid, McOptions, project_montecarlo};
use shlight_core::map::{EnvMap, Layout, TexelSource, contiguous_pixels};

use crate::load::env_map;
use crate::projector::{Projection, Projector};
use crate::settings::{Method, ProjectSettings};
use crate::{PipelineError, Result};

/// The library's projection on the CPU ([`project_radiance_texels`]):
/// quadrature or Monte Carlo, on every core.
#[derive(Clone, Copy, Debug, Default)]
pub struct CpuProjector;

impl Projector for CpuProjector {
    fn project(&self, texels: &dyn TexelSource, s: &ProjectSettings) -> Result<Projection> {
        project_radiance_texels(texels, s)
    }

    /// Quadrature: the ring sums fed rows give
    /// [`shlight_core::map::project`]'s coefficients bit for bit.
    fn projects_rows(&self, s: &ProjectSettings) -> bool {
        s.method == Method::Quadrature
    }
}

/// Projects `map` by the settings' method to radiance coefficients.
///
/// Quadrature sums texel × basis × exact texel solid angle
/// ([`shlight_core::map::project_map`]). Monte Carlo looks the map
/// up bilinearly ([`EnvMap::radiance_bilinear`]) and, for importance
/// sampling, draws from [`ImportanceGrid::from_equirect`] over an equirect
/// map's texels, or from [`ImportanceGrid::from_map`] on a grid of about as
/// many cells as texels (2:1, like the grid's `φ x θ`) otherwise.
#[must_use]
pub fn project_radiance(map: &EnvMap<'_>, s: &ProjectSettings) -> Projection {
    match &s.method {
        Method::Quadrature => Projection::exact(shlight_core::map::project_map(map, s.lmax)),
        Method::MonteCarlo { options, sampler } => {
            let (width, height) = (map.width, map.height);
            let sampler = sampler.sampler(|| match map.layout {
                Layout::Equirect => {
                    ImportanceGrid::from_equirect(width, height, map.pixels, map.orientation)
                }
                _ => {
                    let rows = ((width * height) as f64 / 2.0).sqrt().ceil().max(1.0) as usize;
                    ImportanceGrid::from_map(map, 2 * rows, rows, map.orientation)
                }
            });
            let options = McOptions {
                lmax: s.lmax,
                sampler,
                ..options.clone()
            };
            let estimate = project_montecarlo(map, &options);
            Projection {
                coeffs: estimate.coeffs,
                std_error: Some(estimate.std_error),
                samples: Some(estimate.samples as u64),
                seed: Some(options.seed),
                sampler: Some(options.sampler.name().to_string()),
            }
        }
    }
}

/// [`project_radiance`] of any [`TexelSource`] (read in place, whatever
/// stores it), read in the settings' orientation. Quadrature reads the
/// source through [`shlight_core::map::project`], which gives the
/// same coefficients bit for bit as a contiguous map of the same texels;
/// Monte Carlo looks texels up bilinearly and needs them contiguous: it
/// reads them in place where the source holds them so, and copies them
/// otherwise ([`contiguous_pixels`]).
///
/// # Errors
/// The source's size does not fit its layout.
pub fn project_radiance_texels<S: TexelSource + ?Sized>(
    source: &S,
    s: &ProjectSettings,
) -> Result<Projection> {
    let (w, h) = source.size();
    match &s.method {
        Method::Quadrature => {
            let coeffs = shlight_core::map::project(source, s.lmax, s.orientation)
                .map_err(|e| PipelineError::new(e.to_string()))?;
            Ok(Projection::exact(coeffs))
        }
        Method::MonteCarlo { .. } => {
            source
                .layout()
                .check_size(w, h)
                .map_err(|e| PipelineError::new(e.to_string()))?;
            let pixels = contiguous_pixels(source);
            let map = env_map(source.layout(), s.orientation, (w, h), &pixels)?;
            Ok(project_radiance(&map, s))
        }
    }
}
