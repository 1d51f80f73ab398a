//! [`CubeImage`]: one square cube map, six `size x size` faces in
//! shlight-core's face convention ([`CubeFace`]: `+X -X +Y -Y +Z -Z`, the
//! OpenGL / Vulkan / D3D sampling rule, row 0 at the top), stored side by
//! side as a strip so that shlight-core's [`EnvMap`] does its seam-aware
//! bilinear lookups.

use glam::DVec3;
use rayon::prelude::*;
use shlight_core::map::{CubeFace, EnvMap, Layout, MapOrientation};

/// A cube map of linear RGB texels, in the cube's own axes.
#[derive(Clone, Debug, PartialEq)]
pub struct CubeImage {
    size: usize,
    /// A `6 size x size` strip, row-major.
    pixels: Vec<[f32; 3]>,
}

impl CubeImage {
    /// A cube of `size x size` faces whose texel `(i, j)` of `face` holds
    /// `f(face, i, j)`, rows in parallel.
    ///
    /// # Panics
    /// When `size` is 0.
    #[must_use]
    pub fn from_fn(size: usize, f: impl Fn(CubeFace, usize, usize) -> [f32; 3] + Sync) -> Self {
        assert!(size > 0, "a cube map needs faces of at least one texel");
        let width = 6 * size;
        let mut pixels = vec![[0.0; 3]; width * size];
        pixels
            .par_chunks_mut(width)
            .enumerate()
            .for_each(|(j, row)| {
                for (x, p) in row.iter_mut().enumerate() {
                    *p = f(CubeFace::ALL[x / size], x % size, j);
                }
            });
        Self { size, pixels }
    }

    /// Texels per face edge.
    #[must_use]
    pub fn size(&self) -> usize {
        self.size
    }

    /// Texel `(i, j)` (column, row) of `face`.
    #[must_use]
    pub fn get(&self, face: CubeFace, i: usize, j: usize) -> [f32; 3] {
        self.pixels[j * 6 * self.size + face.index() * self.size + i]
    }

    /// The `size x size` texels of `face`, row-major.
    #[must_use]
    pub fn face(&self, face: CubeFace) -> Vec<[f32; 3]> {
        (0..self.size)
            .flat_map(|j| (0..self.size).map(move |i| (i, j)))
            .map(|(i, j)| self.get(face, i, j))
            .collect()
    }

    /// The whole strip, `6 size x size` texels, faces left to right.
    #[must_use]
    pub fn strip(&self) -> &[[f32; 3]] {
        &self.pixels
    }

    /// The cube as shlight-core's map (a strip in the map's own frame).
    #[must_use]
    pub fn as_env_map(&self) -> EnvMap<'_> {
        EnvMap {
            layout: Layout::Strip,
            orientation: MapOrientation::default(),
            width: 6 * self.size,
            height: self.size,
            pixels: &self.pixels,
        }
    }

    /// Unit direction of the centre of texel `(i, j)` of `face`.
    #[must_use]
    pub fn direction(&self, face: CubeFace, i: usize, j: usize) -> DVec3 {
        let f = self.size as f64;
        let c = |k: usize| (2.0 * k as f64 + 1.0) / f - 1.0;
        face.point(c(i), c(j)).normalize()
    }

    /// The next mip: each texel the mean of the 2x2 it covers (faces of
    /// odd size keep their last row and column in the mean of what exists).
    /// `None` for a 1-texel cube.
    #[must_use]
    pub fn halved(&self) -> Option<CubeImage> {
        if self.size == 1 {
            return None;
        }
        let half = self.size.div_ceil(2);
        Some(CubeImage::from_fn(half, |face, i, j| {
            let mut sum = [0.0f64; 3];
            let mut n = 0.0;
            for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (x, y) = (2 * i + di, 2 * j + dj);
                if x < self.size && y < self.size {
                    let p = self.get(face, x, y);
                    for c in 0..3 {
                        sum[c] += f64::from(p[c]);
                    }
                    n += 1.0;
                }
            }
            sum.map(|s| (s / n) as f32)
        }))
    }
}
