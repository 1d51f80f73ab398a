//! The camera of `shlight view`, orbiting the mesh.

use glam::Vec3;
use shlight_gpu::{Camera, DEFAULT_FOV_Y_DEGREES, DEFAULT_VIEW_FROM};

/// The camera orbiting the mesh: yaw about +Y, pitch above the horizon.
#[derive(Clone, Copy, Debug)]
pub struct Orbit {
    pub target: Vec3,
    pub yaw: f32,
    pub pitch: f32,
    pub distance: f32,
    pub radius: f32,
}

impl Orbit {
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
