//! The geometry shared by every use of a layout: the direction of a texel's
//! centre, its exact solid angle, and where a direction lands in the image.
//! Crate-internal; [`super::EnvMap`] is its public face.

use glam::DVec3;

use super::cube::{CubeFace, cube_texel_solid_angle};
use super::disc::{Disc, DiscRule};
use super::kind::Layout;
use crate::map::equirect::{equirect_angles, equirect_row_solid_angle};
use crate::map::orientation::MapOrientation;
use crate::sh::frame::Frame;

/// The disc mapping of a disc layout; `None` for the others.
fn disc_of(layout: Layout) -> Option<Disc> {
    match layout {
        Layout::Angular => Some(Disc::Angular),
        Layout::MirrorBall => Some(Disc::MirrorBall),
        _ => None,
    }
}

/// The geometry of one map: layout, orientation, size, and the cell size
/// (face size `f` of cube layouts, `N` of disc layouts).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Geometry {
    pub(crate) layout: Layout,
    pub(crate) orientation: MapOrientation,
    pub(crate) w: usize,
    pub(crate) h: usize,
    pub(crate) cell: usize,
}

impl Geometry {
    pub(crate) fn new(layout: Layout, o: MapOrientation, w: usize, h: usize) -> Self {
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

    pub(crate) fn disc_rule(&self) -> Option<DiscRule> {
        disc_of(self.layout).map(|d| DiscRule::new(d, self.cell))
    }

    /// Face and face-local texel `(i, j)` (face orientation) of image
    /// texel `(x, y)` of a cube layout.
    pub(crate) fn face_texel(&self, x: usize, y: usize) -> Option<(CubeFace, usize, usize)> {
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
    pub(crate) fn face_pixel(&self, face: CubeFace, i: usize, j: usize) -> (usize, usize) {
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
    pub(crate) fn disc_square(&self, x: usize, y: usize) -> (f64, f64, f64, f64) {
        let n = self.cell as f64;
        let u = |k: usize| (2.0 * k as f64 - n) / n;
        let v = |k: usize| (n - 2.0 * k as f64) / n;
        (u(x), u(x + 1), v(y + 1), v(y))
    }

    /// Disc coordinates of the centre of disc texel `(x, y)`.
    pub(crate) fn disc_centre(&self, x: usize, y: usize) -> (f64, f64) {
        let n = self.cell as f64;
        (
            (2.0 * x as f64 + 1.0 - n) / n,
            (n - 2.0 * y as f64 - 1.0) / n,
        )
    }

    /// Whether `(x, y)` is a texel of a disc map whose centre lies in the
    /// closed unit disc.
    pub(crate) fn centre_in_disc(&self, x: isize, y: isize) -> bool {
        let n = self.cell as isize;
        if !(0..n).contains(&x) || !(0..n).contains(&y) {
            return false;
        }
        let (u, v) = self.disc_centre(x as usize, y as usize);
        u * u + v * v <= 1.0
    }

    pub(crate) fn direction(&self, x: usize, y: usize) -> Option<DVec3> {
        if x >= self.w || y >= self.h {
            return None;
        }
        let d = match self.layout {
            Layout::Equirect => {
                let (t, p) = equirect_angles(x, y, self.w, self.h);
                Frame::YUp.direction(t, p)
            }
            Layout::Angular | Layout::MirrorBall => {
                let disc = disc_of(self.layout)?;
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

    pub(crate) fn solid_angle(&self, x: usize, y: usize, rule: Option<&DiscRule>) -> f64 {
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

    /// [`Geometry::solid_angle`] of every texel, row-major, with the disc
    /// rule built once.
    pub(crate) fn solid_angles(&self) -> Vec<f64> {
        let rule = self.disc_rule();
        (0..self.h)
            .flat_map(|y| (0..self.w).map(move |x| (x, y)))
            .map(|(x, y)| self.solid_angle(x, y, rule.as_ref()))
            .collect()
    }

    pub(crate) fn image_point(&self, d: DVec3) -> (f64, f64) {
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
                let disc = disc_of(self.layout).expect("a disc layout");
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
