//! Errors of PRT files, each naming the file, and of transfer that does
//! not fit its mesh.

/// Why a PRT file could not be read or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PrtError {
    /// The file could not be written (the message names it).
    #[error(transparent)]
    Write(#[from] shlight_io::IoError),
    /// A `.shprt` file could not be read or written (the message names it).
    #[error(transparent)]
    File(#[from] shlight_format::FormatError),
    /// The transfer does not fit the mesh or light it is used with.
    #[error("{0}")]
    Mismatch(String),
}
