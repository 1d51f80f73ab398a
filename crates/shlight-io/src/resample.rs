//! [`Image::resample`]: an image brought to any size by box filtering.

use crate::image::Image;

impl Image {
    /// This image brought to `width x height` by box filtering: output
    /// texel `(x, y)` is the plain mean (summed in `f64`) of the input
    /// texels of columns `[x W / width, (x + 1) W / width)` and rows
    /// `[y H / height, (y + 1) H / height)` (integer division; at least
    /// one of each, so enlarging repeats the nearest texel). Shrinking by
    /// whole factors averages whole blocks, so on even sizes halving
    /// agrees with [`Image::halve`] (summed in `f32`, kept for GPU texture
    /// limits, which rounds odd sizes up and averages partial blocks). An
    /// empty image gives black.
    #[must_use]
    pub fn resample(&self, width: usize, height: usize) -> Image {
        let (iw, ih) = (self.width(), self.height());
        if iw == 0 || ih == 0 {
            return Image::from_fn(width, height, |_, _| [0.0; 3]);
        }
        let span = |o: usize, n: usize, total: usize| {
            let a = o * total / n;
            let b = ((o + 1) * total / n).max(a + 1).min(total);
            a..b
        };
        Image::from_fn(width, height, |x, y| {
            let mut sum = [0.0f64; 3];
            let mut count = 0.0;
            for yy in span(y, height, ih) {
                for px in &self.row(yy)[span(x, width, iw)] {
                    for c in 0..3 {
                        sum[c] += f64::from(px[c]);
                    }
                    count += 1.0;
                }
            }
            sum.map(|s| (s / count) as f32)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_averages_blocks_and_repeats_when_enlarging() {
        let img = Image::from_fn(4, 2, |x, y| [(x + 4 * y) as f32; 3]);
        let small = img.resample(2, 1);
        assert_eq!(small.get(0, 0)[0], (0.0 + 1.0 + 4.0 + 5.0) / 4.0);
        let big = img.resample(8, 4);
        assert_eq!(big.get(7, 3)[0], 7.0);
        assert_eq!(big.get(0, 0)[0], 0.0);
    }

    /// The same size is the image itself; the mean over the image is kept
    /// by whole-factor shrinking (each block the same number of texels);
    /// halving by whole blocks agrees with `halve`.
    #[test]
    fn resampling_keeps_the_image_and_its_mean() {
        let img = Image::from_fn(12, 6, |x, y| {
            [(x * x + y) as f32, (x + 3 * y) as f32 * 0.25, 1.0]
        });
        assert_eq!(img.resample(12, 6), img);
        let mean = |i: &Image| {
            i.pixels().iter().map(|p| f64::from(p[0])).sum::<f64>() / i.pixels().len() as f64
        };
        for (w, h) in [(6, 3), (4, 2), (3, 1), (1, 1)] {
            assert!(
                (mean(&img.resample(w, h)) - mean(&img)).abs() < 1e-5,
                "{w}x{h}"
            );
        }
        assert_eq!(img.resample(6, 3), img.halve());
        assert_eq!(
            Image::from_fn(0, 0, |_, _| [1.0; 3])
                .resample(2, 1)
                .get(1, 0),
            [0.0; 3]
        );
    }
}
