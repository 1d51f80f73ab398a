//! An edge-aware filter for a lightmap's sampling noise: each texel's
//! light replaced by a weighted mean of the texels around it in the atlas,
//! the weights guided by where each texel lies on the surface and which
//! way it faces, so that light is never averaged across a geometric edge,
//! between two surfaces stacked at different heights, or between charts
//! that sit side by side in the atlas but apart in the scene.
//!
//! For a texel `i` at atlas position `(x_i, y_i)`, world position `p_i`
//! and unit normal `n_i`, and a texel `j` of the same region within
//! `radius` texels on each axis, with `h` the size of a texel on the
//! surface (`1 / density`):
//!
//! ```text
//! w_ij = exp(-((x_j - x_i)^2 + (y_j - y_i)^2) / (2 s^2))    s = radius / 2
//!      * exp(-(n_i . (p_j - p_i) / (h / 2))^2)               off i's plane
//!      * max(0, n_i . n_j)^16                                 facing
//!      * [|p_j - p_i| <= 2 (radius + 1) h]                    near on the surface
//! ```
//!
//! and the filtered light `L'_i` is the value at `p_i` of the plane
//! `a + c . u` fitted to the `L_j` by weighted least squares (`w_ii = 1`),
//! `u_j` the offset `p_j - p_i` in the tangent plane of `n_i`, in texels:
//! a local linear regression. Where the window is whole and symmetric (a
//! flat surface away from any edge) the fitted slope is independent of
//! the intercept and `L'_i` is the weighted mean `sum_j w_ij L_j / sum_j
//! w_ij`; at a chart's edge, where the window is one-sided, a weighted
//! mean would be biased by the light's gradient and the fitted plane is
//! not. The slope is held to the weighted mean's by a ridge of `1e-3 sum_j
//! w_ij` where the neighbours do not span the plane (a strip one texel
//! wide). The result is held within the least and greatest values fitted
//! (per channel): at a chart's edge the plane extrapolates, and a dark
//! texel next to light must not go negative.
//!
//! Texels inside geometry (a wall standing on the floor: guided, with no
//! light) are barriers: a neighbour is left out when one of them lies on
//! the atlas's straight line between the two texels, so the lit and dark
//! sides of a wall standing on a floor of one chart stay apart.
//!
//! The facing term is 0.37 at 20 degrees and under 1e-8 at 90: a crease
//! (a wall's foot, a box's edge) keeps the two sides' light apart. The
//! plane term lets a curved surface's neighbours in (a texel one `h` away
//! on a sphere of radius `10 h` is `h / 20` off the plane) and keeps a
//! table top and the floor below it apart. Only texels that gathered light
//! take part: texels inside geometry and the padding are filled after the
//! filter, from filtered texels.
//!
//! **What it costs.** The filter blurs what the guides cannot see: a
//! shadow's edge on a flat floor is widened by about `radius / 2` texels
//! each side, and the light's curvature adds a bias of order
//! `s^2 h^2 / 2` times its second derivative over its value (under 1e-3
//! for a lamp more than ten texels above the floor). Its gain on an evenly
//! lit surface: the variance of a mean of independent texels with weights
//! `w` is `sum w^2 / (sum w)^2` of one texel's, about `1 / (4 pi s^2)` for
//! the Gaussian (`radius` 2: the noise divided by about 3.3).
//!
//! The result does not depend on the order texels are visited in or the
//! number of threads: each output texel reads only the unfiltered input.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Where a texel lies on the surface, for [`denoise`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TexelGuide {
    /// World position of the texel's sample point.
    pub position: Vec3,
    /// Unit normal the texel was gathered for.
    pub normal: Vec3,
    /// The region (node) the texel belongs to: texels of two regions are
    /// never mixed.
    pub region: u32,
}

/// The facing term's exponent: `max(0, n_i . n_j)^FACING_POWER`.
pub const FACING_POWER: i32 = 16;

/// Filters `values` (texel `(x, y)` at `y width + x`, `None` where a
/// texel gathered no light) guided by `guides` (the same layout), over
/// `radius` texels on each axis, `texel_size` the size of a texel on the
/// surface (`1 / density`). Returns the filtered values; texels that are
/// `None` in `values` or `guides` stay `None`, and a texel with a guide and
/// no value is a barrier (inside geometry). `radius` 0, or a `texel_size`
/// that is not positive and finite, returns the input unchanged; a radius
/// past the grid's larger side reads as that side.
///
/// # Panics
/// If `values` and `guides` are not the same length, a multiple of
/// `width`.
#[must_use]
pub fn denoise<const N: usize>(
    values: &[Option<[f64; N]>],
    guides: &[Option<TexelGuide>],
    width: usize,
    radius: u32,
    texel_size: f64,
) -> Vec<Option<[f64; N]>> {
    assert_eq!(values.len(), guides.len(), "one guide a texel");
    assert!(
        width > 0 && values.len().is_multiple_of(width),
        "whole rows"
    );
    if radius == 0 || !(texel_size.is_finite() && texel_size > 0.0) {
        return values.to_vec();
    }
    let height = values.len() / width;
    // A window wider than the grid reads nothing more.
    let radius = radius.min(width.max(height).min(u32::MAX as usize / 2) as u32);
    let r = i64::from(radius);
    let s2 = (f64::from(radius) / 2.0).powi(2);
    let half_h = texel_size / 2.0;
    let reach = 2.0 * (f64::from(radius) + 1.0) * texel_size;
    let reach2 = reach * reach;
    let mut out = vec![None; values.len()];
    out.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
        for (x, slot) in row.iter_mut().enumerate() {
            let k = y * width + x;
            let (Some(own), Some(g)) = (values[k], guides[k]) else {
                continue;
            };
            let p = g.position.as_dvec3();
            let n = g.normal.as_dvec3();
            let (t, b) = n.any_orthonormal_pair();
            let mut fit = LocalPlane::<N>::new(own);
            for dy in -r..=r {
                let yy = y as i64 + dy;
                if yy < 0 || yy >= height as i64 {
                    continue;
                }
                for dx in -r..=r {
                    let xx = x as i64 + dx;
                    if (dx == 0 && dy == 0) || xx < 0 || xx >= width as i64 {
                        continue;
                    }
                    let j = yy as usize * width + xx as usize;
                    let (Some(v), Some(o)) = (values[j], guides[j]) else {
                        continue;
                    };
                    let w = weight_between(
                        p,
                        n,
                        &g,
                        &o,
                        (dx * dx + dy * dy) as f64,
                        s2,
                        half_h,
                        reach2,
                    );
                    if w.is_nan() || w <= 0.0 {
                        continue;
                    }
                    // The costlier test last.
                    if barrier_between(values, guides, width, (x as i64, y as i64), (dx, dy)) {
                        continue;
                    }
                    let d = (o.position.as_dvec3() - p) / texel_size;
                    fit.add(w, [d.dot(t), d.dot(b)], &v);
                }
            }
            *slot = Some(fit.value_at_centre());
        }
    });
    out
}

