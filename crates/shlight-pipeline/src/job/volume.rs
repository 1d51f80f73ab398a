//! `volume`: an irradiance volume baked through a scene under a distant
//! light — relightable SH probes on a grid, relocated out of geometry,
//! with the distance maps of the visibility-weighted lookup, and the
//! scene's punctual lights in the probes' static light — written as a
//! `.shvol` file, its JSON, Bevy's KTX2 or three.js's grid, with a picture
//! of the probes ([`VolumeRequest`] → [`VolumePlan`] → [`volume`], or
//! [`volume_of`] for a scene read already, [`VolumeScene`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use glam::{DVec3, Vec3};
use shlight_baked::ProbeGrid;
use shlight_core::sh::{Frame, ShCoeffs};
use shlight_format::threejs_volume::Precision;
use shlight_format::{ShvolFile, VolumeFormat};
use shlight_io::{Image, WriteOptions, write_image};
use shlight_mesh::{LightKind, LoadOptions, Mesh, MeshFormat, PunctualLight, Scene, Surfaces};
use shlight_volume::{
    BakedFile, Stage, VolumeBake, VolumeBakeSettings, bake_file, probe_sheet, probe_sheet_exposure,
};

use crate::environment::Environment;
use crate::hooks::{Hooks, Progress};
use crate::output_path::refuse_overwriting;
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

/// What a volume is baked through: the scene's mesh, a glTF scene's
/// surfaces (materials with textures) and its punctual lights
/// (`KHR_lights_punctual`, in world space).
#[derive(Clone, Debug)]
pub struct VolumeScene {
    /// The mesh, with its albedo (vertex colours) and emission.
    pub mesh: Mesh,
    /// A glTF scene's surfaces, whose mesh `mesh` is: cut-outs and the
    /// albedo of the texel a ray hits (`None`: the mesh alone).
    pub surfaces: Option<Arc<Surfaces>>,
    /// The punctual lights (none for a format that has no lights).
    pub lights: Vec<PunctualLight>,
}

impl VolumeScene {
    /// A loaded glTF scene as the volume bakes it: its instances flattened
    /// into one world-space mesh with its surfaces ([`Scene::flatten`],
    /// primitives without a material taking `albedo`) and its punctual
    /// lights.
    ///
    /// # Errors
    /// A transform or mesh the flattening refuses.
    pub fn from_scene(scene: &Scene, albedo: [f32; 3]) -> Result<Self> {
        let surfaces = Arc::new(scene.flatten(Vec3::from_array(albedo))?);
        Ok(Self {
            mesh: surfaces.mesh.clone(),
            surfaces: Some(surfaces),
            lights: scene.lights.clone(),
        })
    }

