//! What the fuzz targets share: the limits they read with, so that
//! `fuzz/run.sh`'s `-rss_limit_mb` and `-timeout` hold what
//! docs/limits.md promises for them.

/// The pixel limit the image targets read with (`ReadOptions::max_pixels`):
/// 2^22 (2048 x 2048). docs/limits.md bounds a read's memory by
/// 64 bytes a pixel of this limit plus a few times the file's size, so
/// 256 MiB here, well inside the targets' 2048 MiB RSS limit.
pub const MAX_PIXELS: usize = 1 << 22;

/// The mesh limits the mesh targets read with (`LoadOptions`): 2^20
/// vertices and 2^21 triangles, so that docs/limits.md's bound (about 40
/// bytes a vertex and 12 a triangle, plus a few times the file's size)
/// stays far inside the targets' RSS limit.
pub const MESH_LIMITS: shlight_mesh::LoadOptions = shlight_mesh::LoadOptions {
    max_vertices: 1 << 20,
    max_triangles: 1 << 21,
};
