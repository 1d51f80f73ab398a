//! `volume`: an irradiance volume baked through a scene under a distant
//! light — relightable SH probes on a grid, relocated out of geometry,
//! with the distance maps of the visibility-weighted lookup — written as a
//! `.shvol` file, its JSON, Bevy's KTX2 or three.js's grid, with a picture
//! of the probes ([`VolumeRequest`] → [`VolumePlan`] → [`volume`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::Vec3;
use shlight_baked::ProbeGrid;
use shlight_core::sh::Frame;
use shlight_format::threejs_volume::Precision;
use shlight_format::{ShvolFile, VolumeFormat};
use shlight_io::{Image, WriteOptions, write_image};
use shlight_volume::{
    BakedFile, Stage, VolumeBake, VolumeBakeSettings, bake_file, probe_sheet, probe_sheet_exposure,
};

use crate::environment::Environment;
use crate::hooks::{Hooks, Progress};
use crate::output_path::refuse_overwriting;
use crate::scene_surfaces::load_scene_surfaces;
use crate::spelling::Spelling;
use crate::{PipelineError, Result};

/// A volume bake as a front end asks for it, before
/// [`VolumeRequest::check`].
#[derive(Clone, Debug)]
pub struct VolumeRequest<'a> {
    /// The scene: `.obj` (+ `.mtl`), `.ply`, `.off`, `.gltf`, `.glb`.
    pub scene: &'a Path,
    /// The distant light: an equirect map (projected to the bake's lmax,
    /// its top row facing +Y) or a radiance coefficient file.
    pub env: &'a Path,
    /// The file to write (none: the volume comes back only).
    pub output: Option<&'a Path>,
    /// Its format [default: [`VolumeFormat::from_path`]].
    pub format: Option<VolumeFormat>,
    /// The numbers of three.js's atlas.
    pub precision: Precision,
    /// The grid and the bake's options.
    pub bake: VolumeBakeSettings,
    /// A picture of the probes, each a white ball lit by its light.
    pub preview: Option<&'a Path>,
    /// Each ball's diameter in pixels.
    pub preview_ball: usize,
}

/// A checked [`VolumeRequest`].
#[derive(Clone, Debug)]
pub struct VolumePlan {
    scene: PathBuf,
    env: PathBuf,
    output: Option<(PathBuf, VolumeFormat, Precision)>,
    bake: VolumeBakeSettings,
    preview: Option<(PathBuf, usize)>,
}

impl VolumeRequest<'_> {
    /// The plan, after the checks every front end makes before anything
    /// is read: the grid's counts and box (shlight-baked's limits), lmax at
    /// most [`shlight_baked::MAX_LMAX`], no output over an input.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<VolumePlan> {
        let (min, max) = self.bake.bounds.unwrap_or((Vec3::ZERO, Vec3::ONE));
        ProbeGrid::new(self.bake.resolution, min, max)
            .map_err(|e| PipelineError::new(e.to_string()))?;
        for out in self.output.iter().chain(&self.preview) {
            refuse_overwriting(out, &[self.scene, self.env])?;
        }
        let lmax = self.bake.options.lmax;
        if lmax > shlight_baked::MAX_LMAX {
            return Err(PipelineError::new(format!(
                "{} is beyond {}, the most a volume holds",
                spelling.option_number("lmax", lmax, lmax),
                shlight_baked::MAX_LMAX
            )));
        }
        Ok(VolumePlan {
            scene: self.scene.to_path_buf(),
            env: self.env.to_path_buf(),
            output: self.output.map(|p| {
                let format = self.format.unwrap_or_else(|| VolumeFormat::from_path(p));
                (p.to_path_buf(), format, self.precision)
            }),
            bake: self.bake.clone(),
            preview: self.preview.map(|p| (p.to_path_buf(), self.preview_ball)),
        })
    }
}

/// The distance maps' size of a bake with (`true`) or without the
/// visibility-weighted lookup's maps.
#[must_use]
pub fn visibility_size(visibility: bool) -> usize {
    if visibility {
        shlight_baked::visibility::VISIBILITY_SIZE
    } else {
        0
    }
}

/// The label of a bake stage's progress.
fn stage_label(stage: Stage) -> String {
    match stage {
        Stage::Surface(shlight_prt::Stage::Rays) => "surface rays".into(),
        Stage::Surface(shlight_prt::Stage::Bounce(k)) => format!("bounce {k}"),
        Stage::Surface(shlight_prt::Stage::Matrices) => "matrices".into(),
        Stage::Relocate => "relocate".into(),
        Stage::Probes => "probes".into(),
    }
}

