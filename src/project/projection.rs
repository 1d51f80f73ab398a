//! The projection step of `shlight project`: the place where layouts and
//! methods (quadrature, Monte Carlo, the GPU) meet.

use anyhow::{Result, anyhow};
use glam::DVec3;
use shlight_core::ShCoeffs;
use shlight_core::layout::{EnvMap, Layout};
use shlight_core::montecarlo::{ImportanceGrid, McOptions, project_montecarlo};
use shlight_io::Image;

use super::settings::Settings;

/// Radiance coefficients of a map, and what the method reports about them.
pub struct Projection {
    pub coeffs: ShCoeffs<DVec3>,
    /// Standard error per coefficient (Monte Carlo).
    pub std_error: Option<ShCoeffs<DVec3>>,
    pub samples: Option<u64>,
    pub seed: Option<u64>,
    pub sampler: Option<String>,
}

/// The projection step: the place where layouts and methods meet.
///
/// Quadrature sums texel × basis × exact texel solid angle
/// ([`shlight_core::projection::project_map`]). Monte Carlo looks the map up bilinearly
/// ([`EnvMap::radiance_bilinear`]) and, for importance sampling, draws from
/// [`ImportanceGrid::from_equirect`] over an equirect map's texels, or from
/// [`ImportanceGrid::from_map`] on a grid of the map's size otherwise.
pub fn project_map(image: &Image, layout: Layout, s: &Settings<'_>) -> Result<Projection> {
    let (width, height, pixels) = (image.width(), image.height(), image.pixels());
    let map =
        EnvMap::new(layout, s.orientation, width, height, pixels).map_err(|e| anyhow!("{e}"))?;
    #[cfg(feature = "gpu")]
    if let (None, Some((ctx, projector))) = (&s.montecarlo, &s.gpu) {
        if layout != Layout::Equirect {
            anyhow::bail!(
                "--gpu projects equirect maps; this one is {}",
                layout.name()
            );
        }
        let view = shlight_core::projection::EquirectView {
            width,
            height,
            pixels,
        };
        return Ok(Projection {
            coeffs: projector.project(ctx, view, s.args.lmax, s.orientation)?,
            std_error: None,
            samples: None,
            seed: None,
            sampler: None,
        });
    }
    Ok(match &s.montecarlo {
        None => Projection {
            coeffs: shlight_core::projection::project_map(&map, s.args.lmax),
            std_error: None,
            samples: None,
            seed: None,
            sampler: None,
        },
        Some((options, kind)) => {
            let sampler = kind.sampler(|| match layout {
                Layout::Equirect => {
                    ImportanceGrid::from_equirect(width, height, pixels, s.orientation)
                }
                _ => {
                    // About as many cells as texels, 2:1 like the grid's φ x θ.
                    let rows = ((width * height) as f64 / 2.0).sqrt().ceil().max(1.0) as usize;
                    ImportanceGrid::from_map(&map, 2 * rows, rows, s.orientation)
                }
            });
            let options = McOptions {
                sampler,
                ..options.clone()
            };
            let estimate = project_montecarlo(&map, &options);
            Projection {
                coeffs: estimate.coeffs,
                std_error: Some(estimate.std_error),
                samples: Some(estimate.samples as u64),
                seed: Some(options.seed),
                sampler: Some(options.sampler.name().to_string()),
            }
        }
    })
}
