//! Environment-map layouts (equirect, cube cross, strip, angular map, mirror
//! ball): texel directions, exact texel solid angles, lookups, projection.
//!
//! An [`EnvMap`] is a borrowed image of linear RGB texels, row-major from
//! the top-left, in one [`Layout`]. Every texel that holds a direction has
//! a unit world direction ([`EnvMap::texel_direction`], at the texel's
//! centre) and the exact solid angle it covers
//! ([`EnvMap::texel_solid_angle`]); [`project_map`] sums
//! `f(texel) Y(centre) Ω(texel)` in `f64` and [`render_map`] draws a function
//! into any layout.
//!
//! # Map frame
//!
//! Each layout first gives a direction `d` in the map's own **y-up** frame;
//! the map's [`MapOrientation`] then takes it to the world exactly as for
//! equirect maps ([`crate::projection::equirect_direction`]):
//! `mirror` negates the map-frame `z` (for the equirect layout that is
//! `φ -> -φ`), then `frame` applies `Frame::YUp.rotation_to(frame)`
//! (`Frame::ZUp`: the y-up sphere turned `+90°` about X,
//! `(x, y, z) -> (x, -z, y)`).
//!
//! | layout | size | map-frame direction |
//! |---|---|---|
//! | `equirect` | any `W x H` (2:1 usual) | `(sin θ cos φ, cos θ, sin θ sin φ)`, `θ = π v`, `φ = 2π (u - 1/2)` (docs/conventions.md) |
//! | `cross-h` | `4f x 3f` | cells: row 0 col 1 `+Y`; row 1 `-X +Z +X -Z`; row 2 col 1 `-Y` |
//! | `cross-v` | `3f x 4f` | row 0 col 1 `+Y`; row 1 `-X +Z +X`; row 2 col 1 `-Y`; row 3 col 1 `-Z` turned 180° |
//! | `strip` | `6f x f` | `+X -X +Y -Y +Z -Z` left to right ([`CubeFace::ALL`]) |
//! | `angular` | `N x N` | `(sin(πr) u/r, sin(πr) v/r, -cos(πr))`: centre `-Z`, right `+X`, up `+Y`, rim `+Z` |
//! | `mirror-ball` | `N x N` | `n = (u, v, sqrt(1-r²))`, `d = (2 n_z u, 2 n_z v, 2 n_z² - 1)`: centre `+Z`, rim `-Z` |
//!
//! Cube faces follow the OpenGL / Vulkan / D3D sampling convention (table on
//! [`CubeFace`]); with these cells every seam inside a cross joins texels of
//! neighbouring directions. Disc layouts use `u = 2(x + 1/2)/N - 1` to the
//! right and `v = 1 - 2(y + 1/2)/N` up, `r = |(u, v)|`: the disc inscribed
//! in the square image. Image coordinates are in pixels from the top-left
//! corner with texel centres at `+0.5`.
//!
//! # Which texels hold a direction
//!
//! Unused cells of a cross hold none. A disc texel holds one when its
//! square meets the open disc. Texels whose centre lies inside the disc
//! carry the direction of the centre. **Rim texels** (centre outside, square
//! partly inside) carry the direction of the rim, a single point of the
//! sphere ([`Layout::Angular`] `+Z`, [`Layout::MirrorBall`] `-Z`, before the
//! orientation), and the solid angle of their part inside the disc, so the
//! quadrature's weights sum to exactly `4π` and constants project exactly.
//! Images that left these texels black (sampled at the centre only) lose
//! that solid angle: `2e-5 sr` for an angular map of `N = 512` but
//! `1.2e-2 sr` for a mirror ball, whose rim squeezes a whole cap around
//! `-Z` into a thin ring (measured in `tests/layout.rs`).
//!
//! # Solid angles
//!
//! Equirect rows: [`crate::projection::equirect_row_solid_angle`]. Cube
//! texels: [`cube_texel_solid_angle`] (closed form). Disc texels integrate
//! `dω = w(r) dA` over the texel's part of the unit disc, `w = π sin(πr)/r`
//! for the angular map (`θ = πr` from `-Z`) and `w = 4` for the mirror ball
//! (`θ = 2 asin r` from `+Z`): interior texels by a tensor Gauss-Legendre
//! rule whose error bound is below `1e-17 π² h²`, texels the rim cuts in
//! polar coordinates with the radial integral in closed form and the
//! angle range cut wherever the integrand has a kink. Every layout's solid
//! angles sum to `4π` within `1e-12` (tests).
//!
//! # Accuracy of projection
//!
//! With exact weights only the texel-centre (midpoint) error is left, which
//! falls as `h²`. Projecting a rendered lmax-4 expansion (constant 3, other
//! coefficients up to 0.3) back to lmax 4, the worst coefficient is off by
//! `6.5e-5` (equirect `512 x 256`), `3.6e-4` / `2.2e-5` (cube faces of
//! `64²` / `256²`), `1.5e-4` / `9.6e-6` (angular `N = 256` / `1024`),
//! `1.1e-3` / `7.2e-5` (mirror ball `N = 256` / `1024`).
//!
//! # Example
//! ```
//! use glam::DVec3;
//! use shlight_core::layout::{EnvMap, Layout, project_map, render_map};
//! use shlight_core::projection::MapOrientation;
//!
//! let o = MapOrientation::default();
//! let layout: Layout = "cross-h".parse().unwrap();
//! let (w, h) = layout.dimensions(32); // faces of 32 x 32 texels
//! let pixels = render_map(layout, o, w, h, |d| DVec3::splat(1.0 + d.y)).unwrap();
//! let map = EnvMap::new(layout, o, w, h, &pixels).unwrap();
//! let sh = project_map(&map, 2);
//! // The weights sum to 4 pi and y cancels between opposite texels, so the
//! // constant term is exact up to the f32 pixels: int 1 Y_0^0 = 2 sqrt(pi).
//! assert!((sh[0].x - 2.0 * std::f64::consts::PI.sqrt()).abs() < 1e-6);
//! // int y Y_1^-1 = -sqrt(4 pi / 3), to the quadrature's O(h^2).
//! assert!((sh[1].x + (4.0 * std::f64::consts::PI / 3.0).sqrt()).abs() < 1e-3);
//! ```

