//! A `.shprt` file on its mesh: read and checked against the mesh
//! ([`read_transfer`]), and handed to a [`Renderer`] as diffuse transfer
//! vectors or as glossy matrices with their BRDF's lobe
//! ([`set_transfer`]).

use std::path::Path;

use shlight_format::ShprtFile;
use shlight_mesh::Mesh;
use shlight_prt::{Brdf, BrdfLobe};

use super::SceneError;
use super::scene_options::refuse;
use crate::{GlossyLobe, GpuContext, Renderer};

/// Reads `path` and checks it was baked for `mesh` (called `mesh_name`):
/// the same vertex count and the same content hash (positions, normals and
/// triangles, docs/shprt.md), so each vertex gets its own transfer.
///
/// # Errors
/// An unreadable or malformed file, or one baked for another mesh; the
/// message names both files.
pub fn read_transfer(path: &Path, mesh: &Mesh, mesh_name: &Path) -> Result<ShprtFile, SceneError> {
    let file = ShprtFile::read(path)?;
    if file.vertex_count != mesh.vertex_count() {
        return refuse(format!(
            "{}: baked for {} vertices, but {} has {} (bake its transfer for that mesh)",
            path.display(),
            file.vertex_count,
            mesh_name.display(),
            mesh.vertex_count()
        ));
    }
    if file.mesh_hash != mesh.content_hash() {
        return refuse(format!(
            "{}: baked for another mesh than {} (mesh hash {:016x}, the file's {:016x}; bake it \
             with `shlight prt {}`)",
            path.display(),
            mesh_name.display(),
            mesh.content_hash(),
            file.mesh_hash,
            mesh_name.display()
        ));
    }
    Ok(file)
}

/// Gives `renderer` (holding the file's mesh) the transfer of `file`:
/// a diffuse file's vectors, or a glossy file's matrices with its BRDF's
/// lobe (shlight-prt's [`Brdf`]: Phong's zonal `Lambda_l`, or GGX's
/// direction table).
///
/// # Errors
/// A transfer the GPU cannot hold, or a glossy file's unknown BRDF.
pub fn set_transfer(
    renderer: &mut Renderer,
    ctx: &GpuContext,
    file: &ShprtFile,
) -> Result<(), SceneError> {
    let (Some(matrices), Some(glossy)) = (file.glossy_view()?, &file.glossy) else {
        return Ok(renderer.set_transfer(ctx, &file.view()?)?);
    };
    let brdf = Brdf::parse(&glossy.brdf).map_err(SceneError::Refused)?;
    match brdf.lobe(file.lmax) {
        BrdfLobe::Zonal(lambda) => {
            renderer.set_glossy(ctx, &matrices, GlossyLobe::Zonal(&lambda))?
        }
        BrdfLobe::Ggx(lobe) => renderer.set_glossy(
            ctx,
            &matrices,
            GlossyLobe::Directions(&lobe.direction_table()),
        )?,
    }
    Ok(())
}
