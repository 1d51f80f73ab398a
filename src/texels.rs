//! Where the texels of a map that shlight writes look: the one thing an
//! image layout has to provide to `synth`, `render` and `--preview`.
//!
//! Every command that fills an image from directions does it through a
//! [`TexelGrid`]: texel `(x, y)` → unit world direction (or nothing, for
//! texels a layout leaves unused), a direction → its texel, a texel's solid
//! angle, and points inside a texel for box filtering. The geometry is
//! `shlight_core::layout`'s (one implementation of each formula); this
//! module only adapts it to the CLI.

use std::sync::OnceLock;

use anyhow::{Result, bail};
use clap::ValueEnum;
use glam::DVec3;
use shlight_core::layout::{EnvMap, Layout};
use shlight_core::projection::MapOrientation;

use std::f64::consts::PI;

/// Image layouts, as `--layout` spells them (docs/conventions.md, "Layouts").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum LayoutArg {
    /// Equirectangular (latitude-longitude), 2:1.
    #[default]
    Equirect,
    /// Horizontal cube cross, 4f x 3f.
    #[value(name = "cross-h")]
    CrossH,
    /// Vertical cube cross, 3f x 4f.
    #[value(name = "cross-v")]
    CrossV,
    /// Six cube faces in a row, +X -X +Y -Y +Z -Z, 6f x f.
    Strip,
    /// Angular map (Debevec light probe), N x N.
    Angular,
    /// Mirror ball, N x N.
    #[value(name = "mirror-ball")]
    MirrorBall,
}

impl LayoutArg {
    /// The core layout.
    pub fn layout(self) -> Layout {
        match self {
            LayoutArg::Equirect => Layout::Equirect,
            LayoutArg::CrossH => Layout::CrossHorizontal,
            LayoutArg::CrossV => Layout::CrossVertical,
            LayoutArg::Strip => Layout::Strip,
            LayoutArg::Angular => Layout::Angular,
            LayoutArg::MirrorBall => Layout::MirrorBall,
        }
    }

    /// Checks that a `width x height` image can hold this layout. The
    /// equirect layout written by shlight is always 2:1.
    pub fn check_size(self, width: usize, height: usize) -> std::result::Result<(), String> {
        if self == LayoutArg::Equirect && (width == 0 || width != 2 * height) {
            return Err(format!(
                "a {width}x{height} image is not an equirect map (its width must be twice its height)"
            ));
        }
        self.layout()
            .check_size(width, height)
            .map_err(|e| e.to_string())
    }
}

/// The size `render` and `synth` use without `--size`: equirect
/// `2n x n`, cube faces of `n / 2`, a disc of `n`.
pub fn default_size(layout: LayoutArg, n: usize) -> (usize, usize) {
    let l = layout.layout();
    l.dimensions(if l.is_cube() { (n / 2).max(1) } else { n })
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
#[derive(Debug)]
pub struct TexelGrid {
    /// The layout.
    pub layout: LayoutArg,
    /// Texels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Frame and mirroring (docs/conventions.md).
    pub orientation: MapOrientation,
    /// Black texels, only so that an [`EnvMap`] (whose geometry ignores
    /// them) can be formed.
    black: Vec<[f32; 3]>,
    /// Every texel's solid angle, computed on first use.
    solid_angles: OnceLock<Vec<f64>>,
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
            black: vec![[0.0; 3]; width * height],
            solid_angles: OnceLock::new(),
        })
    }

    /// The core's view of the grid (its pixels are black).
    pub fn env_map(&self) -> EnvMap<'_> {
        EnvMap::new(
            self.layout.layout(),
            self.orientation,
            self.width,
            self.height,
            &self.black,
        )
        .expect("the size was checked")
    }

    /// The world direction of the frame's up axis (+Y for y-up, +Z for z-up).
    pub fn up(&self) -> DVec3 {
        self.orientation.frame.direction(0.0, 0.0)
    }

    /// The unit direction of the centre of texel `(x, y)`; `None` for a
    /// texel the layout does not use.
    pub fn direction(&self, x: usize, y: usize) -> Option<DVec3> {
        self.env_map().texel_direction(x, y)
    }

    /// A direction inside texel `(x, y)` at `(s, t)` in `[0, 1]^2`, such
    /// that averaging a function over a regular grid of `(s, t)` gives its
    /// mean over the texel. Equirect: `cos θ` and `φ` vary linearly across
    /// the texel (equal areas of `(s, t)` cover equal solid angles). Other
    /// layouts have no such closed form here: every `(s, t)` gives the
    /// texel-centre direction, so `synth` point-samples their texels.
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
            _ => self.direction(x, y),
        }
    }

    /// The exact solid angle texel `(x, y)` covers (0 for unused texels).
    pub fn solid_angle(&self, x: usize, y: usize) -> f64 {
        self.solid_angles
            .get_or_init(|| self.env_map().texel_solid_angles())[y * self.width + x]
    }

    /// The texel that unit direction `d` falls in.
    pub fn texel_of(&self, d: DVec3) -> (usize, usize) {
        let (x, y) = self.env_map().direction_to_image(d);
        let clamp = |v: f64, n: usize| (v.floor().max(0.0) as usize).min(n - 1);
        (clamp(x, self.width), clamp(y, self.height))
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
        for layout in LayoutArg::value_variants() {
            let size = layout.layout().dimensions(8);
            let g = TexelGrid::new(*layout, size, MapOrientation::default()).unwrap();
            for y in 0..size.1 {
                for x in 0..size.0 {
                    if let Some(d) = g.direction(x, y)
                        && g.solid_angle(x, y) > 0.0
                        && !layout.layout().is_disc()
                    {
                        assert_eq!(g.texel_of(d), (x, y), "{layout:?}");
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
