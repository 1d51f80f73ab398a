//! The limits a mesh file is read under: how many vertices and triangles
//! it may make the loader allocate (docs/limits.md).

use std::path::Path;

use crate::MeshError;

/// How [`crate::load_with`], [`crate::load_bytes_with`],
/// [`crate::load_scene`] and [`crate::load_scene_bytes`] read a mesh: the
/// largest mesh and textures accepted.
///
/// The counts are judged from headers (PLY element counts, OFF counts,
/// glTF accessor counts) before the memory for them is allocated, and
/// as vertices and triangles are gathered (every glTF mesh instance and
/// every fanned polygon counts), so a small file cannot make the loader
/// allocate more than about 40 bytes a vertex and 12 bytes a triangle up
/// to these limits. A larger mesh is refused with
/// [`MeshError::TooLarge`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadOptions {
    /// The most vertices accepted. Default
    /// [`LoadOptions::DEFAULT_MAX_VERTICES`].
    pub max_vertices: usize,
    /// The most triangles accepted, counted before degenerate triangles
    /// are dropped. Default [`LoadOptions::DEFAULT_MAX_TRIANGLES`].
    pub max_triangles: usize,
    /// The most pixels (width x height) of one glTF texture, judged from
    /// the image header before it is decoded; all the textures of a file
    /// together may hold 16 times this. Default
    /// [`LoadOptions::DEFAULT_MAX_TEXTURE_PIXELS`].
    pub max_texture_pixels: usize,
}

impl LoadOptions {
    /// The default [`LoadOptions::max_vertices`], 2^26 (67 million, about
    /// 2.5 GB of positions, normals and colours).
    pub const DEFAULT_MAX_VERTICES: usize = 1 << 26;
    /// The default [`LoadOptions::max_triangles`], 2^27 (134 million,
    /// 1.6 GB of indices).
    pub const DEFAULT_MAX_TRIANGLES: usize = 1 << 27;
    /// The default [`LoadOptions::max_texture_pixels`], 2^26 (8192 x 8192,
    /// 256 MiB of 8-bit RGBA texels).
    pub const DEFAULT_MAX_TEXTURE_PIXELS: usize = 1 << 26;

    /// Refuses `count` vertices beyond [`LoadOptions::max_vertices`].
    pub(crate) fn check_vertices(&self, path: &Path, count: usize) -> Result<(), MeshError> {
        check(path, "vertices", count, self.max_vertices)
    }

    /// Refuses `count` triangles beyond [`LoadOptions::max_triangles`].
    pub(crate) fn check_triangles(&self, path: &Path, count: usize) -> Result<(), MeshError> {
        check(path, "triangles", count, self.max_triangles)
    }
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            max_vertices: Self::DEFAULT_MAX_VERTICES,
            max_triangles: Self::DEFAULT_MAX_TRIANGLES,
            max_texture_pixels: Self::DEFAULT_MAX_TEXTURE_PIXELS,
        }
    }
}

fn check(path: &Path, what: &'static str, count: usize, max: usize) -> Result<(), MeshError> {
    if count <= max {
        Ok(())
    } else {
        Err(MeshError::TooLarge {
            path: path.to_path_buf(),
            what,
            count,
            max,
        })
    }
}
