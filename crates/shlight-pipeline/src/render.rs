//! [`render_map`]: coefficients back to an image in any layout.

use glam::DVec3;
use rayon::prelude::*;
use shlight_core::map::{Layout, MapOrientation, TexelGrid};
use shlight_core::sh::{ShBasis, ShCoeffs};
use shlight_io::Image;

use crate::{PipelineError, Result};

/// The image of `coeffs` on a `width x height` map in `layout` and
/// `orientation`: each texel the expansion `sum c_l^m Y_l^m(d)` at its
/// centre direction `d` ([`TexelGrid::direction`]), 0 for texels the
/// layout does not use. Rows are evaluated in parallel, each in batches
/// through [`ShBasis::eval_batch`] and summed in `f64`; `on_row` is called
/// once per finished row (a progress bar).
///
/// Rendering the coefficients of a projected equirect map on the same
/// grid gives that map's band-limited version texel for texel.
///
/// # Errors
/// The size does not fit the layout ([`Layout::check_size`]).
pub fn render_map(
    coeffs: &ShCoeffs<DVec3>,
    layout: Layout,
    (w, h): (usize, usize),
    orientation: MapOrientation,
    on_row: &(dyn Fn() + Sync),
) -> Result<Image> {
    let grid = TexelGrid::new(layout, (w, h), orientation)
        .map_err(|e| PipelineError::new(e.to_string()))?;
    let basis = ShBasis::<f64>::new(coeffs.lmax());
    let count = basis.count();
    let channels: [Vec<f64>; 3] = std::array::from_fn(|c| coeffs.channel(c).as_slice().to_vec());
    // Directions per batch: a multiple of 16 (the basis's lanes), keeping
    // the basis values near 512 KiB, at most 1024.
    let batch = ((65_536 / count) / 16).clamp(1, 64) * 16;
    let mut pixels = vec![[0.0f32; 3]; w * h];
    pixels.par_chunks_mut(w).enumerate().for_each_init(
        || Scratch::new(count, batch),
        |s, (y, row)| {
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
        },
    );
    Image::new(w, h, pixels).map_err(|e| PipelineError::new(e.to_string()))
}

/// Per-thread buffers of [`render_map`].
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
    use shlight_core::map::EnvMap;
    use shlight_core::sh::Frame;

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
                let image = render_map(&coeffs, layout, (w, h), o, &|| {}).unwrap();
                let black = vec![[0.0f32; 3]; w * h];
                let grid = EnvMap::new(layout, o, w, h, &black).unwrap();
                for y in 0..h {
                    for x in 0..w {
                        let want = grid
                            .texel_direction(x, y)
                            .map_or(DVec3::ZERO, |d| coeffs.eval(d));
                        let got = DVec3::from(image.get(x, y).map(f64::from));
                        assert!((got - want).abs().max_element() < F32_TEXEL, "{x} {y}");
                    }
                }
            }
        }
        assert!(
            render_map(
                &coeffs,
                Layout::CrossHorizontal,
                (10, 10),
                MapOrientation::default(),
                &|| {}
            )
            .is_err()
        );
    }
}
