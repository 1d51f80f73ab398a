//! [`LobeCamera`]: the orthographic camera a lobe is drawn with, its
//! default view ([`default_lobe_view`]) and margin ([`LOBE_MARGIN`]).

use glam::DVec3;

use crate::map::lobe::error::LobeError;
use crate::sh::frame::Frame;

/// The picture's half-size (half the smaller side) over the lobe's radius
/// `max |f|`: the largest lobe ends 5% inside the image.
pub const LOBE_MARGIN: f64 = 1.05;

/// The view of [`render_lobe`](crate::map::render_lobe) when none is
/// given: from `(2, 1, 1)` in the z-up frame, about 24° above the equator
/// and 27° round from `+X` towards `+Y`, so `+Z` is up, `+X` points to the
/// lower left and `+Y` to the right; for a y-up file the same view of the
/// same directions turned into its frame, `(2, 1, -1)`
/// ([`Frame::rotation_to`]).
#[must_use]
pub fn default_lobe_view(frame: Frame) -> DVec3 {
    Frame::ZUp.rotation_to(frame) * DVec3::new(2.0, 1.0, 1.0)
}

/// An orthographic camera on a lobe: it looks along `-view` at the
/// origin, the frame's up axis (`+Z` z-up, `+Y` y-up) drawn up the image
/// (or, looking along that axis, `+Y` of the z-up frame turned into the
/// frame: a top view has `+X` to the right), and the image's smaller side
/// spans `2 LOBE_MARGIN radius`.
#[derive(Clone, Copy, Debug)]
pub struct LobeCamera {
    toward_eye: DVec3,
    right: DVec3,
    up: DVec3,
    width: usize,
    height: usize,
    pixel: f64,
}

impl LobeCamera {
    /// A camera on a lobe of `radius` seen from `view` (the direction
    /// from the lobe toward the eye, any length, in `frame`'s
    /// coordinates) onto a `width x height` image.
    ///
    /// # Errors
    /// `view` is zero or not finite ([`LobeError::NoDirection`]), or the
    /// size or radius is zero ([`LobeError::Empty`]).
    pub fn new(
        view: DVec3,
        frame: Frame,
        (width, height): (usize, usize),
        radius: f64,
    ) -> Result<Self, LobeError> {
        let Some(toward_eye) = view.try_normalize() else {
            return Err(LobeError::NoDirection(view));
        };
        if width == 0 || height == 0 || !(radius > 0.0 && radius.is_finite()) {
            return Err(LobeError::Empty {
                width,
                height,
                radius,
            });
        }
        let to_frame = Frame::ZUp.rotation_to(frame);
        let forward = -toward_eye;
        let across = forward.cross(to_frame * DVec3::Z);
        let right = if across.length() > 1e-9 {
            across.normalize()
        } else {
            forward.cross(to_frame * DVec3::Y).normalize()
        };
        let up = right.cross(forward);
        let pixel = 2.0 * LOBE_MARGIN * radius / width.min(height) as f64;
        Ok(Self {
            toward_eye,
            right,
            up,
            width,
            height,
            pixel,
        })
    }

    /// The unit direction toward the eye.
    #[must_use]
    pub fn toward_eye(&self) -> DVec3 {
        self.toward_eye
    }

    /// The image's right and up directions in the frame's coordinates.
    #[must_use]
    pub fn screen_axes(&self) -> (DVec3, DVec3) {
        (self.right, self.up)
    }

    /// The side of a pixel, in the lobe's units.
    #[must_use]
    pub fn pixel_size(&self) -> f64 {
        self.pixel
    }

    /// The ray through image position `(x, y)` (pixels from the top-left
    /// corner; pixel `(i, j)`'s centre is `(i + 0.5, j + 0.5)`): its
    /// origin, in the plane through the lobe's centre facing the eye, and
    /// its unit direction `-toward_eye`.
    #[must_use]
    pub fn ray(&self, x: f64, y: f64) -> (DVec3, DVec3) {
        let sx = (x - 0.5 * self.width as f64) * self.pixel;
        let sy = (0.5 * self.height as f64 - y) * self.pixel;
        (sx * self.right + sy * self.up, -self.toward_eye)
    }

    /// The image position `(x, y)` a point projects to ([`LobeCamera::ray`]'s
    /// inverse).
    #[must_use]
    pub fn project(&self, p: DVec3) -> (f64, f64) {
        (
            0.5 * self.width as f64 + p.dot(self.right) / self.pixel,
            0.5 * self.height as f64 - p.dot(self.up) / self.pixel,
        )
    }
}
