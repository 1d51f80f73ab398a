//! [`texel_means`]: a map whose every texel holds a function's **mean over
//! the texel** (not its value at the centre), the form in which a light
//! with edges (a cap, a sun) is drawn so that its power in the map is its
//! exact power up to the sub-sampling: a constant light projects exactly up
//! to `f32`, and the `L_0^0` (power) of any light linear in `cos θ` about
//! the pole is exact too; higher coefficients carry the projection's own
//! quadrature error (`shlight synth`).

use glam::DVec3;

use crate::map::layout::texel_grid::TexelGrid;

/// The texels of `grid`, each the mean of `f` over `n x n` equal-area
/// points of the texel (below; `n = 0` is taken as 1, and layouts
/// other than equirect take one point, the centre), row-major
/// (`width * height` values, rounded to `f32`). Rows run in parallel with
/// the `rayon` feature; `on_rows(1)` is called as each row finishes (a
/// progress bar).
///
/// Texel `(x, y)` of a `W x H` equirect map covers
/// `φ ∈ 2π [x/W - 1/2, (x+1)/W - 1/2]` and
/// `cos θ ∈ [cos(yπ/H), cos((y+1)π/H)]`; `n x n` points at the centres of
/// an `n x n` grid **uniform in `φ` and `cos θ`**
/// ([`TexelGrid::sample`]) split it into equal solid angles, so their plain
/// average is the texel mean to the midpoint rule's accuracy: exact for
/// functions linear in `cos θ` and `φ`, `O(1/n²)` for smooth ones, and for
/// an edge only the texels it crosses err, by `O(1/n)` of their value.
/// The other layouts take each texel's centre direction (one point), and
/// `0` in texels the layout leaves unused.
#[must_use]
pub fn texel_means(
    grid: &TexelGrid,
    n: usize,
    f: impl Fn(DVec3) -> DVec3 + Sync,
    on_rows: &(dyn Fn(usize) + Sync),
) -> Vec<[f32; 3]> {
    let n = grid.points_per_side(n);
    let w = grid.width();
    let mut pixels = vec![[0.0f32; 3]; w * grid.height()];
    let row = |(y, out): (usize, &mut [[f32; 3]])| {
        for (x, px) in out.iter_mut().enumerate() {
            let mut sum = DVec3::ZERO;
            let mut used = 0usize;
            for i in 0..n {
                for j in 0..n {
                    let (s, t) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                    if let Some(d) = grid.sample(x, y, s, t) {
                        sum += f(d);
                        used += 1;
                    }
                }
            }
            let mean = if used > 0 {
                sum / used as f64
            } else {
                DVec3::ZERO
            };
            *px = mean.as_vec3().to_array();
        }
        on_rows(1);
    };
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        pixels.par_chunks_mut(w).enumerate().for_each(row);
    }
    #[cfg(not(feature = "rayon"))]
    pixels.chunks_mut(w).enumerate().for_each(row);
    pixels
}

#[cfg(test)]
mod tests {
    use core::f64::consts::PI;
    use std::sync::atomic::{AtomicUsize, Ordering};

    use super::*;
    use crate::map::equirect::equirect_row_solid_angle;
    use crate::map::layout::kind::Layout;
    use crate::map::orientation::MapOrientation;
    use crate::map::render::render_map;

    fn equirect(w: usize, h: usize, o: MapOrientation) -> TexelGrid {
        TexelGrid::new(Layout::Equirect, (w, h), o).unwrap()
    }

    #[test]
    fn a_caps_power_converges_to_its_exact_power() {
        // Power Σ mean Ω of a unit cap of half-angle 2° against 2π(1 - cos a).
        let axis = DVec3::new(0.3, 0.7, -0.2).normalize();
        let a = 2f64.to_radians();
        let exact = 4.0 * PI * (a / 2.0).sin().powi(2);
        let (w, h) = (512, 256);
        let grid = equirect(w, h, MapOrientation::default());
        let mut errors = Vec::new();
        for n in [2, 8, 32] {
            let px = texel_means(
                &grid,
                n,
                |d| DVec3::splat(if d.dot(axis) >= a.cos() { 1.0 } else { 0.0 }),
                &|_| {},
            );
            let power: f64 = px
                .iter()
                .enumerate()
                .map(|(k, p)| f64::from(p[0]) * equirect_row_solid_angle(k / w, w, h))
                .sum();
            errors.push((power / exact - 1.0).abs());
        }
        // Measured: the error falls with n (edge texels resolved finer).
        assert!(errors[2] < 2e-3 && errors[2] < errors[0], "{errors:?}");
    }

    /// A function linear in `cos θ` (a gradient about the frame's up axis)
    /// has its exact texel means, `a + b (cos θ_0 + cos θ_1) / 2`, in every
    /// orientation and for any `n`; one row per call of the progress.
    #[test]
    fn a_gradient_about_the_pole_has_exact_means() {
        let (w, h) = (16, 8);
        for o in MapOrientation::ALL {
            let grid = equirect(w, h, o);
            let up = grid.up();
            for n in [1, 3] {
                let rows = AtomicUsize::new(0);
                let px = texel_means(
                    &grid,
                    n,
                    |d| DVec3::new(1.0 + 0.5 * d.dot(up), 2.0, 0.0),
                    &|k| {
                        rows.fetch_add(k, Ordering::Relaxed);
                    },
                );
                assert_eq!(rows.into_inner(), h);
                for y in 0..h {
                    let z0 = (PI * y as f64 / h as f64).cos();
                    let z1 = (PI * (y + 1) as f64 / h as f64).cos();
                    let want = 1.0 + 0.5 * (z0 + z1) / 2.0;
                    for x in 0..w {
                        let got = px[y * w + x];
                        assert!((f64::from(got[0]) - want).abs() < 1e-6, "{o:?} {n} {y}");
                        assert_eq!(got[1], 2.0);
                    }
                }
            }
        }
    }

    /// Layouts other than equirect take the centre: the same map as
    /// drawing the function at texel centres (`render_map`), whatever `n`.
    #[test]
    fn other_layouts_take_the_texel_centres() {
        let f = |d: DVec3| DVec3::new(d.x * d.y, 1.0 + d.z, d.y);
        for layout in [
            Layout::CrossVertical,
            Layout::Strip,
            Layout::Angular,
            Layout::MirrorBall,
        ] {
            let (w, h) = layout.dimensions(8);
            let o = MapOrientation::ALL[3];
            let grid = TexelGrid::new(layout, (w, h), o).unwrap();
            let means = texel_means(&grid, 4, f, &|_| {});
            assert_eq!(means, render_map(layout, o, w, h, f).unwrap(), "{layout:?}");
        }
    }
}
