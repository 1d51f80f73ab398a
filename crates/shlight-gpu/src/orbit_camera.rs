//! [`OrbitCamera`]: a camera orbiting a mesh (the viewer's), by yaw and
//! pitch about its target at a distance.
//!
//! The eye is at `target + distance (cos p sin y, sin p, cos p cos y)`:
//! yaw `y` about +Y from +Z, pitch `p` above the horizon; the camera looks
//! at the target with [`DEFAULT_FOV_Y_DEGREES`] and planes that hold a
//! sphere of `radius` about it ([`Camera::looking_at`]).

use glam::Vec3;

use crate::{Camera, DEFAULT_FOV_Y_DEGREES, DEFAULT_VIEW_FROM};

/// A camera orbiting a target (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at.
    pub target: Vec3,
    /// Radians about +Y, from +Z towards +X.
    pub yaw: f32,
    /// Radians above the horizon.
    pub pitch: f32,
    /// From the target to the eye.
    pub distance: f32,
    /// Radius of the sphere the near and far planes hold.
    pub radius: f32,
}

impl OrbitCamera {
    /// The orbit that starts at [`Camera::framing`]'s view of the bounds
    /// from [`DEFAULT_VIEW_FROM`], holding the bounds' sphere.
    #[must_use]
    pub fn new(bounds: (Vec3, Vec3), aspect: f32) -> Self {
        let framed = Camera::framing(
            bounds,
            DEFAULT_VIEW_FROM,
            DEFAULT_FOV_Y_DEGREES.to_radians(),
            aspect,
        );
        let d = (framed.eye - framed.target).normalize();
        Self {
            target: framed.target,
            yaw: d.x.atan2(d.z),
            pitch: d.y.asin(),
            distance: (framed.eye - framed.target).length(),
            radius: (bounds.1 - bounds.0).length() * 0.5,
        }
    }

    /// The camera at the orbit's eye, looking at its target.
    #[must_use]
    pub fn camera(&self) -> Camera {
        let dir = Vec3::new(
            self.pitch.cos() * self.yaw.sin(),
            self.pitch.sin(),
            self.pitch.cos() * self.yaw.cos(),
        );
        Camera::looking_at(
            self.target + dir * self.distance,
            self.target,
            self.radius,
            DEFAULT_FOV_Y_DEGREES.to_radians(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The orbit starts at the framed view; a quarter turn of yaw moves the
    /// eye a quarter turn about the target's vertical, at the same height
    /// and distance.
    #[test]
    fn the_orbit_starts_framed_and_turns_about_the_vertical() {
        let bounds = (Vec3::new(-1.0, -0.5, -2.0), Vec3::new(2.0, 1.5, 1.0));
        let framed = Camera::framing(
            bounds,
            DEFAULT_VIEW_FROM,
            DEFAULT_FOV_Y_DEGREES.to_radians(),
            1.6,
        );
        let orbit = OrbitCamera::new(bounds, 1.6);
        let start = orbit.camera();
        assert!(
            (start.eye - framed.eye).length() < 1e-4,
            "{start:?} {framed:?}"
        );
        assert_eq!(start.target, framed.target);
        let turned = OrbitCamera {
            yaw: orbit.yaw + std::f32::consts::FRAC_PI_2,
            ..orbit
        }
        .camera();
        let (a, b) = (start.eye - orbit.target, turned.eye - orbit.target);
        assert!((a.y - b.y).abs() < 1e-5);
        assert!((a.length() - b.length()).abs() < 1e-4);
        // A quarter turn about +Y: (x, z) -> (z, -x).
        assert!(
            (b.x - a.z).abs() < 1e-4 && (b.z + a.x).abs() < 1e-4,
            "{a} {b}"
        );
    }
}
