//! [`BorderedCube`]: a cube map's faces each with a one-texel border
//! copied from across the seams, so that a bilinear lookup is four reads
//! of one face with no case at the edges (Filament's
//! `Cubemap::makeSeamless` does the same): the prefilter's inner loop.

use glam::{DVec3, Vec3, Vec3A};
use shlight_core::map::CubeFace;

use crate::cube_image::CubeImage;

/// A direction placed on a cube face: the face's index
/// ([`CubeFace::index`]) and its coordinates `s, t` in `[-1, 1]`, as
/// [`CubeFace::from_direction`] gives them, in `f32`.
#[derive(Clone, Copy, Debug)]
pub struct FacePoint {
    face: usize,
    s: f32,
    t: f32,
}

impl FacePoint {
    /// Where `c` (any length but zero) meets the cube.
    #[inline(always)]
    #[must_use]
    pub fn of(c: Vec3) -> Self {
        let a = c.abs();
        let (face, s, t, major) = if a.x >= a.y && a.x >= a.z {
            if c.x >= 0.0 {
                (0, -c.z, -c.y, a.x)
            } else {
                (1, c.z, -c.y, a.x)
            }
        } else if a.y >= a.z {
            if c.y >= 0.0 {
                (2, c.x, c.z, a.y)
            } else {
                (3, c.x, -c.z, a.y)
            }
        } else if c.z >= 0.0 {
            (4, c.x, -c.y, a.z)
        } else {
            (5, -c.x, -c.y, a.z)
        };
        let inv = 1.0 / major;
        Self {
            face,
            s: s * inv,
            t: t * inv,
        }
    }
}

/// A cube whose faces are `(n + 2) x (n + 2)`: texel `(i, j)` of a face at
/// `(i + 1, j + 1)`, the border holding the nearest texel of the
/// neighbouring face in that direction.
#[derive(Clone, Debug)]
pub struct BorderedCube {
    size: usize,
    /// Six faces of `(size + 2)^2` texels, `+X -X +Y -Y +Z -Z`.
    texels: Vec<Vec3A>,
}

impl BorderedCube {
    /// `cube` with its borders filled.
    #[must_use]
    pub fn new(cube: &CubeImage) -> Self {
        let n = cube.size();
        let w = n + 2;
        let f = n as f64;
        let mut texels = Vec::with_capacity(6 * w * w);
        for face in CubeFace::ALL {
            for j in 0..w {
                for i in 0..w {
                    let (x, y) = (i as isize - 1, j as isize - 1);
                    let inside = (0..n as isize).contains(&x) && (0..n as isize).contains(&y);
                    let p = if inside {
                        cube.get(face, x as usize, y as usize)
                    } else {
                        // The texel across the seam: where the border
                        // texel's centre, on the face's extended plane,
                        // points.
                        let c = |k: isize| (2.0 * k as f64 + 1.0) / f - 1.0;
                        let (other, s, t) = CubeFace::from_direction(face.point(c(x), c(y)));
                        let idx = |v: f64| (((v + 1.0) * 0.5 * f) as usize).min(n - 1);
                        cube.get(other, idx(s), idx(t))
                    };
                    texels.push(Vec3A::from(p));
                }
            }
        }
        Self { size: n, texels }
    }

    /// Texels per face edge (without the border).
    #[must_use]
    pub fn size(&self) -> usize {
        self.size
    }

    /// [`BorderedCube::bilinear`] in `f32` throughout (the face chosen by
    /// the same rule as shlight-core's `CubeFace::from_direction`): the
    /// prefilter's inner loop.
    #[inline]
    #[must_use]
    pub fn bilinear_f32(&self, c: Vec3) -> Vec3 {
        self.bilinear_at(FacePoint::of(c)).into()
    }

