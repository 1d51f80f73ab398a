//! [`ShapeError`]: baked data whose sizes do not fit together.

/// Baked data of the wrong shape: a grid with a zero count or bad bounds,
/// arrays whose lengths do not fit their counts. The text says what is
/// wrong in plain words, so a command line can print it as it is.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct ShapeError(pub String);
