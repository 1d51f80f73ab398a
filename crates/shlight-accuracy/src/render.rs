//! Oracles drawn as environment maps: each texel holds the light's mean
//! over the texel.
//!
//! A texel wholly on one side of every edge of the light holds the
//! radiance at its centre: for the lights with edges (caps, polygons) that
//! is its exact mean (the radiance is constant there), for the smooth ones
//! (sphere, gradient) the mean up to `O(h²)`, which the quadrature's own
//! `O(h²)` matches. A texel within reach of an edge averages
//! [`EDGE_SUPERSAMPLING`]² points, one uniformly at random in each of as
//! many sub-cells of equal solid angle (equirect: equal steps in `cos θ`
//! and `φ`) or weighted by their solid angle (cube faces: equal steps of
//! the face coordinates, weight `(1 + s² + t²)^(-3/2)`).
//!
//! Why jittered points: a regular sub-grid counts an edge that runs along
//! its rows (a polygon edge that is a line of a cube face, or nearly a
//! parallel on an equirect map) with a bias of up to half a sub-row per
//! texel, the same sign all along the edge: an `O(h/k)` error that stops
//! the `O(h²)` convergence. Random points make that coverage error
//! zero-mean and independent from texel to texel, so it adds up to
//! `O(h^1.5 / k^1.5)`, far below the quadrature's `h²` at every size the
//! suite uses. The points come from a fixed hash of the texel, so maps
//! repeat exactly.

use std::f64::consts::PI;

use glam::DVec3;
use rayon::prelude::*;
use shlight_core::map::{EnvMap, Layout, MapOrientation, render_map};
use shlight_core::sh::Frame;

use crate::oracle::Oracle;

/// Sub-cells per texel side for texels that an edge may cross (32: at 16
/// the random coverage error of the 10° cap's few edge texels, relative
/// to its small peak, flattened its rate on cube faces of 256).
pub const EDGE_SUPERSAMPLING: usize = 32;

/// The largest angular distance from a texel's centre to any of its
/// points: equirect `(π/H + 2π/W)/2` (half a row in `θ` plus at most half
/// a column along a parallel), cube cross `√2 / f` for faces of `f`
/// texels (half a texel diagonal at the face centre, where texels are
/// largest).
#[must_use]
pub fn texel_radius(layout: Layout, w: usize, h: usize) -> f64 {
    match layout {
        Layout::Equirect => (PI / h as f64 + 2.0 * PI / w as f64) / 2.0,
        _ => {
            let (cols, _) = layout.cube_grid().unwrap_or((4, 3));
            2f64.sqrt() / (w / cols) as f64
        }
    }
}

/// `o` drawn as a `w x h` map of `layout` (equirect or a cube layout) in
/// the default y-up orientation, each texel its mean (module docs).
///
/// # Panics
/// If the size does not fit the layout, or for a disc layout.
#[must_use]
pub fn render_texel_means(o: &Oracle, layout: Layout, w: usize, h: usize) -> Vec<[f32; 3]> {
    assert!(!layout.is_disc(), "texel means: equirect and cube layouts");
    let orientation = MapOrientation::default();
    let mut px = render_map(layout, orientation, w, h, |d| DVec3::splat(o.radiance(d)))
        .expect("sizes fit their layouts");
    if o.smooth() {
        return px;
    }
    // Geometry only: texel directions need no pixels.
    let geometry = EnvMap {
        layout,
        orientation,
        width: w,
        height: h,
        pixels: &[],
    };
    let reach = 2.0 * texel_radius(layout, w, h);
    let k = EDGE_SUPERSAMPLING;
    px.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
        for (x, texel) in row.iter_mut().enumerate() {
            let Some(d) = geometry.texel_direction(x, y) else {
                continue;
            };
            if o.edge_distance(d) > reach {
                continue;
            }
            let mut rng = SplitMix((y * w + x) as u64 ^ 0x9e37_79b9_7f4a_7c15);
            let (mut sum, mut weight) = (0.0, 0.0);
            for j in 0..k {
                for i in 0..k {
                    let u = (i as f64 + rng.next()) / k as f64;
                    let v = (j as f64 + rng.next()) / k as f64;
                    let (d, wt) = texel_point(layout, w, h, x, y, u, v);
                    sum += wt * o.radiance(d);
                    weight += wt;
                }
            }
            *texel = [(sum / weight) as f32; 3];
        }
    });
    px
}

