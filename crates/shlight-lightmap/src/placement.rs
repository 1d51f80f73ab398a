//! Where a mesh's UVs land in a shared lightmap: a scale and an offset.

use glam::{DVec2, Vec2};

/// A scale and offset applied to a mesh's UVs before they are rasterised:
/// `uv' = uv * scale + offset` (Unity's `lightmapScaleOffset`; Bevy's
/// `Lightmap::uv_rect` is the same map from its rectangle's corners,
/// [`Placement::from_rect`]). Each instance of a mesh gets its own
/// region of an atlas this way without copying the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Multiplies the UV, per axis.
    pub scale: Vec2,
    /// Added after scaling.
    pub offset: Vec2,
}

impl Placement {
    /// The UVs as they are.
    pub const IDENTITY: Placement = Placement {
        scale: Vec2::ONE,
        offset: Vec2::ZERO,
    };

    /// The placement that maps the unit square onto the rectangle from
    /// `min` to `max` (Bevy's `uv_rect`: `mix(min, max, uv)`).
    pub fn from_rect(min: Vec2, max: Vec2) -> Self {
        Placement {
            scale: max - min,
            offset: min,
        }
    }

    /// `uv * scale + offset` in `f64`.
    pub fn apply(&self, uv: DVec2) -> DVec2 {
        uv * self.scale.as_dvec2() + self.offset.as_dvec2()
    }

    /// Whether the scale and offset are finite.
    pub fn is_finite(&self) -> bool {
        self.scale.is_finite() && self.offset.is_finite()
    }
}

impl Default for Placement {
    fn default() -> Self {
        Placement::IDENTITY
    }
}
