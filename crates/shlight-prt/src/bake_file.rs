//! [`bake_file`]: a bake as a front end asks for it (`shlight prt`, the
//! Python package's `bake_transfer`), from its options to the `.shprt`
//! file, so every front end bakes and records a mesh the same way.

use std::path::Path;
use std::sync::Arc;

use shlight_format::ShprtFile;
use shlight_mesh::{Mesh, Surfaces};

use crate::bake::bake;
use crate::brdf::Brdf;
use crate::glossy::{GlossyTransfer, bake_glossy};
use crate::options::{Albedo, BakeOptions, Mode, Stage};
use crate::transfer::Transfer;

/// The albedo of a mesh without vertex colours baked with no albedo given.
pub const DEFAULT_ALBEDO: [f32; 3] = [0.8; 3];

/// The bounces of [`Mode::Interreflected`] when none are given.
pub const DEFAULT_BOUNCES: u32 = 2;

/// The highest lmax a bake takes (diffuse transfer needs 2 to 6).
pub const MAX_BAKE_LMAX: usize = 32;

/// What a front end asks of a bake: `shlight prt`'s options.
#[derive(Clone, Debug, PartialEq)]
pub struct BakeRequest {
    /// Highest SH degree of the transfer.
    pub lmax: usize,
    /// Directions wanted over the sphere ([`BakeOptions::samples`]).
    pub samples: usize,
    /// Light transport.
    pub mode: Mode,
    /// A linear albedo for every vertex; `None`: the mesh's vertex colours
    /// when it has them, otherwise [`DEFAULT_ALBEDO`].
    pub albedo: Option<[f32; 3]>,
    /// Seed of the direction set.
    pub seed: u64,
}

impl BakeRequest {
    /// The bake's options for `mesh` (no emitters), and the albedo to
    /// record ([`BakeRequest::albedo`]).
    #[must_use]
    pub fn options(&self, mesh: &Mesh) -> (BakeOptions, Option<[f32; 3]>) {
        let (albedo, recorded) = self.albedo(mesh);
        let options = BakeOptions {
            lmax: self.lmax,
            samples: self.samples,
            mode: self.mode,
            albedo,
            seed: self.seed,
            emission: None,
            surfaces: None,
            direct_irradiance: None,
        };
        (options, recorded)
    }

    /// The albedo the bake of `mesh` uses, and the one its file records
    /// (`None` for the mesh's vertex colours).
    #[must_use]
    pub fn albedo(&self, mesh: &Mesh) -> (Albedo, Option<[f32; 3]>) {
        match (self.albedo, &mesh.colors) {
            (Some(rgb), _) => (Albedo::Constant(rgb), Some(rgb)),
            (None, Some(colors)) => (Albedo::PerVertex(colors.clone()), None),
            (None, None) => (Albedo::Constant(DEFAULT_ALBEDO), Some(DEFAULT_ALBEDO)),
        }
    }
}

/// The name a `.shprt` file records for the mesh read from `path`: its file
/// name (the path as given when it has none).
#[must_use]
pub fn mesh_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Bakes `mesh` (read from `mesh_path`) as `request` asks and makes its
/// `.shprt` file: the albedo chosen by [`BakeRequest::albedo`], [`bake`]
/// (`progress` as there), and [`Transfer::to_shprt`] with the mode, seed,
/// recorded albedo, the mesh's content hash and [`mesh_name`]. Returns the
/// bake (its ray counts) and the file. `surfaces`: a glTF scene's, whose
/// mesh `mesh` is ([`BakeOptions::surfaces`]: cut-outs, and the albedo of
/// the texel a bounce hits).
///
/// # Panics
/// As [`bake`].
#[must_use]
pub fn bake_file(
    mesh: &Mesh,
    surfaces: Option<&Arc<Surfaces>>,
    mesh_path: &Path,
    request: &BakeRequest,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> (Transfer, ShprtFile) {
    let (mut options, recorded) = request.options(mesh);
    options.surfaces = surfaces.cloned();
    let transfer = bake(mesh, &options, progress);
    let file = transfer.to_shprt(
        request.mode,
        request.seed,
        recorded,
        mesh.content_hash(),
        &mesh_name(mesh_path),
    );
    (transfer, file)
}

/// [`bake_file`] for glossy transfer: `request.mode` is the transport
/// (its bounces the diffuse bounces the matrices gather), `brdf` the lobe
/// the file records ([`bake_glossy`], [`GlossyTransfer::to_shprt`]),
/// `surfaces` as [`bake_file`]'s.
///
/// # Panics
/// As [`bake`].
#[must_use]
pub fn bake_glossy_file(
    mesh: &Mesh,
    surfaces: Option<&Arc<Surfaces>>,
    mesh_path: &Path,
    request: &BakeRequest,
    brdf: Brdf,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> (GlossyTransfer, ShprtFile) {
    let (mut options, recorded) = request.options(mesh);
    options.surfaces = surfaces.cloned();
    let transfer = bake_glossy(mesh, &options, progress);
    let file = transfer.to_shprt(mesh, brdf, request.seed, recorded, &mesh_name(mesh_path));
    (transfer, file)
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_mesh::generate;

    /// The file holds the bake of the options the request makes, and
    /// records the albedo given, the default, or none for vertex colours.
    #[test]
    fn the_file_is_the_bake_of_the_request() {
        let sphere = generate::uv_sphere(1.0, 8, 4);
        let request = BakeRequest {
            lmax: 2,
            samples: 64,
            mode: Mode::Interreflected { bounces: 1 },
            albedo: None,
            seed: 3,
        };
        let (transfer, file) = bake_file(
            &sphere,
            None,
            Path::new("dir/ball.obj"),
            &request,
            &|_, _, _| {},
        );
        let options = BakeOptions {
            lmax: 2,
            samples: 64,
            mode: request.mode,
            albedo: Albedo::Constant(DEFAULT_ALBEDO),
            seed: 3,
            emission: None,
            surfaces: None,
            direct_irradiance: None,
        };
        let direct = bake(&sphere, &options, &|_, _, _| {});
        assert_eq!(transfer.coeffs, direct.coeffs);
        assert_eq!(file.transfer, direct.coeffs);
        assert_eq!(
            (file.mode.as_str(), file.bounces, file.seed),
            ("interreflected", 1, 3)
        );
        assert_eq!(file.albedo, Some(DEFAULT_ALBEDO));
        assert_eq!(file.mesh, "ball.obj");
        assert_eq!(file.mesh_hash, sphere.content_hash());

        let given = BakeRequest {
            albedo: Some([0.5, 0.25, 0.125]),
            ..request.clone()
        };
        assert_eq!(given.albedo(&sphere).1, Some([0.5, 0.25, 0.125]));
        let mut coloured = sphere.clone();
        coloured.colors = Some(vec![
            glam::Vec3::new(0.1, 0.2, 0.3);
            coloured.vertex_count()
        ]);
        let (albedo, recorded) = request.albedo(&coloured);
        assert!(matches!(albedo, Albedo::PerVertex(_)));
        assert_eq!(recorded, None);
        assert_eq!(mesh_name(Path::new("..")), "..");
    }
}
