//! Reading an image file of any supported format.

use std::panic::{self, AssertUnwindSafe};
use std::path::Path;

use crate::panic_message::panic_message;
use crate::{Format, Image, IoError, IoErrorKind, ReadOptions, image_codecs, openexr};

/// Reads the image file at `path` as linear RGB.
///
/// The format is recognised by the file's first bytes (see
/// [`Format::from_magic`]); the extension is the fallback, which matters
/// only for old Radiance files without a signature (a `.exr`, `.png` or
/// `.jpg` file without its signature is reported as corrupt). OpenEXR and Radiance values are taken as they are; PNG and JPEG
/// values are sRGB-decoded to linear. Alpha is dropped. Values are not
/// checked: see [`Image::stats`] and [`Image::sanitize`].
///
/// A decoder that panics on a malformed file is caught and reported as
/// [`IoErrorKind::Corrupt`].
///
/// # Errors
/// An [`IoError`] naming `path`: [`IoErrorKind::NotFound`],
/// [`IoErrorKind::Unreadable`], [`IoErrorKind::Empty`] (0 bytes),
/// [`IoErrorKind::UnknownFormat`], [`IoErrorKind::Truncated`],
/// [`IoErrorKind::Corrupt`], [`IoErrorKind::EmptyImage`],
/// [`IoErrorKind::TooLarge`], [`IoErrorKind::LayerNotFound`] or
/// [`IoErrorKind::Unsupported`] (for example an OpenEXR layer without colour
/// channels).
pub fn read_image(path: &Path, options: &ReadOptions) -> Result<Image, IoError> {
    let error = |e| IoError::new(path, IoErrorKind::from_read_error(e));
    let file = std::fs::File::open(path).map_err(error)?;
    let metadata = file.metadata().map_err(error)?;
    if metadata.is_file() && metadata.len() >= MAP_FROM {
        // SAFETY: the mapping is private and read-only and lives only for
        // this call. The one hazard is another process truncating the file
        // while it is decoded (SIGBUS on the lost pages), as for every
        // reader that maps its input.
        if let Ok(map) = unsafe { memmap2::MmapOptions::new().populate().map(&file) } {
            return read_image_bytes(&map, path, options);
        }
    }
    let mut bytes = Vec::with_capacity(usize::try_from(metadata.len()).unwrap_or(0));
    std::io::Read::read_to_end(&mut &file, &mut bytes).map_err(error)?;
    read_image_bytes(&bytes, path, options)
}

/// Files this large or larger are mapped into memory, not copied: the
/// kernel maps the page cache's pages in one call (`MAP_POPULATE`) instead
/// of copying every byte into freshly zeroed memory, about 1 ms instead of
/// 2 to 30 for a 16 MB OpenEXR file (docs/benchmarks.md).
const MAP_FROM: u64 = 1 << 20;

/// Reads an image file held in memory as linear RGB, exactly as
/// [`read_image`] reads a file with these bytes at `name`.
///
/// `name` only names the file in errors and gives the extension that
/// [`read_image`] falls back on (for old Radiance files without a
/// signature); nothing is read from disk. Useful for files that come from
/// a network, an archive or an embedded asset, and for fuzzing.
///
/// # Errors
/// As [`read_image`], less [`IoErrorKind::NotFound`] and
/// [`IoErrorKind::Unreadable`].
///
/// # Example
/// ```
/// use std::path::Path;
/// use shlight_io::{IoErrorKind, ReadOptions, read_image_bytes};
///
/// // A 2x1 Radiance file: header, resolution line, two flat RGBE pixels.
/// let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n".to_vec();
/// bytes.extend_from_slice(&[128, 64, 32, 129, 0, 0, 0, 0]);
/// let image = read_image_bytes(&bytes, Path::new("tiny.hdr"), &ReadOptions::default())?;
/// assert_eq!((image.width(), image.height()), (2, 1));
/// assert_eq!(image.get(0, 0), [1.0, 0.5, 0.25]);
///
/// let e = read_image_bytes(b"not an image", Path::new("x.png"), &ReadOptions::default())
///     .unwrap_err();
/// assert!(matches!(e.kind(), IoErrorKind::Corrupt(_)));
/// assert!(e.to_string().starts_with("x.png: "));
/// # Ok::<(), shlight_io::IoError>(())
/// ```
pub fn read_image_bytes(
    bytes: &[u8],
    name: &Path,
    options: &ReadOptions,
) -> Result<Image, IoError> {
    let path = name;
    let error = |kind| IoError::new(path, kind);
    if bytes.is_empty() {
        return Err(error(IoErrorKind::Empty));
    }
    let format = match (Format::from_magic(bytes), Format::from_extension(path)) {
        (Some(format), _) => format,
        // Old Radiance files may lack the signature; the others never do.
        (None, Some(Format::Radiance)) => Format::Radiance,
        (None, Some(format)) => {
            return Err(error(IoErrorKind::Corrupt(format!(
                "the file does not start with the {format} signature"
            ))));
        }
        (None, None) => return Err(error(IoErrorKind::UnknownFormat)),
    };
    decode(bytes, format, options).map_err(error)
}

/// Decodes `bytes` as `format`, turning a decoder panic into an error.
fn decode(bytes: &[u8], format: Format, options: &ReadOptions) -> Result<Image, IoErrorKind> {
    let decode = || match format {
        Format::Exr => openexr::decode(bytes, options),
        Format::Radiance | Format::Png | Format::Jpeg => {
            image_codecs::decode(bytes, format, options)
        }
    };
    panic::catch_unwind(AssertUnwindSafe(decode)).unwrap_or_else(|payload| {
        Err(IoErrorKind::Corrupt(format!(
            "the {format} decoder failed: {}",
            panic_message(payload.as_ref())
        )))
    })
}
