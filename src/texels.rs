//! Where the texels of a map that shlight writes look: the one thing an
//! image layout has to provide to `synth`, `render` and `--preview`.
//!
//! Every command that fills an image from directions does it through a
//! [`TexelGrid`]: texel `(x, y)` → unit world direction (or nothing, for
//! texels a layout leaves unused), a direction → its texel, a texel's solid
//! angle, and equal-area points inside a texel for box filtering. Only the
//! equirect layout exists until `shlight_core::layout` lands; a new layout is
//! a new [`LayoutArg`] variant and one more arm in each method here.

use anyhow::{Result, bail};
use clap::ValueEnum;
use glam::{DMat3, DVec3};
use shlight_core::projection::{MapOrientation, equirect_direction, equirect_row_solid_angle};

use std::f64::consts::PI;

/// Image layouts, as `--layout` spells them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum LayoutArg {
    /// Equirectangular (latitude-longitude), 2:1, docs/conventions.md.
    #[default]
    Equirect,
}

impl LayoutArg {
    /// The name written to coefficient files' provenance.
    pub fn name(self) -> &'static str {
        match self {
            LayoutArg::Equirect => "equirect",
        }
    }

    /// Checks that a `width x height` image can hold this layout.
    pub fn check_size(self, width: usize, height: usize) -> std::result::Result<(), String> {
        match self {
            LayoutArg::Equirect if width == 0 || width != 2 * height => Err(format!(
                "a {width}x{height} image is not an equirect map (its width must be twice its height)"
            )),
            LayoutArg::Equirect => Ok(()),
        }
    }
}

/// `--size WxH`, e.g. `1024x512`.
pub fn parse_size(s: &str) -> std::result::Result<(usize, usize), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{s:?} is not WIDTHxHEIGHT (e.g. 1024x512)"))?;
    let parse = |t: &str| {
        t.trim()
            .parse::<usize>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("{s:?}: {t:?} is not a positive whole number"))
    };
    let (w, h) = (parse(w)?, parse(h)?);
    if w.checked_mul(h)
        .is_none_or(|n| n > shlight_io::ReadOptions::DEFAULT_MAX_PIXELS)
    {
        return Err(format!(
            "{s:?}: more than {} pixels",
            shlight_io::ReadOptions::DEFAULT_MAX_PIXELS
        ));
    }
    Ok((w, h))
}

/// A `width x height` image in some layout and orientation, seen as texels
/// that look in world directions.
#[derive(Clone, Copy, Debug)]
pub struct TexelGrid {
    /// The layout.
    pub layout: LayoutArg,
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Frame and mirroring (docs/conventions.md).
    pub orientation: MapOrientation,
}

impl TexelGrid {
    /// A grid, if the size suits the layout.
    pub fn new(
        layout: LayoutArg,
        (width, height): (usize, usize),
        orientation: MapOrientation,
    ) -> Result<Self> {
        if let Err(e) = layout.check_size(width, height) {
            bail!("{e}");
        }
        Ok(Self {
            layout,
            width,
            height,
            orientation,
        })
    }

    /// The world direction of the frame's up axis (+Y for y-up, +Z for z-up).
    pub fn up(&self) -> DVec3 {
        self.orientation.frame.direction(0.0, 0.0)
    }

    /// The unit direction of the centre of texel `(x, y)`; `None` for a
    /// texel the layout does not use.
    pub fn direction(&self, x: usize, y: usize) -> Option<DVec3> {
        match self.layout {
            LayoutArg::Equirect => Some(equirect_direction(
                x,
                y,
                self.width,
                self.height,
                self.orientation,
            )),
        }
    }

    /// A direction inside texel `(x, y)` at `(s, t)` in `[0, 1]^2`, such
    /// that equal areas of `(s, t)` cover equal solid angles: averaging a
    /// function over a regular grid of `(s, t)` gives its mean over the
    /// texel. Equirect: `cos θ` and `φ` vary linearly across the texel.
    pub fn sample(&self, x: usize, y: usize, s: f64, t: f64) -> Option<DVec3> {
        match self.layout {
            LayoutArg::Equirect => {
                let (w, h) = (self.width as f64, self.height as f64);
                let z0 = (PI * y as f64 / h).cos();
                let z1 = (PI * (y + 1) as f64 / h).cos();
                let theta = (z0 + (z1 - z0) * t).clamp(-1.0, 1.0).acos();
                let phi = 2.0 * PI * ((x as f64 + s) / w - 0.5);
                let phi = if self.orientation.mirror { -phi } else { phi };
                Some(self.orientation.frame.direction(theta, phi))
            }
        }
    }

    /// The exact solid angle texel `(x, y)` covers (0 for unused texels).
    pub fn solid_angle(&self, _x: usize, y: usize) -> f64 {
        match self.layout {
            LayoutArg::Equirect => equirect_row_solid_angle(y, self.width, self.height),
        }
    }

    /// The texel that unit direction `d` falls in.
    pub fn texel_of(&self, d: DVec3) -> (usize, usize) {
        match self.layout {
            LayoutArg::Equirect => {
                // Frame::direction(θ, φ) is linear in (sin θ cos φ, sin θ sin φ, cos θ);
                // its columns are the images of those three axes.
                let f = self.orientation.frame;
                let m = DMat3::from_cols(
                    f.direction(PI / 2.0, 0.0),
                    f.direction(PI / 2.0, PI / 2.0),
                    f.direction(0.0, 0.0),
                );
                let c = m.transpose() * d.normalize();
                let theta = c.z.clamp(-1.0, 1.0).acos();
                let phi = c.y.atan2(c.x);
                let phi = if self.orientation.mirror { -phi } else { phi };
                let u = phi / (2.0 * PI) + 0.5;
                let v = theta / PI;
                let x = ((u * self.width as f64).floor() as usize).min(self.width - 1);
                let y = ((v * self.height as f64).floor() as usize).min(self.height - 1);
                (x, y)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::rotation::Frame;

    #[test]
    fn texel_of_inverts_direction_in_every_orientation() {
        for frame in [Frame::YUp, Frame::ZUp] {
            for mirror in [false, true] {
                let g = TexelGrid::new(
                    LayoutArg::Equirect,
                    (32, 16),
                    MapOrientation { frame, mirror },
                )
                .unwrap();
                for y in 0..16 {
                    for x in 0..32 {
                        let d = g.direction(x, y).unwrap();
                        assert_eq!(g.texel_of(d), (x, y), "{frame} {mirror}");
                        let inside = g.sample(x, y, 0.3, 0.8).unwrap();
                        assert_eq!(g.texel_of(inside), (x, y), "{frame} {mirror}");
                    }
                }
            }
        }
    }

    #[test]
    fn sizes_parse_and_equirect_needs_two_to_one() {
        assert_eq!(parse_size("64x32"), Ok((64, 32)));
        assert!(parse_size("64").is_err() && parse_size("0x0").is_err());
        assert!(LayoutArg::Equirect.check_size(64, 32).is_ok());
        assert!(LayoutArg::Equirect.check_size(64, 64).is_err());
    }
}
