//! [`bake_file`]: a bake as a front end asks for it (`shlight prt`, the
//! Python package's `bake_transfer`), from its options to the `.shprt`
//! file, so every front end bakes and records a mesh the same way.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use shlight_format::{ShprtFile, StaticLight};
use shlight_mesh::{LightUnits, Mesh, PunctualLight, Surfaces};
use shlight_rays::Occluder;

use crate::back_sides::BackSides;
use crate::bake::{bake, bake_cast_against};
use crate::brdf::Brdf;
use crate::glossy::{GlossyTransfer, bake_glossy};
use crate::options::{Albedo, BakeOptions, Mode, Stage};
use crate::punctual::{light_counts, punctual_irradiance};
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

/// A glTF scene as the PRT bake reads it: its surfaces flattened
/// ([`shlight_mesh::Scene::flatten`]), whose mesh is baked, and its
/// punctual lights with the units their intensities are read in.
#[derive(Clone, Copy, Debug)]
pub struct SceneLighting<'a> {
    /// The scene's surfaces (their mesh is the one baked).
    pub surfaces: &'a Arc<Surfaces>,
    /// Its punctual lights, in world space.
    pub lights: &'a [PunctualLight],
    /// How their intensities become radiometric units.
    pub units: LightUnits,
}

impl SceneLighting<'_> {
    /// The bake's options for the scene's mesh: the vertices' albedo from
    /// the materials (`Surfaces::mesh`'s colours, clamped to `0..=1`, as a
    /// bounce reads a texel's), its surfaces (cut-outs, the albedo of the
    /// texel a bounce hits), its emission, and the punctual lights' direct
    /// irradiance at each vertex ([`punctual_irradiance`], shadow rays
    /// through the cut-outs, cast against `occluder`, the scene's mesh
    /// made ready with its surfaces' cut-outs; none without lights).
    #[must_use]
    pub fn options(&self, request: &BakeRequest, occluder: &Occluder) -> BakeOptions {
        let mesh = &self.surfaces.mesh;
        let albedo = match &mesh.colors {
            Some(c) => {
                Albedo::PerVertex(c.iter().map(|c| c.clamp(Vec3::ZERO, Vec3::ONE)).collect())
            }
            None => Albedo::Constant(DEFAULT_ALBEDO),
        };
        // At every vertex of the two-sided mesh where triangles are
        // double-sided (their back copies lit from behind), as the bake
        // gathers over it.
        let direct_irradiance =
            (!self.lights.is_empty()).then(|| match BackSides::find(mesh, None, self.surfaces) {
                Some(sides) => {
                    let two = sides.two_sided(mesh);
                    punctual_irradiance(occluder, &two, self.lights, self.units)
                }
                None => punctual_irradiance(occluder, mesh, self.lights, self.units),
            });
        BakeOptions {
            lmax: request.lmax,
            samples: request.samples,
            mode: request.mode,
            albedo,
            seed: request.seed,
            emission: mesh.emission.clone(),
            surfaces: Some(self.surfaces.clone()),
            direct_irradiance,
        }
    }
}

/// [`bake_file`] for a glTF scene ([`SceneLighting::options`]; the request's
/// albedo is not read: the scene's materials give it): the transfer of the
/// distant light, three channels, recorded with the albedo `"vertex"`;
/// and where the scene has light of its own (emission, punctual lights),
/// each vertex's static exit radiance ([`Transfer::emitted`]) as the
/// file's [`StaticLight`] (format version 3), so that the vertex leaves
/// `T . L + S`.
///
/// # Panics
/// As [`bake`].
#[must_use]
pub fn bake_scene_file(
    scene: SceneLighting<'_>,
    scene_path: &Path,
    request: &BakeRequest,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> (Transfer, ShprtFile) {
    let mesh = &scene.surfaces.mesh;
    // Made ready once, for the lights' shadow rays and the bake's rays.
    let occluder = Occluder::for_surfaces(scene.surfaces);
    let options = scene.options(request, &occluder);
    let transfer = bake_cast_against(mesh, &occluder, &options, progress);
    let mut file = transfer.to_shprt(
        request.mode,
        request.seed,
        None,
        mesh.content_hash(),
        &mesh_name(scene_path),
    );
    file.static_light = transfer.emitted.as_ref().map(|e| StaticLight {
        radiance: e.iter().map(|v| v.to_array()).collect(),
        lights: light_counts(scene.lights, scene.units),
        emission: mesh.emission.is_some(),
    });
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
