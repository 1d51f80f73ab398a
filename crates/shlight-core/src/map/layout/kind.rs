//! [`Layout`]: which arrangement of texels an environment-map image uses,
//! its name, the image sizes it accepts, where cube faces sit in it, and the
//! errors of parsing a name and checking a size.

use core::fmt;
use core::str::FromStr;

use super::cube::{CubeFace, FaceCell};

/// How an environment map's texels are arranged in its image (the table
/// below).
///
/// Named `equirect`, `cross-h`, `cross-v`, `strip`, `angular`,
/// `mirror-ball` ([`FromStr`], [`fmt::Display`]).
///
/// An [`EnvMap`](crate::map::EnvMap) is a borrowed image of linear RGB
/// texels, row-major from the top-left, in one [`Layout`]. Every texel that
/// holds a direction has a unit world direction
/// ([`EnvMap::texel_direction`](crate::map::EnvMap::texel_direction), at
/// the texel's centre) and the exact solid angle it covers
/// ([`EnvMap::texel_solid_angle`](crate::map::EnvMap::texel_solid_angle));
/// [`crate::map::project`] sums `f(texel) Y(centre) Ω(texel)` in `f64` and
/// [`crate::map::render_map`] draws a function into any layout. A
/// [`TexelGrid`](crate::map::TexelGrid) is the same geometry without pixels:
/// texel directions, points inside texels, solid angles and the texel a
/// direction falls in, for drawing maps.
///
/// # Map frame
///
/// Each layout first gives a direction `d` in the map's own **y-up** frame;
/// the map's [`MapOrientation`](crate::map::MapOrientation) then takes it to the world exactly as for
/// equirect maps ([`crate::map::equirect_direction`]):
/// `mirror` negates the map-frame `z` (for the equirect layout that is
/// `φ -> -φ`), then `frame` applies `Frame::YUp.rotation_to(frame)`
/// (`Frame::ZUp`: the y-up sphere turned `+90°` about X,
/// `(x, y, z) -> (x, -z, y)`).
///
/// | layout | size | map-frame direction |
/// |---|---|---|
/// | `equirect` | any `W x H` (2:1 usual) | `(sin θ cos φ, cos θ, sin θ sin φ)`, `θ = π v`, `φ = 2π (u - 1/2)` (docs/conventions.md) |
/// | `cross-h` | `4f x 3f` | cells: row 0 col 1 `+Y`; row 1 `-X +Z +X -Z`; row 2 col 1 `-Y` |
/// | `cross-v` | `3f x 4f` | row 0 col 1 `+Y`; row 1 `-X +Z +X`; row 2 col 1 `-Y`; row 3 col 1 `-Z` turned 180° |
/// | `strip` | `6f x f` | `+X -X +Y -Y +Z -Z` left to right ([`CubeFace::ALL`]) |
/// | `angular` | `N x N` | `(sin(πr) u/r, sin(πr) v/r, -cos(πr))`: centre `-Z`, right `+X`, up `+Y`, rim `+Z` |
/// | `mirror-ball` | `N x N` | `n = (u, v, sqrt(1-r²))`, `d = (2 n_z u, 2 n_z v, 2 n_z² - 1)`: centre `+Z`, rim `-Z` |
///
/// Cube faces follow the OpenGL / Vulkan / D3D sampling convention (table on
/// [`CubeFace`]); with these cells every seam inside a cross joins texels of
/// neighbouring directions. Disc layouts use `u = 2(x + 1/2)/N - 1` to the
/// right and `v = 1 - 2(y + 1/2)/N` up, `r = |(u, v)|`: the disc inscribed
/// in the square image. Image coordinates are in pixels from the top-left
/// corner with texel centres at `+0.5`.
///
/// # Which texels hold a direction
///
/// Unused cells of a cross hold none. A disc texel holds one when its
/// square meets the open disc. Texels whose centre lies inside the disc
/// carry the direction of the centre. **Rim texels** (centre outside, square
/// partly inside) carry the direction of the rim, a single point of the
/// sphere ([`Layout::Angular`] `+Z`, [`Layout::MirrorBall`] `-Z`, before the
/// orientation), and the solid angle of their part inside the disc, so the
/// quadrature's weights sum to exactly `4π` and constants project exactly.
/// Images that left these texels black (sampled at the centre only) lose
/// that solid angle: `2e-5 sr` for an angular map of `N = 512` but
/// `1.2e-2 sr` for a mirror ball, whose rim squeezes a whole cap around
/// `-Z` into a thin ring (measured in `tests/layout.rs`).
///
/// # Solid angles
///
/// Equirect rows: [`crate::map::equirect_row_solid_angle`]. Cube
/// texels: [`crate::map::cube_texel_solid_angle`] (closed form). Disc texels integrate
/// `dω = w(r) dA` over the texel's part of the unit disc, `w = π sin(πr)/r`
/// for the angular map (`θ = πr` from `-Z`) and `w = 4` for the mirror ball
/// (`θ = 2 asin r` from `+Z`): interior texels by a tensor Gauss-Legendre
/// rule whose error bound is below `1e-17 π² h²`, texels the rim cuts in
/// polar coordinates with the radial integral in closed form and the
/// angle range cut wherever the integrand has a kink. Every layout's solid
/// angles sum to `4π` within `1e-12` (tests).
///
/// # Example
/// ```
/// use glam::DVec3;
/// use shlight_core::map::{EnvMap, Layout, MapOrientation, project_map, render_map};
///
/// let o = MapOrientation::default();
/// let layout: Layout = "cross-h".parse().unwrap();
/// let (w, h) = layout.dimensions(32); // faces of 32 x 32 texels
/// let pixels = render_map(layout, o, w, h, |d| DVec3::splat(1.0 + d.y)).unwrap();
/// let map = EnvMap::new(layout, o, w, h, &pixels).unwrap();
/// let sh = project_map(&map, 2);
/// // The weights sum to 4 pi and y cancels between opposite texels, so the
/// // constant term is exact up to the f32 pixels: int 1 Y_0^0 = 2 sqrt(pi).
/// assert!((sh[0].x - 2.0 * std::f64::consts::PI.sqrt()).abs() < 1e-6);
/// // int y Y_1^-1 = -sqrt(4 pi / 3), to the quadrature's O(h^2).
/// assert!((sh[1].x + (4.0 * std::f64::consts::PI / 3.0).sqrt()).abs() < 1e-3);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    /// Equirectangular (latitude-longitude), usually 2:1.
    Equirect,
    /// Horizontal cube cross, `4 x 3` cells of square faces.
    CrossHorizontal,
    /// Vertical cube cross, `3 x 4` cells, `-Z` at the bottom turned 180°.
    CrossVertical,
    /// Horizontal strip of the six faces `+X -X +Y -Y +Z -Z`, `6 x 1` cells.
    Strip,
    /// Debevec's angular map (light probe): `θ = π r` from the centre.
    Angular,
    /// Orthographic photograph of a mirror ball.
    MirrorBall,
}

