//! Rendering into maps: a function of direction drawn texel by texel into
//! an image of any layout ([`render_map`]), and an SH expansion evaluated
//! at every texel centre of a [`TexelGrid`] in batches ([`render_coefficients`]),
//! the way back from coefficients to a map.

use glam::DVec3;

use crate::map::layout::geometry::Geometry;
use crate::map::layout::kind::{Layout, LayoutSizeError};
use crate::map::layout::texel_grid::TexelGrid;
use crate::map::orientation::MapOrientation;
use crate::sh::basis::ShBasis;
use crate::sh::sh_coeffs::ShCoeffs;

/// Draws `f` into a new `width x height` image of `layout` read in
/// `orientation`: each texel that holds a direction gets `f` at
/// [`EnvMap::texel_direction`](crate::map::EnvMap::texel_direction) (rounded to `f32`), the others `0`. The
/// image [`crate::map::project_map`] reads back as the projection of `f`.
/// Rows run in parallel with the `rayon` feature.
///
/// # Errors
/// [`LayoutSizeError`] when the size does not fit the layout.
pub fn render_map(
    layout: Layout,
    orientation: MapOrientation,
    width: usize,
    height: usize,
    f: impl Fn(DVec3) -> DVec3 + Sync,
) -> Result<Vec<[f32; 3]>, LayoutSizeError> {
    layout.check_size(width, height)?;
    let geo = Geometry::new(layout, orientation, width, height);
    let mut pixels = vec![[0.0f32; 3]; width * height];
    let row = |(y, out): (usize, &mut [[f32; 3]])| {
        for (x, px) in out.iter_mut().enumerate() {
            if let Some(d) = geo.direction(x, y) {
                *px = f(d).as_vec3().to_array();
            }
        }
    };
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        pixels.par_chunks_mut(width).enumerate().for_each(row);
    }
    #[cfg(not(feature = "rayon"))]
    pixels.chunks_mut(width).enumerate().for_each(row);
    Ok(pixels)
}

/// The image of `coeffs` on `grid`, row-major from the top-left: each texel
/// the expansion `sum c_l^m Y_l^m(d)` at its centre direction `d`
/// ([`TexelGrid::direction`]), rounded to `f32`, and 0 for texels the
/// layout does not use. Rows are evaluated in parallel with the `rayon`
/// feature, each in batches of directions through [`ShBasis::eval_batch`]
/// and summed in `f64`; `on_row` is called once per finished row (a
/// progress bar).
///
/// Rendering the coefficients of a projected equirect map on the same grid
/// gives that map's band-limited version texel for texel.
#[must_use]
pub fn render_coefficients(
    coeffs: &ShCoeffs<DVec3>,
    grid: &TexelGrid,
    on_row: &(dyn Fn() + Sync),
) -> Vec<[f32; 3]> {
    let (w, h) = (grid.width(), grid.height());
    let basis = ShBasis::<f64>::new(coeffs.lmax());
    let count = basis.count();
    let channels: [Vec<f64>; 3] = std::array::from_fn(|c| coeffs.channel(c).as_slice().to_vec());
    // Directions per batch: a multiple of 16 (the basis's lanes), keeping
    // the basis values near 512 KiB, at most 1024.
    let batch = ((65_536 / count) / 16).clamp(1, 64) * 16;
    let mut pixels = vec![[0.0f32; 3]; w * h];
    let row = |s: &mut Scratch, (y, row): (usize, &mut [[f32; 3]])| {
        s.texels.clear();
        for x in 0..w {
            if let Some(d) = grid.direction(x, y) {
                s.texels.push((x, d));
            }
        }
        for chunk in s.texels.chunks(batch) {
            let n = chunk.len();
            for (k, (_, d)) in chunk.iter().enumerate() {
                (s.x[k], s.y[k], s.z[k]) = (d.x, d.y, d.z);
            }
            for acc in &mut s.acc {
                acc[..n].fill(0.0);
            }
            let values = &mut s.values[..count * n];
            basis.eval_batch(&s.x[..n], &s.y[..n], &s.z[..n], values);
            // Coefficient-major: each basis function's values over the
            // batch are contiguous, so the sums vectorise.
            for (i, column) in values.chunks_exact(n).enumerate() {
                for (acc, ch) in s.acc.iter_mut().zip(&channels) {
                    let c = ch[i];
                    for (a, y) in acc[..n].iter_mut().zip(column) {
                        *a += c * y;
                    }
                }
            }
            for (k, (x, _)) in chunk.iter().enumerate() {
                row[*x] = [s.acc[0][k] as f32, s.acc[1][k] as f32, s.acc[2][k] as f32];
            }
        }
        on_row();
    };
    #[cfg(feature = "rayon")]
    {
        use rayon::prelude::*;
        pixels
            .par_chunks_mut(w)
            .enumerate()
            .for_each_init(|| Scratch::new(count, batch), row);
    }
    #[cfg(not(feature = "rayon"))]
    {
        let mut s = Scratch::new(count, batch);
        for r in pixels.chunks_mut(w).enumerate() {
            row(&mut s, r);
        }
    }
    pixels
}

