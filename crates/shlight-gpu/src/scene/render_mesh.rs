//! [`RenderMeshRequest`]: one headless frame of a scene written to an
//! image (`shlight render-mesh`), its [`RenderMeshRequest::check`], and
//! [`render_mesh`], which runs every step.

use std::path::PathBuf;

use shlight_io::{Format, Image, ToneMap, WriteOptions, write_image};
use shlight_pipeline::Spelling;

use shlight_pipeline::Hooks;

use super::scene_options::refuse;
use super::{BuiltIn, Scene, SceneError, SceneOptions, SceneSettings, Shot};
use crate::{Frame, GpuError};

/// A headless frame's settings as a front end was given them.
#[derive(Clone, Debug)]
pub struct RenderMeshRequest {
    /// What is shaded.
    pub scene: SceneOptions,
    /// What the frame shows of it.
    pub shot: Shot,
    /// PNG only: exposure in stops.
    pub exposure: f32,
    /// PNG only: the tone map.
    pub tone_map: ToneMap,
    /// The image written: `.exr` (linear) or `.png`.
    pub output: PathBuf,
}

/// A [`RenderMeshRequest`] checked ([`RenderMeshRequest::check`]), for
/// [`render_mesh`].
#[derive(Clone, Debug)]
pub struct RenderMeshSettings {
    /// The scene's settings, checked.
    pub scene: SceneSettings,
    /// What the frame shows.
    pub shot: Shot,
    /// The output's format: EXR or PNG.
    pub format: Format,
    /// PNG only: exposure in stops.
    pub exposure: f32,
    /// PNG only: the tone map.
    pub tone_map: ToneMap,
    /// The image written.
    pub output: PathBuf,
}

impl RenderMeshRequest {
    /// The settings of [`render_mesh`], after the checks every front end
    /// makes before a file is read: the output is an `.exr` or `.png`
    /// file; the scene's checks ([`SceneOptions::check`]); the field of
    /// view lies between 1 and 179 degrees.
    ///
    /// # Errors
    /// The first check that fails, naming the settings as `spelling` does.
    pub fn check(&self, spelling: Spelling) -> Result<RenderMeshSettings, SceneError> {
        let format = match Format::from_extension(&self.output) {
            Some(format @ (Format::Exr | Format::Png)) => format,
            _ => {
                return refuse(format!(
                    "{}: render-mesh writes .exr (linear) or .png",
                    self.output.display()
                ));
            }
        };
        let scene = self.scene.check(spelling)?;
        let fov = self.shot.fov_degrees;
        if !(fov > 1.0 && fov < 179.0) {
            return refuse(format!(
                "{}: expected degrees between 1 and 179",
                spelling.option_number("fov", fov, fov)
            ));
        }
        let settings = RenderMeshSettings {
            scene,
            shot: self.shot,
            format,
            exposure: self.exposure,
            tone_map: self.tone_map,
            output: self.output.clone(),
        };
        shlight_pipeline::refuse_overwriting(&self.output, &settings.inputs())?;
        Ok(settings)
    }
}

impl RenderMeshSettings {
    /// The files read: the mesh, the light, the transfer, the volume and
    /// its object (the output is never one of them).
    #[must_use]
    pub fn inputs(&self) -> Vec<PathBuf> {
        let o = &self.scene.options;
        [&o.mesh, &o.env, &o.prt, &o.volume, &o.object]
            .into_iter()
            .flatten()
            .cloned()
            .collect()
    }
}

/// Every step of `render-mesh`: the scene read and checked
/// ([`Scene::read`], the built-in files where none is named), drawn on a
/// headless GPU ([`Scene::render_headless`]) and written to
/// [`RenderMeshSettings::output`] ([`write_frame`]).
///
/// # Errors
/// As [`Scene::read`], [`Scene::render_headless`] and [`write_frame`].
pub fn render_mesh(
    settings: &RenderMeshSettings,
    built_in: &BuiltIn<'_>,
    hooks: &dyn Hooks,
) -> Result<(), SceneError> {
    let scene = Scene::read(&settings.scene, built_in, hooks)?;
    let frame = scene.render_headless(&settings.shot, hooks)?;
    write_frame(settings, &frame)
}

/// Writes `frame` to [`RenderMeshSettings::output`]: linear for EXR, with
/// the exposure and the tone map for PNG.
///
/// # Errors
/// A file that cannot be written, naming it.
pub fn write_frame(settings: &RenderMeshSettings, frame: &Frame) -> Result<(), SceneError> {
    let image = Image::new(frame.width, frame.height, frame.rgb())
        .map_err(|e| GpuError::Invalid(e.to_string()))?;
    let options = match settings.format {
        Format::Png => WriteOptions {
            exposure_ev: settings.exposure,
            tone_map: settings.tone_map,
            ..WriteOptions::default()
        },
        _ => WriteOptions::default(),
    };
    write_image(&settings.output, &image, &options).map_err(|source| SceneError::Write {
        path: settings.output.clone(),
        source,
    })
}
