//! Writing an [`Image`] as an OpenEXR file.

use std::io::{Seek, Write};

use exr::prelude::{Blocks, Encoding, LayerAttributes, LineOrder, SpecificChannels, WritableImage};

use crate::{ExrCompression, Image, IoErrorKind};

/// Encodes `image` as a scan-line OpenEXR file with 32-bit float R, G, B
/// channels, every value multiplied by `scale`.
pub(crate) fn encode<W: Write + Seek>(
    image: &Image,
    scale: f32,
    compression: ExrCompression,
    write: W,
) -> Result<(), IoErrorKind> {
    let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
        let [r, g, b] = image.get(p.x(), p.y());
        (r * scale, g * scale, b * scale)
    });
    let encoding = Encoding {
        compression: match compression {
            ExrCompression::None => exr::compression::Compression::Uncompressed,
            ExrCompression::Zip => exr::compression::Compression::ZIP16,
        },
        blocks: Blocks::ScanLines,
        line_order: LineOrder::Increasing,
    };
    let layer = exr::image::Layer::new(
        (image.width(), image.height()),
        LayerAttributes::default(),
        encoding,
        channels,
    );
    exr::image::Image::from_layer(layer)
        .write()
        .to_buffered(write)
        .map_err(|e| match e {
            exr::error::Error::Io(e) => IoErrorKind::Write(e),
            other => IoErrorKind::Write(std::io::Error::other(other.to_string())),
        })
}
