//! The error type of every fallible file operation in this crate.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// A failed read or write of an image file: the file's path and what went
/// wrong with it.
///
/// `Display` names the file and the problem in plain words, for example
/// `envmaps/x.exr: truncated file (the image data ends early)`, so a command
/// line tool can print it as it is. Match on [`IoError::kind`] to react to a
/// particular problem.
#[derive(Debug, thiserror::Error)]
#[error("{}: {kind}", path.display())]
pub struct IoError {
    path: PathBuf,
    kind: IoErrorKind,
}

impl IoError {
    /// An error about the file at `path`.
    #[must_use]
    pub fn new(path: impl Into<PathBuf>, kind: IoErrorKind) -> Self {
        Self {
            path: path.into(),
            kind,
        }
    }

    /// The file that could not be read or written.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// What went wrong.
    #[must_use]
    pub fn kind(&self) -> &IoErrorKind {
        &self.kind
    }

    /// What went wrong, by value.
    #[must_use]
    pub fn into_kind(self) -> IoErrorKind {
        self.kind
    }
}

/// What went wrong in an [`IoError`].
///
/// New kinds may be added in later versions, so a `match` needs a `_` arm.
/// The `Display` text of each kind is a short plain-words description without
/// the file name (which [`IoError`] adds).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum IoErrorKind {
    /// The file does not exist.
    #[error("file not found")]
    NotFound,

    /// The file exists but could not be read (permissions, a directory, a
    /// device error...).
    #[error("cannot read the file ({0})")]
    Unreadable(io::Error),

    /// The file is zero bytes long.
    #[error("empty file (0 bytes)")]
    Empty,

    /// Neither the first bytes nor the extension name a supported format.
    /// Reads support OpenEXR, Radiance HDR, PNG and JPEG.
    #[error("unknown image format (not OpenEXR, Radiance HDR, PNG or JPEG)")]
    UnknownFormat,

    /// The file ends before all of its image data.
    #[error("truncated file (the image data ends early)")]
    Truncated,

    /// The file's contents do not follow its format. The string is the
    /// decoder's own description.
    #[error("corrupt image data ({0})")]
    Corrupt(String),

    /// The image has no pixels (a width or height of 0).
    #[error("the image has no pixels (size {width}x{height})")]
    EmptyImage {
        /// Width in pixels.
        width: usize,
        /// Height in pixels.
        height: usize,
    },

    /// The image has more pixels than [`crate::ReadOptions::max_pixels`]
    /// allows. Reported from the file's header, before any pixel memory is
    /// allocated.
    #[error("image too large ({width}x{height} pixels; the limit is {max_pixels} pixels)")]
    TooLarge {
        /// Width in pixels, from the header.
        width: usize,
        /// Height in pixels, from the header.
        height: usize,
        /// The limit in force.
        max_pixels: usize,
    },

    /// [`crate::ReadOptions::layer`] names a layer that the file does not
    /// have.
    #[error("no layer named {wanted:?} (the file has {})", LayerList(available))]
    LayerNotFound {
        /// The layer asked for.
        wanted: String,
        /// The layers in the file, in file order (`""` is the unnamed
        /// layer).
        available: Vec<String>,
    },

    /// The file is valid but uses something this crate does not read or
    /// write: an OpenEXR compression or feature the decoder lacks, a layer
    /// without colour channels, an output extension without an encoder.
    #[error("unsupported: {0}")]
    Unsupported(String),

    /// The texels given to a writer are not `width * height` values.
    #[error("{given} texels given for a {width}x{height} image")]
    TexelCount {
        /// Width in texels.
        width: usize,
        /// Height in texels.
        height: usize,
        /// How many texels were given.
        given: usize,
    },

    /// Writing the file failed; the destination is unchanged.
    #[error("cannot write the file ({0})")]
    Write(io::Error),
}

impl IoErrorKind {
    /// The kind for an [`io::Error`] met while opening or reading a file.
    pub(crate) fn from_read_error(error: io::Error) -> Self {
        match error.kind() {
            io::ErrorKind::NotFound => Self::NotFound,
            io::ErrorKind::UnexpectedEof => Self::Truncated,
            _ => Self::Unreadable(error),
        }
    }
}

/// Formats layer names for [`IoErrorKind::LayerNotFound`]: quoted, with the
/// unnamed layer spelled out.
struct LayerList<'a>(&'a [String]);

impl fmt::Display for LayerList<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_empty() {
            return f.write_str("no layers");
        }
        f.write_str(if self.0.len() == 1 {
            "layer "
        } else {
            "layers "
        })?;
        for (i, name) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            if name.is_empty() {
                f.write_str("\"\" (unnamed)")?;
            } else {
                write!(f, "{name:?}")?;
            }
        }
        Ok(())
    }
}
