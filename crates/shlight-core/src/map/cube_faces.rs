//! [`CubeFaces`]: a cube map as six separate face images (six files, a GPU
//! cubemap's layers), projected without being assembled into a cross or a
//! strip.

use crate::map::layout::cube::CubeFace;
use crate::map::layout::kind::{Layout, LayoutSizeError, LayoutSizeErrorKind};
use crate::map::texel_source::TexelSource;

/// Six borrowed `f x f` face images in [`CubeFace::ALL`] order
/// (`+X -X +Y -Y +Z -Z`), each row-major from its top-left corner in the
/// face orientation of [`CubeFace`] (OpenGL / Vulkan / D3D sampling), linear
/// RGB.
///
/// As a [`TexelSource`] the faces are a [`Layout::Strip`] of `6f x f`
/// texels, face `k` at `x` in `k f..(k+1) f`: the directions, solid angles
/// and sums are those of the same faces laid out as a strip image, and so
/// is the projection, bit for bit.
#[derive(Clone, Copy, Debug)]
pub struct CubeFaces<'a> {
    size: usize,
    faces: [&'a [[f32; 3]]; 6],
}

impl<'a> CubeFaces<'a> {
    /// The faces after checking that `size > 0` and that every face holds
    /// `size * size` texels.
    ///
    /// # Errors
    /// [`LayoutSizeError`] for the strip of these faces: kind
    /// [`LayoutSizeErrorKind::Empty`] for `size == 0`,
    /// [`LayoutSizeErrorKind::FacePixelCount`] naming the first face of the
    /// wrong size.
    pub fn new(size: usize, faces: [&'a [[f32; 3]]; 6]) -> Result<Self, LayoutSizeError> {
        let width = size.saturating_mul(6);
        let error = |kind| LayoutSizeError {
            layout: Layout::Strip,
            width,
            height: size,
            kind,
        };
        if width.checked_mul(size).is_none() {
            return Err(error(LayoutSizeErrorKind::TooLarge));
        }
        Layout::Strip.check_size(width, size)?;
        for (face, px) in CubeFace::ALL.into_iter().zip(faces) {
            if px.len() != size * size {
                return Err(error(LayoutSizeErrorKind::FacePixelCount {
                    face,
                    got: px.len(),
                }));
            }
        }
        Ok(Self { size, faces })
    }

    /// Texels along a face's edge, `f`.
    #[must_use]
    pub fn face_size(&self) -> usize {
        self.size
    }

    /// The image of `face`, `f * f` texels.
    #[must_use]
    pub fn face(&self, face: CubeFace) -> &'a [[f32; 3]] {
        self.faces[face.index()]
    }
}

impl TexelSource for CubeFaces<'_> {
    fn layout(&self) -> Layout {
        Layout::Strip
    }
    fn size(&self) -> (usize, usize) {
        Layout::Strip.dimensions(self.size)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        let f = self.size;
        self.faces[x / f][y * f + x % f]
    }
}
