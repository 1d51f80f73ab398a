//! The camera: a right-handed look-at view with a perspective projection.
//!
//! World space is the mesh's own space (shlight's world, where the SH are
//! evaluated). The view looks from `eye` at `target`, with `up` (default +Y)
//! pointing up on screen; clip depth runs from 0 at `near` to 1 at `far`
//! (wgpu's convention), and the image's row 0 is the top of the screen.

use glam::{Mat4, Vec3, Vec4};

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Where the camera is.
    pub eye: Vec3,
    /// The point at the centre of the image.
    pub target: Vec3,
    /// The world direction shown as up on screen (need not be orthogonal
    /// to the view direction; when parallel to it, +Z or +X is used).
    pub up: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Near clipping distance.
    pub near: f32,
    /// Far clipping distance.
    pub far: f32,
}

/// Default vertical field of view of framed cameras: 35 degrees.
pub const DEFAULT_FOV_Y_DEGREES: f32 = 35.0;

/// Default viewing direction of [`Camera::framing`], from the target
/// towards the eye: in front (+Z) and a little above (+Y) and to the right (+X).
pub const DEFAULT_VIEW_FROM: Vec3 = Vec3::new(0.35, 0.3, 1.0);

impl Camera {
    /// A camera looking at the bounding sphere of `(min, max)` from
    /// direction `from` (target towards eye), at the distance where that
    /// sphere just fits the smaller of the two fields of view, plus 5%.
    #[must_use]
    pub fn framing(bounds: (Vec3, Vec3), from: Vec3, fov_y: f32, aspect: f32) -> Self {
        let (min, max) = bounds;
        let centre = (min + max) * 0.5;
        let radius = ((max - min).length() * 0.5).max(1e-6);
        let fov_x = 2.0 * ((fov_y * 0.5).tan() * aspect).atan();
        let half = 0.5 * fov_y.min(fov_x);
        let distance = 1.05 * radius / half.sin();
        let dir = from.try_normalize().unwrap_or(Vec3::Z);
        Self::looking_at(centre + dir * distance, centre, radius, fov_y)
    }

    /// The camera for a mesh of `bounds` from an optional `eye` towards an
    /// optional `target` (default: the bounds' centre `c`):
    ///
    /// - neither: [`Camera::framing`] from [`DEFAULT_VIEW_FROM`];
    /// - a target only: the framed camera moved by `target - c` (the same
    ///   view, aimed at the target);
    /// - an eye: from it towards the target.
    ///
    /// The near and far planes hold the bounds' sphere (radius `r`) seen
    /// about the target: a sphere of `r + |target - c|`. `None` when the
    /// eye is the target (no direction to look in).
    #[must_use]
    pub fn aimed(
        bounds: (Vec3, Vec3),
        eye: Option<Vec3>,
        target: Option<Vec3>,
        fov_y: f32,
        aspect: f32,
    ) -> Option<Self> {
        let centre = (bounds.0 + bounds.1) * 0.5;
        let radius = (bounds.1 - bounds.0).length() * 0.5;
        let target = target.unwrap_or(centre);
        Some(match eye {
            None if target == centre => Self::framing(bounds, DEFAULT_VIEW_FROM, fov_y, aspect),
            None => {
                let framed = Self::framing(bounds, DEFAULT_VIEW_FROM, fov_y, aspect);
                Self::looking_at(
                    framed.eye - centre + target,
                    target,
                    radius + (target - centre).length(),
                    fov_y,
                )
            }
            Some(eye) => {
                if (eye - target).length() <= 0.0 {
                    return None;
                }
                Self::looking_at(eye, target, radius + (target - centre).length(), fov_y)
            }
        })
    }

    /// A camera at `eye` looking at `target`, with near and far planes that
    /// hold a sphere of `radius` about `target`.
    #[must_use]
    pub fn looking_at(eye: Vec3, target: Vec3, radius: f32, fov_y: f32) -> Self {
        let distance = (eye - target).length();
        let near = (distance - 2.0 * radius).max(distance * 1e-3).max(1e-5);
        let far = distance + 2.0 * radius;
        Self {
            eye,
            target,
            up: Vec3::Y,
            fov_y,
            near,
            far,
        }
    }

