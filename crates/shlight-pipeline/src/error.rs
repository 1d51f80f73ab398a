//! [`PipelineError`]: what went wrong, as one message that names the input.

use std::fmt;

/// An error of a pipeline step: one message naming the input and the
/// problem, with the causes joined by `": "` (the same text the `shlight`
/// command prints after `error: `).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PipelineError {
    message: String,
}

/// The result of a pipeline step.
pub type Result<T> = std::result::Result<T, PipelineError>;

impl PipelineError {
    /// An error with this message.
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
        }
    }

    /// This error with `context` in front: `"{context}: {self}"`.
    #[must_use]
    pub fn context(self, context: impl fmt::Display) -> Self {
        Self::new(format!("{context}: {}", self.message))
    }

    /// This error with `hint` after it: `"{self}; {hint}"` (what to do
    /// about it, in the words of the caller's front end).
    #[must_use]
    pub fn context_after(self, hint: impl fmt::Display) -> Self {
        Self::new(format!("{}; {hint}", self.message))
    }

    /// The message.
    #[must_use]
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for PipelineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for PipelineError {}

/// `e` and each of its sources, joined by `": "` (as `anyhow` prints an
/// error with `{:#}`).
#[must_use]
pub fn error_chain(e: &(dyn std::error::Error + 'static)) -> String {
    let mut out = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        out.push_str(": ");
        out.push_str(&s.to_string());
        source = s.source();
    }
    out
}

impl From<shlight_io::IoError> for PipelineError {
    fn from(e: shlight_io::IoError) -> Self {
        Self::new(error_chain(&e))
    }
}

impl From<shlight_format::FormatError> for PipelineError {
    fn from(e: shlight_format::FormatError) -> Self {
        Self::new(error_chain(&e))
    }
}

impl From<shlight_mesh::MeshError> for PipelineError {
    fn from(e: shlight_mesh::MeshError) -> Self {
        Self::new(error_chain(&e))
    }
}

impl From<shlight_prt::PrtError> for PipelineError {
    fn from(e: shlight_prt::PrtError) -> Self {
        Self::new(error_chain(&e))
    }
}

impl From<shlight_volume::VolumeError> for PipelineError {
    fn from(e: shlight_volume::VolumeError) -> Self {
        Self::new(error_chain(&e))
    }
}
