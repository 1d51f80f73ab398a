//! KTX 2.0 files of linear float texels: one 2D image, one mip level, no
//! supercompression, in `VK_FORMAT_R16G16B16A16_SFLOAT` or
//! `VK_FORMAT_B10G11R11_UFLOAT_PACK32` (lightmaps for Bevy and three.js).
//!
//! Layout (KTX 2.0 specification, sections 3 and 4): the 12-byte
//! identifier, the header (vkFormat, typeSize, width, height, depth 0,
//! layers 0, faces 1, levels 1, supercompression 0), the index, one level
//! index entry, the data format descriptor, the key/value data (one key,
//! `KTXwriter`), then the level's texels, aligned to 8 bytes (the least
//! common multiple of the texel block size and 4). Rows are stored as given,
//! the first at the top (KTX2 and glTF both put `v = 0` at the first row).
//!
//! The data format descriptor is one basic block (Khronos Data Format
//! 1.3, version number 2) as libktx's `vk2dfd` makes it for the format:
//! colour model RGBSDA, BT.709 primaries, linear transfer, straight
//! alpha, a 1x1x1x1 texel block, `bytesPlane0` the texel's size, and one
//! sample per channel. `R16G16B16A16_SFLOAT`: R, G, B, A (channel ids 0,
//! 1, 2, 15) at bits 0, 16, 32, 48, 16 bits each, float and signed, sample
//! range -1.0 to 1.0. `B10G11R11_UFLOAT_PACK32`: R at bit 0 (11 bits), G at
//! bit 11 (11 bits), B at bit 22 (10 bits), float, unsigned, range 0.0 to
//! 1.0 (libktx's `createDFDPacked(0, 3, {11,11,10}, {0,1,2}, s_UFLOAT)`).
//!
//! Texel encodings:
//! - half floats (IEEE 754 binary16): round to nearest, ties to even;
//!   values at or past 65520 in magnitude become infinities, as IEEE
//!   conversion does; NaN becomes the quiet NaN `0x7E00` with the input's
//!   sign.
//! - the packed format's unsigned 11- and 10-bit floats (5-bit exponent,
//!   bias 15; 6- and 5-bit mantissas; no sign; Vulkan's "Unsigned 11-Bit
//!   Floating-Point Numbers", after OpenGL 4.6 section 2.3.4.4): round to
//!   nearest, ties to even; negative values and -infinity become 0; finite
//!   values past the largest finite one (65024 in 11 bits, 64512 in 10)
//!   become it; +infinity stays infinite; NaN becomes the format's quiet
//!   NaN (exponent 31, top mantissa bit set). Alpha is dropped.

use std::path::Path;

use crate::{IoError, IoErrorKind, write_atomically};

/// The 12 bytes every KTX 2.0 file starts with.
const IDENTIFIER: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// The identifier, header, index and one level index entry.
const HEADER_BYTES: usize = 12 + 9 * 4 + 4 * 4 + 2 * 8 + 3 * 8;

/// The texel format of a lightmap KTX2 file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ktx2TexelFormat {
    /// `VK_FORMAT_R16G16B16A16_SFLOAT` (97): four half floats, 8 bytes a
    /// texel.
    Rgba16Float,
    /// `VK_FORMAT_B10G11R11_UFLOAT_PACK32` (122): unsigned 11-bit R and
    /// G, 10-bit B floats in one little-endian 32-bit word, 4 bytes a
    /// texel; no alpha, no negative values.
    B10G11R11Ufloat,
}

impl Ktx2TexelFormat {
    /// The Vulkan format number KTX2 names the format by.
    #[must_use]
    pub fn vk_format(self) -> u32 {
        match self {
            Self::Rgba16Float => 97,
            Self::B10G11R11Ufloat => 122,
        }
    }

    /// The format named by a Vulkan format number, if it is one of these.
    #[must_use]
    pub fn from_vk_format(vk_format: u32) -> Option<Self> {
        match vk_format {
            97 => Some(Self::Rgba16Float),
            122 => Some(Self::B10G11R11Ufloat),
            _ => None,
        }
    }

