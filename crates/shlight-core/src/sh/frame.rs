//! [`Frame`]: the y-up and z-up frames in which an equirect map's texels
//! are read as world directions, and the quarter turn between them.

use core::fmt;
use core::str::FromStr;

use glam::{DMat3, DVec3};

/// The frame in which an equirectangular map's texel `(t, p)` is read as a
/// world direction: `t = pi v` the polar angle from the top row, `p = 2 pi
/// (u - 0.5)` the azimuth across the columns (`u, v` texel centres in
/// `[0, 1]`, see `docs/conventions.md`); see [`Frame::direction`].
///
/// The two frames differ by a quarter turn about X:
/// `d_zup = Rx(+90 deg) d_yup`, `(x, y, z) -> (x, -z, y)`; neither is
/// mirrored. Parsed from and displayed as `"y-up"` / `"z-up"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Frame {
    /// three.js / glTF equirect convention, `+Y` up:
    /// `d = (sin t cos p, cos t, sin t sin p)`. The default.
    #[default]
    YUp,
    /// Blender convention, `+Z` up:
    /// `d = (sin t cos p, -sin t sin p, cos t)`.
    ZUp,
}

impl Frame {
    /// The world direction of texel `(t, p)` read in this frame:
    /// y-up `(sin t cos p, cos t, sin t sin p)`,
    /// z-up `(sin t cos p, -sin t sin p, cos t)`.
    #[must_use]
    pub fn direction(self, t: f64, p: f64) -> DVec3 {
        let (st, ct) = t.sin_cos();
        let (sp, cp) = p.sin_cos();
        match self {
            Frame::YUp => DVec3::new(st * cp, ct, st * sp),
            Frame::ZUp => DVec3::new(st * cp, -st * sp, ct),
        }
    }

    /// The rotation `R` with `to.direction(t, p) = R * self.direction(t, p)`
    /// for every texel: `Rx(+90 deg)` = `(x, y, z) -> (x, -z, y)` from y-up
    /// to z-up, its transpose from z-up to y-up, the identity otherwise.
    /// Entries are exactly `0` or `+-1`.
    #[must_use]
    pub fn rotation_to(self, to: Frame) -> DMat3 {
        // Columns are the images of +X, +Y, +Z.
        let yup_to_zup = DMat3::from_cols(DVec3::X, DVec3::Z, DVec3::NEG_Y);
        match (self, to) {
            (Frame::YUp, Frame::ZUp) => yup_to_zup,
            (Frame::ZUp, Frame::YUp) => yup_to_zup.transpose(),
            _ => DMat3::IDENTITY,
        }
    }
}

impl fmt::Display for Frame {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Frame::YUp => "y-up",
            Frame::ZUp => "z-up",
        })
    }
}

/// The error of parsing a [`Frame`] from anything but `"y-up"` or `"z-up"`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseFrameError {
    input: String,
}

impl fmt::Display for ParseFrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "unknown frame {:?}: expected \"y-up\" or \"z-up\"",
            self.input
        )
    }
}

impl std::error::Error for ParseFrameError {}

impl FromStr for Frame {
    type Err = ParseFrameError;
    /// `"y-up"` or `"z-up"`, ASCII case-insensitive.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s.eq_ignore_ascii_case("y-up") {
            Ok(Frame::YUp)
        } else if s.eq_ignore_ascii_case("z-up") {
            Ok(Frame::ZUp)
        } else {
            Err(ParseFrameError {
                input: s.to_owned(),
            })
        }
    }
}
