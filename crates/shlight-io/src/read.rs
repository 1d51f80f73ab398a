//! Reading an image file of any supported format.

use std::panic::{self, AssertUnwindSafe};
use std::path::Path;

use crate::{Format, Image, IoError, IoErrorKind, image_codecs, openexr};

/// How [`read_image`] reads a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadOptions {
    /// The OpenEXR layer to read, by name (`""` is the unnamed layer; see
    /// the crate docs for how layers are named). `None` takes the first
    /// layer with R, G, B channels, else the first with a lone Y channel.
    /// Ignored for other formats.
    pub layer: Option<String>,
    /// The largest pixel count (width x height) accepted. Larger images are
    /// refused with [`IoErrorKind::TooLarge`], judged from the file's header
    /// before any pixel memory is allocated. Default: 2^28 (e.g. 16384 x
    /// 16384).
    pub max_pixels: usize,
}

impl ReadOptions {
    /// The default [`ReadOptions::max_pixels`], 2^28.
    pub const DEFAULT_MAX_PIXELS: usize = 1 << 28;
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            layer: None,
            max_pixels: Self::DEFAULT_MAX_PIXELS,
        }
    }
}

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
    let error = |kind| IoError::new(path, kind);
    let bytes = std::fs::read(path).map_err(|e| error(IoErrorKind::from_read_error(e)))?;
    if bytes.is_empty() {
        return Err(error(IoErrorKind::Empty));
    }
    let format = match (Format::from_magic(&bytes), Format::from_extension(path)) {
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
    decode(&bytes, format, options).map_err(error)
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

/// The message of a caught panic.
pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown cause".to_owned())
}