    /// Bytes per texel.
    #[must_use]
    pub fn texel_bytes(self) -> usize {
        match self {
            Self::Rgba16Float => 8,
            Self::B10G11R11Ufloat => 4,
        }
    }

    /// KTX2's `typeSize`: the size of the data type the texels are
    /// swapped by on a big-endian machine (2 for half floats, 4 for the
    /// packed word).
    fn type_size(self) -> u32 {
        match self {
            Self::Rgba16Float => 2,
            Self::B10G11R11Ufloat => 4,
        }
    }

    /// The Vulkan name, for messages.
    fn name(self) -> &'static str {
        match self {
            Self::Rgba16Float => "VK_FORMAT_R16G16B16A16_SFLOAT",
            Self::B10G11R11Ufloat => "VK_FORMAT_B10G11R11_UFLOAT_PACK32",
        }
    }
}

/// A KTX2 image read back by [`read_ktx2`]: its format, size and texels
/// (row-major, row 0 at the top) as RGBA `f32` (alpha 1 for
/// [`Ktx2TexelFormat::B10G11R11Ufloat`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Ktx2Image {
    /// The texel format of the file.
    pub format: Ktx2TexelFormat,
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// `width * height` texels, decoded exactly.
    pub texels: Vec<[f32; 4]>,
}

/// The bytes of a KTX2 file holding `texels` (`width * height` RGBA values,
/// row-major, row 0 at the top) in `format`, with `KTXwriter` =
/// `shlight VERSION`. See the module documentation for the layout and the
/// encodings.
///
/// # Errors
/// [`IoErrorKind::EmptyImage`] for a width or height of 0,
/// [`IoErrorKind::TexelCount`] when `texels` does not hold
/// `width * height` values, [`IoErrorKind::Unsupported`] for a size past
/// KTX2's 32-bit fields.
pub fn encode_ktx2(
    format: Ktx2TexelFormat,
    width: usize,
    height: usize,
    texels: &[[f32; 4]],
) -> Result<Vec<u8>, IoErrorKind> {
    if width == 0 || height == 0 {
        return Err(IoErrorKind::EmptyImage { width, height });
    }
    let count = width.checked_mul(height);
    if count != Some(texels.len()) {
        return Err(IoErrorKind::TexelCount {
            width,
            height,
            given: texels.len(),
        });
    }
    let level_bytes = texels.len() * format.texel_bytes();
    let (Ok(w), Ok(h)) = (u32::try_from(width), u32::try_from(height)) else {
        return Err(IoErrorKind::Unsupported(format!(
            "a {width}x{height} image is past KTX2's 32-bit sizes"
        )));
    };

    let dfd = data_format_descriptor(format);
    let kvd = key_value_data(&format!("shlight {}", env!("CARGO_PKG_VERSION")));
    let dfd_offset = HEADER_BYTES;
    let kvd_offset = dfd_offset + dfd.len();
    let level_offset = (kvd_offset + kvd.len()).next_multiple_of(8);

    let mut out = Vec::with_capacity(level_offset + level_bytes);
    out.extend(IDENTIFIER);
    for v in [format.vk_format(), format.type_size(), w, h, 0, 0, 1, 1, 0] {
        out.extend(v.to_le_bytes());
    }
    for v in [dfd_offset, dfd.len(), kvd_offset, kvd.len()] {
        out.extend((v as u32).to_le_bytes());
    }
    out.extend([0u8; 16]); // no supercompression global data
    for v in [level_offset, level_bytes, level_bytes] {
        out.extend((v as u64).to_le_bytes());
    }
    out.extend(&dfd);
    out.extend(&kvd);
    out.resize(level_offset, 0);
    match format {
        Ktx2TexelFormat::Rgba16Float => {
            for t in texels {
                for v in t {
                    out.extend(f32_to_f16_bits(*v).to_le_bytes());
                }
            }
        }
        Ktx2TexelFormat::B10G11R11Ufloat => {
            for t in texels {
                out.extend(pack_b10g11r11([t[0], t[1], t[2]]).to_le_bytes());
            }
        }
    }
    Ok(out)
}

