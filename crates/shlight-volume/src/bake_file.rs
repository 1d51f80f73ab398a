//! [`bake_file`]: a volume baked through a scene and lit, from its
//! settings to the `.shvol` file with its provenance.
//!
//! shlight-pipeline's `volume` job reads the inputs (the scene with
//! [`shlight_mesh::load`] and its punctual lights, the light with its
//! `Environment`, turned to the y-up frame); [`check_environment`] refuses a light too short for the
//! bake before the scene is read; [`bake_file`] does the rest: the grid
//! ([`VolumeBakeSettings::grid`]), the bake, the probes lit by the
//! environment, and the file with its provenance.

use std::path::Path;
use std::sync::Arc;

use glam::{DVec3, Vec3};
use shlight_baked::ProbeGrid;
use shlight_core::sh::ShCoeffs;
use shlight_format::ShvolFile;
use shlight_mesh::{Mesh, PunctualLight, Surfaces};

use crate::bake::{Stage, VolumeOptions, bake_surfaces, bake_with_lights};
use crate::error::VolumeError;
use crate::volume_bake::{FileMeta, VolumeBake};

/// The frame a volume is baked in (its scene's): the environment is turned
/// to it before [`bake_file`].
pub const BAKE_FRAME: &str = "y-up";

/// The settings of a volume bake through a scene: the grid asked for and
/// the bake's options (shlight-pipeline's `VolumeRequest` holds them).
#[derive(Clone, Debug, PartialEq)]
pub struct VolumeBakeSettings {
    /// Probes along x, y and z.
    pub resolution: [usize; 3],
    /// The grid's box `(min, max)`; `None`: the scene's bounding box,
    /// padded ([`ProbeGrid::around`]).
    pub bounds: Option<(Vec3, Vec3)>,
    /// The bake's options (lmax, rays, bounces, albedo, relocation,
    /// distance maps...).
    pub options: VolumeOptions,
    /// Keep the transfer matrices and emitted light in the file, so it
    /// can be relit (`false`: a static volume).
    pub relightable: bool,
}

impl VolumeBakeSettings {
    /// The probe grid over `scene`: [`VolumeBakeSettings::bounds`], or the
    /// scene's padded bounding box.
    ///
    /// # Errors
    /// A zero count, too many probes, or bounds that are not a box.
    pub fn grid(&self, scene: &Mesh) -> Result<ProbeGrid, VolumeError> {
        Ok(match self.bounds {
            Some((min, max)) => ProbeGrid::new(self.resolution, min, max)?,
            None => ProbeGrid::around(self.resolution, scene.bounds())?,
        })
    }
}

/// What [`bake_file`] makes: the bake and its file.
#[derive(Clone, Debug)]
pub struct BakedFile {
    /// The bake (probe counts, relocation, rays cast).
    pub bake: VolumeBake,
    /// The `.shvol` file: the probes lit by the environment, and its
    /// provenance.
    pub file: ShvolFile,
}

/// Refuses `env` (radiance coefficients read from `env_path`) when it stops
/// below the bake's `lmax`: a coefficient file projected to a lower lmax.
///
/// # Errors
/// `env` holds fewer degrees than `lmax`; the message names the file and
/// how to project it again.
pub fn check_environment(
    env: &ShCoeffs<DVec3>,
    env_path: &Path,
    lmax: usize,
) -> Result<(), VolumeError> {
    if env.lmax() < lmax {
        return Err(VolumeError::Options(format!(
            "{}: holds coefficients to lmax {}, the bake needs {lmax} (project the map to lmax {lmax})",
            env_path.display(),
            env.lmax()
        )));
    }
    Ok(())
}

/// The name a `.shvol` file records for an input read from `path`: its
/// file name (the path as given when it has none).
#[must_use]
pub fn input_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// What writes the files: `shlight` and its version.
#[must_use]
pub fn generator() -> String {
    format!("shlight {}", env!("CARGO_PKG_VERSION"))
}

