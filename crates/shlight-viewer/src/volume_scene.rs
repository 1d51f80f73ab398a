//! [`VolumeScene`]: an irradiance volume with the object moved through it,
//! as `render-mesh --volume` and `view --volume` shade them: relit from the
//! transfer matrices under the (turned) environment, or kept as stored.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Result, bail};
use glam::{DVec3, Vec3};
use shlight_baked::VolumeView;
use shlight_core::sh::ShCoeffs;
use shlight_format::ShvolFile;
use shlight_gpu::{GpuContext, VolumeRenderer, place, wgpu};
use shlight_mesh::Mesh;

/// Whether the probes follow the environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeLight {
    /// Relit from the transfer matrices under the (turned) environment.
    Relit,
    /// `--static`: the stored SH, whatever the environment does.
    Stored,
}

/// A volume read and checked, with its object, before the GPU.
pub struct VolumeScene {
    /// The `.shvol` file (its radiance replaced when relit).
    pub file: ShvolFile,
    /// Its path.
    pub path: PathBuf,
    /// The object moved through the volume.
    pub object: Mesh,
    /// The object's file name (or the bundled bunny's).
    pub object_name: String,
    /// Where the object's bounding-box centre is.
    pub at: Vec3,
    /// The object's bounding-box diagonal.
    pub size: f32,
}

impl VolumeScene {
    /// The volume `file` read from `path` with `object` (named
    /// `object_name`) at `at` [default: the volume box's centre], of
    /// bounding-box diagonal `size` [default: a third of the box's
    /// shortest side].
    ///
    /// # Errors
    /// An `at` that is not finite.
    pub fn new(
        file: ShvolFile,
        path: PathBuf,
        (object, object_name): (Mesh, String),
        at: Option<Vec3>,
        size: Option<f32>,
    ) -> Result<Self> {
        let grid = file.grid();
        let at = at.unwrap_or((grid.min + grid.max) * 0.5);
        if !at.is_finite() {
            bail!("--at {at}: expected finite coordinates");
        }
        let size = size.unwrap_or((grid.max - grid.min).min_element() / 3.0);
        Ok(Self {
            file,
            path,
            object,
            object_name,
            at,
            size,
        })
    }

    /// How the probes meet the environment.
    #[must_use]
    pub fn light(&self) -> VolumeLight {
        if self.file.transfer.is_some() {
            VolumeLight::Relit
        } else {
            VolumeLight::Stored
        }
    }

    /// The grid box.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let grid = self.file.grid();
        (grid.min, grid.max)
    }

    /// Relights a relightable volume under `env` (radiance SH in the
    /// world frame, already turned), returning the time it took; `None`
    /// for a static one (left as stored).
    pub fn relight(&mut self, env: &ShCoeffs<DVec3>) -> Option<Duration> {
        if self.light() == VolumeLight::Stored {
            return None;
        }
        let start = Instant::now();
        let env = env.resized(self.file.lmax);
        shlight_volume::relight_file(&mut self.file, &env).expect("a relightable file");
        Some(start.elapsed())
    }

    /// The probes as the GPU takes them.
    #[must_use]
    pub fn probes(&self) -> VolumeView<'_> {
        self.file.view()
    }

    /// The object's placement at `at`.
    #[must_use]
    pub fn placement(&self, at: Vec3) -> shlight_gpu::VolumeInstance {
        place(self.object.bounds(), at, self.size)
    }

    /// The volume pass for colour targets of `format`: `scene` (if any)
    /// and the object, both of `albedo` where they have no colours.
    ///
    /// # Errors
    /// Probes the GPU cannot hold.
    pub fn renderer(
        &self,
        ctx: &GpuContext,
        format: wgpu::TextureFormat,
        scene: Option<&Mesh>,
        albedo: [f32; 3],
    ) -> Result<VolumeRenderer> {
        let mut r = VolumeRenderer::new(ctx, format, &self.probes())?;
        if let Some(scene) = scene {
            r.set_scene(ctx, scene, albedo);
        }
        r.set_object(ctx, &self.object, albedo, self.placement(self.at));
        Ok(r)
    }
}