/// Cells of the horizontal cross: `(col, row, face, rotated)`.
const CROSS_H: [(usize, usize, CubeFace, bool); 6] = [
    (1, 0, CubeFace::PosY, false),
    (0, 1, CubeFace::NegX, false),
    (1, 1, CubeFace::PosZ, false),
    (2, 1, CubeFace::PosX, false),
    (3, 1, CubeFace::NegZ, false),
    (1, 2, CubeFace::NegY, false),
];

/// Cells of the vertical cross: `(col, row, face, rotated)`.
const CROSS_V: [(usize, usize, CubeFace, bool); 6] = [
    (1, 0, CubeFace::PosY, false),
    (0, 1, CubeFace::NegX, false),
    (1, 1, CubeFace::PosZ, false),
    (2, 1, CubeFace::PosX, false),
    (1, 2, CubeFace::NegY, false),
    (1, 3, CubeFace::NegZ, true),
];

/// Cells of the strip: `(col, row, face, rotated)`.
const STRIP: [(usize, usize, CubeFace, bool); 6] = [
    (0, 0, CubeFace::PosX, false),
    (1, 0, CubeFace::NegX, false),
    (2, 0, CubeFace::PosY, false),
    (3, 0, CubeFace::NegY, false),
    (4, 0, CubeFace::PosZ, false),
    (5, 0, CubeFace::NegZ, false),
];

impl Layout {
    /// Every layout, in the order of their names in error messages.
    pub const ALL: [Layout; 6] = [
        Layout::Equirect,
        Layout::CrossHorizontal,
        Layout::CrossVertical,
        Layout::Strip,
        Layout::Angular,
        Layout::MirrorBall,
    ];

