//! [`SceneError`]: why a scene could not be read, checked or drawn.

use std::path::PathBuf;

use crate::GpuError;

/// Why a scene could not be read, checked or drawn. Each message names the
/// file, or the setting as the front end spells it
/// ([`shlight_pipeline::Spelling`]); the errors of the crates that read the
/// files come through unchanged, causes included.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// Settings that do not go together, or a file that does not fit the
    /// scene (a transfer baked for another mesh, a background map without a
    /// map, a static volume turned).
    #[error("{0}")]
    Refused(String),
    /// A mesh that cannot be read.
    #[error(transparent)]
    Mesh(#[from] shlight_mesh::MeshError),
    /// A `.shprt` or `.shvol` file that cannot be read.
    #[error(transparent)]
    Format(#[from] shlight_format::FormatError),
    /// A baked file's arrays that do not fit their shape.
    #[error(transparent)]
    Shape(#[from] shlight_baked::ShapeError),
    /// A light that cannot be read, or a rotation that does not parse.
    #[error(transparent)]
    Light(#[from] shlight_pipeline::PipelineError),
    /// The built-in map's bytes do not decode.
    #[error("reading the bundled {name}")]
    BuiltIn {
        /// The map's name.
        name: String,
        /// The decoder's reason.
        source: shlight_io::IoError,
    },
    /// The GPU refused the scene or failed while drawing it.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// The frame could not be written.
    #[error("{}: writing", path.display())]
    Write {
        /// The image file.
        path: PathBuf,
        /// The writer's reason.
        source: shlight_io::IoError,
    },
}
