//! `--prt FILE` of `render-mesh` and `view`: a `.shprt` transfer file
//! checked against the mesh it is drawn on.

use std::path::Path;

use anyhow::{Result, bail};
use shlight_format::ShprtFile;
use shlight_mesh::Mesh;

/// Reads `path` and checks it was baked for `mesh` (read from `mesh_path`):
/// the same vertex count and the same content hash (positions, normals and
/// triangles, docs/shprt.md), so each vertex gets its own transfer vector.
///
/// # Errors
/// An unreadable or malformed file, or one baked for another mesh; the
/// message names both files.
pub fn load_transfer(path: &Path, mesh: &Mesh, mesh_path: &Path) -> Result<ShprtFile> {
    let file = ShprtFile::read(path)?;
    if file.vertex_count != mesh.vertex_count() {
        bail!(
            "{}: baked for {} vertices, but {} has {} (bake it with `shlight prt {}`)",
            path.display(),
            file.vertex_count,
            mesh_path.display(),
            mesh.vertex_count(),
            mesh_path.display()
        );
    }
    if file.mesh_hash != mesh.content_hash() {
        bail!(
            "{}: baked for another mesh than {} (mesh hash {:016x}, the file's {:016x}; bake it \
             with `shlight prt {}`)",
            path.display(),
            mesh_path.display(),
            mesh.content_hash(),
            file.mesh_hash,
            mesh_path.display()
        );
    }
    Ok(file)
}
