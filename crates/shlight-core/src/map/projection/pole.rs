//! [`to_frame`]: coefficients computed about an equirect map's own pole
//! (z-up) turned into the map's frame.

use glam::DVec3;

use crate::sh::frame::Frame;
use crate::sh::sh_coeffs::ShCoeffs;

/// Coefficients computed about the map's pole (z-up) turned into `frame`:
/// unchanged for z-up, a quarter turn about X (`Rx(-90°)`,
/// [`crate::sh::quarter_turn_x`]) for y-up. The last step of [`super::project_equirect`],
/// public for other routes to the same ring sums (the GPU's).
#[must_use]
pub fn to_frame(zup: ShCoeffs<DVec3>, frame: Frame) -> ShCoeffs<DVec3> {
    match frame {
        Frame::ZUp => zup,
        // z-up -> y-up is Rx(-90°) (`Frame::rotation_to`).
        Frame::YUp => crate::sh::quarter_turn::quarter_turn_x(&zup, -1),
    }
}
