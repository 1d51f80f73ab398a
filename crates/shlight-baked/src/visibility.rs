//! Probe visibility (DDGI: Majercik, Guertin, Nowrouzezahrai & McGuire
//! 2019, "Dynamic Diffuse Global Illumination with Ray-Traced Irradiance
//! Fields", JCGT 8(2)): per probe, the mean and mean square of the distance
//! to the nearest surface in each direction, filtered over a cosine-power
//! lobe and stored in a small octahedral map; and the weights a shaded
//! point gives the probes around it, which let a probe light a point only
//! where the probe can see it. This file is the one definition of both:
//! the bake fills the maps with [`MomentFilter`], `shlight sample` weighs
//! the probes with [`visibility_weights`], and shlight-shader's
//! `visibility.rs` writes the same arithmetic as shader code, once, for
//! the GPU's volume pass and the volume snippets alike.
//!
//! # The distance moments
//! A probe's ray along the unit direction `s` reaches distance
//!
//! ```text
//! r(s) = t               the ray first meets the front of a surface at t,
//!      = 0.2 t           it meets the back of one at t (DDGI's shortening:
//!                        what is behind a back face is not free space),
//!      = r_max           it escapes,
//! ```
//!
//! clamped to `r_max = 1.5 |cell|` (DDGI's maximum: one and a half cell
//! diagonals, as far as a shaded point can be from a probe that lights it).
//! Texel `k` of a probe's `size x size` octahedral map ([`crate::octahedral`])
//! holds, with `d_k` the direction through its centre and
//! `w(s) = max(0, d_k . s)^50` ([`DISTANCE_SHARPNESS`]) over the probe's rays,
//!
//! ```text
//! mean    = sum w(s) r(s)   / sum w(s)
//! mean_sq = sum w(s) r(s)^2 / sum w(s)
//! ```
//!
//! (rays with `w < 10^-3` left out of the sums; a texel with no ray in its
//! lobe holds `r_max` and `r_max^2`).
//!
//! # The weights
//! Of the up to eight probes around the point `p` with unit normal `n`
//! ([`ProbeGrid::trilinear`], by their cell centres, weights `t_k`), each
//! valid probe `k` at its position `q_k` (its cell centre plus its offset,
//! where the bake moved it) is tested against the point moved off its
//! surface by `b = 0.25` ([`NORMAL_BIAS`]) of the smallest cell side,
//! `p' = p + b n` (DDGI's normal bias; `shlight sample` has no camera, so
//! DDGI's view bias is left out, here and on the GPU):
//!
//! ```text
//! d     = |p' - q_k|,  (mean, mean_sq) = the map of k at (p' - q_k) / d, bilinear
//! cheb  = 1                                  where d <= mean
//!       = (v / (v + (d - mean)^2))^3,  v = |mean_sq - mean^2|   beyond it (Chebyshev)
//! w     = max(0.05, cheb)
//! w     = w^3 / 0.2^2                        where w < 0.2 (DDGI's crushing of small weights)
//! w_k   = w t_k
//! ```
//!
//! and the light at `p` is `sum w_k L_k / sum w_k`. Invalid probes take no
//! weight; with none valid around the point there is no light. In open
//! space every probe sees past every point it lights (`d < r_max`), so
//! every `w` is 1 and the lookup is the trilinear one exactly.
//!
//! DDGI also weighs each probe by a smooth backface term,
//! `((normalize(q_k - p) . n + 1) / 2)^2 + 0.2`, and takes the trilinear
//! weights at `p'`. Both tilt the light where nothing is in the way (where
//! the light varies with direction, against trilinear interpolation), and
//! in shlight's sealed rooms (crates/shlight-volume/tests/leaks.rs) they
//! changed nothing of what crosses the wall. So shlight leaves both out.

use glam::Vec3;

use crate::octahedral::{bilinear, texel_direction};
use crate::{ProbeGrid, ShapeError};

pub use crate::visibility_weights::visibility_weights;

/// Texels per side of a probe's distance map, by default.
pub const VISIBILITY_SIZE: usize = 16;

/// Largest texels per side of a probe's distance map.
pub const MAX_VISIBILITY_SIZE: usize = 64;

