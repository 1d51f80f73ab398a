//! The in-memory image: linear RGB, `f32` per channel.

use std::fmt;

/// A rectangular image of linear, scene-referred Rec.709 RGB pixels.
///
/// Pixels are stored row-major with row 0 at the top and column 0 at the
/// left; the pixel at column `x`, row `y` is `pixels()[y * width + x]`.
/// Values are linear light (no transfer curve) and unbounded: HDR values above
/// 1, and even negative or non-finite values, can be present after reading a
/// file (see [`Image::stats`] and [`Image::sanitize`]).
///
/// An image may have a width or height of 0 (no pixels); such an image cannot
/// be written to a file.
#[derive(Clone, PartialEq)]
pub struct Image {
    width: usize,
    height: usize,
    pixels: Vec<[f32; 3]>,
}

/// Lists the pixels of small images only (at most 64), so that a failed
/// `assert_eq!` on a large image stays readable.
impl fmt::Debug for Image {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut debug = f.debug_struct("Image");
        debug
            .field("width", &self.width)
            .field("height", &self.height);
        if self.pixels.len() <= 64 {
            debug.field("pixels", &self.pixels);
        } else {
            debug.field("stats", &self.stats());
        }
        debug.finish()
    }
}

/// The error of [`Image::new`]: the pixel count does not match the size.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{len} pixels given for a {width}x{height} image")]
pub struct PixelCountError {
    /// The width asked for.
    pub width: usize,
    /// The height asked for.
    pub height: usize,
    /// The number of pixels given.
    pub len: usize,
}

impl Image {
    /// An image from row-major pixels (row 0 at the top).
    ///
    /// # Errors
    /// [`PixelCountError`] when `pixels.len() != width * height` (or that
    /// product overflows).
    pub fn new(
        width: usize,
        height: usize,
        pixels: Vec<[f32; 3]>,
    ) -> Result<Self, PixelCountError> {
        if width.checked_mul(height) != Some(pixels.len()) {
            return Err(PixelCountError {
                width,
                height,
                len: pixels.len(),
            });
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// An image whose pixel at column `x`, row `y` is `f(x, y)`; `f` is
    /// called in row-major order.
    ///
    /// # Panics
    /// When `width * height` overflows `usize`.
    #[must_use]
    pub fn from_fn(
        width: usize,
        height: usize,
        mut f: impl FnMut(usize, usize) -> [f32; 3],
    ) -> Self {
        let len = width
            .checked_mul(height)
            .expect("image size overflows usize");
        let mut pixels = Vec::with_capacity(len);
        for y in 0..height {
            for x in 0..width {
                pixels.push(f(x, y));
            }
        }
        Self {
            width,
            height,
            pixels,
        }
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> usize {
        self.height
    }

    /// Whether the image has no pixels (a width or height of 0).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.pixels.is_empty()
    }

    /// All pixels, row-major, row 0 at the top.
    #[must_use]
    pub fn pixels(&self) -> &[[f32; 3]] {
        &self.pixels
    }

    /// All pixels, mutable, row-major, row 0 at the top.
    #[must_use]
    pub fn pixels_mut(&mut self) -> &mut [[f32; 3]] {
        &mut self.pixels
    }

    /// The pixels of row `y` (0 at the top), left to right.
    ///
    /// # Panics
    /// When `y >= height`.
    #[must_use]
    pub fn row(&self, y: usize) -> &[[f32; 3]] {
        assert!(
            y < self.height,
            "row {y} outside a {}-row image",
            self.height
        );
        &self.pixels[y * self.width..(y + 1) * self.width]
    }

    /// The pixel at column `x`, row `y` (0, 0 is the top left).
    ///
    /// # Panics
    /// When `x >= width` or `y >= height`.
    #[must_use]
    pub fn get(&self, x: usize, y: usize) -> [f32; 3] {
        self.pixels[self.index(x, y)]
    }

    /// Sets the pixel at column `x`, row `y`.
    ///
    /// # Panics
    /// When `x >= width` or `y >= height`.
    pub fn set(&mut self, x: usize, y: usize, value: [f32; 3]) {
        let i = self.index(x, y);
        self.pixels[i] = value;
    }

    /// The pixels, giving up the image.
    #[must_use]
    pub fn into_pixels(self) -> Vec<[f32; 3]> {
        self.pixels
    }

    fn index(&self, x: usize, y: usize) -> usize {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside a {}x{} image",
            self.width,
            self.height
        );
        y * self.width + x
    }
}
