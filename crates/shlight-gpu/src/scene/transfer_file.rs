//! A `.shprt` file on its mesh: read and checked against the mesh
//! ([`read_transfer`]), and handed to a [`Renderer`] as diffuse transfer
//! vectors with their static term, if any, or as glossy matrices with
//! their BRDF's lobe ([`set_transfer`]); a diffuse file's transfer per
//! unit albedo ([`per_unit_albedo`]), for surfaces whose albedo varies
//! within a triangle (a glTF scene's textures); its static term
//! ([`static_radiance`]).

use std::path::Path;

use glam::Vec3;
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
/// a diffuse file's vectors and its static term ([`static_radiance`]:
/// PRT mode then shades `T . L + S`, as shlight-prt's
/// `file_exit_radiance`), or a glossy file's matrices with its BRDF's
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
        return Ok(renderer.set_transfer_with_static(ctx, &file.view()?, static_radiance(file))?);
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

/// The static term of `file` (format version 3, docs/shprt.md): each
/// vertex's static exit radiance `S` as linear RGB, added to `T . L`;
/// empty for a file without one.
#[must_use]
pub fn static_radiance(file: &ShprtFile) -> &[[f32; 3]] {
    file.static_light
        .as_ref()
        .map_or(&[], |s| s.radiance.as_slice())
}

/// The diffuse transfer of `file` per unit albedo: each vertex's rows
/// divided, channel by channel, by the albedo the bake folded in (the
/// file's constant albedo, else the vertex colours it was baked with,
/// `vertex_albedo`; a vertex beyond them counts as white), so that a
/// fragment can multiply in its own albedo. A one-channel file (a grey
/// albedo) is divided by the mean of the three channels. A channel baked
/// with an albedo below `1e-6` reflected nothing, and stays 0. The
/// interreflected light a file holds depends on the albedo around each
/// vertex too; that part is kept as baked.
#[must_use]
pub fn per_unit_albedo(file: &ShprtFile, vertex_albedo: &[Vec3]) -> Vec<f32> {
    let nc = (file.lmax + 1) * (file.lmax + 1);
    let channels = file.channels.max(1);
    let mut out = file.transfer.clone();
    for (v, rows) in out.chunks_exact_mut(channels * nc).enumerate() {
        let albedo = match file.albedo {
            Some(a) => Vec3::from_array(a),
            None => vertex_albedo.get(v).copied().unwrap_or(Vec3::ONE),
        };
        for (c, row) in rows.chunks_exact_mut(nc).enumerate() {
            let rho = if channels == 1 {
                albedo.element_sum() / 3.0
            } else {
                albedo[c.min(2)]
            };
            if rho.abs() < 1e-6 {
                row.fill(0.0);
            } else {
                row.iter_mut().for_each(|t| *t /= rho);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-vertex, three-channel file at lmax 1 whose transfer is the
    /// albedo times `k + 1` for coefficient `k`.
    fn file(albedo: Option<[f32; 3]>, vertex: &[Vec3], channels: usize) -> ShprtFile {
        let mut transfer = Vec::new();
        for v in 0..2 {
            let a = albedo.map_or(vertex[v], Vec3::from_array);
            for c in 0..channels {
                let rho = if channels == 1 { a.x } else { a[c] };
                transfer.extend((0..4).map(|k| rho * (k + 1) as f32));
            }
        }
        ShprtFile {
            lmax: 1,
            channels,
            vertex_count: 2,
            transfer,
            mode: "shadowed".into(),
            rays_per_vertex: 1,
            bounces: 0,
            seed: 0,
            albedo,
            mesh_hash: 0,
            mesh: "quad.glb".into(),
            glossy: None,
            static_light: None,
        }
    }

    #[test]
    fn transfer_per_unit_albedo_divides_each_channel_by_its_albedo() {
        let vertex = [Vec3::new(0.5, 0.25, 0.0), Vec3::new(0.8, 0.4, 0.2)];
        let want = [1.0, 2.0, 3.0, 4.0];
        // Baked with the vertex colours: the coefficients are k + 1 again,
        // but for the channel of albedo 0, which stays 0.
        let close = |got: &[f32], want: &[f32]| {
            assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(want) {
                assert!((g - w).abs() <= 1e-6 * w.abs(), "{got:?} against {want:?}");
            }
        };
        let f = file(None, &vertex, 3);
        let t = per_unit_albedo(&f, &vertex);
        close(&t[0..4], &want);
        close(&t[4..8], &want);
        assert_eq!(&t[8..12], &[0.0; 4]);
        close(&t[12..24], &[want; 3].concat());
        // A constant albedo recorded in the file wins over the colours.
        let f = file(Some([0.25, 0.5, 1.0]), &vertex, 3);
        close(&per_unit_albedo(&f, &vertex), &[want; 6].concat());
        // One channel: divided by the grey albedo.
        let grey = [Vec3::splat(0.5), Vec3::splat(0.25)];
        let f = file(None, &grey, 1);
        close(&per_unit_albedo(&f, &grey), &[want; 2].concat());
    }
}
