//! [`LobeError`]: why a lobe cannot be drawn.

use core::fmt;

use glam::DVec3;

/// Why [`render_lobe`](crate::map::render_lobe) (or the surface or camera
/// it draws with) refuses its input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LobeError {
    /// A coefficient of the function is not finite.
    NotFinite,
    /// The function is zero everywhere: its lobe is a point.
    Zero,
    /// The view (the direction from the lobe toward the eye) is zero or
    /// not finite.
    NoDirection(DVec3),
    /// The picture has no pixels, or the lobe no finite radius.
    Empty {
        /// The picture's width in pixels.
        width: usize,
        /// The picture's height in pixels.
        height: usize,
        /// The lobe's radius.
        radius: f64,
    },
}

impl fmt::Display for LobeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LobeError::NotFinite => f.write_str("a coefficient is not finite: no lobe to draw"),
            LobeError::Zero => {
                f.write_str("the function is zero everywhere: its lobe is a point, nothing to draw")
            }
            LobeError::NoDirection(view) => write!(
                f,
                "the view {},{},{} has no direction: give the direction from the lobe toward the eye, e.g. 2,1,1",
                view.x, view.y, view.z
            ),
            LobeError::Empty {
                width,
                height,
                radius,
            } => write!(
                f,
                "a lobe picture needs a size and a radius (got {width}x{height}, radius {radius})"
            ),
        }
    }
}

impl std::error::Error for LobeError {}
