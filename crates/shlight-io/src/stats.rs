//! Pixel statistics of an [`Image`], and the clean-up of values that
//! radiance cannot have (non-finite and negative).
//!
//! Counts are of channel values, not pixels: a pixel whose three channels
//! are all NaN counts three times.

use crate::Image;

/// What [`Image::stats`] found in an image's channel values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelStats {
    /// Channel values that are NaN or infinite.
    pub non_finite: usize,
    /// Column and row of the first pixel (in row-major order) with a
    /// non-finite channel; `None` when all values are finite.
    pub first_non_finite: Option<(usize, usize)>,
    /// Finite channel values below 0 (`-0.0` does not count).
    pub negative: usize,
    /// The smallest finite channel value; 0 when there is none.
    pub min_value: f32,
    /// The largest finite channel value; 0 when there is none.
    pub max_value: f32,
}

impl PixelStats {
    /// Whether every channel value is finite and not negative.
    #[must_use]
    pub fn is_clean(&self) -> bool {
        self.non_finite == 0 && self.negative == 0
    }
}

/// What [`Image::sanitize`] replaced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SanitizeReport {
    /// NaN values, set to 0.
    pub nan: usize,
    /// `+inf` values, set to [`SanitizeReport::infinity_replacement`].
    pub positive_infinite: usize,
    /// `-inf` values, set to 0.
    pub negative_infinite: usize,
    /// Finite negative values, set to 0.
    pub negative: usize,
    /// The value that replaced `+inf`: the largest finite channel value of
    /// the image, or 0 when that is negative or there is none.
    pub infinity_replacement: f32,
}

impl SanitizeReport {
    /// How many channel values were replaced in all.
    #[must_use]
    pub fn total(&self) -> usize {
        self.nan + self.positive_infinite + self.negative_infinite + self.negative
    }
}

impl Image {
    /// Counts of non-finite and negative channel values, and the range of the
    /// finite ones: [`PixelStats::of_pixels`] of this image's pixels.
    #[must_use]
    pub fn stats(&self) -> PixelStats {
        PixelStats::of_pixels(self.pixels(), self.width())
    }
}

impl PixelStats {
    /// [`Image::stats`] of pixels stored row-major, `width` to a row, as
    /// they lie (an image borrowed from elsewhere, e.g. a numpy array):
    /// counts of non-finite and negative channel values and the range of
    /// the finite ones, `first_non_finite` as a column and row.
    ///
    /// One pass over the values, in blocks of 12 288 values with
    /// branch-free lanes (they vectorise); only a block that holds a
    /// non-finite value is scanned again, for the first one's position.
    /// Large images are split into as many runs of whole blocks as there
    /// are cores, each on a scoped thread, and the runs' results combined
    /// in order (the result does not depend on the split).
    #[must_use]
    pub fn of_pixels(pixels: &[[f32; 3]], width: usize) -> PixelStats {
        let width = width.max(1);
        let values = pixels.as_flattened();
        let blocks = values.len().div_ceil(STATS_BLOCK);
        // The core count is asked for only when the image is worth
        // splitting: it is not cached (a system call and cgroup files each
        // time), and a map's rows may come here one at a time.
        let threads = if blocks < 2 * PARALLEL_BLOCKS {
            1
        } else {
            std::thread::available_parallelism()
                .map_or(1, usize::from)
                .min(blocks / PARALLEL_BLOCKS)
        };
        let (mut stats, first) = stats_in_runs(values, threads);
        stats.first_non_finite = first.map(|i| ((i / 3) % width, (i / 3) / width));
        if stats.min_value > stats.max_value {
            // No finite value at all.
            stats.min_value = 0.0;
            stats.max_value = 0.0;
        }
        stats
    }
}

/// Blocks per scoped thread at the least: below `2 x` this many blocks
/// (about 200 000 values), [`PixelStats::of_pixels`] stays on the calling
/// thread, where starting threads would cost more than it saves.
const PARALLEL_BLOCKS: usize = 8;

