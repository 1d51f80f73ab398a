//! [`render_map`]: coefficients back to an image in any layout.

use glam::DVec3;
use shlight_core::map::{Layout, MapOrientation, TexelGrid, render_coefficients};
use shlight_core::sh::ShCoeffs;
use shlight_io::Image;

use crate::{PipelineError, Result};

/// The image of `coeffs` on a `width x height` map in `layout` and
/// `orientation`: each texel the expansion `sum c_l^m Y_l^m(d)` at its
/// centre direction `d` ([`TexelGrid::direction`]), 0 for texels the
/// layout does not use, evaluated by shlight-core's [`render_coefficients`]
/// (rows in parallel, each in batches, summed in `f64`); `on_row` is called
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
    let pixels = render_coefficients(coeffs, &grid, on_row);
    Image::new(w, h, pixels).map_err(|e| PipelineError::new(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The image holds the core's texels at the map's size, and a size
    /// that does not fit the layout is an error (the core's evaluation is
    /// tested against `ShCoeffs::eval` in shlight-core).
    #[test]
    fn render_map_wraps_the_core_render_and_refuses_bad_sizes() {
        let coeffs = ShCoeffs::<DVec3>::from_fn(7, |l, m| {
            DVec3::new(1.0 / (1 + l) as f64, m as f64 * 0.1, 0.5 - 0.01 * l as f64)
        });
        let (w, h) = Layout::CrossHorizontal.dimensions(12);
        let o = MapOrientation::default();
        let image = render_map(&coeffs, Layout::CrossHorizontal, (w, h), o, &|| {}).unwrap();
        let grid = TexelGrid::new(Layout::CrossHorizontal, (w, h), o).unwrap();
        let want = render_coefficients(&coeffs, &grid, &|| {});
        assert_eq!((image.width(), image.height()), (w, h));
        for y in 0..h {
            for x in 0..w {
                assert_eq!(image.get(x, y), want[y * w + x], "{x} {y}");
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
