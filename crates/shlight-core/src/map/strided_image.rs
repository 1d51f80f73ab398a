//! [`StridedImage`]: an environment map whose rows lie `stride` texels
//! apart in a larger buffer (a row pitch wider than the image, a crop of a
//! bigger image), projected without a copy.

use crate::map::layout::kind::{Layout, LayoutSizeError, LayoutSizeErrorKind};
use crate::map::texel_source::TexelSource;

/// A borrowed `width x height` image in a [`Layout`] whose row `y` is
/// `pixels[y * stride..y * stride + width]`, linear RGB, rows from the top.
/// A [`TexelSource`]: rows go to the projection as they lie in the buffer.
#[derive(Clone, Copy, Debug)]
pub struct StridedImage<'a> {
    layout: Layout,
    width: usize,
    height: usize,
    stride: usize,
    pixels: &'a [[f32; 3]],
}

impl<'a> StridedImage<'a> {
    /// An image after checking that `width x height` fits `layout`, that
    /// `stride >= width`, and that `pixels` holds the last row
    /// (`(height - 1) * stride + width` texels; the padding after it may be
    /// missing).
    ///
    /// # Errors
    /// [`LayoutSizeError`] when a check fails (kind
    /// [`LayoutSizeErrorKind::Stride`] for the stride and the slice).
    pub fn new(
        layout: Layout,
        width: usize,
        height: usize,
        stride: usize,
        pixels: &'a [[f32; 3]],
    ) -> Result<Self, LayoutSizeError> {
        layout.check_size(width, height)?;
        let need = (height - 1)
            .checked_mul(stride)
            .and_then(|n| n.checked_add(width));
        if stride < width || need.is_none_or(|n| pixels.len() < n) {
            return Err(LayoutSizeError {
                layout,
                width,
                height,
                kind: LayoutSizeErrorKind::Stride {
                    stride,
                    got: pixels.len(),
                },
            });
        }
        Ok(Self {
            layout,
            width,
            height,
            stride,
            pixels,
        })
    }

    /// Texels from the start of one row to the start of the next.
    #[must_use]
    pub fn stride(&self) -> usize {
        self.stride
    }
}

impl TexelSource for StridedImage<'_> {
    fn layout(&self) -> Layout {
        self.layout
    }
    fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        self.pixels[y * self.stride + x]
    }
    fn row(&self, y: usize) -> Option<&[[f32; 3]]> {
        self.pixels
            .get(y * self.stride..y * self.stride + self.width)
    }
}