use core::fmt;
use core::str::FromStr;

use glam::DVec3;

use crate::montecarlo::RadianceMap;
use crate::projection::{
    EquirectView, MapOrientation, equirect_angles, equirect_row_solid_angle, project_equirect,
};
use crate::rotation::Frame;
use crate::{ShBasis, ShCoeffs};

mod cube;
mod disc;

pub use cube::{CubeFace, FaceCell, cube_texel_solid_angle};
use disc::{Disc, DiscRule};

/// How an environment map's texels are arranged in its image (the table in
/// the [module documentation](self)).
///
/// Named `equirect`, `cross-h`, `cross-v`, `strip`, `angular`,
/// `mirror-ball` ([`FromStr`], [`fmt::Display`]).
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

    fn disc(self) -> Option<Disc> {
        match self {
            Layout::Angular => Some(Disc::Angular),
            Layout::MirrorBall => Some(Disc::MirrorBall),
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

/// A borrowed environment map in any [`Layout`]: `width x height` linear
/// RGB texels, row-major from the top-left corner, read in `orientation`
/// (see the [module documentation](self) for every convention).
///
/// The methods assume the size fits the layout ([`Layout::check_size`]);
/// [`EnvMap::new`] checks it and the pixel count. With a size that does not
/// fit they return meaningless (but memory-safe) values or panic on an
/// out-of-range pixel index.
#[derive(Clone, Copy, Debug)]
pub struct EnvMap<'a> {
    /// How texels are arranged.
    pub layout: Layout,
    /// How the map's y-up frame meets world directions.
    pub orientation: MapOrientation,
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` linear RGB texels, row-major from the top-left.
    pub pixels: &'a [[f32; 3]],
}

impl<'a> EnvMap<'a> {
    /// A map after checking that `width x height` fits `layout` and that
    /// `pixels` holds `width * height` texels.
    ///
    /// # Errors
    /// [`LayoutSizeError`] when either check fails.
    pub fn new(
        layout: Layout,
        orientation: MapOrientation,
        width: usize,
        height: usize,
        pixels: &'a [[f32; 3]],
    ) -> Result<Self, LayoutSizeError> {
        layout.check_size(width, height)?;
        if pixels.len() != width * height {
            return Err(LayoutSizeError {
                layout,
                width,
                height,
                kind: LayoutSizeErrorKind::PixelCount { got: pixels.len() },
            });
        }
        Ok(Self {
            layout,
            orientation,
            width,
            height,
            pixels,
        })
    }

    fn geometry(&self) -> Geometry {
        Geometry::new(self.layout, self.orientation, self.width, self.height)
    }

    /// Unit world direction of the centre of texel `(x, y)`; `None` for
    /// texels that hold no direction (unused cells of a cross, disc texels
    /// wholly outside the disc) and for `x >= width` or `y >= height`.
    /// Disc rim texels whose centre lies outside the disc give the rim's
    /// single direction (module docs).
    #[must_use]
    pub fn texel_direction(&self, x: usize, y: usize) -> Option<DVec3> {
        self.geometry().direction(x, y)
    }

    /// Exact solid angle (steradians) covered by texel `(x, y)`; `0` for
    /// texels that hold no direction. Over all texels the values sum to `4π`.
    ///
    /// Equirect `(2π/W)(cos(yπ/H) - cos((y+1)π/H))`; cube
    /// [`cube_texel_solid_angle`]; disc `int w(r) dA` over the texel's part
    /// of the disc (module docs). A disc texel costs a few microseconds
    /// here (the rules are rebuilt per call); [`project_map`] builds them
    /// once.
    #[must_use]
    pub fn texel_solid_angle(&self, x: usize, y: usize) -> f64 {
        let geo = self.geometry();
        geo.solid_angle(x, y, geo.disc_rule().as_ref())
    }

    /// [`EnvMap::texel_solid_angle`] of every texel, row-major
    /// (`width * height` values), with the quadrature rules built once.
    #[must_use]
    pub fn texel_solid_angles(&self) -> Vec<f64> {
        let geo = self.geometry();
        let rule = geo.disc_rule();
        (0..self.height)
            .flat_map(|y| (0..self.width).map(move |x| (x, y)))
            .map(|(x, y)| geo.solid_angle(x, y, rule.as_ref()))
            .collect()
    }

    /// Continuous image coordinates `(x, y)` in pixels (texel centres at
    /// `+0.5`) where the world direction `d` lands. `d` must be finite and
    /// non-zero; it need not be unit length. `direction_to_image` of
    /// [`EnvMap::texel_direction`]`(x, y)` is `(x + 0.5, y + 0.5)` for every
    /// texel whose centre carries its own direction.
    ///
    /// Equirect: `x = W (φ/2π + 1/2)` in `[0, W]`, `y = H θ/π`. Cube: the
    /// face of the major axis ([`CubeFace::from_direction`]), placed in its
    /// cell. Disc: the inverse of the disc mapping; the rim direction (where
    /// the azimuth is undefined) lands at `(u, v) = (1, 0)`.
    #[must_use]
    pub fn direction_to_image(&self, d: DVec3) -> (f64, f64) {
        self.geometry().image_point(d)
    }

    /// Radiance arriving from world direction `d` (finite, non-zero), by
    /// bilinear interpolation between the four texel centres around the
    /// point [`EnvMap::direction_to_image`] gives.
    ///
    /// - Equirect: columns wrap around (`x` modulo `W`); above the first
    ///   row's centres the missing row is the first row half a turn around
    ///   (column `x + W/2`; exact for even `W`), likewise below the last,
    ///   so the lookup is continuous over the poles.
    /// - Cube layouts: interpolation runs in the face of `d`; a tap beyond
    ///   the face's edge (a virtual texel centre on the face's extended
    ///   plane) is fetched across the seam: the bilinear lookup of its
    ///   direction on the face it falls on, clamped within that face. So
    ///   filtering is continuous over seams, stays second-order accurate
    ///   there, and never reads an unused cell.
    /// - Disc layouts: taps whose centre lies outside the disc are dropped
    ///   and the remaining weights renormalised (the nearest texel if none
    ///   is left).
    ///
    /// Panics if `pixels` is shorter than `width * height`.
    #[must_use]
    pub fn radiance_bilinear(&self, d: DVec3) -> DVec3 {
        let geo = self.geometry();
        let texel =
            |x: usize, y: usize| DVec3::from(self.pixels[y * self.width + x].map(f64::from));
        match self.layout {
            Layout::Equirect => {
                let (px, py) = geo.image_point(d);
                let (w, h) = (self.width as isize, self.height as isize);
                let (x0, tx) = split(px - 0.5);
                let (y0, ty) = split(py - 0.5);
                // Columns wrap; a row beyond a pole is the first (last) row
                // half a turn around.
                let tap = |x: isize, y: isize| {
                    let (x, y) = if y < 0 {
                        (x + w / 2, -1 - y)
                    } else if y >= h {
                        (x + w / 2, 2 * h - 1 - y)
                    } else {
                        (x, y)
                    };
                    texel(x.rem_euclid(w) as usize, y.clamp(0, h - 1) as usize)
                };
                (tap(x0, y0) * (1.0 - tx) + tap(x0 + 1, y0) * tx) * (1.0 - ty)
                    + (tap(x0, y0 + 1) * (1.0 - tx) + tap(x0 + 1, y0 + 1) * tx) * ty
            }
            Layout::Angular | Layout::MirrorBall => {
                let (px, py) = geo.image_point(d);
                let (x0, tx) = split(px - 0.5);
                let (y0, ty) = split(py - 0.5);
                let (mut sum, mut weight) = (DVec3::ZERO, 0.0);
                for (dy, wy) in [(0, 1.0 - ty), (1, ty)] {
                    for (dx, wx) in [(0, 1.0 - tx), (1, tx)] {
                        let (x, y) = (x0 + dx, y0 + dy);
                        if geo.centre_in_disc(x, y) && wx * wy > 0.0 {
                            sum += texel(x as usize, y as usize) * (wx * wy);
                            weight += wx * wy;
                        }
                    }
                }
                if weight > 0.0 {
                    sum / weight
                } else {
                    let n = self.width as isize;
                    let x = (px.floor() as isize).clamp(0, n - 1) as usize;
                    let y = (py.floor() as isize).clamp(0, n - 1) as usize;
                    texel(x, y)
                }
            }
            _ => {
                let (face, sc, tc) = CubeFace::from_direction(geo.orientation.map_from_world(d));
                self.cube_bilinear(&geo, face, sc, tc, true)
            }
        }
    }

    /// Bilinear interpolation on `face` at face coordinates `(sc, tc)`.
    /// A tap beyond the face's edge stands for the virtual texel centre on
    /// the face's extended plane: with `across_seams` its value is the
    /// bilinear lookup (clamped, one level deep) of that direction on the
    /// face it falls on; otherwise the nearest texel of `face`.
    fn cube_bilinear(
        &self,
        geo: &Geometry,
        face: CubeFace,
        sc: f64,
        tc: f64,
        across_seams: bool,
    ) -> DVec3 {
        let n = geo.cell as isize;
        let f = geo.cell as f64;
        let (i0, ti) = split(0.5 * (sc + 1.0) * f - 0.5);
        let (j0, tj) = split(0.5 * (tc + 1.0) * f - 0.5);
        let tap = |i: isize, j: isize| {
            let inside = (0..n).contains(&i) && (0..n).contains(&j);
            if !inside && across_seams {
                let centre = |k: isize| (2.0 * k as f64 + 1.0 - f) / f;
                let (other, sc, tc) = CubeFace::from_direction(face.point(centre(i), centre(j)));
                return self.cube_bilinear(geo, other, sc, tc, false);
            }
            let (i, j) = (i.clamp(0, n - 1) as usize, j.clamp(0, n - 1) as usize);
            let (x, y) = geo.face_pixel(face, i, j);
            DVec3::from(self.pixels[y * self.width + x].map(f64::from))
        };
        (tap(i0, j0) * (1.0 - ti) + tap(i0 + 1, j0) * ti) * (1.0 - tj)
            + (tap(i0, j0 + 1) * (1.0 - ti) + tap(i0 + 1, j0 + 1) * ti) * tj
    }
}

impl RadianceMap for EnvMap<'_> {
    /// [`EnvMap::radiance_bilinear`].
    fn radiance(&self, d: DVec3) -> DVec3 {
        self.radiance_bilinear(d)
    }
}

/// `(floor(p), p - floor(p))` with the floor as an integer.
fn split(p: f64) -> (isize, f64) {
    let f = p.floor();
    (f as isize, p - f)
}

/// Radiance coefficients up to `lmax` of a map in any layout by exact
/// texel-solid-angle quadrature, accumulated in `f64`:
///
/// ```text
/// L_l^m ≈ sum over texels with a direction of f(texel) Y_l^m(d(texel)) Ω(texel)
/// ```
///
/// Equirect maps go through [`project_equirect`] (the ring path); the other
/// layouts evaluate the basis in batches ([`ShBasis::eval_batch`]) per row,
/// rows in parallel with the `rayon` feature. The quadrature is exact for
/// constants (the weights sum to `4π`); for a smooth band-limited function
/// its error falls as `h²` with the texel size (figures in
/// `tests/layout.rs`).
///
/// # Panics
/// If the size does not fit the layout ([`Layout::check_size`]) or
/// `pixels.len() != width * height` ([`EnvMap::new`] checks both).
#[must_use]
pub fn project_map(map: &EnvMap<'_>, lmax: usize) -> ShCoeffs<DVec3> {
    if let Err(e) = map.layout.check_size(map.width, map.height) {
        panic!("project_map: {e}");
    }
    let (w, h) = (map.width, map.height);
    assert_eq!(
        map.pixels.len(),
        w * h,
        "project_map: pixel count must be width * height"
    );
    if map.layout == Layout::Equirect {
        let view = EquirectView {
            width: w,
            height: h,
            pixels: map.pixels,
        };
        return project_equirect(view, lmax, map.orientation);
    }
    let geo = map.geometry();
    let rule = geo.disc_rule();
    let basis = ShBasis::<f64>::new(lmax);
    let row = |y: usize, acc: &mut Batch| {
        for x in 0..w {
            let Some(d) = geo.direction(x, y) else {
                continue;
            };
            let omega = geo.solid_angle(x, y, rule.as_ref());
            let f = DVec3::from(map.pixels[y * w + x].map(f64::from));
            acc.push(d, f * omega, &basis);
        }
        acc.flush(&basis);
    };
    crate::projection::run_rows::<Batch>(h, lmax, row)
}

/// Draws `f` into a new `width x height` image of `layout` read in
/// `orientation`: each texel that holds a direction gets `f` at
/// [`EnvMap::texel_direction`] (rounded to `f32`), the others `0`. The
/// image [`project_map`] reads back as the projection of `f`; the CLI's
/// `render` draws SH this way. Rows run in parallel with the `rayon`
/// feature.
///
/// # Errors
/// [`LayoutSizeError`] when the size does not fit the layout.
pub fn render_map(
    layout: Layout,
    orientation: MapOrientation,
    width: usize,
    height: usize,
    f: impl Fn(DVec3) -> DVec3 + Sync,
) -> Result<Vec<[f32; 3]>, LayoutSizeError> {
    layout.check_size(width, height)?;
    let geo = Geometry::new(layout, orientation, width, height);
    let mut pixels = vec![[0.0f32; 3]; width * height];
    let row = |(y, out): (usize, &mut [[f32; 3]])| {
        for (x, px) in out.iter_mut().enumerate() {
            if let Some(d) = geo.direction(x, y) {
                *px = f(d).as_vec3().to_array();
            }
        }
    };
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        pixels.par_chunks_mut(width).enumerate().for_each(row);
    }
    #[cfg(not(feature = "rayon"))]
    pixels.chunks_mut(width).enumerate().for_each(row);
    Ok(pixels)
}

/// Texels per basis batch: `(lmax+1)^2 * BATCH` values of scratch.
const BATCH: usize = 128;

/// Per-thread partial sums and a batch of weighted texels.
struct Batch {
    sh: ShCoeffs<DVec3>,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    /// `f(texel) Ω(texel)`.
    fw: Vec<DVec3>,
    /// Basis values, coefficient-major.
    basis: Vec<f64>,
}

impl Batch {
    fn new(lmax: usize) -> Self {
        let count = crate::sh_count(lmax);
        Self {
            sh: ShCoeffs::zeros(lmax),
            x: Vec::with_capacity(BATCH),
            y: Vec::with_capacity(BATCH),
            z: Vec::with_capacity(BATCH),
            fw: Vec::with_capacity(BATCH),
            basis: vec![0.0; count * BATCH],
        }
    }

    fn push(&mut self, d: DVec3, fw: DVec3, basis: &ShBasis<f64>) {
        self.x.push(d.x);
        self.y.push(d.y);
        self.z.push(d.z);
        self.fw.push(fw);
        if self.x.len() == BATCH {
            self.flush(basis);
        }
    }

    fn flush(&mut self, basis: &ShBasis<f64>) {
        let n = self.x.len();
        if n == 0 {
            return;
        }
        let count = basis.count();
        let values = &mut self.basis[..count * n];
        basis.eval_batch(&self.x, &self.y, &self.z, values);
        for i in 0..count {
            let mut s = DVec3::ZERO;
            for (fw, yk) in self.fw.iter().zip(&values[i * n..(i + 1) * n]) {
                s += *fw * *yk;
            }
            self.sh[i] += s;
        }
        self.x.clear();
        self.y.clear();
        self.z.clear();
        self.fw.clear();
    }
}

impl crate::projection::RowState for Batch {
    fn new(lmax: usize) -> Self {
        Batch::new(lmax)
    }
    fn into_coeffs(self) -> ShCoeffs<DVec3> {
        self.sh
    }
}

/// The geometry of one map: layout, orientation, size, and the cell size
/// (face size `f` of cube layouts, `N` of disc layouts).
#[derive(Clone, Copy, Debug)]
struct Geometry {
    layout: Layout,
    orientation: MapOrientation,
    w: usize,
    h: usize,
    cell: usize,
}

impl Geometry {
    fn new(layout: Layout, o: MapOrientation, w: usize, h: usize) -> Self {
        let cell = match layout.cube_grid() {
            Some((c, _)) => w / c,
            None => w,
        };
        Self {
            layout,
            orientation: o,
            w,
            h,
            cell,
        }
    }

    fn disc_rule(&self) -> Option<DiscRule> {
        self.layout.disc().map(|d| DiscRule::new(d, self.cell))
    }

    /// Face and face-local texel `(i, j)` (face orientation) of image
    /// texel `(x, y)` of a cube layout.
    fn face_texel(&self, x: usize, y: usize) -> Option<(CubeFace, usize, usize)> {
        let f = self.cell;
        let (face, cell) = self.layout.face_at(x / f, y / f)?;
        let (i, j) = (x % f, y % f);
        Some(if cell.rotated {
            (face, f - 1 - i, f - 1 - j)
        } else {
            (face, i, j)
        })
    }

    /// Image texel of face-local texel `(i, j)` of `face`.
    fn face_pixel(&self, face: CubeFace, i: usize, j: usize) -> (usize, usize) {
        let f = self.cell;
        let cell = self
            .layout
            .face_cell(face)
            .expect("a cube layout holds every face");
        let (i, j) = if cell.rotated {
            (f - 1 - i, f - 1 - j)
        } else {
            (i, j)
        };
        (cell.col * f + i, cell.row * f + j)
    }

    /// Disc coordinates `[u0, u1] x [v0, v1]` of disc texel `(x, y)`.
    fn disc_square(&self, x: usize, y: usize) -> (f64, f64, f64, f64) {
        let n = self.cell as f64;
        let u = |k: usize| (2.0 * k as f64 - n) / n;
        let v = |k: usize| (n - 2.0 * k as f64) / n;
        (u(x), u(x + 1), v(y + 1), v(y))
    }

    /// Disc coordinates of the centre of disc texel `(x, y)`.
    fn disc_centre(&self, x: usize, y: usize) -> (f64, f64) {
        let n = self.cell as f64;
        (
            (2.0 * x as f64 + 1.0 - n) / n,
            (n - 2.0 * y as f64 - 1.0) / n,
        )
    }

    /// Whether `(x, y)` is a texel of a disc map whose centre lies in the
    /// closed unit disc.
    fn centre_in_disc(&self, x: isize, y: isize) -> bool {
        let n = self.cell as isize;
        if !(0..n).contains(&x) || !(0..n).contains(&y) {
            return false;
        }
        let (u, v) = self.disc_centre(x as usize, y as usize);
        u * u + v * v <= 1.0
    }

    fn direction(&self, x: usize, y: usize) -> Option<DVec3> {
        if x >= self.w || y >= self.h {
            return None;
        }
        let d = match self.layout {
            Layout::Equirect => {
                let (t, p) = equirect_angles(x, y, self.w, self.h);
                Frame::YUp.direction(t, p)
            }
            Layout::Angular | Layout::MirrorBall => {
                let disc = self.layout.disc()?;
                let (u, v) = self.disc_centre(x, y);
                if u * u + v * v <= 1.0 {
                    disc.direction(u, v)
                } else {
                    let (u0, u1, v0, v1) = self.disc_square(x, y);
                    let (nu, nv) = (0.0f64.clamp(u0, u1), 0.0f64.clamp(v0, v1));
                    if nu * nu + nv * nv >= 1.0 {
                        return None;
                    }
                    disc.pole()
                }
            }
            _ => {
                let (face, i, j) = self.face_texel(x, y)?;
                let f = self.cell as f64;
                let c = |k: usize| (2.0 * k as f64 + 1.0 - f) / f;
                face.point(c(i), c(j)).normalize()
            }
        };
        Some(self.orientation.world_from_map(d))
    }

    fn solid_angle(&self, x: usize, y: usize, rule: Option<&DiscRule>) -> f64 {
        if x >= self.w || y >= self.h {
            return 0.0;
        }
        match self.layout {
            Layout::Equirect => equirect_row_solid_angle(y, self.w, self.h),
            Layout::Angular | Layout::MirrorBall => {
                let (u0, u1, v0, v1) = self.disc_square(x, y);
                rule.map_or(0.0, |r| r.solid_angle(u0, u1, v0, v1))
            }
            _ => self
                .face_texel(x, y)
                .map_or(0.0, |(_, i, j)| cube_texel_solid_angle(i, j, self.cell)),
        }
    }

    fn image_point(&self, d: DVec3) -> (f64, f64) {
        let d = self.orientation.map_from_world(d);
        match self.layout {
            Layout::Equirect => {
                use core::f64::consts::{PI, TAU};
                let theta = d.x.hypot(d.z).atan2(d.y);
                let phi = d.z.atan2(d.x);
                (
                    self.w as f64 * (phi / TAU + 0.5),
                    self.h as f64 * theta / PI,
                )
            }
            Layout::Angular | Layout::MirrorBall => {
                let disc = self.layout.disc().expect("a disc layout");
                let (u, v) = disc.image_point(d);
                let n = self.cell as f64;
                (0.5 * (u + 1.0) * n, 0.5 * (1.0 - v) * n)
            }
            _ => {
                let (face, sc, tc) = CubeFace::from_direction(d);
                let cell = self
                    .layout
                    .face_cell(face)
                    .expect("a cube layout holds every face");
                let f = self.cell as f64;
                let (mut s, mut t) = (0.5 * (sc + 1.0) * f, 0.5 * (tc + 1.0) * f);
                if cell.rotated {
                    (s, t) = (f - s, f - t);
                }
                (cell.col as f64 * f + s, cell.row as f64 * f + t)
            }
        }
    }
}

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

    #[test]
    fn orientation_round_trips() {
        for frame in [Frame::YUp, Frame::ZUp] {
            for mirror in [false, true] {
                let geo = Geometry::new(Layout::Strip, MapOrientation { frame, mirror }, 6, 1);
                let d = DVec3::new(0.2, -0.5, 0.84);
                assert!(
                    (geo.orientation
                        .map_from_world(geo.orientation.world_from_map(d))
                        - d)
                        .length()
                        < 1e-15
                );
            }
        }
    }
}