/// Writes [`encode_ktx2`]'s file to `path`, atomically.
///
/// # Errors
/// [`encode_ktx2`]'s errors and a failed write ([`IoErrorKind::Write`]),
/// each naming `path`.
pub fn write_ktx2(
    path: &Path,
    format: Ktx2TexelFormat,
    width: usize,
    height: usize,
    texels: &[[f32; 4]],
) -> Result<(), IoError> {
    let bytes = encode_ktx2(format, width, height, texels).map_err(|e| IoError::new(path, e))?;
    write_atomically(path, |w| w.write_all(&bytes))
}

/// Reads a KTX2 file of the kind [`write_ktx2`] writes: one 2D image, one
/// level (or a level count of 0), no supercompression, in one of
/// [`Ktx2TexelFormat`]'s formats. Key/value data and the data format
/// descriptor are not read.
///
/// # Errors
/// [`IoErrorKind::NotFound`] or [`IoErrorKind::Unreadable`] when the file
/// cannot be read, and [`decode_ktx2`]'s errors, each naming `path`.
pub fn read_ktx2(path: &Path) -> Result<Ktx2Image, IoError> {
    let bytes =
        std::fs::read(path).map_err(|e| IoError::new(path, IoErrorKind::from_read_error(e)))?;
    decode_ktx2(&bytes).map_err(|e| IoError::new(path, e))
}

/// [`read_ktx2`] of bytes in memory.
///
/// # Errors
/// [`IoErrorKind::Empty`] for no bytes, [`IoErrorKind::UnknownFormat`]
/// without the KTX2 identifier, [`IoErrorKind::Truncated`] when the file
/// ends before its level, [`IoErrorKind::Unsupported`] for another format,
/// a 3D, array, cube or supercompressed texture or more than one level,
/// [`IoErrorKind::Corrupt`] for inconsistent sizes or offsets.
pub fn decode_ktx2(bytes: &[u8]) -> Result<Ktx2Image, IoErrorKind> {
    if bytes.is_empty() {
        return Err(IoErrorKind::Empty);
    }
    if !bytes.starts_with(&IDENTIFIER) {
        return Err(IoErrorKind::UnknownFormat);
    }
    if bytes.len() < HEADER_BYTES {
        return Err(IoErrorKind::Truncated);
    }
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let u64_at = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().expect("8 bytes"));
    let vk_format = u32_at(12);
    let format = Ktx2TexelFormat::from_vk_format(vk_format).ok_or_else(|| {
        IoErrorKind::Unsupported(format!(
            "KTX2 vkFormat {vk_format} (only {} and {} are read)",
            Ktx2TexelFormat::Rgba16Float.name(),
            Ktx2TexelFormat::B10G11R11Ufloat.name()
        ))
    })?;
    let (width, height) = (u32_at(20) as usize, u32_at(24) as usize);
    let (depth, layers, faces, levels, scheme) =
        (u32_at(28), u32_at(32), u32_at(36), u32_at(40), u32_at(44));
    if depth != 0 || layers != 0 || faces != 1 {
        return Err(IoErrorKind::Unsupported(format!(
            "a KTX2 texture of depth {depth}, {layers} layers and {faces} faces (only one 2D image is read)"
        )));
    }
    if levels > 1 {
        return Err(IoErrorKind::Unsupported(format!(
            "{levels} KTX2 mip levels (only one is read)"
        )));
    }
    if scheme != 0 {
        return Err(IoErrorKind::Unsupported(format!(
            "KTX2 supercompression scheme {scheme}"
        )));
    }
    if width == 0 || height == 0 {
        return Err(IoErrorKind::EmptyImage { width, height });
    }
    let (offset, length) = (u64_at(80), u64_at(88));
    // At most (2^32 - 1)^2 texels of 8 bytes: past u64, so checked.
    let expected = (width as u64)
        .checked_mul(height as u64)
        .and_then(|n| n.checked_mul(format.texel_bytes() as u64));
    if Some(length) != expected {
        let expected = expected.map_or_else(|| "more than 2^64".to_string(), |e| e.to_string());
        return Err(IoErrorKind::Corrupt(format!(
            "the level holds {length} bytes, a {width}x{height} image of {} takes {expected}",
            format.name()
        )));
    }
    let end = offset.checked_add(length).ok_or_else(|| {
        IoErrorKind::Corrupt(format!("the level's offset {offset} is out of range"))
    })?;
    if end > bytes.len() as u64 {
        return Err(IoErrorKind::Truncated);
    }
    let data = &bytes[offset as usize..end as usize];
    let texels = match format {
        Ktx2TexelFormat::Rgba16Float => data
            .chunks_exact(8)
            .map(|t| {
                std::array::from_fn(|c| {
                    f16_bits_to_f32(u16::from_le_bytes([t[2 * c], t[2 * c + 1]]))
                })
            })
            .collect(),
        Ktx2TexelFormat::B10G11R11Ufloat => data
            .chunks_exact(4)
            .map(|t| {
                let [r, g, b] = unpack_b10g11r11(u32::from_le_bytes([t[0], t[1], t[2], t[3]]));
                [r, g, b, 1.0]
            })
            .collect(),
    };
    Ok(Ktx2Image {
        format,
        width,
        height,
        texels,
    })
}