    /// World to view: right-handed, looking down the view's -Z.
    #[must_use]
    pub fn view(&self) -> Mat4 {
        let forward = (self.target - self.eye).normalize_or(Vec3::NEG_Z);
        let up = [self.up, Vec3::Z, Vec3::X]
            .into_iter()
            .find(|u| forward.cross(*u).length_squared() > 1e-8)
            .unwrap_or(Vec3::Y);
        let s = forward.cross(up).normalize();
        let u = s.cross(forward);
        Mat4::from_cols(
            Vec4::new(s.x, u.x, -forward.x, 0.0),
            Vec4::new(s.y, u.y, -forward.y, 0.0),
            Vec4::new(s.z, u.z, -forward.z, 0.0),
            Vec4::new(
                -s.dot(self.eye),
                -u.dot(self.eye),
                forward.dot(self.eye),
                1.0,
            ),
        )
    }

    /// View to clip: `x_clip = x / (a tan(fov_y/2))`, `y_clip = y / tan(fov_y/2)`,
    /// depth `z_ndc = f (z + n) / ((n - f) z)` in `[0, 1]` from near to far, `w = -z`.
    #[must_use]
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let h = 1.0 / (0.5 * self.fov_y).tan();
        let r = self.far / (self.near - self.far);
        Mat4::from_cols(
            Vec4::new(h / aspect, 0.0, 0.0, 0.0),
            Vec4::new(0.0, h, 0.0, 0.0),
            Vec4::new(0.0, 0.0, r, -1.0),
            Vec4::new(0.0, 0.0, r * self.near, 0.0),
        )
    }

    /// Clip from world for an image of `aspect` = width / height.
    #[must_use]
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_target_lands_at_the_centre_and_depth_runs_from_0_to_1() {
        let c = Camera::looking_at(Vec3::new(1.0, 2.0, 5.0), Vec3::new(0.5, 0.0, 0.0), 1.0, 0.7);
        let m = c.view_proj(1.5);
        let centre = m * c.target.extend(1.0);
        assert!(centre.x.abs() < 1e-5 && centre.y.abs() < 1e-5);
        let dir = (c.target - c.eye).normalize();
        let near = m * (c.eye + dir * c.near).extend(1.0);
        let far = m * (c.eye + dir * c.far).extend(1.0);
        assert!((near.z / near.w).abs() < 1e-5, "{near}");
        assert!((far.z / far.w - 1.0).abs() < 1e-5, "{far}");
        // World up is up on screen: a point above the target has y > 0.
        let above = m * (c.target + Vec3::Y * 0.1).extend(1.0);
        assert!(above.y / above.w > 0.0);
        // Right-handed: looking down -Z from +Z, +X is to the right.
        let c = Camera::looking_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 1.0, 0.7);
        let right = c.view_proj(1.0) * Vec3::new(0.1, 0.0, 0.0).extend(1.0);
        assert!(right.x / right.w > 0.0);
    }

    /// `aimed` frames by default, keeps the framed view when only the
    /// target moves, looks from a given eye, holds the bounds between its
    /// planes in every case, and refuses an eye on the target.
    #[test]
    fn an_aimed_camera_frames_moves_and_holds_the_bounds() {
        let bounds = (Vec3::new(-1.0, 0.0, -2.0), Vec3::new(3.0, 1.0, 0.0));
        let (fov, aspect) = (0.6, 1.5);
        let framed = Camera::framing(bounds, DEFAULT_VIEW_FROM, fov, aspect);
        assert_eq!(Camera::aimed(bounds, None, None, fov, aspect), Some(framed));
        let target = Vec3::new(2.0, 0.5, -1.0);
        let moved = Camera::aimed(bounds, None, Some(target), fov, aspect).unwrap();
        assert_eq!(moved.target, target);
        assert!((moved.eye - moved.target - (framed.eye - framed.target)).length() < 1e-5);
        let eye = Vec3::new(0.0, 4.0, 6.0);
        let given = Camera::aimed(bounds, Some(eye), Some(target), fov, aspect).unwrap();
        assert_eq!((given.eye, given.target), (eye, target));
        for c in [framed, moved, given] {
            for k in 0..8 {
                let corner = Vec3::new(
                    if k & 1 == 0 { bounds.0.x } else { bounds.1.x },
                    if k & 2 == 0 { bounds.0.y } else { bounds.1.y },
                    if k & 4 == 0 { bounds.0.z } else { bounds.1.z },
                );
                let d = (corner - c.eye).length();
                assert!(c.near <= d && d <= c.far, "{c:?} {corner}");
            }
        }
        assert_eq!(
            Camera::aimed(bounds, Some(target), Some(target), fov, aspect),
            None
        );
        assert_eq!(
            Camera::aimed(bounds, Some(Vec3::new(1.0, 0.5, -1.0)), None, fov, aspect),
            None
        );
    }
}
