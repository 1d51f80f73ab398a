//! The mip levels of an 8-bit RGBA texture, made on the CPU so that a
//! minified texture is filtered instead of aliasing.
//!
//! Level `k + 1` is `max(1, floor(w / 2)) x max(1, floor(h / 2))` of level
//! `k`; each of its texels is the mean of the 2x2 texels `(2i, 2j)` to
//! `(2i + 1, 2j + 1)` of the level above, a coordinate beyond an odd edge
//! clamped to it (the last row or column counted twice). Colour textures
//! (`srgb`) are averaged in linear light: each texel sRGB-decoded, the mean
//! encoded again; alpha, and every channel of a data texture, is averaged
//! as stored. Means are rounded to the nearest 8-bit value.

use shlight_io::{linear_to_srgb, srgb_to_linear};

/// One level: width, height and texels in rows, the top row first.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MipLevel {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[u8; 4]>,
}

/// The levels of a `width x height` texture down to 1x1, leaving out the
/// leading levels with a side beyond `max_side` (the device's largest 2D
/// texture): the first level kept is the largest that fits.
///
/// # Panics
/// If `texels` does not hold `width * height` texels or a side is 0 (a
/// [`shlight_mesh::Texture`] never does).
pub(crate) fn mip_chain(
    width: usize,
    height: usize,
    texels: &[[u8; 4]],
    srgb: bool,
    max_side: u32,
) -> Vec<MipLevel> {
    assert!(width > 0 && height > 0 && texels.len() == width * height);
    let mut level = MipLevel {
        width: width as u32,
        height: height as u32,
        texels: texels.to_vec(),
    };
    let mut levels = Vec::new();
    loop {
        let (w, h) = (level.width, level.height);
        let next = (w > 1 || h > 1).then(|| halve(&level, srgb));
        if w <= max_side && h <= max_side {
            levels.push(level);
        }
        match next {
            Some(n) => level = n,
            None => return levels,
        }
    }
}

/// The next level of `level` (module documentation).
fn halve(level: &MipLevel, srgb: bool) -> MipLevel {
    let (w, h) = (level.width as usize, level.height as usize);
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let decode = |v: u8, c: usize| {
        let x = f32::from(v) / 255.0;
        if srgb && c < 3 { srgb_to_linear(x) } else { x }
    };
    let encode = |x: f32, c: usize| {
        let y = if srgb && c < 3 { linear_to_srgb(x) } else { x };
        (y.clamp(0.0, 1.0) * 255.0).round() as u8
    };
    let mut texels = Vec::with_capacity(nw * nh);
    for j in 0..nh {
        let rows = [(2 * j).min(h - 1), (2 * j + 1).min(h - 1)];
        for i in 0..nw {
            let cols = [(2 * i).min(w - 1), (2 * i + 1).min(w - 1)];
            let mut out = [0u8; 4];
            for (c, o) in out.iter_mut().enumerate() {
                let mut sum = 0.0f32;
                for &r in &rows {
                    for &q in &cols {
                        sum += decode(level.texels[r * w + q][c], c);
                    }
                }
                *o = encode(sum / 4.0, c);
            }
            texels.push(out);
        }
    }
    MipLevel {
        width: nw as u32,
        height: nh as u32,
        texels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_levels_average_light_and_data_levels_average_values() {
        // A 2x2 of black and white: the light's mean is 0.5, sRGB 188
        // (0.5^(1/2.4) * 1.055 - 0.055 = 0.7354, * 255 = 187.5); alpha and
        // a data texture average the stored values, 127.5 -> 128.
        let t = [
            [0, 0, 0, 0],
            [255, 255, 255, 255],
            [0, 0, 0, 0],
            [255, 255, 255, 255],
        ];
        let colour = mip_chain(2, 2, &t, true, 4096);
        assert_eq!(colour.len(), 2);
        assert_eq!(colour[1].texels, vec![[188, 188, 188, 128]]);
        let data = mip_chain(2, 2, &t, false, 4096);
        assert_eq!(data[1].texels, vec![[128; 4]]);
    }

    #[test]
    fn odd_sides_clamp_and_every_level_down_to_one_texel() {
        // 5x3: levels 5x3, 2x1, 1x1.
        let t: Vec<[u8; 4]> = (0..15u8).map(|k| [k * 10, 0, 0, 255]).collect();
        let levels = mip_chain(5, 3, &t, false, 4096);
        let sizes: Vec<(u32, u32)> = levels.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(5, 3), (2, 1), (1, 1)]);
        // Level 1 texel (1, 0): columns 2, 3 of rows 0, 1: values 20, 30,
        // 70, 80 -> 50.
        assert_eq!(levels[1].texels[1][0], 50);
        // A level beyond the side limit is left out; the chain starts at
        // the largest that fits.
        let capped = mip_chain(5, 3, &t, false, 2);
        assert_eq!(capped[0].width, 2);
        assert_eq!(capped.len(), 2);
    }
}
