//! [`source_stats`]: the value statistics of texels read in place.

use shlight_core::map::{TexelSource, read_row};
use shlight_io::PixelStats;

/// [`PixelStats`] of every texel of `source` (the whole image, texels the
/// layout leaves unused included, as [`shlight_io::Image::stats`] counts
/// them), read row by row ([`read_row`]: in place, or texel by texel).
#[must_use]
pub fn source_stats<S: TexelSource + ?Sized>(source: &S) -> PixelStats {
    let (w, h) = source.size();
    let mut total = PixelStats {
        non_finite: 0,
        first_non_finite: None,
        negative: 0,
        min_value: f32::INFINITY,
        max_value: f32::NEG_INFINITY,
    };
    let mut any_finite = false;
    let mut buf = Vec::with_capacity(w);
    for y in 0..h {
        let row = read_row(source, y, &mut buf);
        let part = PixelStats::of_pixels(row, w);
        total.non_finite += part.non_finite;
        total.negative += part.negative;
        if total.first_non_finite.is_none()
            && let Some((x, _)) = part.first_non_finite
        {
            total.first_non_finite = Some((x, y));
        }
        // A row without finite values reports a range of 0..0; skip it.
        if part.non_finite < 3 * w {
            any_finite = true;
            total.min_value = total.min_value.min(part.min_value);
            total.max_value = total.max_value.max(part.max_value);
        }
    }
    if !any_finite {
        total.min_value = 0.0;
        total.max_value = 0.0;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::map::{Layout, StridedImage};

    /// Read in place with a row pitch, the statistics equal those of the
    /// contiguous copy (an independent route: `PixelStats::of_pixels` over
    /// the whole buffer at once).
    #[test]
    fn strided_texels_give_the_statistics_of_their_copy() {
        let (w, h, stride) = (16, 8, 20);
        let mut buf = vec![[0.25_f32; 3]; stride * h];
        buf[3 * stride + 5] = [f32::NAN, 1.0, -2.0];
        buf[6 * stride + 1] = [-0.5, 7.0, f32::INFINITY];
        buf[2 * stride + 17] = [f32::NAN; 3]; // padding: not part of the image
        let image = StridedImage::new(Layout::Equirect, w, h, stride, &buf).unwrap();
        let copy: Vec<[f32; 3]> = (0..h)
            .flat_map(|y| buf[y * stride..y * stride + w].to_vec())
            .collect();
        assert_eq!(source_stats(&image), PixelStats::of_pixels(&copy, w));
        let s = source_stats(&image);
        assert_eq!(
            (s.non_finite, s.first_non_finite, s.negative),
            (2, Some((5, 3)), 2)
        );
        assert_eq!((s.min_value, s.max_value), (-2.0, 7.0));
    }
}
