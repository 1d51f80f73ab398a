//! [`render_lobe`]: an SH function drawn as its lobe, as an [`Image`]
//! (shlight-core's [`shlight_core::map::render_lobe`] draws it).

use glam::DVec3;
use shlight_core::sh::{Frame, ShCoeffs};
use shlight_io::Image;

use crate::{PipelineError, Result};

/// `f` (scalar coefficients in `frame`) drawn as its lobe, the surface
/// `|p| = |f(p / |p|)|` coloured by sign, seen from `view` (toward the eye,
/// in `frame`; [`shlight_core::map::default_lobe_view`]) on a `width x
/// height` image: shlight-core's [`shlight_core::map::render_lobe`], whose
/// documentation states the drawing, as an [`Image`]. `on_row` is called
/// once per row.
///
/// # Errors
/// The core's [`shlight_core::map::LobeError`] (a coefficient not finite,
/// a function zero everywhere, a view with no direction, an empty
/// picture), as its message.
pub fn render_lobe(
    f: &ShCoeffs<f64>,
    frame: Frame,
    view: DVec3,
    size: (usize, usize),
    on_row: &(dyn Fn() + Sync),
) -> Result<Image> {
    let pixels = shlight_core::map::render_lobe(f, frame, view, size, on_row)
        .map_err(|e| PipelineError::new(e.to_string()))?;
    Image::new(size.0, size.1, pixels).map_err(|e| PipelineError::new(e.to_string()))
}
