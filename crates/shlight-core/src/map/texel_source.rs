//! [`TexelSource`]: an environment map's texels in one [`Layout`], as the
//! projection reads them, whatever stores them; [`read_row`] and
//! [`contiguous_pixels`], its rows and its whole image in one slice.

use std::borrow::Cow;

use crate::map::equirect::EquirectView;
use crate::map::layout::env_map::EnvMap;
use crate::map::layout::kind::Layout;

/// Texels of an environment map in one [`Layout`], as the projection reads
/// them, whatever stores them.
///
/// A source says its layout, the size of the layout's image and the
/// radiance of texel `(x, y)`; when it stores a row contiguously it hands
/// that row out whole ([`TexelSource::row`]) and the equirect ring transform
/// reads it without a copy. The crate's own maps ([`EnvMap`],
/// [`EquirectView`]) are sources, and so are [`crate::map::StridedImage`] (rows
/// with a pitch wider than the image) and [`crate::map::CubeFaces`] (six separate
/// face images); a user's own cubemap or image type implements the trait in
/// a few lines and is projected by [`crate::map::project`] without
/// being copied into one layout first.
///
/// The image is `size().0 x size().1` texels and must fit the layout
/// ([`Layout::check_size`]; [`crate::map::project`] checks it).
/// Texel coordinates are those of the layout's image: a cube map given as six
/// faces presents itself as a [`Layout::Strip`], face `k` of
/// [`crate::map::CubeFace::ALL`] holding texels `x` in `k f..(k+1) f`.
///
/// ```
/// use shlight_core::map::{Layout, MapOrientation, TexelSource, project};
///
/// /// A grey equirect sky computed on the fly: no pixel buffer at all.
/// struct Grey;
/// impl TexelSource for Grey {
///     fn layout(&self) -> Layout {
///         Layout::Equirect
///     }
///     fn size(&self) -> (usize, usize) {
///         (64, 32)
///     }
///     fn texel(&self, _x: usize, _y: usize) -> [f32; 3] {
///         [0.5; 3]
///     }
/// }
/// let sh = project(&Grey, 2, MapOrientation::default()).unwrap();
/// // int 0.5 Y_0^0 = 0.5 * 2 sqrt(pi); the row solid angles sum to 4 pi.
/// assert!((sh[0].x - std::f64::consts::PI.sqrt()).abs() < 1e-12);
/// ```
pub trait TexelSource: Sync {
    /// How the texels are arranged.
    fn layout(&self) -> Layout;

    /// `(width, height)` of the layout's image in texels.
    fn size(&self) -> (usize, usize);

    /// Linear RGB radiance of texel `(x, y)`, `x < width`, `y < height`,
    /// counted from the top-left corner. Texels that hold no direction
    /// (unused cells of a cross, the corners of a disc image) are never
    /// read by the projection.
    fn texel(&self, x: usize, y: usize) -> [f32; 3];

    /// Row `y` as one contiguous slice of `width` texels, when the source
    /// stores it so; `None` (the default) when it does not, and the row is
    /// then read texel by texel. A slice of another length is ignored.
    fn row(&self, y: usize) -> Option<&[[f32; 3]]> {
        let _ = y;
        None
    }

    /// Every texel as one contiguous slice of `width * height`, row after
    /// row from the top, when the source stores them so; `None` (the
    /// default) when it does not. A slice of another length is ignored.
    /// Readers that need the whole image at once (Monte Carlo's bilinear
    /// lookups, a GPU upload) read it in place instead of copying it.
    fn pixels(&self) -> Option<&[[f32; 3]]> {
        None
    }
}

/// Row `y` of `source`: its own slice ([`TexelSource::row`]) when it has
/// one of `width` texels, otherwise read texel by texel into `buf`.
pub fn read_row<'a, S: TexelSource + ?Sized>(
    source: &'a S,
    y: usize,
    buf: &'a mut Vec<[f32; 3]>,
) -> &'a [[f32; 3]] {
    let w = source.size().0;
    match source.row(y) {
        Some(row) if row.len() == w => row,
        _ => {
            buf.clear();
            buf.extend((0..w).map(|x| source.texel(x, y)));
            buf
        }
    }
}

/// Every texel of `source` as one slice of `width * height`, row after row
/// from the top: borrowed where the source stores them so
/// ([`TexelSource::pixels`]), otherwise copied row by row ([`read_row`]).
#[must_use]
pub fn contiguous_pixels<S: TexelSource + ?Sized>(source: &S) -> Cow<'_, [[f32; 3]]> {
    let (w, h) = source.size();
    if let Some(pixels) = source.pixels().filter(|p| p.len() == w * h) {
        return Cow::Borrowed(pixels);
    }
    let mut copy = Vec::with_capacity(w * h);
    let mut buf = Vec::new();
    for y in 0..h {
        copy.extend_from_slice(read_row(source, y, &mut buf));
    }
    Cow::Owned(copy)
}

/// A contiguous `width * height` image: its [`Layout`], rows straight from
/// the slice. [`EnvMap::orientation`] is not part of the source; it is the
/// argument of [`crate::map::project`].
impl TexelSource for EnvMap<'_> {
    fn layout(&self) -> Layout {
        self.layout
    }
    fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        self.pixels[y * self.width + x]
    }
    fn row(&self, y: usize) -> Option<&[[f32; 3]]> {
        self.pixels.get(y * self.width..(y + 1) * self.width)
    }
    fn pixels(&self) -> Option<&[[f32; 3]]> {
        Some(self.pixels)
    }
}

/// A contiguous equirect image, rows straight from the slice.
impl TexelSource for EquirectView<'_> {
    fn layout(&self) -> Layout {
        Layout::Equirect
    }
    fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }
    fn texel(&self, x: usize, y: usize) -> [f32; 3] {
        self.pixels[y * self.width + x]
    }
    fn row(&self, y: usize) -> Option<&[[f32; 3]]> {
        self.pixels.get(y * self.width..(y + 1) * self.width)
    }
    fn pixels(&self) -> Option<&[[f32; 3]]> {
        Some(self.pixels)
    }
}
