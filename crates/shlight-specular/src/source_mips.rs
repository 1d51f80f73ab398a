//! [`SourceMips`]: the environment resampled into a cube in the output's
//! axes, with its box-filtered mip chain, looked up trilinearly: what the
//! prefilter's samples read, each at the mip whose texels match its share
//! of the sphere (Colbert & Krivanek 2007).

use glam::{DMat3, DVec3, Vec3, Vec3A};
use shlight_core::map::{CubeFace, EnvMap};

use crate::bordered_cube::{BorderedCube, FacePoint};
use crate::cube_image::CubeImage;

/// The largest face the source cube is resampled to.
pub const MAX_SOURCE_SIZE: usize = 2048;

/// A map as a cube with mips, in the axes of the cube being made.
#[derive(Clone, Debug)]
pub struct SourceMips {
    levels: Vec<BorderedCube>,
}

impl SourceMips {
    /// The face size the source cube of `map` is resampled to for an
    /// output of `size`: the power of two nearest a cube with as many
    /// texels as the map, at least `size`, at most [`MAX_SOURCE_SIZE`].
    #[must_use]
    pub fn base_size(map: &EnvMap, size: usize) -> usize {
        let texels = (map.width * map.height) as f64;
        let face = (texels / 6.0).sqrt().max(1.0);
        let nearest = 1usize << (face.log2().round() as u32);
        nearest.max(size).clamp(1, MAX_SOURCE_SIZE.max(size))
    }

    /// `map` resampled to a cube of `base` pixels whose texel in direction
    /// `c` is the map's radiance at `world_from_cube * c`: each texel the
    /// mean of `k x k` bilinear lookups spread over it, `k` enough to
    /// touch every map texel under it (at most 4); then halved to 1 pixel.
    #[must_use]
    pub fn new(map: &EnvMap, world_from_cube: DMat3, base: usize) -> Self {
        let texels = (map.width * map.height) as f64;
        let k = ((texels / (6.0 * (base * base) as f64)).sqrt().ceil() as usize).clamp(1, 4);
        let f = base as f64;
        let cube = CubeImage::from_fn(base, |face: CubeFace, i, j| {
            let mut sum = DVec3::ZERO;
            for b in 0..k {
                for a in 0..k {
                    let s = (i as f64 + (a as f64 + 0.5) / k as f64) * 2.0 / f - 1.0;
                    let t = (j as f64 + (b as f64 + 0.5) / k as f64) * 2.0 / f - 1.0;
                    sum += map.radiance_bilinear(world_from_cube * face.point(s, t));
                }
            }
            (sum / (k * k) as f64).as_vec3().to_array()
        });
        Self::from_cube(cube)
    }

    /// A cube and its box-filtered mips.
    #[must_use]
    pub fn from_cube(cube: CubeImage) -> Self {
        let mut levels = vec![BorderedCube::new(&cube)];
        let mut current = cube;
        while let Some(next) = current.halved() {
            levels.push(BorderedCube::new(&next));
            current = next;
        }
        Self { levels }
    }

    /// Face size of mip 0.
    #[must_use]
    pub fn size(&self) -> usize {
        self.levels[0].size()
    }

    /// The highest mip (the 1-pixel cube).
    #[must_use]
    pub fn max_level(&self) -> usize {
        self.levels.len() - 1
    }

    /// [`SourceMips::trilinear`] in `f32` (the prefilter's inner loop):
    /// mip `l0` blended with `l0 + 1` by `t`.
    #[inline]
    #[must_use]
    pub fn trilinear_f32(&self, c: Vec3, l0: usize, t: f32) -> Vec3A {
        let p = FacePoint::of(c);
        let a = self.levels[l0].bilinear_at(p);
        if t <= 0.0 || l0 >= self.max_level() {
            return a;
        }
        let b = self.levels[l0 + 1].bilinear_at(p);
        a + (b - a) * t
    }

    /// Radiance in cube direction `c` at level of detail `lod` (clamped to
    /// the chain): bilinear in the two mips around it (each face bordered
    /// by its neighbours' texels, [`BorderedCube`]), blended linearly.
    #[must_use]
    pub fn trilinear(&self, c: DVec3, lod: f64) -> DVec3 {
        let lod = lod.clamp(0.0, self.max_level() as f64);
        let l0 = lod.floor() as usize;
        let t = lod - l0 as f64;
        let a = self.levels[l0].bilinear(c);
        if t <= 0.0 || l0 == self.max_level() {
            return a;
        }
        let b = self.levels[l0 + 1].bilinear(c);
        a + (b - a) * t
    }
}
