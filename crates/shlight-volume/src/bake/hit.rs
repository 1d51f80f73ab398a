//! [`Hit`]: what one probe ray met, as the bake casts it and its sums
//! ([`super::sums`]) read it.

use shlight_baked::visibility::ray_distance;

/// What one probe ray met: a triangle's front (its index and the
/// barycentric weights of corners 1 and 2), a back face, or nothing; and
/// how far away.
#[derive(Clone, Copy, Debug)]
pub(super) struct Hit {
    pub(super) triangle: u32,
    pub(super) b1: f32,
    pub(super) b2: f32,
    pub(super) t: f32,
}

impl Hit {
    /// [`Hit::triangle`] of a ray that escaped.
    pub(super) const ESCAPED_ID: u32 = u32::MAX;
    /// [`Hit::triangle`] of a ray that met a back face.
    pub(super) const BACK_ID: u32 = u32::MAX - 1;
    pub(super) const ESCAPED: Hit = Hit {
        triangle: Self::ESCAPED_ID,
        b1: 0.0,
        b2: 0.0,
        t: f32::INFINITY,
    };
    pub(super) const BACK: Hit = Hit {
        triangle: Self::BACK_ID,
        b1: 0.0,
        b2: 0.0,
        t: 0.0,
    };

    /// A back face at distance `t`.
    pub(super) fn back(t: f32) -> Hit {
        Hit { t, ..Hit::BACK }
    }

    /// The distance the ray reaches for a distance map
    /// ([`shlight_baked::visibility::ray_distance`]).
    pub(super) fn distance(&self, max_distance: f32) -> f32 {
        match self.triangle {
            Self::ESCAPED_ID => ray_distance(None, false, max_distance),
            Self::BACK_ID => ray_distance(Some(self.t), true, max_distance),
            _ => ray_distance(Some(self.t), false, max_distance),
        }
    }
}