    /// The layout's name: `equirect`, `cross-h`, `cross-v`, `strip`,
    /// `angular` or `mirror-ball`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Layout::Equirect => "equirect",
            Layout::CrossHorizontal => "cross-h",
            Layout::CrossVertical => "cross-v",
            Layout::Strip => "strip",
            Layout::Angular => "angular",
            Layout::MirrorBall => "mirror-ball",
        }
    }

    /// Guesses the layout of a `width x height` image from its exact aspect
    /// ratio: `2:1` equirect, `4:3` horizontal cross, `3:4` vertical cross,
    /// `6:1` strip, `1:1` **angular map**. A square image may equally be a
    /// mirror ball; that must be asked for explicitly. `None` for other
    /// ratios and empty images. A detected layout always passes
    /// [`Layout::check_size`].
    #[must_use]
    pub fn detect(width: usize, height: usize) -> Option<Layout> {
        let (w, h) = (width as u128, height as u128);
        if w == 0 || h == 0 {
            None
        } else if w == 2 * h {
            Some(Layout::Equirect)
        } else if 3 * w == 4 * h {
            Some(Layout::CrossHorizontal)
        } else if 4 * w == 3 * h {
            Some(Layout::CrossVertical)
        } else if w == 6 * h {
            Some(Layout::Strip)
        } else if w == h {
            Some(Layout::Angular)
        } else {
            None
        }
    }

    /// The grid of square face cells `(columns, rows)` of the cube layouts:
    /// `(4, 3)`, `(3, 4)`, `(6, 1)`; `None` for the others.
    #[must_use]
    pub fn cube_grid(self) -> Option<(usize, usize)> {
        match self {
            Layout::CrossHorizontal => Some((4, 3)),
            Layout::CrossVertical => Some((3, 4)),
            Layout::Strip => Some((6, 1)),
            _ => None,
        }
    }

    /// True for the cube layouts (crosses and strip).
    #[must_use]
    pub fn is_cube(self) -> bool {
        self.cube_grid().is_some()
    }

    /// True for the disc layouts (angular map and mirror ball).
    #[must_use]
    pub fn is_disc(self) -> bool {
        matches!(self, Layout::Angular | Layout::MirrorBall)
    }

    /// Image size `(width, height)` of this layout for `size`: the height
    /// of an equirect map (`2 size x size`), the face size `f` of a cube
    /// layout (`4f x 3f`, `3f x 4f`, `6f x f`), the diameter `N` of a disc
    /// layout (`N x N`).
    #[must_use]
    pub fn dimensions(self, size: usize) -> (usize, usize) {
        match self {
            Layout::Equirect => (2 * size, size),
            Layout::Angular | Layout::MirrorBall => (size, size),
            cube => {
                let (c, r) = cube.cube_grid().unwrap_or((1, 1));
                (c * size, r * size)
            }
        }
    }

    /// Checks that a `width x height` image fits the layout: not empty
    /// (and `width * height` representable); cube layouts made of square
    /// faces (`4f x 3f`, `3f x 4f`, `6f x f`); disc layouts square. Any
    /// non-empty size is an equirect map (texels need not be square).
    ///
    /// # Errors
    /// A [`LayoutSizeError`] whose message says what is wrong and what
    /// size was expected.
    pub fn check_size(self, width: usize, height: usize) -> Result<(), LayoutSizeError> {
        let error = |kind| LayoutSizeError {
            layout: self,
            width,
            height,
            kind,
        };
        if width == 0 || height == 0 {
            return Err(error(LayoutSizeErrorKind::Empty));
        }
        if width.checked_mul(height).is_none() {
            return Err(error(LayoutSizeErrorKind::TooLarge));
        }
        let fits = match self {
            Layout::Equirect => true,
            Layout::Angular | Layout::MirrorBall => width == height,
            cube => {
                let (c, r) = cube.cube_grid().unwrap_or((1, 1));
                width.is_multiple_of(c) && height.is_multiple_of(r) && width / c == height / r
            }
        };
        if fits {
            Ok(())
        } else {
            Err(error(LayoutSizeErrorKind::Shape))
        }
    }

    /// Where `face` sits in a cube layout's grid; `None` for the other
    /// layouts. See [`Layout::face_at`] for the inverse.
    #[must_use]
    pub fn face_cell(self, face: CubeFace) -> Option<FaceCell> {
        self.cells()?
            .iter()
            .find(|c| c.2 == face)
            .map(|&(col, row, _, rotated)| FaceCell { col, row, rotated })
    }

    /// The face stored in cell `(col, row)` of a cube layout's grid; `None`
    /// for unused cells and for the other layouts.
    #[must_use]
    pub fn face_at(self, col: usize, row: usize) -> Option<(CubeFace, FaceCell)> {
        self.cells()?
            .iter()
            .find(|c| c.0 == col && c.1 == row)
            .map(|&(col, row, face, rotated)| (face, FaceCell { col, row, rotated }))
    }

    fn cells(self) -> Option<&'static [(usize, usize, CubeFace, bool); 6]> {
        match self {
            Layout::CrossHorizontal => Some(&CROSS_H),
            Layout::CrossVertical => Some(&CROSS_V),
            Layout::Strip => Some(&STRIP),
            _ => None,
        }
    }
}

impl fmt::Display for Layout {
    /// The layout's [name](Layout::name).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Layout {
    type Err = ParseLayoutError;
    /// One of the [names](Layout::name), ASCII case-insensitive.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Layout::ALL
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| ParseLayoutError {
                input: s.to_owned(),
            })
    }
}

