//! Errors from loading or building a mesh, each naming the file when there is one.

use std::path::PathBuf;

/// Why a mesh could not be loaded or built.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The extension names no format shlight reads.
    #[error("{path}: unknown mesh format (expected {expected})")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
        /// The formats that are read.
        expected: &'static str,
    },
    /// The file is not valid in its format.
    #[error("{path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong, with a line or element number where known.
        message: String,
    },
    /// The data parsed but does not make a usable mesh.
    #[error("{path}: {message}")]
    Invalid {
        /// The file (or a generator's name).
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The mesh is larger than the [`crate::LoadOptions`] limit, judged
    /// from the file's counts before the memory is allocated.
    #[error("{path}: the mesh has {count} {what}, more than the limit of {max}")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// `"vertices"` or `"triangles"`.
        what: &'static str,
        /// How many the file holds (or at least, when counting stopped).
        count: usize,
        /// The limit.
        max: usize,
    },
    /// An output file could not be written (the error names it).
    #[error(transparent)]
    Write(shlight_io::IoError),
    /// A glTF texture has more pixels than
    /// [`crate::LoadOptions::max_texture_pixels`], judged from its image
    /// header before it is decoded.
    #[error("{path}: {texture} has {pixels} pixels, more than the texture limit of {max}")]
    TextureTooLarge {
        /// The glTF file.
        path: PathBuf,
        /// Which texture (`"texture 2 (wood)"`).
        texture: String,
        /// Its pixel count.
        pixels: u64,
        /// The limit.
        max: usize,
    },
}
