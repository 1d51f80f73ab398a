//! [`output_grid`] and [`default_output_size`]: the texels of a map that
//! shlight writes (`shlight render`, `synth`, `irradiance`, `--preview`).

use shlight_core::map::{Layout, MapOrientation, TexelGrid};

use crate::{PipelineError, Result};

/// The size of a map of `layout` written without an explicit size, from a
/// base `n`: equirect `2n x n`, cube faces of `n / 2` (at least 1), a disc
/// of `n x n`.
#[must_use]
pub fn default_output_size(layout: Layout, n: usize) -> (usize, usize) {
    layout.dimensions(if layout.is_cube() { (n / 2).max(1) } else { n })
}

/// The texels of a `width x height` map of `layout` that shlight writes,
/// read in `orientation`: the size must fit the layout
/// ([`Layout::check_size`]) and an equirect map is always 2:1 (the maps
/// shlight writes are read back by aspect ratio).
///
/// # Errors
/// A size that does not fit, saying what was expected.
pub fn output_grid(
    layout: Layout,
    (width, height): (usize, usize),
    orientation: MapOrientation,
) -> Result<TexelGrid> {
    if layout == Layout::Equirect && (width == 0 || width != 2 * height) {
        return Err(PipelineError::new(format!(
            "a {width}x{height} image is not an equirect map (its width must be twice its height)"
        )));
    }
    TexelGrid::new(layout, (width, height), orientation)
        .map_err(|e| PipelineError::new(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equirect_outputs_are_two_to_one_and_others_fit_their_layout() {
        let o = MapOrientation::default();
        assert!(output_grid(Layout::Equirect, (64, 32), o).is_ok());
        let e = output_grid(Layout::Equirect, (64, 64), o).unwrap_err();
        assert!(e.message().contains("twice its height"), "{e}");
        assert!(output_grid(Layout::Equirect, (0, 0), o).is_err());
        assert!(output_grid(Layout::CrossHorizontal, (40, 30), o).is_ok());
        let e = output_grid(Layout::CrossHorizontal, (40, 40), o).unwrap_err();
        assert_eq!(
            e.message(),
            Layout::CrossHorizontal
                .check_size(40, 40)
                .unwrap_err()
                .to_string()
        );
    }

    #[test]
    fn default_sizes_fit_their_layouts() {
        assert_eq!(default_output_size(Layout::Equirect, 256), (512, 256));
        assert_eq!(default_output_size(Layout::CrossVertical, 256), (384, 512));
        assert_eq!(default_output_size(Layout::Strip, 1), (6, 1));
        assert_eq!(default_output_size(Layout::MirrorBall, 256), (256, 256));
        for layout in Layout::ALL {
            for n in [1, 2, 7, 512] {
                let size = default_output_size(layout, n);
                assert!(output_grid(layout, size, MapOrientation::default()).is_ok());
            }
        }
    }
}
