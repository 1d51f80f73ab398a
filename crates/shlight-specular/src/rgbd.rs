//! Babylon.js's RGBD encoding: HDR radiance in an 8-bit RGBA texel, as
//! Babylon's `toRGBD` / `fromRGBD` (`helperFunctions.fx`) write and read
//! it, and as `EXT_lights_image_based`'s `specularImages` hold it.
//!
//! ```text
//! m = max(r, g, b, 1e-7),  D = clamp(floor(max(255 / m, 1)) / 255, 0, 1),
//! stored rgb = clamp((c D)^(1/2.2), 0, 1),  stored a = D;
//! decoded c = rgb_stored^2.2 / a_stored.
//! ```
//!
//! Values up to 255 survive (above that `D = 1/255` and channels clip).
//! A texel whose largest channel `m` is 1 or more is scaled into `[0, 1]`
//! by `D`, and the 8-bit rounding leaves at most about 0.5% of `m`; below
//! 1, `D = 1` and the channels are plain 8-bit gamma 2.2, an error of at
//! most `2.2 · 0.5/255 · m^(1 - 1/2.2)`.

/// Babylon's `rgbdMaxRange`.
pub const RGBD_MAX_RANGE: f32 = 255.0;

/// Babylon's `toGammaSpace` / `toLinearSpace` exponent (`GammaEncodePowerApprox = 1/2.2`).
const GAMMA: f32 = 2.2;

/// `c` (linear, non-negative) as RGBD bytes `[r, g, b, d]`, rounded to the
/// nearest 8-bit value.
#[must_use]
pub fn rgbd_encode(c: [f32; 3]) -> [u8; 4] {
    let c = c.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
    let m = c[0].max(c[1]).max(c[2]).max(1e-7);
    let d = ((RGBD_MAX_RANGE / m).max(1.0).floor() / 255.0).clamp(0.0, 1.0);
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let rgb = c.map(|v| byte((v * d).powf(1.0 / GAMMA)));
    [rgb[0], rgb[1], rgb[2], byte(d)]
}

/// The linear value Babylon's `fromRGBD` reads from RGBD bytes.
#[must_use]
pub fn rgbd_decode(p: [u8; 4]) -> [f32; 3] {
    let d = f32::from(p[3]) / 255.0;
    [p[0], p[1], p[2]].map(|v| (f32::from(v) / 255.0).powf(GAMMA) / d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values across the range come back within the 8-bit step (module
    /// docs); D is the largest integer scale that keeps the texel in range,
    /// as Babylon's shader computes it.
    #[test]
    fn values_round_trip_within_the_8_bit_step() {
        for &v in &[0.001f32, 0.05, 0.5, 1.0, 3.7, 42.0, 200.0, 255.0] {
            for c in [[v, 0.5 * v, 0.1 * v], [0.2 * v, v, 0.7 * v]] {
                let back = rgbd_decode(rgbd_encode(c));
                for k in 0..3 {
                    let scale = c[0].max(c[1]).max(c[2]);
                    let step = 0.005 * scale.max(scale.powf(1.0 - 1.0 / 2.2));
                    assert!((back[k] - c[k]).abs() <= step, "{c:?} -> {back:?}");
                }
            }
        }
        // 2.0: D = floor(127.5) / 255 = 127/255; rgb = (2 * 127/255)^(1/2.2).
        let p = rgbd_encode([2.0, 2.0, 2.0]);
        assert_eq!(p[3], 127);
        assert_eq!(
            p[0],
            ((2.0f32 * 127.0 / 255.0).powf(1.0 / 2.2) * 255.0).round() as u8
        );
        // Above 255 the channel clips at 255.
        assert!((rgbd_decode(rgbd_encode([1000.0, 0.0, 0.0]))[0] - 255.0).abs() < 1e-3);
    }
}
