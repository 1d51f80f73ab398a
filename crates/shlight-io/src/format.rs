//! The file formats this crate knows, and how a file's format is recognised.

use std::fmt;
use std::path::Path;

/// An image file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Format {
    /// OpenEXR (`.exr`): read and written.
    Exr,
    /// Radiance RGBE (`.hdr`, `.pic`): read and written.
    Radiance,
    /// PNG (`.png`): read (8 and 16 bit) and written (8 bit).
    Png,
    /// JPEG (`.jpg`, `.jpeg`): read only.
    Jpeg,
}

impl Format {
    /// The format whose signature starts `bytes`, if any.
    ///
    /// Signatures: OpenEXR `76 2f 31 01`; Radiance `#?RADIANCE` or `#?RGBE`;
    /// PNG `89 50 4e 47 0d 0a 1a 0a`; JPEG `ff d8 ff`.
    #[must_use]
    pub fn from_magic(bytes: &[u8]) -> Option<Self> {
        const SIGNATURES: [(&[u8], Format); 5] = [
            (&[0x76, 0x2f, 0x31, 0x01], Format::Exr),
            (b"#?RADIANCE", Format::Radiance),
            (b"#?RGBE", Format::Radiance),
            (
                &[0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a],
                Format::Png,
            ),
            (&[0xff, 0xd8, 0xff], Format::Jpeg),
        ];
        SIGNATURES
            .iter()
            .find(|(signature, _)| bytes.starts_with(signature))
            .map(|&(_, format)| format)
    }

    /// The format named by the extension of `path` (case-insensitive), if
    /// any.
    #[must_use]
    pub fn from_extension(path: &Path) -> Option<Self> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "exr" => Some(Self::Exr),
            "hdr" | "pic" | "rgbe" => Some(Self::Radiance),
            "png" => Some(Self::Png),
            "jpg" | "jpeg" => Some(Self::Jpeg),
            _ => None,
        }
    }

    /// Whether [`crate::write_image`] can write this format.
    #[must_use]
    pub fn can_write(self) -> bool {
        !matches!(self, Self::Jpeg)
    }

    /// The format's usual name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Exr => "OpenEXR",
            Self::Radiance => "Radiance HDR",
            Self::Png => "PNG",
            Self::Jpeg => "JPEG",
        }
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
