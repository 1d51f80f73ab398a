//! Radiance HDR, PNG and JPEG, through the `image` crate.
//!
//! Radiance files hold linear RGBE values and are read as they are. PNG
//! (8 or 16 bit; grey, grey + alpha, RGB, RGBA or palette) and JPEG hold
//! sRGB-encoded values, decoded with the exact sRGB EOTF; alpha is dropped,
//! not multiplied in, and grey becomes equal R, G, B. Colour profiles,
//! `gAMA` chunks and Radiance `EXPOSURE` lines are ignored.

use std::io::{Cursor, Write};

use image::codecs::hdr::{HdrDecoder, HdrEncoder};
use image::codecs::jpeg::JpegDecoder;
use image::codecs::png::{CompressionType, FilterType, PngDecoder, PngEncoder};
use image::{
    DynamicImage, ExtendedColorType, ImageDecoder, ImageEncoder, ImageError, ImageResult, Limits,
    Rgb,
};

use crate::srgb::{linear_to_srgb8, srgb8_table, srgb16_table};
use crate::{Format, Image, IoErrorKind, ReadOptions, ToneMap};

/// Decodes a Radiance, PNG or JPEG file held in `bytes`.
pub(crate) fn decode(
    bytes: &[u8],
    format: Format,
    options: &ReadOptions,
) -> Result<Image, IoErrorKind> {
    let result = decode_inner(bytes, format, options);
    match result {
        // A JPEG decoder may fill in missing data without complaint.
        Ok(_) if format == Format::Jpeg && !jpeg_is_complete(bytes) => Err(IoErrorKind::Truncated),
        Err(IoErrorKind::Corrupt(_)) if ends_early(bytes, format) => Err(IoErrorKind::Truncated),
        other => other,
    }
}

fn decode_inner(bytes: &[u8], format: Format, options: &ReadOptions) -> Result<Image, IoErrorKind> {
    let input = Cursor::new(bytes);
    match format {
        // Not strict: old files have no `#?RADIANCE` line, or `#?RGBE`.
        Format::Radiance => decode_with(HdrDecoder::with_strictness(input, false), options),
        Format::Png => decode_with(PngDecoder::new(input), options),
        Format::Jpeg => decode_with(JpegDecoder::new(input), options),
        Format::Exr => unreachable!("OpenEXR is read by the exr crate"),
    }
}

/// Checks the size the decoder read from the header, then decodes and
/// converts to linear RGB.
fn decode_with(
    decoder: ImageResult<impl ImageDecoder>,
    options: &ReadOptions,
) -> Result<Image, IoErrorKind> {
    let mut decoder = decoder.map_err(map_error)?;
    let (width, height) = decoder.dimensions();
    let (width, height) = (width as usize, height as usize);
    match width.checked_mul(height) {
        Some(0) => return Err(IoErrorKind::EmptyImage { width, height }),
        Some(n) if n <= options.max_pixels => {}
        _ => {
            return Err(IoErrorKind::TooLarge {
                width,
                height,
                max_pixels: options.max_pixels,
            });
        }
    }
    // The pixel count is checked; this only bounds what the decoder may
    // allocate besides (at most 32 bytes a pixel in all).
    let mut limits = Limits::no_limits();
    limits.max_alloc = Some((width as u64 * height as u64).saturating_mul(32));
    decoder.set_limits(limits).map_err(map_error)?;

    let decoded = DynamicImage::from_decoder(decoder).map_err(map_error)?;
    let colour = decoded.color();
    let bits = 8 * colour.bytes_per_pixel() / colour.channel_count();
    let pixels: Vec<[f32; 3]> = match bits {
        8 => {
            let table = srgb8_table();
            let rgb = decoded.into_rgb8();
            rgb.pixels()
                .map(|p| p.0.map(|c| table[usize::from(c)]))
                .collect()
        }
        16 => {
            let table = srgb16_table();
            let rgb = decoded.into_rgb16();
            rgb.pixels()
                .map(|p| p.0.map(|c| table[usize::from(c)]))
                .collect()
        }
        // Radiance: already linear.
        _ => decoded.into_rgb32f().pixels().map(|p| p.0).collect(),
    };
    Ok(Image::new(width, height, pixels).expect("decoder size"))
}

fn map_error(error: ImageError) -> IoErrorKind {
    match error {
        ImageError::IoError(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            IoErrorKind::Truncated
        }
        ImageError::Unsupported(e) => IoErrorKind::Unsupported(e.to_string()),
        other => IoErrorKind::Corrupt(other.to_string()),
    }
}

/// Whether a file that failed to decode ends before its format's closing
/// structure: the PNG chunk list runs past the end before `IEND`, the JPEG
/// has no end-of-image marker, or the Radiance header is incomplete.
fn ends_early(bytes: &[u8], format: Format) -> bool {
    match format {
        Format::Png => !png_is_complete(bytes),
        Format::Jpeg => !jpeg_is_complete(bytes),
        Format::Radiance => !radiance_header_is_complete(bytes),
        Format::Exr => false,
    }
}