/// The data format descriptor: its total size, then one basic block (see
/// the module documentation).
fn data_format_descriptor(format: Ktx2TexelFormat) -> Vec<u8> {
    // (channel id, bit offset, bit length, qualifiers, lower, upper)
    const FLOAT: u8 = 0x80;
    const SIGNED: u8 = 0x40;
    let (minus_one, zero, one) = ((-1.0f32).to_bits(), 0.0f32.to_bits(), 1.0f32.to_bits());
    let samples: Vec<(u8, u16, u8, u8, u32, u32)> = match format {
        Ktx2TexelFormat::Rgba16Float => [0u8, 1, 2, 15]
            .iter()
            .enumerate()
            .map(|(k, &id)| (id, 16 * k as u16, 16, FLOAT | SIGNED, minus_one, one))
            .collect(),
        Ktx2TexelFormat::B10G11R11Ufloat => vec![
            (0, 0, 11, FLOAT, zero, one),
            (1, 11, 11, FLOAT, zero, one),
            (2, 22, 10, FLOAT, zero, one),
        ],
    };
    let block_size = 24 + 16 * samples.len();
    let mut dfd = Vec::with_capacity(4 + block_size);
    dfd.extend(((4 + block_size) as u32).to_le_bytes());
    dfd.extend(0u32.to_le_bytes()); // vendor 0 (Khronos), descriptor type 0 (basic)
    dfd.extend(2u16.to_le_bytes()); // version number 2 (Data Format 1.3)
    dfd.extend((block_size as u16).to_le_bytes());
    dfd.extend([1, 1, 1, 0]); // RGBSDA, BT.709, linear, straight alpha
    dfd.extend([0, 0, 0, 0]); // texel block 1x1x1x1
    dfd.extend([format.texel_bytes() as u8, 0, 0, 0, 0, 0, 0, 0]); // bytesPlane0..7
    for (id, bit_offset, bits, qualifiers, lower, upper) in samples {
        dfd.extend(bit_offset.to_le_bytes());
        dfd.push(bits - 1);
        dfd.push(id | qualifiers);
        dfd.extend([0, 0, 0, 0]); // sample position
        dfd.extend(lower.to_le_bytes());
        dfd.extend(upper.to_le_bytes());
    }
    dfd
}

/// One key/value pair, `KTXwriter` = `writer` (NUL-terminated), padded to
/// 4 bytes.
fn key_value_data(writer: &str) -> Vec<u8> {
    let entry = [b"KTXwriter\0".as_slice(), writer.as_bytes(), b"\0"].concat();
    let mut kvd = Vec::with_capacity(4 + entry.len() + 3);
    kvd.extend((entry.len() as u32).to_le_bytes());
    kvd.extend(&entry);
    kvd.resize(kvd.len().next_multiple_of(4), 0);
    kvd
}

/// `x` as an IEEE binary16 bit pattern, rounded to nearest, ties to even
/// (overflow to infinity; NaN to `0x7E00` with `x`'s sign).
#[must_use]
pub fn f32_to_f16_bits(x: f32) -> u16 {
    let sign = ((x.to_bits() >> 16) & 0x8000) as u16;
    if x.is_nan() {
        return sign | 0x7E00;
    }
    sign | small_float(x.abs(), 10) as u16
}