/// Per-thread buffers of [`render_coefficients`].
struct Scratch {
    texels: Vec<(usize, DVec3)>,
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    values: Vec<f64>,
    acc: [Vec<f64>; 3],
}

impl Scratch {
    fn new(count: usize, batch: usize) -> Self {
        Self {
            texels: Vec::new(),
            x: vec![0.0; batch],
            y: vec![0.0; batch],
            z: vec![0.0; batch],
            values: vec![0.0; count * batch],
            acc: std::array::from_fn(|_| vec![0.0; batch]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::layout::env_map::EnvMap;
    use crate::sh::frame::Frame;

    /// Tolerance of a rendered texel against scalar evaluation: the image
    /// holds `f32`, about 6e-8 relative of values near 1.
    const F32_TEXEL: f64 = 1e-5;

    /// The batched render equals `ShCoeffs::eval` (one direction at a
    /// time, an independent evaluation of the basis) in every layout.
    #[test]
    fn render_matches_scalar_evaluation() {
        let coeffs = ShCoeffs::<DVec3>::from_fn(7, |l, m| {
            DVec3::new(1.0 / (1 + l) as f64, m as f64 * 0.1, 0.5 - 0.01 * l as f64)
        });
        // The layouts at faces (discs, rows) of 12, and the 36x18 equirect
        // map the command line's test drew.
        let sizes = [
            (Layout::Equirect, Layout::Equirect.dimensions(12)),
            (Layout::Equirect, (36, 18)),
            (
                Layout::CrossHorizontal,
                Layout::CrossHorizontal.dimensions(12),
            ),
            (Layout::Angular, Layout::Angular.dimensions(12)),
        ];
        for (layout, (w, h)) in sizes {
            for frame in [Frame::YUp, Frame::ZUp] {
                let o = MapOrientation {
                    frame,
                    mirror: true,
                };
                let grid = TexelGrid::new(layout, (w, h), o).unwrap();
                let image = render_coefficients(&coeffs, &grid, &|| {});
                assert_eq!(image.len(), w * h);
                let black = vec![[0.0f32; 3]; w * h];
                let map = EnvMap::new(layout, o, w, h, &black).unwrap();
                for y in 0..h {
                    for x in 0..w {
                        let want = map
                            .texel_direction(x, y)
                            .map_or(DVec3::ZERO, |d| coeffs.eval(d));
                        let got = DVec3::from(image[y * w + x].map(f64::from));
                        assert!((got - want).abs().max_element() < F32_TEXEL, "{x} {y}");
                    }
                }
            }
        }
    }

    /// `on_row` is called once per row.
    #[test]
    fn on_row_counts_every_row() {
        use std::sync::atomic::{AtomicUsize, Ordering};
        let coeffs = ShCoeffs::<DVec3>::from_fn(2, |l, _| DVec3::splat(1.0 / (1 + l) as f64));
        let grid = TexelGrid::new(Layout::Angular, (10, 10), MapOrientation::default()).unwrap();
        let rows = AtomicUsize::new(0);
        let _ = render_coefficients(&coeffs, &grid, &|| {
            rows.fetch_add(1, Ordering::Relaxed);
        });
        assert_eq!(rows.into_inner(), 10);
    }
}