/// The direction at fraction `(u, v)` across texel `(x, y)` (right, down)
/// and its relative solid-angle density.
fn texel_point(
    layout: Layout,
    w: usize,
    h: usize,
    x: usize,
    y: usize,
    u: f64,
    v: f64,
) -> (DVec3, f64) {
    if layout == Layout::Equirect {
        let z0 = (PI * y as f64 / h as f64).cos();
        let z1 = (PI * (y + 1) as f64 / h as f64).cos();
        let z = (z0 + (z1 - z0) * v).clamp(-1.0, 1.0);
        let phi = 2.0 * PI * ((x as f64 + u) / w as f64 - 0.5);
        return (Frame::YUp.direction(z.acos(), phi), 1.0);
    }
    let (cols, _) = layout.cube_grid().expect("a cube layout");
    let f = w / cols;
    let (face, cell) = layout
        .face_at(x / f, y / f)
        .expect("a texel with a direction lies on a face");
    let (mut i, mut j) = ((x % f) as f64 + u, (y % f) as f64 + v);
    if cell.rotated {
        (i, j) = (f as f64 - i, f as f64 - j);
    }
    let (s, t) = (2.0 * i / f as f64 - 1.0, 2.0 * j / f as f64 - 1.0);
    let p = face.point(s, t);
    (p.normalize(), (1.0 + s * s + t * t).powf(-1.5))
}

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny deterministic stream of
/// uniform numbers in `[0, 1)`.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texel_points_at_the_centre_are_the_texel_centres() {
        for layout in [
            Layout::Equirect,
            Layout::CrossHorizontal,
            Layout::CrossVertical,
        ] {
            let (w, h) = if layout == Layout::Equirect {
                (16, 8)
            } else {
                layout.dimensions(4)
            };
            let geometry = EnvMap {
                layout,
                orientation: MapOrientation::default(),
                width: w,
                height: h,
                pixels: &[],
            };
            for y in 0..h {
                for x in 0..w {
                    if let Some(d) = geometry.texel_direction(x, y) {
                        let (p, _) = texel_point(layout, w, h, x, y, 0.5, 0.5);
                        // Equirect texel centres are at the centre in θ, not
                        // in cos θ: the point need only lie in the texel.
                        let tol = if layout == Layout::Equirect {
                            texel_radius(layout, w, h)
                        } else {
                            1e-12
                        };
                        assert!((p - d).length() < tol, "{layout} {x} {y}: {p} vs {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn texel_means_keep_a_polygon_area() {
        let o = crate::oracle::suite_oracles()
            .into_iter()
            .find(|o| o.name == "rect")
            .unwrap();
        // Girard's area of the anchor rectangle, independently: 4 corner
        // angles minus 2π.
        let v = match &o.shape {
            crate::oracle::Shape::Polygon { vertices } => vertices.clone(),
            _ => unreachable!(),
        };
        let angle = |p: DVec3, c: DVec3, q: DVec3| {
            let a = (p - c * c.dot(p)).normalize();
            let b = (q - c * c.dot(q)).normalize();
            a.dot(b).acos()
        };
        let area: f64 = (0..4)
            .map(|i| angle(v[(i + 3) % 4], v[i], v[(i + 1) % 4]))
            .sum::<f64>()
            - 2.0 * PI;
        for (layout, (w, h)) in [
            (Layout::Equirect, (512, 256)),
            (
                Layout::CrossHorizontal,
                Layout::CrossHorizontal.dimensions(128),
            ),
        ] {
            let px = render_texel_means(&o, layout, w, h);
            let map = EnvMap::new(layout, MapOrientation::default(), w, h, &px).unwrap();
            let got: f64 = px
                .iter()
                .zip(map.texel_solid_angles())
                .map(|(p, a)| f64::from(p[0]) * a)
                .sum();
            // Jittered coverage: random error ~1e-6 here; a regular 16x16
            // grid was off by 5e-4 on the equirect map.
            assert!((got - area).abs() < 2e-5, "{layout}: {got} vs {area}");
        }
    }
}
