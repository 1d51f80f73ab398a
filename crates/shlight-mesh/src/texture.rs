//! A decoded texture image and its sampler: 8-bit RGBA texels, the wrap
//! modes of glTF's sampler, bilinear or nearest filtering.
//!
//! Texels are stored as the file holds them (8 bits a channel); colour
//! textures (base colour, emissive) are sRGB-decoded when sampled
//! ([`Texture::sample`] with `srgb`), data textures (metallic-roughness)
//! are read linearly. Texel `(i, j)` covers `[i, i + 1) / width` by
//! `[j, j + 1) / height` in UV, `j = 0` the top row (glTF's UV origin is the
//! image's top-left corner), and bilinear filtering weighs the four texels
//! whose centres surround the point, as GPUs do.

use glam::{Vec2, Vec4};

/// How a coordinate outside `[0, 1)` is brought back (glTF sampler
/// `wrapS` / `wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image repeats (`10497`, the default).
    #[default]
    Repeat,
    /// The image repeats, every other copy mirrored (`33648`).
    MirroredRepeat,
    /// The edge texels extend (`33071`).
    ClampToEdge,
}

impl Wrap {
    /// The wrap mode of a glTF sampler's enum value (`None` for an unknown
    /// one).
    pub fn from_gl(value: u32) -> Option<Self> {
        match value {
            10497 => Some(Wrap::Repeat),
            33648 => Some(Wrap::MirroredRepeat),
            33071 => Some(Wrap::ClampToEdge),
            _ => None,
        }
    }

    /// Texel index `i` (any integer) brought into `0..n`.
    fn index(self, i: i64, n: usize) -> usize {
        let n = n as i64;
        let i = match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::MirroredRepeat => {
                let m = i.rem_euclid(2 * n);
                if m < n { m } else { 2 * n - 1 - m }
            }
        };
        i as usize
    }
}

/// Magnification and minification filtering, as far as a baker uses it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// The four nearest texels, weighted (the default).
    #[default]
    Linear,
    /// The nearest texel (glTF `NEAREST`, 9728, as the sampler's
    /// `magFilter`).
    Nearest,
}

/// A decoded image with its sampler.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Width in texels (at least 1).
    pub width: usize,
    /// Height in texels (at least 1).
    pub height: usize,
    /// Texels in rows, the top row first, RGBA, as the file stores them
    /// (alpha 255 where the image has none).
    pub texels: Vec<[u8; 4]>,
    /// Wrap mode along U (glTF `wrapS`).
    pub wrap_u: Wrap,
    /// Wrap mode along V (glTF `wrapT`).
    pub wrap_v: Wrap,
    /// Filtering.
    pub filter: Filter,
}

impl Texture {
    /// The texture at `uv`, RGBA in `[0, 1]`; RGB sRGB-decoded to linear
    /// when `srgb` (alpha is always linear).
    pub fn sample(&self, uv: Vec2, srgb: bool) -> Vec4 {
        let decode = |t: [u8; 4]| {
            let c = |v: u8| {
                if srgb {
                    SRGB_TO_LINEAR[v as usize]
                } else {
                    f32::from(v) / 255.0
                }
            };
            Vec4::new(c(t[0]), c(t[1]), c(t[2]), f32::from(t[3]) / 255.0)
        };
        let texel = |i: i64, j: i64| {
            let i = self.wrap_u.index(i, self.width);
            let j = self.wrap_v.index(j, self.height);
            decode(self.texels[j * self.width + i])
        };
        let x = uv.x * self.width as f32;
        let y = uv.y * self.height as f32;
        if !x.is_finite() || !y.is_finite() {
            return texel(0, 0);
        }
        match self.filter {
            Filter::Nearest => texel(x.floor() as i64, y.floor() as i64),
            Filter::Linear => {
                let (x, y) = (x - 0.5, y - 0.5);
                let (x0, y0) = (x.floor(), y.floor());
                let (fx, fy) = (x - x0, y - y0);
                let (i, j) = (x0 as i64, y0 as i64);
                let top = texel(i, j).lerp(texel(i + 1, j), fx);
                let bottom = texel(i, j + 1).lerp(texel(i + 1, j + 1), fx);
                top.lerp(bottom, fy)
            }
        }
    }
}

/// The sRGB transfer function's inverse at each 8-bit value.
static SRGB_TO_LINEAR: std::sync::LazyLock<[f32; 256]> = std::sync::LazyLock::new(|| {
    let mut table = [0.0; 256];
    for (v, t) in table.iter_mut().enumerate() {
        *t = shlight_io::srgb_to_linear(v as f32 / 255.0);
    }
    table
});

#[cfg(test)]
mod tests {
    use super::*;

    fn two_by_two(wrap: Wrap) -> Texture {
        Texture {
            width: 2,
            height: 2,
            texels: vec![
                [0, 0, 0, 255],
                [255, 0, 0, 255],
                [0, 255, 0, 0],
                [255, 255, 255, 0],
            ],
            wrap_u: wrap,
            wrap_v: wrap,
            filter: Filter::Linear,
        }
    }

    #[test]
    fn texel_centres_give_their_texel_and_the_middle_their_mean() {
        let t = two_by_two(Wrap::ClampToEdge);
        assert_eq!(
            t.sample(Vec2::new(0.25, 0.25), false),
            Vec4::new(0.0, 0.0, 0.0, 1.0)
        );
        assert_eq!(
            t.sample(Vec2::new(0.75, 0.25), false),
            Vec4::new(1.0, 0.0, 0.0, 1.0)
        );
        assert_eq!(
            t.sample(Vec2::new(0.25, 0.75), false),
            Vec4::new(0.0, 1.0, 0.0, 0.0)
        );
        let mid = t.sample(Vec2::new(0.5, 0.5), false);
        assert!((mid - Vec4::new(0.5, 0.5, 0.25, 0.5)).abs().max_element() < 1e-6);
    }

    #[test]
    fn wraps_repeat_mirror_and_clamp() {
        let uv = Vec2::new(1.25, 0.25);
        assert_eq!(two_by_two(Wrap::Repeat).sample(uv, false).x, 0.0);
        assert_eq!(two_by_two(Wrap::MirroredRepeat).sample(uv, false).x, 1.0);
        assert_eq!(two_by_two(Wrap::ClampToEdge).sample(uv, false).x, 1.0);
        assert_eq!(
            two_by_two(Wrap::Repeat)
                .sample(Vec2::new(-0.25, 0.25), false)
                .x,
            1.0
        );
    }

    #[test]
    fn colour_textures_are_srgb_decoded() {
        let t = Texture {
            width: 1,
            height: 1,
            texels: vec![[188, 188, 188, 188]],
            ..two_by_two(Wrap::Repeat)
        };
        let c = t.sample(Vec2::splat(0.5), true);
        // sRGB 188/255 is linear 0.5029; alpha stays 188/255.
        assert!((c.x - 0.5029).abs() < 1e-3, "{c}");
        assert!((c.w - 188.0 / 255.0).abs() < 1e-6);
    }
}