/// The power of the cosine lobe a texel's distances are averaged over
/// (DDGI's depth sharpness).
pub const DISTANCE_SHARPNESS: i32 = 50;

/// The distances are clamped to this many cell diagonals.
pub const MAX_DISTANCE_CELLS: f32 = 1.5;

/// A ray that meets a back face counts this fraction of its distance.
pub const BACKFACE_DISTANCE: f32 = 0.2;

/// The shaded point is moved this fraction of the smallest cell side along
/// its normal before the probes are weighed.
pub const NORMAL_BIAS: f32 = 0.25;

/// The least the Chebyshev factor multiplies a weight by.
pub const CHEBYSHEV_FLOOR: f32 = 0.05;
/// Weights below this are crushed, `w^3 / CRUSH^2` (DDGI's crushing of
/// small weights). The GPU's volume pass takes this and
/// [`CHEBYSHEV_FLOOR`] from here, `CRUSH * CRUSH` as the f32 product.
pub const CRUSH: f32 = 0.2;
/// Lobe weights below this are left out of a texel's sums.
const LOBE_CUTOFF: f32 = 1e-3;

/// A volume's probe distance maps, borrowed: per probe `size` rows of
/// `size` texels (column fastest) of `[mean, mean_sq]`, probes in probe
/// order.
#[derive(Clone, Copy, Debug)]
pub struct Visibility<'a> {
    /// Texels per side of each probe's map.
    pub size: usize,
    /// The distance the maps are clamped to, `r_max`.
    pub max_distance: f32,
    /// `probes * size * size * 2` floats.
    pub moments: &'a [f32],
}

impl Visibility<'_> {
    /// Floats per probe: `2 size^2`.
    #[must_use]
    pub fn floats_per_probe(size: usize) -> usize {
        2 * size * size
    }

    /// The bilinear `(mean, mean_sq)` of probe `probe`'s map along the
    /// unit direction `dir` (from the probe outwards).
    #[must_use]
    pub fn moments_at(&self, probe: usize, dir: Vec3) -> (f32, f32) {
        let map = &self.moments[probe * Self::floats_per_probe(self.size)..];
        let (mut mean, mut mean_sq) = (0.0f32, 0.0f32);
        for ((i, j), w) in bilinear(dir, self.size) {
            let t = 2 * (j * self.size + i);
            mean += w * map[t];
            mean_sq += w * map[t + 1];
        }
        (mean, mean_sq)
    }

    /// Checks the shape for `probes` probes.
    ///
    /// # Errors
    /// A size of 0 or over [`MAX_VISIBILITY_SIZE`], a `max_distance` that
    /// is not positive, or another number of floats.
    pub fn check(&self, probes: usize) -> Result<(), ShapeError> {
        if self.size == 0 || self.size > MAX_VISIBILITY_SIZE {
            return Err(ShapeError(format!(
                "visibility maps of {0}x{0} texels: the size must be 1 to {MAX_VISIBILITY_SIZE}",
                self.size
            )));
        }
        if !(self.max_distance > 0.0 && self.max_distance.is_finite()) {
            return Err(ShapeError(format!(
                "visibility max_distance {} is not a positive distance",
                self.max_distance
            )));
        }
        let want = probes.checked_mul(Self::floats_per_probe(self.size));
        if want != Some(self.moments.len()) {
            return Err(ShapeError(format!(
                "{probes} probes' {0}x{0} visibility maps need {1} values, not {2}",
                self.size,
                want.map_or_else(|| "too many".to_string(), |v| v.to_string()),
                self.moments.len()
            )));
        }
        Ok(())
    }
}

/// A volume's probe distance maps, owned (what a bake makes and a file
/// holds); [`ProbeVisibility::view`] borrows them as [`Visibility`].
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeVisibility {
    /// Texels per side of each probe's map.
    pub size: usize,
    /// The distance the maps are clamped to, `r_max`.
    pub max_distance: f32,
    /// Per probe `size` rows of `size` texels of `[mean, mean_sq]`.
    pub moments: Vec<f32>,
}

impl ProbeVisibility {
    /// The maps borrowed.
    #[must_use]
    pub fn view(&self) -> Visibility<'_> {
        Visibility {
            size: self.size,
            max_distance: self.max_distance,
            moments: &self.moments,
        }
    }
}

