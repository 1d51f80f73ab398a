//! [`ImageInfo`]: what an image file's header says (its format, size and
//! channels), read without decoding a pixel.

use std::io::Cursor;
use std::panic::{self, AssertUnwindSafe};
use std::path::Path;

use crate::panic_message::panic_message;
use crate::{Format, IoError, IoErrorKind};

/// An image file's header: the format, the size, and the channels as the
/// file stores them (before [`crate::read_image`] turns them into linear
/// RGB).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImageInfo {
    /// The file's format, from its signature.
    pub format: Format,
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// The channels stored, in the file's order: OpenEXR's names as
    /// written (`R`, `G`, `B`, `A`, or a layer's `diffuse.R`), `R`, `G`,
    /// `B`, `A` or `grey` (with `A`) for PNG and JPEG, `palette index` for
    /// an indexed PNG; `R`, `G`, `B` for Radiance.
    pub channels: Vec<String>,
    /// How each value is stored: `8-bit`, `16-bit` (PNG: the sample depth),
    /// `half float`, `32-bit float` or `32-bit unsigned integer` (OpenEXR;
    /// `mixed` when the channels differ), `RGBE` (Radiance: 8-bit
    /// mantissas and a shared exponent).
    pub sample: String,
}

/// The header of the image file held in `bytes`; `name` names it in errors.
///
/// # Errors
/// An [`IoError`] naming `name`: [`IoErrorKind::Empty`],
/// [`IoErrorKind::UnknownFormat`] for bytes without an image signature,
/// [`IoErrorKind::Corrupt`] for a header the format's decoder refuses.
pub fn image_info(bytes: &[u8], name: &Path) -> Result<ImageInfo, IoError> {
    let error = |kind| IoError::new(name, kind);
    if bytes.is_empty() {
        return Err(error(IoErrorKind::Empty));
    }
    let format = Format::from_magic(bytes).ok_or_else(|| error(IoErrorKind::UnknownFormat))?;
    // A decoder that panics on a malformed header is caught, as in
    // `read_image`.
    panic::catch_unwind(AssertUnwindSafe(|| header(bytes, format)))
        .unwrap_or_else(|payload| {
            Err(IoErrorKind::Corrupt(format!(
                "the {format} decoder failed: {}",
                panic_message(payload.as_ref())
            )))
        })
        .map_err(error)
}

/// [`image_info`] of bytes whose signature is `format`'s.
fn header(bytes: &[u8], format: Format) -> Result<ImageInfo, IoErrorKind> {
    let corrupt =
        |e: &dyn std::fmt::Display| IoErrorKind::Corrupt(format!("the {format} header: {e}"));
    let rgb = |names: &[&str]| names.iter().map(|s| (*s).to_string()).collect();
    let (width, height, channels, sample) = match format {
        Format::Exr => {
            let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
                .map_err(|e| corrupt(&e))?;
            let header = meta.headers.first().ok_or_else(|| corrupt(&"no header"))?;
            let list: Vec<&exr::meta::attribute::ChannelDescription> = meta
                .headers
                .iter()
                .flat_map(|h| h.channels.list.iter())
                .collect();
            let kind = |c: &exr::meta::attribute::ChannelDescription| match c.sample_type {
                exr::meta::attribute::SampleType::F16 => "half float",
                exr::meta::attribute::SampleType::F32 => "32-bit float",
                exr::meta::attribute::SampleType::U32 => "32-bit unsigned integer",
            };
            let sample = match list.first() {
                Some(first) if list.iter().all(|c| kind(c) == kind(first)) => kind(first),
                Some(_) => "mixed",
                None => "no channels",
            };
            (
                header.layer_size.x(),
                header.layer_size.y(),
                list.iter().map(|c| c.name.to_string()).collect(),
                sample.to_string(),
            )
        }
        Format::Png => {
            let reader = png::Decoder::new(Cursor::new(bytes))
                .read_info()
                .map_err(|e| corrupt(&e))?;
            let info = reader.info();
            let channels = match info.color_type {
                png::ColorType::Grayscale => rgb(&["grey"]),
                png::ColorType::GrayscaleAlpha => rgb(&["grey", "A"]),
                png::ColorType::Rgb => rgb(&["R", "G", "B"]),
                png::ColorType::Rgba => rgb(&["R", "G", "B", "A"]),
                png::ColorType::Indexed => rgb(&["palette index"]),
            };
            (
                info.width as usize,
                info.height as usize,
                channels,
                format!("{}-bit", info.bit_depth as u8),
            )
        }
        Format::Radiance => {
            let decoder =
                image::codecs::hdr::HdrDecoder::with_strictness(Cursor::new(bytes), false)
                    .map_err(|e| corrupt(&e))?;
            let m = decoder.metadata();
            (
                m.width as usize,
                m.height as usize,
                rgb(&["R", "G", "B"]),
                "RGBE".to_string(),
            )
        }
        Format::Jpeg => {
            use image::ImageDecoder as _;
            let decoder = image::codecs::jpeg::JpegDecoder::new(Cursor::new(bytes))
                .map_err(|e| corrupt(&e))?;
            let (w, h) = decoder.dimensions();
            let channels = match decoder.color_type().channel_count() {
                1 => rgb(&["grey"]),
                _ => rgb(&["R", "G", "B"]),
            };
            (w as usize, h as usize, channels, "8-bit".to_string())
        }
    };
    Ok(ImageInfo {
        format,
        width,
        height,
        channels,
        sample,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Image, WriteOptions, write_image};

    /// Each format shlight writes, written by its writer and read back by
    /// the header alone: the size written and the channels stored.
    #[test]
    fn the_header_gives_the_size_and_channels_written() {
        let dir = std::env::temp_dir().join(format!("shlight-image-info-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let image = Image::from_fn(7, 3, |x, y| [x as f32, y as f32, 0.5]);
        for (file, format, channels, sample) in [
            ("a.exr", Format::Exr, vec!["B", "G", "R"], "32-bit float"), // stored sorted
            ("a.png", Format::Png, vec!["R", "G", "B"], "8-bit"),
            ("a.hdr", Format::Radiance, vec!["R", "G", "B"], "RGBE"),
        ] {
            let path = dir.join(file);
            write_image(&path, &image, &WriteOptions::default()).unwrap();
            let info = image_info(&std::fs::read(&path).unwrap(), &path).unwrap();
            assert_eq!(
                (info.format, info.width, info.height),
                (format, 7, 3),
                "{file}"
            );
            assert_eq!(info.channels, channels, "{file}");
            assert_eq!(info.sample, sample, "{file}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
        let e = image_info(b"not an image", Path::new("x.bin")).unwrap_err();
        assert!(matches!(e.kind(), IoErrorKind::UnknownFormat), "{e}");
        let e = image_info(b"\x89PNG\r\n\x1a\n\0", Path::new("x.png")).unwrap_err();
        assert!(e.to_string().starts_with("x.png: "), "{e}");
    }
}
