//! Geometric operations on an [`Image`]: crop, flips, quarter-turn
//! rotations, and halving.
//!
//! All but [`Image::halve`] move pixels without resampling, so they are
//! exact. All of them return a new image; the source is left as it is.

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

    /// The image at half the size (rounded up), each pixel the mean of the
    /// up to 2x2 pixels it covers (an odd last column or row averages what
    /// it has). For textures that must fit a GPU's size limit.
    #[must_use]
    pub fn halve(&self) -> Image {
        let (w, h) = (self.width(), self.height());
        Image::from_fn(w.div_ceil(2), h.div_ceil(2), |x, y| {
            let mut sum = [0.0f32; 3];
            let mut n = 0.0f32;
            for (sx, sy) in [
                (2 * x, 2 * y),
                (2 * x + 1, 2 * y),
                (2 * x, 2 * y + 1),
                (2 * x + 1, 2 * y + 1),
            ] {
                if sx < w && sy < h {
                    let p = self.get(sx, sy);
                    sum = [sum[0] + p[0], sum[1] + p[1], sum[2] + p[2]];
                    n += 1.0;
                }
            }
            sum.map(|s| s / n)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halving_averages_two_by_two_blocks_and_keeps_odd_edges() {
        // 3x3: values 0..9 row by row.
        let image = Image::from_fn(3, 3, |x, y| [(y * 3 + x) as f32, 1.0, -2.0]);
        let half = image.halve();
        assert_eq!((half.width(), half.height()), (2, 2));
        assert_eq!(half.get(0, 0), [(0.0 + 1.0 + 3.0 + 4.0) / 4.0, 1.0, -2.0]);
        assert_eq!(half.get(1, 0), [(2.0 + 5.0) / 2.0, 1.0, -2.0]);
        assert_eq!(half.get(0, 1), [(6.0 + 7.0) / 2.0, 1.0, -2.0]);
        assert_eq!(half.get(1, 1), [8.0, 1.0, -2.0]);
        let one = Image::from_fn(1, 1, |_, _| [5.0; 3]).halve();
        assert_eq!((one.width(), one.height(), one.get(0, 0)), (1, 1, [5.0; 3]));
    }
}
