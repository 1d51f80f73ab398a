//! Monte Carlo projection of a distant radiance field to SH, with standard errors.

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