/// [`run_stats`] of `values` split into `threads` runs of whole blocks,
/// each on a scoped thread, the results combined in order (the first
/// non-finite value's index is into all of `values`).
fn stats_in_runs(values: &[f32], threads: usize) -> (PixelStats, Option<usize>) {
    if threads <= 1 {
        return run_stats(values);
    }
    let per_run = values.len().div_ceil(STATS_BLOCK).div_ceil(threads) * STATS_BLOCK;
    let runs: Vec<(PixelStats, Option<usize>)> = std::thread::scope(|scope| {
        let handles: Vec<_> = values
            .chunks(per_run)
            .map(|run| scope.spawn(move || run_stats(run)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    let mut total = (empty_stats(), None);
    for (r, (part, first)) in runs.into_iter().enumerate() {
        total.0 = merge(total.0, part);
        total.1 = total.1.or(first.map(|i| r * per_run + i));
    }
    total
}

/// Nothing counted yet: the identity of [`merge`].
fn empty_stats() -> PixelStats {
    PixelStats {
        non_finite: 0,
        first_non_finite: None,
        negative: 0,
        min_value: f32::INFINITY,
        max_value: f32::NEG_INFINITY,
    }
}

/// Counts added, ranges joined (`first_non_finite` left to the caller).
fn merge(a: PixelStats, b: PixelStats) -> PixelStats {
    PixelStats {
        non_finite: a.non_finite + b.non_finite,
        first_non_finite: None,
        negative: a.negative + b.negative,
        min_value: a.min_value.min(b.min_value),
        max_value: a.max_value.max(b.max_value),
    }
}

/// The counts and range of `values` (a whole number of blocks, but for the
/// last run), and the index in `values` of the first non-finite one.
fn run_stats(values: &[f32]) -> (PixelStats, Option<usize>) {
    let mut stats = empty_stats();
    let mut first = None;
    for (b, block) in values.chunks(STATS_BLOCK).enumerate() {
        let part = block_stats(block);
        if part.non_finite > 0 && first.is_none() {
            let at = block.iter().position(|v| !v.is_finite()).expect("counted");
            first = Some(b * STATS_BLOCK + at);
        }
        stats = merge(stats, part);
    }
    (stats, first)
}

impl Image {
    /// Makes every channel value finite and not negative, in place: NaN
    /// becomes 0, `+inf` the largest finite value of the image (computed
    /// before any replacement; 0 if negative or absent), `-inf` and finite
    /// negatives 0. Returns what was replaced.
    pub fn sanitize(&mut self) -> SanitizeReport {
        let largest = self.stats().max_value.max(0.0);
        sanitize_pixels(self.pixels_mut(), largest)
    }
}

/// [`Image::sanitize`] of some of an image's pixels (a band of rows read
/// by [`crate::open_rows`]), `+inf` replaced by `infinity_replacement`
/// (the whole image's largest finite value, or 0 when that is negative or
/// there is none). Reports of the bands of an image add up
/// ([`SanitizeReport::combined`]) to the whole image's.
pub fn sanitize_pixels(pixels: &mut [[f32; 3]], infinity_replacement: f32) -> SanitizeReport {
    let mut report = SanitizeReport {
        nan: 0,
        positive_infinite: 0,
        negative_infinite: 0,
        negative: 0,
        infinity_replacement,
    };
    for v in pixels.iter_mut().flatten() {
        if v.is_nan() {
            report.nan += 1;
            *v = 0.0;
        } else if *v == f32::INFINITY {
            report.positive_infinite += 1;
            *v = infinity_replacement;
        } else if *v == f32::NEG_INFINITY {
            report.negative_infinite += 1;
            *v = 0.0;
        } else if *v < 0.0 {
            report.negative += 1;
            *v = 0.0;
        }
    }
    report
}

impl SanitizeReport {
    /// The counts of `self` and `other` added (the replacement is
    /// `self`'s): the report of two parts of one image.
    #[must_use]
    pub fn combined(self, other: SanitizeReport) -> SanitizeReport {
        SanitizeReport {
            nan: self.nan + other.nan,
            positive_infinite: self.positive_infinite + other.positive_infinite,
            negative_infinite: self.negative_infinite + other.negative_infinite,
            negative: self.negative + other.negative,
            infinity_replacement: self.infinity_replacement,
        }
    }
}

/// Channel values per block of [`Image::stats`]: small enough for the
/// lanes' `u32` counts, large enough that the per-block work is nothing.
const STATS_BLOCK: usize = 3 << 12;

/// Lanes of the branch-free loop of [`block_stats`].
const LANES: usize = 8;

/// The counts and range of one block (`first_non_finite` not set). Kept
/// out of line: inlined into its callers it lost its vectorised form.
#[inline(never)]
fn block_stats(values: &[f32]) -> PixelStats {
    let mut non_finite = [0_u32; LANES];
    let mut negative = [0_u32; LANES];
    let mut min = [f32::INFINITY; LANES];
    let mut max = [f32::NEG_INFINITY; LANES];
    let (blocks, tail) = values.as_chunks::<LANES>();
    for block in blocks {
        for k in 0..LANES {
            let v = block[k];
            // NaN compares false: not finite.
            let finite = v.abs() < f32::INFINITY;
            non_finite[k] += u32::from(!finite);
            negative[k] += u32::from(finite & (v < 0.0));
            let low = if finite { v } else { f32::INFINITY };
            let high = if finite { v } else { f32::NEG_INFINITY };
            min[k] = if low < min[k] { low } else { min[k] };
            max[k] = if high > max[k] { high } else { max[k] };
        }
    }
    for (k, &v) in tail.iter().enumerate() {
        let finite = v.abs() < f32::INFINITY;
        non_finite[k] += u32::from(!finite);
        negative[k] += u32::from(finite & (v < 0.0));
        if finite {
            min[k] = min[k].min(v);
            max[k] = max[k].max(v);
        }
    }
    PixelStats {
        non_finite: non_finite.iter().map(|&n| n as usize).sum(),
        first_non_finite: None,
        negative: negative.iter().map(|&n| n as usize).sum(),
        min_value: min.into_iter().fold(f32::INFINITY, f32::min),
        max_value: max.into_iter().fold(f32::NEG_INFINITY, f32::max),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Any split into runs gives the one run's result, whatever the number
    /// of cores: ten blocks and a ragged tail, with the special values in
    /// different runs.
    #[test]
    fn every_split_gives_the_single_runs_result() {
        let mut values: Vec<f32> = (0..10 * STATS_BLOCK + 100)
            .map(|i| (i % 101) as f32 / 100.0)
            .collect();
        let n = values.len();
        values[7 * STATS_BLOCK + 5] = f32::NAN;
        values[9 * STATS_BLOCK + 1] = f32::INFINITY;
        values[STATS_BLOCK + 3] = -2.5;
        values[n - 1] = 42.0;
        let one = run_stats(&values);
        assert_eq!(one.1, Some(7 * STATS_BLOCK + 5));
        assert_eq!((one.0.non_finite, one.0.negative), (2, 1));
        assert_eq!((one.0.min_value, one.0.max_value), (-2.5, 42.0));
        for threads in [2, 3, 7, 11, 20] {
            assert_eq!(stats_in_runs(&values, threads), one, "{threads} runs");
        }
    }
}
