//! Helpers shared by the crate's unit tests.

use glam::DVec3;

/// The unit roundoff of `f32`, `2^-24`.
pub(crate) const U32: f64 = f32::EPSILON as f64 / 2.0;

/// The largest difference between two runs of coefficients, over every
/// coefficient and channel.
pub(crate) fn max_diff(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).abs().max_element())
        .fold(0.0, f64::max)
}

/// A seeded stream of numbers in `[-0.5, 0.5)` (Knuth's MMIX linear
/// congruential generator, its top 53 bits).
pub(crate) fn numbers(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}
