//! [`EnvMap`]: a borrowed environment-map image in any layout, with its
//! texel directions, exact texel solid angles, the inverse lookup from a
//! direction to image coordinates, and bilinear radiance lookups.

use glam::DVec3;

use super::cube::CubeFace;
use super::geometry::Geometry;
use super::kind::{Layout, LayoutSizeError, LayoutSizeErrorKind};
use crate::map::orientation::MapOrientation;
use crate::map::radiance_map::RadianceMap;

/// A borrowed environment map in any [`Layout`]: `width x height` linear
/// RGB texels, row-major from the top-left corner, read in `orientation`
/// (see [`Layout`] for every convention).
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
    /// single direction ([`Layout`]).
    #[must_use]
    pub fn texel_direction(&self, x: usize, y: usize) -> Option<DVec3> {
        self.geometry().direction(x, y)
    }

    /// Exact solid angle (steradians) covered by texel `(x, y)`; `0` for
    /// texels that hold no direction. Over all texels the values sum to `4π`.
    ///
    /// Equirect `(2π/W)(cos(yπ/H) - cos((y+1)π/H))`; cube
    /// [`cube_texel_solid_angle`](crate::map::cube_texel_solid_angle); disc
    /// `int w(r) dA` over the texel's part of the disc ([`Layout`]). A disc texel costs a few microseconds
    /// here (the rules are rebuilt per call); [`EnvMap::texel_solid_angles`]
    /// and the projection build them once.
    #[must_use]
    pub fn texel_solid_angle(&self, x: usize, y: usize) -> f64 {
        let geo = self.geometry();
        geo.solid_angle(x, y, geo.disc_rule().as_ref())
    }

    /// [`EnvMap::texel_solid_angle`] of every texel, row-major
    /// (`width * height` values), with the quadrature rules built once.
    #[must_use]
    pub fn texel_solid_angles(&self) -> Vec<f64> {
        self.geometry().solid_angles()
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
