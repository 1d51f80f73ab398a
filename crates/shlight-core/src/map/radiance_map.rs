//! [`RadianceMap`]: a distant radiance field looked up by direction (what
//! Monte Carlo projection and brute-force irradiance sample), and the
//! [`luminance`] of linear RGB.

use glam::DVec3;

/// A distant radiance field that can be looked up in any direction.
pub trait RadianceMap: Sync {
    /// Radiance arriving from the unit world direction `d`, linear RGB.
    fn radiance(&self, d: DVec3) -> DVec3;
}

impl<F: Fn(DVec3) -> DVec3 + Sync> RadianceMap for F {
    fn radiance(&self, d: DVec3) -> DVec3 {
        self(d)
    }
}

/// Rec.709 / sRGB-primaries luminance of linear RGB:
/// `Y = 0.2126 R + 0.7152 G + 0.0722 B`.
#[inline]
#[must_use]
pub fn luminance(rgb: DVec3) -> f64 {
    0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z
}
