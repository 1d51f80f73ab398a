//! The projection step of `shlight project`: the library's
//! ([`shlight_pipeline::project_radiance`]), or the GPU's for `--gpu`.

use anyhow::{Result, anyhow};
use shlight_core::map::{EnvMap, Layout};
use shlight_io::Image;
use shlight_pipeline::{Projection, project_radiance};

use super::settings::Settings;

/// Projects `image` in `layout`: on the GPU for `--gpu` (equirect maps,
/// quadrature), otherwise by [`project_radiance`] (quadrature or Monte
/// Carlo).
pub fn project_map(image: &Image, layout: Layout, s: &Settings<'_>) -> Result<Projection> {
    let (width, height, pixels) = (image.width(), image.height(), image.pixels());
    let map =
        EnvMap::new(layout, s.orientation, width, height, pixels).map_err(|e| anyhow!("{e}"))?;
    #[cfg(feature = "gpu")]
    if let Some((ctx, projector)) = &s.gpu {
        if layout != Layout::Equirect {
            anyhow::bail!(
                "--gpu projects equirect maps; this one is {}",
                layout.name()
            );
        }
        let view = shlight_core::map::EquirectView {
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
    Ok(project_radiance(&map, &s.project))
}
