//! The compression of written OpenEXR files, an option of
//! [`crate::write_image`] that the OpenEXR encoder reads.

/// The compression of written OpenEXR files; both are lossless.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ExrCompression {
    /// No compression.
    None,
    /// zlib over blocks of 16 scan lines (OpenEXR `ZIP_COMPRESSION`).
    #[default]
    Zip,
}
