//! [`Shot`]: the camera, size and window of a headless frame of a
//! [`Scene`], and [`Scene::render_headless`], which draws it.

use glam::Vec3;
use shlight_core::encoding::Encoding;
use shlight_core::sh::Window;

use shlight_pipeline::{Hooks, Progress};

use super::scene_options::refuse;
use super::scene_renderers::{light_renderer, scene_renderer};
use super::{Scene, SceneError, VolumeLight};
use crate::{Camera, Frame, GpuContext, HEADLESS_FORMAT, Mode, Offscreen, Shading, render_frame};

/// What a headless frame shows of a scene, and at what size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shot {
    /// Where the camera is [default: framing the mesh, [`Camera::aimed`]].
    pub camera: Option<Vec3>,
    /// The point it looks at [default: the centre of the mesh's bounds].
    pub target: Option<Vec3>,
    /// Vertical field of view in degrees, between 1 and 179.
    pub fov_degrees: f32,
    /// The frame's `(width, height)` in pixels.
    pub size: (usize, usize),
    /// The ringing window on the light.
    pub window: Window,
}

impl Shot {
    /// The camera for a mesh of `bounds`, framed or aimed
    /// ([`Camera::aimed`]).
    fn camera(&self, bounds: (Vec3, Vec3), scene: &Scene) -> Result<Camera, SceneError> {
        let (w, h) = self.size;
        match Camera::aimed(
            bounds,
            self.camera,
            self.target,
            self.fov_degrees.to_radians(),
            w as f32 / h as f32,
        ) {
            Some(camera) => Ok(camera),
            None => refuse(format!(
                "{} and {} are the same point",
                scene.spelling.option("camera"),
                scene.spelling.option("target")
            )),
        }
    }
}

impl Scene {
    /// Renders the scene on a headless GPU as `shot` sees it, in linear
    /// `f32` (no exposure, no tone map): the light turned by
    /// [`Scene::rotation`] (and a relightable volume relit under it), the
    /// map background with it; an encoding's snippet made from the light
    /// before it was turned (the renderer turns the normal back).
    ///
    /// # Errors
    /// The light too short for its encoding, no GPU adapter, a scene the
    /// GPU cannot hold, the camera at its target.
    pub fn render_headless(mut self, shot: &Shot, hooks: &dyn Hooks) -> Result<Frame, SceneError> {
        if self.volume.is_some() {
            return self.render_volume(shot, hooks);
        }
        let snippet = match self.encoding {
            Encoding::Sh => None,
            encoding => {
                hooks.progress(Progress::Step(&format!("encoding the light as {encoding}")));
                let (encoded, snippet) = self.light.encoded_light(encoding, self.lmax)?;
                if matches!(encoding, Encoding::DominantSh | Encoding::SloanSh) {
                    hooks.note(&format!(
                        "{encoding}: {} light(s) kept apart from the SH",
                        encoded.lights().len()
                    ));
                }
                Some(snippet)
            }
        };
        self.light.radiance = self.turned_radiance(self.rotation);
        hooks.progress(Progress::Step("opening the GPU"));
        let ctx = GpuContext::headless()?;
        let mut renderer = scene_renderer(&ctx, HEADLESS_FORMAT, &self)?;
        renderer.set_environment_rotation(self.rotation);
        if let Some(snippet) = &snippet {
            renderer.set_encoding(&ctx, snippet)?;
        }
        let camera = shot.camera(self.mesh.bounds(), &self)?;
        let shading = Shading {
            mode: match self.mode {
                Mode::Sh if snippet.is_some() => Mode::Encoded,
                mode => mode,
            },
            lmax: self.lmax,
            window: shot.window,
            exposure_ev: 0.0,
            tone_map: None,
            albedo: self.albedo(self.mode),
            background: self.background,
        };
        let held = self.light.radiance.lmax();
        if held < self.lmax {
            hooks.note(&format!(
                "{} holds lmax {held}; shading to lmax {held}",
                self.light.path.display()
            ));
        }
        let (w, h) = shot.size;
        hooks.progress(Progress::Step(&format!(
            "rendering {w}x{h} on {}",
            ctx.adapter_name()
        )));
        Ok(render_frame(&ctx, &renderer, &camera, &shading, w, h)?)
    }

    /// [`Scene::render_headless`] with a volume: the mesh and the object
    /// lit per fragment by the probes, over the light's background.
    fn render_volume(mut self, shot: &Shot, hooks: &dyn Hooks) -> Result<Frame, SceneError> {
        self.light.radiance = self.turned_radiance(self.rotation);
        let mut volume = self.volume.take().expect("a scene with a volume");
        match volume.light() {
            VolumeLight::Stored => hooks.note(&format!(
                "{}: static volume, its stored light is shown ({} is the background only)",
                volume.path.display(),
                self.spelling.option("env")
            )),
            VolumeLight::Relit => {
                let held = self.light.radiance.lmax();
                if held < volume.file.lmax {
                    hooks.note(&format!(
                        "{} holds lmax {held}; the volume's lmax {} is relit with the higher bands zero",
                        self.light.path.display(),
                        volume.file.lmax
                    ));
                }
                volume.relight(&self.light.radiance);
            }
        }
        hooks.progress(Progress::Step("opening the GPU"));
        let ctx = GpuContext::headless()?;
        let mut background = light_renderer(&ctx, HEADLESS_FORMAT, &self.light);
        background.set_environment_rotation(self.rotation);
        let albedo = self.albedo(Mode::Sh);
        let shaded = volume.renderer(&ctx, HEADLESS_FORMAT, Some(self.geometry()), albedo)?;
        let camera = shot.camera(self.mesh.bounds(), &self)?;
        let shading = Shading {
            mode: Mode::Sh,
            lmax: self.lmax,
            window: shot.window,
            exposure_ev: 0.0,
            tone_map: None,
            albedo,
            background: self.background,
        };
        let (w, h) = shot.size;
        hooks.progress(Progress::Step(&format!(
            "rendering {w}x{h} on {}",
            ctx.adapter_name()
        )));
        let target = Offscreen::new(&ctx, w, h)?;
        let aspect = target.aspect();
        let frame = target
            .render_with(&ctx, true, |encoder, color, depth| {
                background.draw(&ctx, encoder, color, depth, &camera, aspect, &shading)?;
                shaded.draw(
                    &ctx, encoder, color, depth, &camera, aspect, &shading, false,
                );
                Ok(())
            })?
            .expect("read back");
        Ok(frame)
    }
}
