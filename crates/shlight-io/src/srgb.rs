//! The sRGB transfer function (IEC 61966-2-1), exact piecewise form.
//!
//! 8- and 16-bit files (PNG, JPEG) hold sRGB-encoded values; they are decoded
//! to linear light on reading and encoded on writing. The functions are
//! evaluated in `f64` and rounded once to `f32`.

/// Decodes an sRGB-encoded value to linear light (the sRGB EOTF):
///
/// `c / 12.92` for `c <= 0.04045`, else `((c + 0.055) / 1.055)^2.4`.
///
/// `encoded` is expected in `[0, 1]`; values outside are clamped. For
/// example `srgb_to_linear(128.0 / 255.0)` is `0.2158605`.
#[must_use]
pub fn srgb_to_linear(encoded: f32) -> f32 {
    eotf(f64::from(encoded.clamp(0.0, 1.0))) as f32
}

/// The sRGB EOTF in `f64`, for `c` in `[0, 1]`.
fn eotf(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Encodes linear light as an sRGB value (the inverse of
/// [`srgb_to_linear`]):
///
/// `12.92 l` for `l <= 0.0031308`, else `1.055 l^(1/2.4) - 0.055`.
///
/// `linear` is clamped to `[0, 1]` first; NaN gives 0.
#[must_use]
pub fn linear_to_srgb(linear: f32) -> f32 {
    if linear.is_nan() {
        return 0.0;
    }
    let l = f64::from(linear.clamp(0.0, 1.0));
    let encoded = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    encoded as f32
}

/// The linear value of each 8-bit sRGB code, `srgb_to_linear(i / 255)`.
pub(crate) fn srgb8_table() -> [f32; 256] {
    std::array::from_fn(|i| eotf(i as f64 / 255.0) as f32)
}

/// The linear value of a 16-bit sRGB code, `srgb_to_linear(code / 65535)`.
pub(crate) fn srgb16_to_linear(code: u16) -> f32 {
    eotf(f64::from(code) / 65535.0) as f32
}

/// [`srgb16_to_linear`] of every 16-bit code, computed once per process
/// (65,536 evaluations of the transfer function: milliseconds, more than
/// decoding a small PNG takes).
pub(crate) fn srgb16_table() -> &'static [f32] {
    static TABLE: std::sync::OnceLock<Vec<f32>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| (0..=u16::MAX).map(srgb16_to_linear).collect())
}

/// The 8-bit sRGB code of a linear value: [`linear_to_srgb`], scaled to 255
/// and rounded to nearest.
pub(crate) fn linear_to_srgb8(linear: f32) -> u8 {
    (linear_to_srgb(linear) * 255.0).round() as u8
}