/// The error of parsing a [`Layout`] from an unknown name; its message
/// lists the valid names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseLayoutError {
    input: String,
}

impl fmt::Display for ParseLayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "unknown layout {:?}: expected one of ", self.input)?;
        for (i, l) in Layout::ALL.iter().enumerate() {
            write!(f, "{}{l}", if i == 0 { "" } else { ", " })?;
        }
        Ok(())
    }
}

impl std::error::Error for ParseLayoutError {}

/// What is wrong with an image size for a layout ([`LayoutSizeError`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LayoutSizeErrorKind {
    /// Width or height is zero.
    Empty,
    /// `width * height` overflows `usize`.
    TooLarge,
    /// The size does not fit the layout (faces not square, a dimension not
    /// a multiple of the cell count, a disc image not square).
    Shape,
    /// The pixel slice does not hold `width * height` texels.
    PixelCount {
        /// Texels the slice holds.
        got: usize,
    },
    /// A strided image ([`crate::map::StridedImage`]) whose row stride is below
    /// its width, or whose slice is too short for `height` rows of that
    /// stride (`(height - 1) * stride + width` texels).
    Stride {
        /// Texels from the start of one row to the start of the next.
        stride: usize,
        /// Texels the slice holds.
        got: usize,
    },
    /// One of six face images ([`crate::map::CubeFaces`]) does not hold
    /// `f * f` texels.
    FacePixelCount {
        /// The face whose image is wrong.
        face: CubeFace,
        /// Texels its slice holds.
        got: usize,
    },
}

/// An image size that does not fit its [`Layout`]; the message names the
/// layout, the size, the problem and the expected shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LayoutSizeError {
    /// The layout asked for.
    pub layout: Layout,
    /// Image width in texels.
    pub width: usize,
    /// Image height in texels.
    pub height: usize,
    /// What is wrong.
    pub kind: LayoutSizeErrorKind,
}

impl fmt::Display for LayoutSizeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (l, w, h) = (self.layout, self.width, self.height);
        write!(f, "{l} map of {w}x{h} texels: ")?;
        match self.kind {
            LayoutSizeErrorKind::Empty => f.write_str("the image is empty"),
            LayoutSizeErrorKind::TooLarge => f.write_str("the image is too large"),
            LayoutSizeErrorKind::PixelCount { got } => {
                write!(f, "needs {} texels, the pixel buffer holds {got}", w * h)
            }
            LayoutSizeErrorKind::Stride { stride, got } => {
                if stride < w {
                    write!(f, "the row stride {stride} is below the width {w}")
                } else {
                    let need = (h - 1) * stride + w;
                    write!(
                        f,
                        "rows {stride} texels apart need {need} texels, the pixel buffer holds {got}"
                    )
                }
            }
            LayoutSizeErrorKind::FacePixelCount { face, got } => {
                write!(
                    f,
                    "face {face} needs {} texels ({h}x{h}), its image holds {got}",
                    h * h
                )
            }
            LayoutSizeErrorKind::Shape => match l.cube_grid() {
                Some((c, r)) => {
                    if w % c != 0 {
                        write!(f, "width {w} is not a multiple of {c}")?;
                    } else if h % r != 0 {
                        write!(f, "height {h} is not a multiple of {r}")?;
                    } else {
                        write!(f, "faces of {}x{} texels are not square", w / c, h / r)?;
                    }
                    let (ew, eh) = l.dimensions(256);
                    write!(
                        f,
                        "; expected {c}f x {r}f texels for square faces of f x f (e.g. {ew}x{eh})"
                    )
                }
                None => write!(f, "a {l} map must be square (e.g. 512x512)"),
            },
        }
    }
}

impl std::error::Error for LayoutSizeError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_face_has_one_cell_in_every_cube_layout() {
        for layout in [
            Layout::CrossHorizontal,
            Layout::CrossVertical,
            Layout::Strip,
        ] {
            let (c, r) = layout.cube_grid().unwrap();
            let mut seen = Vec::new();
            for row in 0..r {
                for col in 0..c {
                    if let Some((face, cell)) = layout.face_at(col, row) {
                        assert_eq!(layout.face_cell(face), Some(cell));
                        assert_eq!((cell.col, cell.row), (col, row));
                        seen.push(face);
                    }
                }
            }
            seen.sort_by_key(|f| f.index());
            assert_eq!(seen, CubeFace::ALL, "{layout}");
        }
        assert_eq!(Layout::Equirect.face_cell(CubeFace::PosX), None);
        assert_eq!(Layout::Strip.face_at(6, 0), None);
    }
}