/// Walks the PNG chunks: complete if `IEND` is reached inside the file.
fn png_is_complete(bytes: &[u8]) -> bool {
    let mut at = 8;
    while let Some(head) = bytes.get(at..at + 8) {
        let length = u32::from_be_bytes(head[..4].try_into().expect("4 bytes")) as usize;
        if &head[4..] == b"IEND" {
            return true;
        }
        // Length, type, data, CRC.
        at = match at.checked_add(12).and_then(|a| a.checked_add(length)) {
            Some(next) => next,
            None => return false,
        };
    }
    false
}

/// Whether an end-of-image marker (`ff d9`) follows the first start-of-scan
/// marker (`ff da`). Entropy-coded data cannot contain `ff d9` (a data `ff`
/// is followed by `00`), so this finds the real end.
fn jpeg_is_complete(bytes: &[u8]) -> bool {
    let find = |from: usize, marker: u8| {
        bytes
            .get(from..)?
            .windows(2)
            .position(|w| w == [0xff, marker])
            .map(|i| from + i)
    };
    find(0, 0xda).is_some_and(|sos| find(sos + 2, 0xd9).is_some())
}

/// Whether the Radiance header (lines up to an empty line) and the
/// resolution line after it are complete.
fn radiance_header_is_complete(bytes: &[u8]) -> bool {
    bytes
        .windows(2)
        .position(|w| w == b"\n\n")
        .is_some_and(|end| bytes[end + 2..].contains(&b'\n'))
}

/// Encodes `image` as a Radiance RGBE file, every value multiplied by
/// `scale`. RGBE holds no negative or non-finite values: NaN, negatives and
/// values below `f32::MIN_POSITIVE` become 0, and values are capped at
/// 1e38.
pub(crate) fn encode_radiance<W: Write>(
    image: &Image,
    scale: f32,
    write: W,
) -> Result<(), IoErrorKind> {
    let representable = |v: f32| {
        let v = v * scale;
        if v >= f32::MIN_POSITIVE {
            v.min(1e38)
        } else {
            0.0
        }
    };
    let pixels: Vec<Rgb<f32>> = image
        .pixels()
        .iter()
        .map(|p| Rgb(p.map(representable)))
        .collect();
    HdrEncoder::new(write)
        .encode(&pixels, image.width(), image.height())
        .map_err(encode_error)
}

/// Encodes `image` as an 8-bit sRGB PNG: each value is multiplied by
/// `scale`, tone mapped, then sRGB encoded and rounded.
pub(crate) fn encode_png<W: Write>(
    image: &Image,
    scale: f32,
    tone_map: ToneMap,
    write: W,
) -> Result<(), IoErrorKind> {
    let (Ok(width), Ok(height)) = (u32::try_from(image.width()), u32::try_from(image.height()))
    else {
        return Err(IoErrorKind::Unsupported(format!(
            "a {}x{} PNG (sides are at most {} pixels)",
            image.width(),
            image.height(),
            u32::MAX
        )));
    };
    let bytes: Vec<u8> = image
        .pixels()
        .iter()
        .flatten()
        .map(|&v| linear_to_srgb8(tone_map.apply(v * scale)))
        .collect();
    PngEncoder::new_with_quality(write, CompressionType::Default, FilterType::Adaptive)
        .write_image(&bytes, width, height, ExtendedColorType::Rgb8)
        .map_err(encode_error)
}

fn encode_error(error: ImageError) -> IoErrorKind {
    match error {
        ImageError::IoError(e) => IoErrorKind::Write(e),
        other => IoErrorKind::Write(std::io::Error::other(other.to_string())),
    }
}

/// An 8-bit RGBA PNG of `width x height` texels (`rgba`, 4 bytes a texel,
/// row-major from the top-left, written as they are: no sRGB or tone
/// curve), in memory. `name` names the image in errors.
///
/// # Errors
/// [`IoErrorKind::Unsupported`] when `rgba` is not `4 width height` bytes
/// or a side exceeds `u32`; [`IoErrorKind::Write`] when encoding fails.
pub fn encode_png_rgba8(
    name: &str,
    width: usize,
    height: usize,
    rgba: &[u8],
) -> Result<Vec<u8>, crate::IoError> {
    let error = |kind| crate::IoError::new(name, kind);
    let (Ok(w), Ok(h)) = (u32::try_from(width), u32::try_from(height)) else {
        return Err(error(IoErrorKind::Unsupported(format!(
            "a {width}x{height} PNG"
        ))));
    };
    if rgba.len() != 4 * width * height {
        return Err(error(IoErrorKind::Unsupported(format!(
            "{} bytes for a {width}x{height} RGBA image",
            rgba.len()
        ))));
    }
    let mut bytes = Vec::new();
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Default, FilterType::Adaptive)
        .write_image(rgba, w, h, ExtendedColorType::Rgba8)
        .map_err(|e| error(encode_error(e)))?;
    Ok(bytes)
}
