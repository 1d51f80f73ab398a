//! [`render_map`]: draws a function of direction into an image of any layout.

use glam::DVec3;

use crate::map::layout::geometry::Geometry;
use crate::map::layout::kind::{Layout, LayoutSizeError};
use crate::map::orientation::MapOrientation;

/// Draws `f` into a new `width x height` image of `layout` read in
/// `orientation`: each texel that holds a direction gets `f` at
/// [`EnvMap::texel_direction`](crate::map::EnvMap::texel_direction) (rounded to `f32`), the others `0`. The
/// image [`crate::map::project_map`] reads back as the projection of `f`; the CLI's
/// `render` draws SH this way. Rows run in parallel with the `rayon`
/// feature.
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