    /// The bilinear lookup at a point already placed on its face
    /// ([`FacePoint::of`]), so that the mips of one cube share the work.
    #[inline(always)]
    #[must_use]
    pub fn bilinear_at(&self, p: FacePoint) -> Vec3A {
        let n = self.size;
        let w = n + 2;
        let half = 0.5 * n as f32;
        // Texel coordinates with the border: (s + 1) / 2 n + 1, less the
        // half texel to the centres, kept within the border.
        // (`max`, `min` rather than `clamp`, and through `i32`: the
        // conversions to `usize` cost more than the lookup's arithmetic.)
        let far = n as f32 + 1.0;
        let x = (p.s * half + half + 0.5).max(0.0).min(far);
        let y = (p.t * half + half + 0.5).max(0.0).min(far);
        let (x0, y0) = ((x as i32).min(n as i32), (y as i32).min(n as i32));
        let (tx, ty) = (x - x0 as f32, y - y0 as f32);
        let (x0, y0) = (x0 as usize, y0 as usize);
        let base = p.face * w * w + y0 * w + x0;
        let t = &self.texels[base..base + w + 2];
        let top = t[0] + (t[1] - t[0]) * tx;
        let bottom = t[w] + (t[w + 1] - t[w]) * tx;
        top + (bottom - top) * ty
    }

    /// Bilinear radiance in direction `c` (finite, non-zero).
    #[inline]
    #[must_use]
    pub fn bilinear(&self, c: DVec3) -> DVec3 {
        let (face, s, t) = CubeFace::from_direction(c);
        let n = self.size;
        let w = n + 2;
        let f = n as f64;
        // Face pixels, shifted by the border: bordered texel m has its
        // centre at m + 1/2; the border's centres bound the lookup.
        let x = ((s + 1.0) * 0.5 * f + 1.0).clamp(0.5, f + 1.5) - 0.5;
        let y = ((t + 1.0) * 0.5 * f + 1.0).clamp(0.5, f + 1.5) - 0.5;
        let (x0, y0) = ((x.floor() as usize).min(n), (y.floor() as usize).min(n));
        let (tx, ty) = ((x - x0 as f64) as f32, (y - y0 as f64) as f32);
        let base = face.index() * w * w + y0 * w + x0;
        let p = &self.texels;
        let top = p[base] * (1.0 - tx) + p[base + 1] * tx;
        let bottom = p[base + w] * (1.0 - tx) + p[base + w + 1] * tx;
        (top * (1.0 - ty) + bottom * ty).as_dvec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear function of the direction's face coordinates is reproduced
    /// exactly inside a face, and lookups across every seam match
    /// shlight-core's seam-aware bilinear lookup to within a texel's
    /// difference of a smooth function.
    #[test]
    fn lookups_match_the_seam_aware_envmap_lookup() {
        let n = 16;
        let smooth = |d: DVec3| {
            let d = d.normalize();
            [
                1.0 + 0.5 * d.x as f32,
                2.0 + d.y as f32 * d.z as f32,
                0.5 + 0.25 * d.z as f32,
            ]
        };
        let c = |k: usize| (2.0 * k as f64 + 1.0) / n as f64 - 1.0;
        let cube = CubeImage::from_fn(n, |face, i, j| smooth(face.point(c(i), c(j))));
        let bordered = BorderedCube::new(&cube);
        let env = cube.as_env_map();
        let mut worst = 0.0f64;
        for k in 0..4000 {
            let u = (k as f64 + 0.5) / 4000.0;
            let z = 1.0 - 2.0 * u;
            let r = (1.0 - z * z).sqrt();
            let phi = k as f64 * 2.399_963_229_728_653;
            let d = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            let a = bordered.bilinear(d);
            let b = env.radiance_bilinear(d);
            worst = worst.max((a - b).abs().max_element());
            let c = bordered.bilinear_f32(d.as_vec3()).as_dvec3();
            assert!((a - c).abs().max_element() < 1e-5, "{a} {c}");
        }
        assert!(worst < 0.02, "{worst}");
    }
}
