//! Pictures: images (renders, previews, prefiltered faces, DFG tables,
//! maps) by their headers, and SVG plots. Their pixels are for an image
//! viewer; the table says what the header says.

use std::path::Path;

use super::Header;
use crate::{FormatError, Result};

/// What the table says to do with a picture.
const VIEWER: &str = "an image: its pixels are for an image viewer (shlight project reads \
     maps, shlight irradiance and compare measure them)";

/// An OpenEXR, Radiance, PNG or JPEG file; `None` for bytes without an
/// image signature.
pub(super) fn describe_image(bytes: &[u8], name: &str) -> Result<Option<Header>> {
    if shlight_io::Format::from_magic(bytes).is_none() {
        return Ok(None);
    }
    let info = shlight_io::image_info(bytes, Path::new(name))
        .map_err(|e| FormatError::invalid(name, format!("an image, but {}", e.kind())))?;
    let mut h = Header::new(format!("{} image", info.format));
    h.field("size", format!("{} x {}", info.width, info.height));
    h.field(
        "channels",
        format!("{} ({})", info.channels.join(", "), info.sample),
    );
    h.field("note", VIEWER);
    Ok(Some(h))
}

/// An SVG picture (`shlight compare`'s and `accuracy`'s plots); `None`
/// for other text.
pub(super) fn describe_svg(text: &str) -> Option<Header> {
    let start = text.trim_start();
    if !(start.starts_with("<svg") || start.starts_with("<?xml") && text.contains("<svg")) {
        return None;
    }
    let root = &text[text.find("<svg")?..];
    let root = &root[..root.find('>').unwrap_or(root.len())];
    let attribute = |key: &str| {
        let at = root.find(&format!(" {key}=\""))? + key.len() + 3;
        let rest = &root[at..];
        Some(rest[..rest.find('"')?].to_string())
    };
    let mut h = Header::new("SVG picture (shlight compare's and accuracy's plots)");
    if let (Some(w), Some(hh)) = (attribute("width"), attribute("height")) {
        h.field("size", format!("{w} x {hh}"));
    }
    h.field("note", "a picture: open it in a browser or an image viewer");
    Some(h)
}