/// The `r_max` of a grid: [`MAX_DISTANCE_CELLS`] cell diagonals.
#[must_use]
pub fn max_distance(grid: &ProbeGrid) -> f32 {
    MAX_DISTANCE_CELLS * grid.cell().length()
}

/// The distance a probe's ray reaches for its map: `t` for a front hit,
/// [`BACKFACE_DISTANCE`]` t` for a back face, `r_max` for an escaped ray
/// (`t = None`), clamped to `r_max`.
#[inline]
#[must_use]
pub fn ray_distance(t: Option<f32>, back: bool, max_distance: f32) -> f32 {
    match t {
        None => max_distance,
        Some(t) if back => (BACKFACE_DISTANCE * t).min(max_distance),
        Some(t) => t.min(max_distance),
    }
}

/// A direction set's rays sorted into the texels of a `size x size`
/// octahedral map: per texel the rays in its lobe with their weights
/// `max(0, d_k . s)^50`, made once for the set every probe shares.
#[derive(Clone, Debug)]
pub struct MomentFilter {
    size: usize,
    starts: Vec<usize>,
    rays: Vec<u32>,
    weights: Vec<f32>,
}

impl MomentFilter {
    /// The filter of `size x size` texels over the unit directions `dirs`.
    #[must_use]
    pub fn new(size: usize, dirs: &[Vec3]) -> Self {
        let mut starts = Vec::with_capacity(size * size + 1);
        let (mut rays, mut weights) = (Vec::new(), Vec::new());
        for j in 0..size {
            for i in 0..size {
                starts.push(rays.len());
                let d = texel_direction(i, j, size);
                for (r, s) in dirs.iter().enumerate() {
                    let c = d.dot(*s);
                    if c <= 0.0 {
                        continue;
                    }
                    let w = c.powi(DISTANCE_SHARPNESS);
                    if w >= LOBE_CUTOFF {
                        rays.push(r as u32);
                        weights.push(w);
                    }
                }
            }
        }
        starts.push(rays.len());
        Self {
            size,
            starts,
            rays,
            weights,
        }
    }

    /// Texels per side.
    #[must_use]
    pub fn size(&self) -> usize {
        self.size
    }

