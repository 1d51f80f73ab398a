//! Geometric operations on an [`Image`]: crop, flips, quarter-turn rotations.
//!
//! They move pixels without resampling, so they are exact. All of them
//! return a new image; the source is left as it is.

use crate::Image;

impl Image {
    /// The `width` x `height` rectangle whose top-left pixel is at column
    /// `x`, row `y`; `None` when that rectangle is not inside the image.
    ///
    /// Used to cut the six faces out of a cube-map cross.
    #[must_use]
    pub fn crop(&self, x: usize, y: usize, width: usize, height: usize) -> Option<Image> {
        let inside = x.checked_add(width).is_some_and(|end| end <= self.width())
            && y.checked_add(height)
                .is_some_and(|end| end <= self.height());
        if !inside {
            return None;
        }
        Some(Image::from_fn(width, height, |cx, cy| {
            self.get(x + cx, y + cy)
        }))
    }

    /// The mirror image left to right: column `x` becomes column
    /// `width - 1 - x`.
    #[must_use]
    pub fn flip_horizontal(&self) -> Image {
        let w = self.width();
        Image::from_fn(w, self.height(), |x, y| self.get(w - 1 - x, y))
    }

    /// The mirror image top to bottom: row `y` becomes row `height - 1 - y`.
    #[must_use]
    pub fn flip_vertical(&self) -> Image {
        let h = self.height();
        Image::from_fn(self.width(), h, |x, y| self.get(x, h - 1 - y))
    }

    /// The image turned a quarter turn clockwise; width and height swap.
    ///
    /// The top-left pixel ends at the top right, and the bottom-left pixel at
    /// the top left. See also [`Image::rotate270`], its inverse.
    #[must_use]
    pub fn rotate90(&self) -> Image {
        let h = self.height();
        Image::from_fn(h, self.width(), |x, y| self.get(y, h - 1 - x))
    }

    /// The image turned half a turn; the same as flipping both ways.
    #[must_use]
    pub fn rotate180(&self) -> Image {
        let (w, h) = (self.width(), self.height());
        Image::from_fn(w, h, |x, y| self.get(w - 1 - x, h - 1 - y))
    }

    /// The image turned a quarter turn counter-clockwise (three quarter turns
    /// clockwise); width and height swap.
    ///
    /// The top-left pixel ends at the bottom left. See also
    /// [`Image::rotate90`], its inverse.
    #[must_use]
    pub fn rotate270(&self) -> Image {
        let w = self.width();
        Image::from_fn(self.height(), w, |x, y| self.get(w - 1 - y, x))
    }
}