/// `shlight volume`: reads the light first (a bad light fails before the
/// scene is read; one short of the bake's lmax before it is baked, by
/// shlight-volume's `bake_file`), then the scene; notes the grid; bakes (progress
/// per stage: the surfaces' rays and bounces, relocation, the probes);
/// notes what was baked and how fast; writes the picture of the probes and
/// the file.
///
/// # Errors
/// A light or scene that cannot be read; a light that stops below the
/// bake's lmax; a grid or options the bake refuses; a file that cannot be
/// written.
pub fn volume(plan: &VolumePlan, hooks: &dyn Hooks) -> Result<BakedFile> {
    let lmax = plan.bake.options.lmax;
    let light = Environment::load(&plan.env, Frame::YUp, lmax)?;
    light.warnings.iter().for_each(|w| hooks.warn(w));
    let radiance = light.radiance_in(Frame::YUp);
    let name = plan.scene.display().to_string();
    let albedo = Vec3::from_array(plan.bake.options.albedo);
    let (scene, surfaces) = load_scene_surfaces(&plan.scene, albedo)?;
    if scene.report.degenerate_triangles > 0 {
        hooks.warn(&format!(
            "{name}: skipped {} degenerate triangles",
            scene.report.degenerate_triangles
        ));
    }
    let grid = plan.bake.grid(&scene)?;
    let [nx, ny, nz] = plan.bake.resolution;
    hooks.note(&format!(
        "{name}: {} triangles, {}; grid {nx}x{ny}x{nz} over {}:{}",
        scene.triangle_count(),
        match (&scene.colors, &scene.emission) {
            (Some(_), Some(_)) => "albedo and emission from its materials",
            (Some(_), None) => "albedo from its colours",
            (None, Some(_)) => "emission from its materials",
            (None, None) => "constant albedo",
        },
        grid.min,
        grid.max
    ));
    let start = Instant::now();
    let baked = bake_file(
        &scene,
        surfaces.as_ref(),
        &plan.scene,
        &radiance,
        &plan.env,
        &plan.bake,
        &|stage, done, total| {
            hooks.progress(Progress::Count {
                stage: &stage_label(stage),
                done,
                total,
            });
        },
    )?;
    note_bake(&baked.bake, start.elapsed().as_secs_f64(), hooks);
    if let Some((path, ball)) = &plan.preview {
        write_probe_sheet(path, &baked.file, *ball)?;
    }
    if let Some((path, format, precision)) = &plan.output {
        for note in baked.file.write_as(path, *format, *precision)? {
            hooks.note(&note);
        }
    }
    Ok(baked)
}

/// The note of a finished bake: its probes, how many are invalid or were
/// moved, and its rays.
fn note_bake(volume: &VolumeBake, seconds: f64, hooks: &dyn Hooks) {
    hooks.note(&format!(
        "{} probes ({} invalid: inside geometry; {} moved out of geometry, at most {:.2} of a cell), {} rays in {seconds:.2} s ({:.1} M rays/s)",
        volume.probe_count(),
        volume.invalid_count(),
        volume.relocated_count(),
        volume.largest_move(),
        volume.rays,
        volume.rays as f64 / seconds.max(1e-9) / 1e6
    ));
}

/// The picture of the probes ([`probe_sheet`]) at its exposure.
fn write_probe_sheet(path: &Path, file: &ShvolFile, ball: usize) -> Result<()> {
    let (w, h, pixels) = probe_sheet(&file.view(), ball);
    let exposure = probe_sheet_exposure(&pixels);
    let image = Image::new(w, h, pixels)
        .map_err(|e| PipelineError::new(format!("{}: {e}", path.display())))?;
    let options = WriteOptions {
        exposure_ev: exposure,
        ..WriteOptions::default()
    };
    write_image(path, &image, &options)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_volume::VolumeOptions;

    fn request() -> VolumeRequest<'static> {
        VolumeRequest {
            scene: Path::new("box.obj"),
            env: Path::new("park.exr"),
            output: Some(Path::new("box.shvol")),
            format: None,
            precision: Precision::Half,
            bake: VolumeBakeSettings {
                resolution: [2, 2, 2],
                bounds: None,
                options: VolumeOptions::default(),
                relightable: true,
            },
            preview: None,
            preview_ball: 32,
        }
    }

    #[test]
    fn refusals_name_the_settings_of_each_front_end() {
        let mut deep = request();
        deep.bake.options.lmax = 9;
        let e = deep.check(Spelling::CommandLine).unwrap_err();
        assert_eq!(e.message(), "--lmax 9 is beyond 8, the most a volume holds");
        let e = deep.check(Spelling::Python).unwrap_err();
        assert_eq!(e.message(), "lmax=9 is beyond 8, the most a volume holds");
        let mut empty = request();
        empty.bake.resolution = [0, 2, 2];
        let e = empty.check(Spelling::Python).unwrap_err();
        assert!(e.message().contains("each count must be at least 1"), "{e}");
        let over = VolumeRequest {
            output: Some(Path::new("park.exr")),
            ..request()
        };
        assert!(over.check(Spelling::Python).is_err());
    }

    #[test]
    fn the_format_follows_the_output_unless_given() {
        let plan = VolumeRequest {
            output: Some(Path::new("box.ktx2")),
            ..request()
        }
        .check(Spelling::Python)
        .unwrap();
        assert_eq!(plan.output.unwrap().1, VolumeFormat::Bevy);
    }
}