    /// One probe's map from its rays' distances (`distances[r]` along the
    /// set's direction `r`, from [`ray_distance`]) into `out`
    /// (`2 size^2` floats): each texel's weighted mean and mean square,
    /// summed in `f64`.
    ///
    /// # Panics
    /// If `out` has another length.
    pub fn filter(&self, distances: &[f32], max_distance: f32, out: &mut [f32]) {
        assert_eq!(out.len(), 2 * self.size * self.size);
        for (k, texel) in out.chunks_exact_mut(2).enumerate() {
            let range = self.starts[k]..self.starts[k + 1];
            let (mut w_sum, mut r_sum, mut r2_sum) = (0.0f64, 0.0f64, 0.0f64);
            for (&r, &w) in self.rays[range.clone()].iter().zip(&self.weights[range]) {
                let (w, d) = (f64::from(w), f64::from(distances[r as usize]));
                w_sum += w;
                r_sum += w * d;
                r2_sum += w * d * d;
            }
            if w_sum > 0.0 {
                texel[0] = (r_sum / w_sum) as f32;
                texel[1] = (r2_sum / w_sum) as f32;
            } else {
                texel[0] = max_distance;
                texel[1] = max_distance * max_distance;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::VolumeView;

    /// A probe's map where every ray reaches `r`: every texel holds `r` and
    /// `r^2` whatever the lobe.
    #[test]
    fn constant_distances_give_constant_moments() {
        let dirs: Vec<Vec3> = (0..400)
            .map(|k| {
                let z = 1.0 - 2.0 * (k as f32 + 0.5) / 400.0;
                let phi = k as f32 * 2.399_963;
                let r = (1.0 - z * z).sqrt();
                Vec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect();
        let f = MomentFilter::new(8, &dirs);
        let mut out = vec![0.0; 128];
        f.filter(&vec![2.5; 400], 9.0, &mut out);
        for t in out.chunks(2) {
            assert!(
                (t[0] - 2.5).abs() < 1e-5 && (t[1] - 6.25).abs() < 1e-4,
                "{t:?}"
            );
        }
        // A wall at distance 1 across the +x half-space (rays with
        // s.x > 0 reach 1 / s.x, clamped to 3), the rest escapes: texels
        // looking along +x read about 1, those looking along -x read 3.
        let max = 3.0;
        let distances: Vec<f32> = dirs
            .iter()
            .map(|s| ray_distance((s.x > 0.0).then(|| 1.0 / s.x), false, max))
            .collect();
        let f = MomentFilter::new(16, &dirs);
        let mut out = vec![0.0; 512];
        f.filter(&distances, max, &mut out);
        let vis = Visibility {
            size: 16,
            max_distance: max,
            moments: &out,
        };
        let (m, m2) = vis.moments_at(0, Vec3::X);
        assert!((m - 1.0).abs() < 0.05 && m2 >= m * m - 1e-4, "{m} {m2}");
        let (m, _) = vis.moments_at(0, Vec3::NEG_X);
        assert!((m - 3.0).abs() < 1e-4, "{m}");
        assert_eq!(ray_distance(Some(10.0), true, 3.0), 2.0);
        assert_eq!(ray_distance(Some(1.0), true, 3.0), 0.2);
        assert_eq!(ray_distance(None, false, 3.0), 3.0);
    }

    /// Two probes along x at 0.5 and 1.5, a point at 0.9 facing +y. With
    /// nothing in the way (every map at `r_max`) the weights are the
    /// trilinear ones exactly; with a wall
    /// between the point and probe 1 (its map reads 0.2 towards the point),
    /// probe 1 is all but shut out.
    #[test]
    fn a_probe_behind_a_wall_takes_almost_no_weight() {
        let grid = ProbeGrid::new([2, 1, 1], Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)).unwrap();
        let size = 4;
        let max = max_distance(&grid);
        let mut open = vec![0.0f32; 2 * 2 * size * size];
        for t in open.chunks_mut(2) {
            t.copy_from_slice(&[max, max * max]);
        }
        let valid = [true, true];
        let vis = Visibility {
            size,
            max_distance: max,
            moments: &open,
        };
        let view = VolumeView {
            grid,
            lmax: 0,
            valid: &valid,
            radiance: &[0.0; 6],
            offsets: None,
            visibility: Some(vis),
        };
        let p = Vec3::new(0.9, 0.5, 0.5);
        let w = visibility_weights(&view, p, Vec3::Y).unwrap();
        // Open space: the trilinear weights at p, to the bit.
        let tri = grid.trilinear(p);
        for ((k, a), (j, b)) in w.iter().zip(&tri) {
            assert_eq!(k, j);
            assert_eq!(a, b);
        }
        // A wall at x = 1.2: probe 1 sees 0.3 towards -x; the point, moved
        // up by the bias of 0.25, is 0.65 from it: probe 1's weight is
        // 0.05^3 / 0.04 of its trilinear 0.4 against probe 0's 0.6.
        let mut walled = open.clone();
        let per = Visibility::floats_per_probe(size);
        for t in walled[per..].chunks_mut(2) {
            t.copy_from_slice(&[0.3, 0.09]);
        }
        let walled_view = VolumeView {
            visibility: Some(Visibility {
                moments: &walled,
                ..vis
            }),
            ..view
        };
        let w = visibility_weights(&walled_view, p, Vec3::Y).unwrap();
        assert_eq!(w[0].0, 0);
        let want = 0.4 * 0.05f32.powi(3) / 0.04 / (0.6 + 0.4 * 0.05f32.powi(3) / 0.04);
        assert!((w[1].1 - want).abs() < 1e-6, "{w:?} {want}");
        // None valid: no weights.
        let none_valid = VolumeView {
            valid: &[false, false],
            ..walled_view
        };
        assert_eq!(visibility_weights(&none_valid, p, Vec3::Y), Some(vec![]));
        // No maps: no visibility weights.
        let blind = VolumeView {
            visibility: None,
            ..view
        };
        assert_eq!(visibility_weights(&blind, p, Vec3::Y), None);
    }
}