/// The weighted least-squares plane `a + c . u` through a texel's
/// neighbours' values (per channel), `u` in texels of the tangent plane.
struct LocalPlane<const N: usize> {
    /// `sum w [1, u1, u2]^T [1, u1, u2]` (symmetric; the upper triangle).
    m: [f64; 6],
    /// `sum w v [1, u1, u2]` per channel.
    rhs: [[f64; 3]; N],
    /// The least and greatest value per channel among the texels fitted.
    range: [[f64; 2]; N],
}

impl<const N: usize> LocalPlane<N> {
    /// The centre texel alone (weight 1, at `u = 0`).
    fn new(own: [f64; N]) -> Self {
        Self {
            m: [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            rhs: own.map(|v| [v, 0.0, 0.0]),
            range: own.map(|v| [v, v]),
        }
    }

    fn add(&mut self, w: f64, u: [f64; 2], v: &[f64; N]) {
        let [u1, u2] = u;
        self.m[0] += w;
        self.m[1] += w * u1;
        self.m[2] += w * u2;
        self.m[3] += w * u1 * u1;
        self.m[4] += w * u1 * u2;
        self.m[5] += w * u2 * u2;
        for ((r, range), &x) in self.rhs.iter_mut().zip(&mut self.range).zip(v) {
            r[0] += w * x;
            r[1] += w * x * u1;
            r[2] += w * x * u2;
            range[0] = range[0].min(x);
            range[1] = range[1].max(x);
        }
    }

    /// The fitted `a` per channel (the first row of the 3 x 3 system's
    /// inverse, the slopes' diagonal raised by the ridge), held within the
    /// values fitted: a one-sided window extrapolates, and a shadowed
    /// texel at a chart's edge must not go below its darkest neighbour.
    fn value_at_centre(&self) -> [f64; N] {
        let ridge = 1e-3 * self.m[0];
        let [s, a, b, c, d, e] = self.m;
        let (c, e) = (c + ridge, e + ridge);
        // | s a b |
        // | a c d |
        // | b d e |
        let k0 = c * e - d * d;
        let k1 = b * d - a * e;
        let k2 = a * d - b * c;
        let det = s * k0 + a * k1 + b * k2;
        let mut out = [0.0; N];
        for ((o, r), range) in out.iter_mut().zip(&self.rhs).zip(&self.range) {
            let a = if det.is_finite() && det > 0.0 {
                (k0 * r[0] + k1 * r[1] + k2 * r[2]) / det
            } else {
                r[0] / s
            };
            *o = a.clamp(range[0], range[1]);
        }
        out
    }
}

/// Whether a texel inside geometry (a guide without a value: a wall
/// standing on the floor) lies on the atlas's straight line from texel `at`
/// to `at + d`, ends excluded.
fn barrier_between<const N: usize>(
    values: &[Option<[f64; N]>],
    guides: &[Option<TexelGuide>],
    width: usize,
    at: (i64, i64),
    d: (i64, i64),
) -> bool {
    let steps = d.0.abs().max(d.1.abs());
    (1..steps).any(|k| {
        let x = at.0 + (d.0 * k * 2 + steps).div_euclid(2 * steps);
        let y = at.1 + (d.1 * k * 2 + steps).div_euclid(2 * steps);
        let c = y as usize * width + x as usize;
        values[c].is_none() && guides[c].is_some()
    })
}

/// `w_ij` of the module's formula.
#[allow(clippy::too_many_arguments)]
fn weight_between(
    p: DVec3,
    n: DVec3,
    own: &TexelGuide,
    other: &TexelGuide,
    texels2: f64,
    s2: f64,
    half_h: f64,
    reach2: f64,
) -> f64 {
    if other.region != own.region {
        return 0.0;
    }
    let d = other.position.as_dvec3() - p;
    if d.length_squared() > reach2 {
        return 0.0;
    }
    let facing = n.dot(other.normal.as_dvec3());
    if facing <= 0.0 {
        return 0.0;
    }
    let off = n.dot(d) / half_h;
    (-texels2 / (2.0 * s2) - off * off).exp() * facing.powi(FACING_POWER)
}
