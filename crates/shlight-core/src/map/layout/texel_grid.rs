//! [`TexelGrid`]: the texels of a map of any layout without its pixels:
//! where each texel looks, points spread over it, its solid angle, and the
//! texel a direction falls in. What a map is drawn through (the texel means
//! of [`crate::map::texel_means()`], a delta light in
//! [`crate::map::directional_texels()`], SH rendered at texel centres).

use core::f64::consts::PI;

use glam::DVec3;

use super::geometry::Geometry;
use super::kind::{Layout, LayoutSizeError};
use crate::map::orientation::MapOrientation;

/// A `width x height` image of one [`Layout`] read in one
/// [`MapOrientation`], seen as texels that look in world directions (the
/// conventions of [`Layout`]).
///
/// - [`TexelGrid::direction`]: the unit world direction of a texel's
///   centre (`None` for texels the layout leaves unused), as
///   [`EnvMap::texel_direction`](crate::map::EnvMap::texel_direction);
/// - [`TexelGrid::sample`]: points inside a texel whose regular grids
///   average a function over the texel;
/// - [`TexelGrid::solid_angle`]: the exact solid angle a texel covers;
/// - [`TexelGrid::texel_of`]: the texel a direction falls in, the inverse
///   of [`TexelGrid::direction`].
#[derive(Debug)]
pub struct TexelGrid {
    geo: Geometry,
}

impl TexelGrid {
    /// A grid of `width x height` texels of `layout` read in `orientation`.
    ///
    /// # Errors
    /// [`LayoutSizeError`] when the size does not fit the layout
    /// ([`Layout::check_size`]).
    pub fn new(
        layout: Layout,
        (width, height): (usize, usize),
        orientation: MapOrientation,
    ) -> Result<Self, LayoutSizeError> {
        layout.check_size(width, height)?;
        Ok(Self {
            geo: Geometry::new(layout, orientation, width, height),
        })
    }

    /// The layout.
    #[must_use]
    pub fn layout(&self) -> Layout {
        self.geo.layout
    }

    /// Frame and mirroring.
    #[must_use]
    pub fn orientation(&self) -> MapOrientation {
        self.geo.orientation
    }

    /// Texels per row.
    #[must_use]
    pub fn width(&self) -> usize {
        self.geo.w
    }

    /// Rows.
    #[must_use]
    pub fn height(&self) -> usize {
        self.geo.h
    }

    /// The world direction of the frame's up axis (+Y for y-up, +Z for
    /// z-up): the direction of polar angle 0.
    #[must_use]
    pub fn up(&self) -> DVec3 {
        self.geo.orientation.frame.direction(0.0, 0.0)
    }

    /// The unit world direction of the centre of texel `(x, y)`; `None`
    /// for a texel the layout does not use and for `x >= width` or
    /// `y >= height`.
    #[must_use]
    pub fn direction(&self, x: usize, y: usize) -> Option<DVec3> {
        self.geo.direction(x, y)
    }

    /// A direction inside texel `(x, y)` at `(s, t)` in `[0, 1]^2`, such
    /// that the plain average of a function over a regular grid of
    /// `(s, t)` (cell centres) is its mean over the texel to the midpoint
    /// rule's accuracy.
    ///
    /// Equirect: texel `(x, y)` of a `W x H` map covers
    /// `φ ∈ 2π [x/W - 1/2, (x+1)/W - 1/2]` and
    /// `cos θ ∈ [cos(yπ/H), cos((y+1)π/H)]`, and `dω = d(cos θ) dφ`, so
    /// points with `φ` linear in `s` and `cos θ` linear in `t` split it
    /// into equal solid angles: `φ = 2π((x + s)/W - 1/2)` (negated when
    /// mirrored) and `θ = acos(cos θ_0 + (cos θ_1 - cos θ_0) t)`. The mean
    /// of any function linear in `cos θ` is then exact.
    ///
    /// The other layouts have no such closed form here: every `(s, t)`
    /// gives the texel-centre direction ([`TexelGrid::direction`]), so
    /// their texels are point-sampled.
    #[must_use]
    pub fn sample(&self, x: usize, y: usize, s: f64, t: f64) -> Option<DVec3> {
        match self.geo.layout {
            Layout::Equirect => {
                if x >= self.geo.w || y >= self.geo.h {
                    return None;
                }
                let (w, h) = (self.geo.w as f64, self.geo.h as f64);
                let z0 = (PI * y as f64 / h).cos();
                let z1 = (PI * (y + 1) as f64 / h).cos();
                let theta = (z0 + (z1 - z0) * t).clamp(-1.0, 1.0).acos();
                let phi = 2.0 * PI * ((x as f64 + s) / w - 0.5);
                let o = self.geo.orientation;
                let phi = if o.mirror { -phi } else { phi };
                Some(o.frame.direction(theta, phi))
            }
            _ => self.direction(x, y),
        }
    }

    /// How many points per texel side of [`TexelGrid::sample`] are worth
    /// taking when `n` are asked for: `n` (at least 1) for equirect, 1 for
    /// the other layouts, whose points are all the texel's centre.
    #[must_use]
    pub fn points_per_side(&self, n: usize) -> usize {
        match self.geo.layout {
            Layout::Equirect => n.max(1),
            _ => 1,
        }
    }

