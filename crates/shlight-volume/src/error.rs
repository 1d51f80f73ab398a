//! The error type of the volume crate.

/// Why a volume could not be baked, relit or read: each text says what is
/// wrong in plain words, so a command line can print it as it is.
///
/// New variants may be added in later versions, so a `match` needs a `_` arm.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VolumeError {
    /// A bad grid: resolution or bounds.
    #[error(transparent)]
    Grid(#[from] shlight_baked::ShapeError),
    /// Bad bake settings (lmax, samples, an environment of another lmax).
    #[error("{0}")]
    Options(String),
    /// A file's content does not make a volume, or a volume cannot do what
    /// was asked (relighting a static volume).
    #[error("{0}")]
    Invalid(String),
    /// A file could not be read or written.
    #[error(transparent)]
    Format(#[from] shlight_format::FormatError),
}
