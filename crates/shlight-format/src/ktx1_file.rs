//! [`filament_ktx1`]: a cube map with mips as the KTX 1.1 file Filament's
//! `KtxBundle` reads for an `IndirectLight`'s reflections, laid out field
//! for field as `cmgen --format=ktx --ibl-ld` writes it: texels packed as
//! `R11F_G11F_B10F` (unsigned 11- and 10-bit floats, one `u32` a texel,
//! red in the low bits: `GL_UNSIGNED_INT_10F_11F_11F_REV`), six faces per
//! level (`+X -X +Y -Y +Z -Z`, row 0 first), each level's `imageSize` the
//! bytes of one face, no key/value data.

/// `GL_R11F_G11F_B10F`, which cmgen writes in `glType`, `glInternalFormat`
/// and `glBaseInternalFormat` alike (`glFormat` is `GL_RGB`).
pub const GL_R11F_G11F_B10F: u32 = 0x8C3A;
/// `GL_RGB`.
const GL_RGB: u32 = 0x1907;

/// `v` (linear, clamped to `[0, 65024]`, NaN as 0) as an unsigned float
/// of 5 exponent bits and `mantissa` bits, rounded to nearest: the top bits
/// of its IEEE half.
fn unsigned_float(v: f32, mantissa: u32) -> u32 {
    let v = if v.is_nan() {
        0.0
    } else {
        v.clamp(0.0, 65024.0)
    };
    let h = u32::from(half::f16::from_f32(v).to_bits()) & 0x7fff;
    let drop = 10 - mantissa;
    ((h + (1 << (drop - 1))) >> drop).min((30 << mantissa) | ((1 << mantissa) - 1))
}

/// `[r, g, b]` packed as `R11F_G11F_B10F`.
#[must_use]
pub fn pack_r11g11b10(p: [f32; 3]) -> u32 {
    unsigned_float(p[0], 6) | (unsigned_float(p[1], 6) << 11) | (unsigned_float(p[2], 5) << 22)
}

/// A packed `R11F_G11F_B10F` texel back to `[r, g, b]`.
#[must_use]
pub fn unpack_r11g11b10(t: u32) -> [f32; 3] {
    let decode = |v: u32, mantissa: u32| {
        let (e, m) = (v >> mantissa, v & ((1 << mantissa) - 1));
        let m = m as f32 / (1u32 << mantissa) as f32;
        if e == 0 {
            m * 2f32.powi(-14)
        } else {
            (1.0 + m) * 2f32.powi(e as i32 - 15)
        }
    };
    [
        decode(t & 0x7ff, 6),
        decode((t >> 11) & 0x7ff, 6),
        decode(t >> 22, 5),
    ]
}

/// A cube map with mips as Filament's KTX 1.1 (module docs):
/// `levels[k][f]` the `s_k x s_k` linear RGB texels of face `f` of mip `k`,
/// `s_k = size >> k`.
///
/// # Panics
/// When a face does not hold `s_k * s_k` texels.
#[must_use]
pub fn filament_ktx1(size: usize, levels: &[[Vec<[f32; 3]>; 6]]) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend([
        0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31, 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
    ]);
    for v in [
        0x0403_0201, // endianness
        GL_R11F_G11F_B10F,
        1, // glTypeSize, as cmgen writes it
        GL_RGB,
        GL_R11F_G11F_B10F,
        GL_R11F_G11F_B10F,
        size as u32,
        size as u32,
        0, // pixelDepth
        0, // numberOfArrayElements
        6, // numberOfFaces
        levels.len() as u32,
        0, // bytesOfKeyValueData
    ] {
        out.extend(u32::to_le_bytes(v));
    }
    for (k, faces) in levels.iter().enumerate() {
        let s = (size >> k).max(1);
        out.extend(((s * s * 4) as u32).to_le_bytes());
        for face in faces {
            assert_eq!(face.len(), s * s, "mip {k}: a face of {s}x{s} texels");
            for p in face {
                out.extend(pack_r11g11b10(*p).to_le_bytes());
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Packing keeps 6 (red, green) and 5 (blue) mantissa bits: within
    /// half a step, 1/128 and 1/64 relative; exact powers of two exactly.
    #[test]
    fn texels_round_trip_within_the_packed_precision() {
        for v in [0.0f32, 1.0, 0.5, 3.7, 0.0123, 250.0, 1.0e-5] {
            let back = unpack_r11g11b10(pack_r11g11b10([v, 2.0 * v, 0.5 * v]));
            for (got, want, rel) in [
                (back[0], v, 1.0 / 128.0),
                (back[1], 2.0 * v, 1.0 / 128.0),
                (back[2], 0.5 * v, 1.0 / 64.0),
            ] {
                assert!((got - want).abs() <= rel * want + 1.0e-6, "{want}: {got}");
            }
        }
        assert_eq!(
            unpack_r11g11b10(pack_r11g11b10([1.0, 2.0, 0.25])),
            [1.0, 2.0, 0.25]
        );
        assert_eq!(
            unpack_r11g11b10(pack_r11g11b10([-1.0, f32::NAN, 0.0])),
            [0.0, 0.0, 0.0]
        );
    }
}
