//! [`auto_exposure`]: the exposure that brings a picture's mean luminance
//! to a chosen grey.

/// The exposure in stops, `log2(key / mean_luminance)`, that maps a mean
/// luminance to `key` (0.18 is photographic middle grey), for
/// [`crate::WriteOptions::exposure_ev`]; 0 when the mean is not a positive
/// finite number (a black picture).
#[must_use]
pub fn auto_exposure(mean_luminance: f64, key: f64) -> f32 {
    if mean_luminance > 0.0 && mean_luminance.is_finite() {
        (key / mean_luminance).log2() as f32
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exposure_brings_the_mean_to_the_key() {
        assert_eq!(auto_exposure(0.09, 0.18), 1.0);
        assert_eq!(auto_exposure(0.18 * 8.0, 0.18), -3.0);
        // 2^EV times the mean is the key.
        let ev = auto_exposure(3.7, 0.25);
        assert!((f64::from(ev).exp2() * 3.7 - 0.25).abs() < 1e-7);
        for dark in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert_eq!(auto_exposure(dark, 0.18), 0.0, "{dark}");
        }
    }
}