/// Bakes the volume `request` asks for through `scene` (read from
/// `scene_path`) lit by its punctual `lights` (none for a scene without)
/// and makes its `.shvol` file: the grid
/// ([`VolumeBakeSettings::grid`]), [`bake_with_lights`] (`progress` as there), the probes
/// relit under `env` (radiance coefficients in the y-up frame, read from
/// `env_path`; [`VolumeBake::relight`]), and [`VolumeBake::to_shvol`]
/// recording the frame, the inputs' file names, the generator
/// (`shlight VERSION`) and the lights' units and kinds. `surfaces`: a glTF
/// scene's, whose mesh `scene` is, baked through by [`bake_surfaces`]
/// (cut-outs, and the albedo of the texel a ray hits).
///
/// # Errors
/// An environment too short for the bake ([`check_environment`]), a bad
/// grid, surfaces of another mesh, or options [`bake()`](crate::bake())
/// refuses.
pub fn bake_file(
    scene: &Mesh,
    surfaces: Option<&Arc<Surfaces>>,
    lights: &[PunctualLight],
    scene_path: &Path,
    env: &ShCoeffs<DVec3>,
    env_path: &Path,
    request: &VolumeBakeSettings,
    progress: &(dyn Fn(Stage, usize, usize) + Sync),
) -> Result<BakedFile, VolumeError> {
    check_environment(env, env_path, request.options.lmax)?;
    let grid = request.grid(scene)?;
    let volume = match surfaces {
        Some(s) => {
            if s.mesh.vertex_count() != scene.vertex_count()
                || s.mesh.triangle_count() != scene.triangle_count()
            {
                return Err(VolumeError::Options(format!(
                    "{}: the surfaces given are not those of the scene's mesh",
                    scene_path.display()
                )));
            }
            bake_surfaces(s, lights, &grid, &request.options, progress)?
        }
        None => bake_with_lights(Some(scene), lights, &grid, &request.options, progress)?,
    };
    let radiance = volume.relight(env);
    let meta = FileMeta {
        frame: BAKE_FRAME.into(),
        scene: input_name(scene_path),
        environment: input_name(env_path),
        generator: generator(),
    };
    let file = volume.to_shvol(radiance, request.relightable, &meta);
    Ok(BakedFile { bake: volume, file })
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::sh::closed_form;
    use shlight_mesh::generate;

    /// The file holds the bake of the request's options over its grid,
    /// lit by the environment, with the inputs' names; a static request
    /// keeps no transfer; a short environment is refused.
    #[test]
    fn the_file_is_the_bake_of_the_request() {
        let scene = generate::uv_sphere(0.3, 8, 4);
        let options = VolumeOptions {
            samples: 64,
            surface_samples: 16,
            bounces: 1,
            ..VolumeOptions::default()
        };
        let request = VolumeBakeSettings {
            resolution: [2, 1, 2],
            bounds: Some((Vec3::splat(-1.0), Vec3::ONE)),
            options: options.clone(),
            relightable: true,
        };
        let env = closed_form::constant(2, DVec3::new(1.0, 0.5, 0.25));
        let baked = bake_file(
            &scene,
            None,
            &[],
            Path::new("dir/ball.obj"),
            &env,
            Path::new("maps/sky.exr"),
            &request,
            &|_, _, _| {},
        )
        .unwrap();
        let grid = ProbeGrid::new([2, 1, 2], Vec3::splat(-1.0), Vec3::ONE).unwrap();
        let direct = crate::bake(Some(&scene), &grid, &options, &|_, _, _| {}).unwrap();
        assert_eq!(baked.bake, direct);
        assert_eq!(baked.file.radiance, direct.relight(&env));
        assert_eq!(baked.file.transfer.as_ref(), Some(&direct.transfer));
        assert_eq!(
            (baked.file.scene.as_str(), baked.file.environment.as_str()),
            ("ball.obj", "sky.exr")
        );
        assert_eq!((baked.file.frame.as_str(), baked.file.seed), ("y-up", 0));
        assert_eq!(baked.file.generator, generator());

        let fixed = VolumeBakeSettings {
            bounds: None,
            relightable: false,
            ..request.clone()
        };
        assert_eq!(
            fixed.grid(&scene).unwrap(),
            ProbeGrid::around([2, 1, 2], scene.bounds()).unwrap()
        );
        let baked = bake_file(
            &scene,
            None,
            &[],
            Path::new("ball.obj"),
            &env,
            Path::new("sky.exr"),
            &fixed,
            &|_, _, _| {},
        )
        .unwrap();
        assert!(baked.file.transfer.is_none() && !baked.file.relightable());

        let short = closed_form::constant(1, DVec3::ONE);
        let e = bake_file(
            &scene,
            None,
            &[],
            Path::new("ball.obj"),
            &short,
            Path::new("l1.json"),
            &request,
            &|_, _, _| {},
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "l1.json: holds coefficients to lmax 1, the bake needs 2 (project the map to lmax 2)"
        );
        assert_eq!(input_name(Path::new("..")), "..");
    }
}