    /// Reads the scene file at `path` (`albedo` for primitives without a
    /// material): a glTF file as a scene ([`shlight_mesh::load_scene`],
    /// then [`VolumeScene::from_scene`]: its surfaces and its punctual
    /// lights from one reading), another format as a mesh.
    ///
    /// # Errors
    /// A file the loader refuses (an invalid light, named).
    pub fn read(path: &Path, albedo: [f32; 3]) -> Result<Self> {
        if MeshFormat::from_path(path) == Some(MeshFormat::Gltf) {
            let scene = shlight_mesh::load_scene(path, &LoadOptions::default())?;
            return Self::from_scene(&scene, albedo);
        }
        Ok(Self {
            mesh: shlight_mesh::load(path)?,
            surfaces: None,
            lights: Vec::new(),
        })
    }
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
        if let Some(e) = self.bake.options.max_edge
            && !(e.is_finite() && e > 0.0)
        {
            return Err(PipelineError::new(format!(
                "{} is not a positive length",
                spelling.option_number("max_edge", e, e)
            )));
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

/// The label of a bake stage's progress (a volume's, or a lightmap's,
/// whose points are texels).
pub(crate) fn stage_label(stage: Stage) -> String {
    match stage {
        Stage::Surface(shlight_prt::Stage::Rays) => "surface rays".into(),
        Stage::Surface(shlight_prt::Stage::Bounce(k)) => format!("bounce {k}"),
        Stage::Surface(shlight_prt::Stage::Matrices) => "matrices".into(),
        Stage::Relocate => "relocate".into(),
        Stage::Probes => "probes".into(),
        Stage::Points => "texels".into(),
    }
}

/// `shlight volume`: reads the light first (a bad light fails before the
/// scene is read; one short of the bake's lmax before it is baked, by
/// shlight-volume's `bake_file`), then the scene ([`VolumeScene::read`]);
/// then as [`volume_of`].
///
/// # Errors
/// A light or scene that cannot be read; a light that stops below the
/// bake's lmax; a grid or options the bake refuses; a file that cannot be
/// written.
pub fn volume(plan: &VolumePlan, hooks: &dyn Hooks) -> Result<BakedFile> {
    let radiance = environment(plan, hooks)?;
    let scene = VolumeScene::read(&plan.scene, plan.bake.options.albedo)?;
    bake_and_write(plan, &radiance, &scene, hooks)
}

/// The volume job through a scene read (or built) already: reads the
/// light; notes the grid and the scene's lights; bakes (progress per
/// stage: the surfaces' rays and bounces, relocation, the probes); notes
/// what was baked and how fast; writes the picture of the probes and the
/// file. The plan's scene path names the scene in notes and the file.
///
/// # Errors
/// As [`volume`], the scene's reading aside.
pub fn volume_of(plan: &VolumePlan, scene: &VolumeScene, hooks: &dyn Hooks) -> Result<BakedFile> {
    let radiance = environment(plan, hooks)?;
    bake_and_write(plan, &radiance, scene, hooks)
}

/// [`volume_of`] through a glTF scene loaded already
/// ([`VolumeScene::from_scene`], primitives without a material taking the
/// plan's albedo), as [`volume`] bakes a glTF path.
///
/// # Errors
/// As [`volume_of`]; a transform or mesh the flattening refuses.
pub fn volume_of_scene(plan: &VolumePlan, scene: &Scene, hooks: &dyn Hooks) -> Result<BakedFile> {
    let lit = VolumeScene::from_scene(scene, plan.bake.options.albedo)?;
    volume_of(plan, &lit, hooks)
}

/// The plan's light as radiance coefficients in the bake's frame, its
/// warnings told.
fn environment(plan: &VolumePlan, hooks: &dyn Hooks) -> Result<ShCoeffs<DVec3>> {
    let light = Environment::load(&plan.env, Frame::YUp, plan.bake.options.lmax)?;
    light.warnings.iter().for_each(|w| hooks.warn(w));
    Ok(light.radiance_in(Frame::YUp))
}

/// [`volume_of`]'s steps after the light is read.
fn bake_and_write(
    plan: &VolumePlan,
    radiance: &ShCoeffs<DVec3>,
    volume_scene: &VolumeScene,
    hooks: &dyn Hooks,
) -> Result<BakedFile> {
    let scene = &volume_scene.mesh;
    let name = plan.scene.display().to_string();
    if scene.report.degenerate_triangles > 0 {
        hooks.warn(&format!(
            "{name}: skipped {} degenerate triangles",
            scene.report.degenerate_triangles
        ));
    }
    let grid = plan.bake.grid(scene)?;
    let [nx, ny, nz] = plan.bake.resolution;
    hooks.note(&format!(
        "{name}: {} triangles, {}; grid {nx}x{ny}x{nz} over {}:{}",
        scene.triangle_count(),
        match (&volume_scene.surfaces, &scene.colors, &scene.emission) {
            (Some(s), _, _) => format!(
                "{} materials and {} textures (albedo per texel)",
                s.materials.len(),
                s.textures.len()
            ),
            (None, Some(_), Some(_)) => "albedo and emission from its materials".into(),
            (None, Some(_), None) => "albedo from its colours".into(),
            (None, None, Some(_)) => "emission from its materials".into(),
            (None, None, None) => "constant albedo".into(),
        },
        grid.min,
        grid.max
    ));
    if let Some(note) = lights_note(&volume_scene.lights, plan) {
        hooks.note(&format!("{name}: {note}"));
    }
    if let Some(note) = volume_scene.surfaces.as_deref().and_then(two_level_note) {
        hooks.note(&format!("{name}: {note}"));
    }
    let start = Instant::now();
    let baked = bake_file(
        scene,
        volume_scene.surfaces.as_ref(),
        &volume_scene.lights,
        &plan.scene,
        radiance,
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

/// The note of a scene's punctual lights: how many of each kind and the
/// units their intensities are read in (`None` without lights).
fn lights_note(lights: &[PunctualLight], plan: &VolumePlan) -> Option<String> {
    if lights.is_empty() {
        return None;
    }
    let count = |f: fn(&LightKind) -> bool| lights.iter().filter(|l| f(&l.kind)).count();
    let units = plan.bake.options.light_units;
    Some(format!(
        "{} punctual light{} ({} point, {} spot, {} directional), intensities {}",
        lights.len(),
        if lights.len() == 1 { "" } else { "s" },
        count(|k| matches!(k, LightKind::Point)),
        count(|k| matches!(k, LightKind::Spot { .. })),
        count(|k| matches!(k, LightKind::Directional)),
        match units {
            shlight_mesh::LightUnits::Blender => "divided by 683 (blender units)",
            shlight_mesh::LightUnits::AsWritten => "as written",
        }
    ))
}

/// The note of a scene whose rays are cast through its unique primitives
/// and their instances ([`shlight_rays::Occluder::casts_two_level`]);
/// `None` when they go through one hierarchy of every triangle.
pub(crate) fn two_level_note(surfaces: &Surfaces) -> Option<String> {
    let scene = surfaces
        .placement
        .as_ref()
        .filter(|_| shlight_rays::Occluder::casts_two_level(surfaces))?;
    let (primitives, unique) = scene.unique_geometry();
    Some(format!(
        "rays cast through its unique geometry ({primitives} primitive{}, {unique} triangles) placed {} times, not through {} flattened triangles",
        if primitives == 1 { "" } else { "s" },
        scene.instances.len(),
        surfaces.mesh.triangle_count()
    ))
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
    fn a_scene_with_a_light_bakes_its_light_and_the_file_records_it() {
        // A hand-built glTF scene: a 4 m floor (y = 0, the default
        // material, albedo 0 so that only the light's direct part is seen)
        // and a white point light of 683 x 10 cd 1 m above its centre; a
        // black sky. The one probe, 0.5 m above the floor, straight under
        // the light, gets E_perp = 10 / 0.5^2 = 40 W/m2 from +Y: its SH
        // are 40 Y_lm(+Y), Y_00 = 1 / (2 sqrt(pi)), Y_1-1 = -sqrt(3 / 4 pi)
        // y, the rest of degree 1 zero.
        use crate::hooks::Collected;
        use shlight_mesh::{Instance, Primitive, generate};
        let dir =
            std::env::temp_dir().join(format!("shlight-volume-lights-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let env = dir.join("black.json");
        let doc = serde_json::json!({
            "format": "shlight-sh", "format_version": 1, "lmax": 2, "frame": "y-up",
            "mirror": false, "quantity": "radiance",
            "coefficients": vec![[0.0; 3]; 9], "provenance": {},
        });
        std::fs::write(&env, doc.to_string()).unwrap();
        let out = dir.join("floor.json");
        let scene = Scene {
            source: "floor.glb".into(),
            primitives: vec![Primitive::new(
                generate::plane(4.0, 1),
                None,
                "mesh 0 primitive 0",
            )],
            instances: vec![Instance {
                primitive: 0,
                transform: glam::Mat4::IDENTITY,
            }],
            lights: vec![PunctualLight {
                name: Some("Lamp".into()),
                kind: LightKind::Point,
                color: Vec3::ONE,
                intensity: 6830.0,
                range: None,
                position: Vec3::new(0.0, 1.0, 0.0),
                direction: Vec3::NEG_Z,
            }],
            ..Scene::default()
        };
        let mut request = VolumeRequest {
            scene: Path::new("floor.glb"),
            env: &env,
            output: Some(&out),
            ..request()
        };
        request.bake = VolumeBakeSettings {
            resolution: [1, 1, 1],
            bounds: Some((Vec3::new(-0.1, 0.4, -0.1), Vec3::new(0.1, 0.6, 0.1))),
            options: VolumeOptions {
                samples: 256,
                surface_samples: 16,
                bounces: 0,
                albedo: [0.0; 3],
                relocate: false,
                visibility_size: 0,
                ..VolumeOptions::default()
            },
            relightable: true,
        };
        let plan = request.check(Spelling::Python).unwrap();
        let lit = VolumeScene::from_scene(&scene, plan.bake.options.albedo).unwrap();
        let hooks = Collected::new();
        let baked = volume_of(&plan, &lit, &hooks).unwrap();
        assert!(
            hooks.notes().iter().any(|n| n
                == "floor.glb: 1 punctual light (1 point, 0 spot, 0 directional), intensities divided by 683 (blender units)"),
            "{:?}",
            hooks.notes()
        );
        let file: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        assert_eq!(
            file["lights"],
            serde_json::json!({"units": "blender", "point": 1, "spot": 0, "directional": 0})
        );
        let y00 = 0.5 / std::f64::consts::PI.sqrt();
        let y1 = -(3.0 / (4.0 * std::f64::consts::PI)).sqrt();
        let want = [40.0 * y00, 40.0 * y1, 0.0, 0.0];
        for (i, w) in want.iter().enumerate() {
            for ch in 0..3 {
                let got = file["coefficients"][0][i][ch].as_f64().unwrap();
                assert!((got - w).abs() <= 1e-5 * 40.0, "row {i}: {got} vs {w}");
            }
        }
        // Relit or not, the light stays: the file's radiance under the black
        // sky is the static part, and so is the bake's.
        assert_eq!(baked.file.radiance, baked.bake.emitted);
        std::fs::remove_dir_all(&dir).unwrap();
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