/// An IEEE binary16 bit pattern's value, exactly.
#[must_use]
pub fn f16_bits_to_f32(bits: u16) -> f32 {
    let magnitude = small_float_value(u32::from(bits & 0x7FFF), 10);
    if bits & 0x8000 != 0 {
        -magnitude
    } else {
        magnitude
    }
}

/// `rgb` packed as `VK_FORMAT_B10G11R11_UFLOAT_PACK32`: R in bits 0-10, G
/// in 11-21, B in 22-31 (see the module documentation for the rounding).
#[must_use]
pub fn pack_b10g11r11(rgb: [f32; 3]) -> u32 {
    unsigned_small_float(rgb[0], 6)
        | (unsigned_small_float(rgb[1], 6) << 11)
        | (unsigned_small_float(rgb[2], 5) << 22)
}

/// The RGB values of a `VK_FORMAT_B10G11R11_UFLOAT_PACK32` word, exactly.
#[must_use]
pub fn unpack_b10g11r11(word: u32) -> [f32; 3] {
    [
        small_float_value(word & 0x7FF, 6),
        small_float_value((word >> 11) & 0x7FF, 6),
        small_float_value(word >> 22, 5),
    ]
}

/// `x` as an unsigned float of a 5-bit exponent and `mantissa` bits: 0 for
/// negative values and -infinity, the largest finite value for finite
/// values past it, the quiet NaN for NaN.
fn unsigned_small_float(x: f32, mantissa: u32) -> u32 {
    let infinity = 0x1F << mantissa;
    if x.is_nan() {
        return infinity | (1 << (mantissa - 1));
    }
    if x <= 0.0 {
        return 0;
    }
    let bits = small_float(x, mantissa);
    if bits == infinity && x.is_finite() {
        infinity - 1
    } else {
        bits
    }
}

/// The non-negative, non-NaN `x` as a float of a 5-bit exponent (bias 15)
/// and `mantissa` bits, without sign: rounded to nearest, ties to even;
/// past the largest finite value, infinity.
fn small_float(x: f32, mantissa: u32) -> u32 {
    let infinity = 0x1F << mantissa;
    let bits = x.to_bits();
    let exponent = (bits >> 23) as i32 - 127;
    if exponent > 15 {
        return infinity;
    }
    let fraction = bits & 0x7F_FFFF;
    // The value as an integer count of units of its last place in the
    // small format, before rounding: `kept`, with `dropped` bits below.
    let (kept, dropped, shift) = if exponent >= -14 {
        let shift = 23 - mantissa;
        let biased = (exponent + 15) as u32;
        ((biased << mantissa) | (fraction >> shift), fraction, shift)
    } else {
        if bits >> 23 == 0 {
            return 0; // an f32 subnormal is far below the smallest subnormal
        }
        let significand = fraction | 0x80_0000;
        let shift = (9 - mantissa as i32 - exponent) as u32; // LSB 2^(-14-m)
        if shift >= 32 {
            return 0;
        }
        (significand >> shift, significand, shift)
    };
    let rest = dropped & ((1 << shift) - 1);
    let half = 1 << (shift - 1);
    let rounded = if rest > half || (rest == half && kept & 1 == 1) {
        kept + 1
    } else {
        kept
    };
    rounded.min(infinity)
}

/// The value of an unsigned float of a 5-bit exponent (bias 15) and
/// `mantissa` bits (infinity and NaN included).
fn small_float_value(bits: u32, mantissa: u32) -> f32 {
    let exponent = (bits >> mantissa) as i32;
    let fraction = bits & ((1 << mantissa) - 1);
    let unit = (1u32 << mantissa) as f32;
    match exponent {
        0 => fraction as f32 / unit * 2f32.powi(-14),
        31 if fraction == 0 => f32::INFINITY,
        31 => f32::NAN,
        _ => (1.0 + fraction as f32 / unit) * 2f32.powi(exponent - 15),
    }
}
