//! Errors of PRT files, each naming the file.

use std::path::PathBuf;

/// Why a PRT file could not be read or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PrtError {
    /// The file could not be read.
    #[error("{path}: cannot read: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The file is not a valid `.shprt` file (bad header, wrong length,
    /// truncated data).
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The file could not be written (the message names it).
    #[error(transparent)]
    Write(#[from] shlight_io::IoError),
    /// The transfer does not fit the mesh or light it is used with.
    #[error("{0}")]
    Mismatch(String),
}