    /// The exact solid angle texel `(x, y)` covers (steradians; 0 for
    /// unused texels and outside the image), as
    /// [`EnvMap::texel_solid_angle`](crate::map::EnvMap::texel_solid_angle):
    /// a disc texel rebuilds its rules per call, so for many texels use
    /// [`TexelGrid::solid_angles`]. Over all texels they sum to `4π`.
    #[must_use]
    pub fn solid_angle(&self, x: usize, y: usize) -> f64 {
        self.geo.solid_angle(x, y, self.geo.disc_rule().as_ref())
    }

    /// Every texel's solid angle, row-major (`width * height` values), as
    /// [`EnvMap::texel_solid_angles`](crate::map::EnvMap::texel_solid_angles).
    #[must_use]
    pub fn solid_angles(&self) -> Vec<f64> {
        self.geo.solid_angles()
    }

    /// The texel that direction `d` (finite, non-zero) falls in: the image
    /// point of [`EnvMap::direction_to_image`](crate::map::EnvMap::direction_to_image),
    /// floored and clamped to the image. For every texel whose centre
    /// carries its own direction, `texel_of(direction(x, y)) == (x, y)`.
    #[must_use]
    pub fn texel_of(&self, d: DVec3) -> (usize, usize) {
        let (x, y) = self.geo.image_point(d);
        let clamp = |v: f64, n: usize| (v.floor().max(0.0) as usize).min(n - 1);
        (clamp(x, self.geo.w), clamp(y, self.geo.h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::layout::env_map::EnvMap;
    use crate::sh::frame::Frame;

    #[test]
    fn texel_of_inverts_direction_in_every_orientation() {
        for frame in [Frame::YUp, Frame::ZUp] {
            for mirror in [false, true] {
                let g =
                    TexelGrid::new(Layout::Equirect, (32, 16), MapOrientation { frame, mirror })
                        .unwrap();
                for y in 0..16 {
                    for x in 0..32 {
                        let d = g.direction(x, y).unwrap();
                        assert_eq!(g.texel_of(d), (x, y), "{frame} {mirror}");
                        let inside = g.sample(x, y, 0.3, 0.8).unwrap();
                        assert_eq!(g.texel_of(inside), (x, y), "{frame} {mirror}");
                    }
                }
            }
        }
        for layout in Layout::ALL {
            let size = layout.dimensions(8);
            let g = TexelGrid::new(layout, size, MapOrientation::default()).unwrap();
            for y in 0..size.1 {
                for x in 0..size.0 {
                    if let Some(d) = g.direction(x, y)
                        && g.solid_angle(x, y) > 0.0
                        && !layout.is_disc()
                    {
                        assert_eq!(g.texel_of(d), (x, y), "{layout:?}");
                    }
                }
            }
        }
    }

    /// Directions and solid angles are the `EnvMap`'s (one geometry), and
    /// the solid angles sum to 4π in every layout and orientation.
    #[test]
    fn the_grid_is_the_env_maps_geometry_and_covers_the_sphere() {
        for layout in Layout::ALL {
            for o in MapOrientation::ALL {
                let (w, h) = layout.dimensions(6);
                let g = TexelGrid::new(layout, (w, h), o).unwrap();
                let black = vec![[0.0f32; 3]; w * h];
                let map = EnvMap::new(layout, o, w, h, &black).unwrap();
                for y in 0..h {
                    for x in 0..w {
                        assert_eq!(g.direction(x, y), map.texel_direction(x, y));
                        assert_eq!(g.solid_angle(x, y), map.texel_solid_angle(x, y));
                    }
                }
                let total: f64 = g.solid_angles().iter().sum();
                assert!((total - 4.0 * PI).abs() < 1e-12, "{layout:?} {total}");
                assert_eq!(g.solid_angle(w, 0), 0.0);
                assert_eq!(g.direction(0, h), None);
            }
        }
        assert!(
            TexelGrid::new(Layout::CrossHorizontal, (10, 10), MapOrientation::default()).is_err()
        );
    }

    /// An equirect texel's points split it into equal solid angles: the
    /// mean of `cos θ` (linear in `t`) over a regular grid of points is its
    /// exact mean over the texel, `(cos θ_0 + cos θ_1) / 2`, and `φ` spans
    /// the texel's columns.
    #[test]
    fn equirect_points_average_cos_theta_exactly() {
        let (w, h) = (24, 12);
        for o in MapOrientation::ALL {
            let g = TexelGrid::new(Layout::Equirect, (w, h), o).unwrap();
            let up = g.up();
            for y in 0..h {
                let z0 = (PI * y as f64 / h as f64).cos();
                let z1 = (PI * (y + 1) as f64 / h as f64).cos();
                let n = 5;
                let mean: f64 = (0..n)
                    .flat_map(|i| (0..n).map(move |j| (i, j)))
                    .map(|(i, j)| {
                        let (s, t) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                        g.sample(3, y, s, t).unwrap().dot(up)
                    })
                    .sum::<f64>()
                    / (n * n) as f64;
                assert!((mean - (z0 + z1) / 2.0).abs() < 1e-14, "{y}: {mean}");
            }
            // The texel's corners are on its edges: s = 0 and s = 1 are the
            // neighbouring columns' shared meridians.
            let left = g.sample(5, 4, 0.0, 0.5).unwrap();
            let right_of_previous = g.sample(4, 4, 1.0, 0.5).unwrap();
            assert!((left - right_of_previous).length() < 1e-14);
            assert_eq!(g.sample(w, 0, 0.5, 0.5), None);
        }
        // Other layouts: the centre.
        let g = TexelGrid::new(Layout::Strip, (24, 4), MapOrientation::default()).unwrap();
        assert_eq!(g.sample(5, 2, 0.1, 0.9), g.direction(5, 2));
    }
}
