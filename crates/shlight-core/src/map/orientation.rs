//! [`MapOrientation`]: how an environment map's own y-up frame meets world
//! directions (which world axis is up, and whether azimuth runs mirrored).
//! Every layout ([`Layout`](crate::map::Layout)) first gives a direction in the map's
//! frame; the orientation takes it to the world.

use glam::DVec3;

use crate::sh::frame::Frame;

/// How an equirect map's texels meet world directions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MapOrientation {
    /// Which world axis row 0 faces (docs/conventions.md).
    pub frame: Frame,
    /// Read maps made for the mirrored pbrt / google mapping: `φ` runs the
    /// other way around the pole.
    pub mirror: bool,
}

impl MapOrientation {
    /// Every orientation: both frames, unmirrored and mirrored.
    pub const ALL: [Self; 4] = [
        Self {
            frame: Frame::YUp,
            mirror: false,
        },
        Self {
            frame: Frame::YUp,
            mirror: true,
        },
        Self {
            frame: Frame::ZUp,
            mirror: false,
        },
        Self {
            frame: Frame::ZUp,
            mirror: true,
        },
    ];

    /// World direction of a direction `d` given in the map's own y-up frame:
    /// `mirror` negates its `z` (for equirect maps that is `φ -> -φ`), then
    /// `Frame::YUp.rotation_to(frame)` turns it into the frame.
    #[inline]
    #[must_use]
    pub fn world_from_map(self, d: DVec3) -> DVec3 {
        let d = if self.mirror {
            d * DVec3::new(1.0, 1.0, -1.0)
        } else {
            d
        };
        Frame::YUp.rotation_to(self.frame) * d
    }

    /// `s` in `ψ = s φ`: the azimuth `ψ` about the map's pole (its z-up
    /// frame, `d_zup = (sin θ cos φ, -sin θ sin φ, cos θ)`) of texel azimuth
    /// `φ`; -1, or +1 when mirrored. What the ring transforms (CPU and GPU)
    /// turn each row by.
    #[inline]
    #[must_use]
    pub fn pole_azimuth_sign(self) -> f64 {
        if self.mirror { 1.0 } else { -1.0 }
    }

    /// The inverse of [`MapOrientation::world_from_map`].
    #[inline]
    #[must_use]
    pub fn map_from_world(self, d: DVec3) -> DVec3 {
        let d = self.frame.rotation_to(Frame::YUp) * d;
        if self.mirror {
            d * DVec3::new(1.0, 1.0, -1.0)
        } else {
            d
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_from_world_inverts_world_from_map() {
        let d = DVec3::new(0.2, -0.5, 0.84);
        for o in MapOrientation::ALL {
            assert!(
                (o.map_from_world(o.world_from_map(d)) - d).length() < 1e-15,
                "{o:?}"
            );
        }
    }
}
