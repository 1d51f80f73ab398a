//! Writing an image file, in the format its extension names.

use std::path::Path;

use crate::atomic::write_file_atomically;
use crate::{ExrCompression, Format, Image, IoError, IoErrorKind, ToneMap, image_codecs, openexr};

/// How [`write_image`] writes a file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WriteOptions {
    /// Exposure in stops: every value is multiplied by `2^exposure_ev`
    /// before anything else. Default 0 (no change), for every format.
    pub exposure_ev: f32,
    /// The curve that brings HDR values into `[0, 1]` for PNG; ignored by
    /// OpenEXR and Radiance, which store linear values. Default
    /// [`ToneMap::Clamp`].
    pub tone_map: ToneMap,
    /// The compression of OpenEXR files. Default [`ExrCompression::Zip`].
    pub exr_compression: ExrCompression,
}

impl Default for WriteOptions {
    fn default() -> Self {
        Self {
            exposure_ev: 0.0,
            tone_map: ToneMap::Clamp,
            exr_compression: ExrCompression::Zip,
        }
    }
}

/// Writes `image` to `path`, in the format its extension names
/// (case-insensitive):
///
/// - `.exr`: OpenEXR, 32-bit float R, G, B channels, scan lines, ZIP or no
///   compression; values exact (times `2^exposure_ev`).
/// - `.hdr` (or `.pic`): Radiance RGBE, run-length encoded; about 1% relative
///   precision on each pixel's largest channel, no negative or non-finite
///   values (they become 0).
/// - `.png`: 8-bit sRGB RGB, after exposure and [`WriteOptions::tone_map`];
///   NaN becomes 0.
///
/// The file is written atomically (see [`crate::write_atomically`]): on any
/// error an existing file at `path` is unchanged.
///
/// # Errors
/// [`IoErrorKind::Unsupported`] for another extension (JPEG is read-only),
/// [`IoErrorKind::EmptyImage`] for an image without pixels, and
/// [`IoErrorKind::Write`] when writing fails.
pub fn write_image(path: &Path, image: &Image, options: &WriteOptions) -> Result<(), IoError> {
    let error = |kind| IoError::new(path, kind);
    let format = match Format::from_extension(path) {
        Some(format) if format.can_write() => format,
        _ => {
            let extension = path
                .extension()
                .map(|e| format!(".{}", e.to_string_lossy()))
                .unwrap_or_else(|| "no extension".to_owned());
            return Err(error(IoErrorKind::Unsupported(format!(
                "cannot write {extension} files (use .exr, .hdr or .png)"
            ))));
        }
    };
    if image.is_empty() {
        return Err(error(IoErrorKind::EmptyImage {
            width: image.width(),
            height: image.height(),
        }));
    }
    let scale = options.exposure_ev.exp2();
    write_file_atomically(path, |w| match format {
        Format::Exr => openexr::encode(image, scale, options.exr_compression, w),
        Format::Radiance => image_codecs::encode_radiance(image, scale, w),
        Format::Png => image_codecs::encode_png(image, scale, options.tone_map, w),
        Format::Jpeg => unreachable!("checked by can_write"),
    })
}
