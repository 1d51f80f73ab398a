//! The error type of every fallible operation in this crate.

use std::path::PathBuf;

/// Why a file could not be read or written, or coefficients could not be
/// exported: each variant's text names the file (where there is one) and
/// the problem in plain words, so a command line can print it as it is.
///
/// New variants may be added in later versions, so a `match` needs a `_` arm.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FormatError {
    /// The file could not be read.
    #[error("{}: cannot read ({source})", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The content is not a file of the expected kind, or breaks its
    /// format (a missing field, a wrong count, a value out of range).
    #[error("{name}: {message}")]
    Invalid {
        /// The file (or the name the caller gave the text).
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The coefficients cannot be written in the asked format (not finite,
    /// beyond the range of a 32-bit float, or a quantity that cannot be
    /// converted).
    #[error("{0}")]
    Export(String),
    /// The file could not be written (the message names it).
    #[error(transparent)]
    Write(#[from] shlight_io::IoError),
}

impl FormatError {
    /// An [`FormatError::Invalid`] about `name`.
    pub(crate) fn invalid(name: &str, message: impl Into<String>) -> Self {
        Self::Invalid {
            name: name.to_string(),
            message: message.into(),
        }
    }
}

/// The result of this crate's fallible operations.
pub type Result<T, E = FormatError> = std::result::Result<T, E>;
