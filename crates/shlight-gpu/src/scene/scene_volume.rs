//! [`SceneVolume`]: an irradiance volume with the object moved through
//! it, as `render-mesh --volume` and `view --volume` shade them: relit
//! from the transfer matrices under the (turned) light, or kept as stored
//! ([`VolumeLight`]).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::{DVec3, Vec3};
use shlight_baked::{SHADED_MAX_LMAX, VolumeView};
use shlight_core::sh::ShCoeffs;
use shlight_format::ShvolFile;
use shlight_mesh::Mesh;

use shlight_pipeline::Hooks;

use super::scene_options::refuse;
use super::{BuiltIn, SceneError, SceneGeometry, SceneOptions};
use crate::{GpuContext, GpuError, VolumeInstance, VolumeRenderer, place};

/// Whether the probes follow the light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeLight {
    /// Relit from the transfer matrices under the (turned) light.
    Relit,
    /// Baked static: the stored SH, whatever the light does.
    Stored,
}

/// A volume read and checked, with its object.
#[derive(Clone, Debug)]
pub struct SceneVolume {
    /// The `.shvol` file (its radiance replaced when relit).
    pub file: ShvolFile,
    /// Its path.
    pub path: PathBuf,
    /// The object moved through the volume.
    pub object: Mesh,
    /// The object's file name (or the built-in mesh's).
    pub object_name: String,
    /// Where the object's bounding-box centre is.
    pub at: Vec3,
    /// The object's bounding-box diagonal.
    pub size: f32,
}

impl SceneVolume {
    /// Reads the volume `options` name and its object (the built-in mesh
    /// where none is named), warning when `scene` (called `scene_name`) is
    /// not the mesh the volume was baked in and noting a volume above the
    /// shading lmax, then what was read.
    ///
    /// # Errors
    /// A missing, unreadable or invalid file.
    pub(super) fn read(
        path: &Path,
        options: &SceneOptions,
        (scene, scene_name): (&Mesh, &Path),
        built_in: &BuiltIn<'_>,
        hooks: &dyn Hooks,
    ) -> Result<Self, SceneError> {
        if !path.exists() {
            return refuse(format!("{}: no such volume file", path.display()));
        }
        let file = ShvolFile::read(path)?;
        let name = path.display();
        if file.scene_hash != scene.content_hash() {
            hooks.warn(&format!(
                "{name} was baked in {} (fnv1a64:{:016x}), not in {} (fnv1a64:{:016x}): its light does not match this scene",
                file.scene,
                file.scene_hash,
                scene_name.display(),
                scene.content_hash()
            ));
        }
        if file.lmax > SHADED_MAX_LMAX {
            hooks.note(&format!(
                "{name} holds lmax {}; the GPU shades volumes to lmax {SHADED_MAX_LMAX}",
                file.lmax
            ));
        }
        let (object, object_name) = match &options.object {
            Some(p) => (shlight_mesh::load(p)?, p.display().to_string()),
            None => (built_in.mesh()?, built_in.mesh_name.to_string()),
        };
        let grid = file.grid();
        let volume = Self {
            at: options.at.unwrap_or((grid.min + grid.max) * 0.5),
            size: options
                .object_size
                .unwrap_or((grid.max - grid.min).min_element() / 3.0),
            file,
            path: path.to_path_buf(),
            object,
            object_name,
        };
        let file = &volume.file;
        let valid = file.valid.iter().filter(|v| **v).count();
        hooks.note(&format!(
            "{name}: {}x{}x{} probes ({valid} valid of {}), lmax {}, {}",
            file.resolution[0],
            file.resolution[1],
            file.resolution[2],
            file.valid.len(),
            file.lmax,
            if file.transfer.is_some() {
                "relightable"
            } else {
                "static"
            }
        ));
        Ok(volume)
    }

    /// How the probes meet the light.
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

    /// The lmax the probes are shaded at: the volume's, at most
    /// [`SHADED_MAX_LMAX`].
    #[must_use]
    pub fn shaded_lmax(&self) -> usize {
        self.file.lmax.min(SHADED_MAX_LMAX)
    }

    /// Relights a relightable volume under `radiance` (SH in the world
    /// frame, already turned), returning the time it took; `None` for a
    /// static one (left as stored).
    pub fn relight(&mut self, radiance: &ShCoeffs<DVec3>) -> Option<Duration> {
        if self.light() == VolumeLight::Stored {
            return None;
        }
        let start = Instant::now();
        let radiance = radiance.resized(self.file.lmax);
        shlight_volume::relight_file(&mut self.file, &radiance).expect("a relightable file");
        Some(start.elapsed())
    }

    /// The probes as the GPU takes them.
    #[must_use]
    pub fn probes(&self) -> VolumeView<'_> {
        self.file.view()
    }

    /// The object's placement at `at`.
    #[must_use]
    pub fn placement(&self, at: Vec3) -> VolumeInstance {
        place(self.object.bounds(), at, self.size)
    }

    /// The volume pass for colour targets of `format`: `scene` (if any; a
    /// glTF scene with its materials, textures and instances) and the
    /// object, both of `albedo` where they have no colours or material.
    ///
    /// # Errors
    /// Probes the GPU cannot hold, a glTF scene it refuses.
    pub fn renderer(
        &self,
        ctx: &GpuContext,
        format: wgpu::TextureFormat,
        scene: Option<SceneGeometry<'_>>,
        albedo: [f32; 3],
    ) -> Result<VolumeRenderer, GpuError> {
        let mut r = VolumeRenderer::new(ctx, format, &self.probes())?;
        match scene {
            Some(SceneGeometry::Mesh(mesh)) => r.set_scene(ctx, mesh, albedo),
            Some(SceneGeometry::Gltf(gltf)) => {
                r.set_scene_surfaces(ctx, &gltf.scene, gltf.default_albedo)?;
            }
            None => {}
        }
        r.set_object(ctx, &self.object, albedo, self.placement(self.at));
        Ok(r)
    }
}
