//! The options of reading an image file, shared by [`crate::read_image`]
//! and the decoders it calls.

/// How [`crate::read_image`] reads a file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ReadOptions {
    /// The OpenEXR layer to read, by name (`""` is the unnamed layer; see
    /// the crate docs for how layers are named). `None` takes the first
    /// layer with R, G, B channels, else the first with a lone Y channel.
    /// Ignored for other formats.
    pub layer: Option<String>,
    /// The largest pixel count (width x height) accepted. Larger images are
    /// refused with [`crate::IoErrorKind::TooLarge`], judged from the file's header
    /// before any pixel memory is allocated. Default: 2^29 (e.g. 32768 x
    /// 16384, the largest equirect maps HDRI libraries publish).
    ///
    /// This also bounds a read's memory: at most about 64 bytes a pixel of
    /// this limit plus a few times the file's size (docs/limits.md), so a
    /// program reading untrusted files should lower it to what it needs.
    pub max_pixels: usize,
}

impl ReadOptions {
    /// The default [`ReadOptions::max_pixels`], 2^29.
    pub const DEFAULT_MAX_PIXELS: usize = 1 << 29;
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            layer: None,
            max_pixels: Self::DEFAULT_MAX_PIXELS,
        }
    }
}
