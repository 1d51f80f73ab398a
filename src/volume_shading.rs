//! `--volume FILE.shvol` of `render-mesh` and `view`: the scene lit by its
//! baked irradiance volume and a dynamic object moved through it, both
//! shaded per fragment by trilinear interpolation of the valid probes on
//! the GPU (shlight-gpu's `VolumeRenderer`; docs/shvol.md, "Shading").
//!
//! A relightable volume is relit on the CPU from its transfer matrices
//! under `--env`, turned by the environment's rotation
//! (`L_probe = M R(L_env) + L_emitted`, shlight-volume's `relight_file`);
//! a `--static` one keeps its stored SH, and turning the environment is
//! refused (`render-mesh --rotate`) or moves only the background (`view`).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use glam::Vec3;
use shlight_baked::SHADED_MAX_LMAX;

/// The volume options shared by `render-mesh` and `view`.
#[derive(Args, Debug, Clone, Default)]
pub struct VolumeShadingArgs {
    /// An irradiance volume baked through MESH by `shlight volume`
    /// (.shvol): MESH and --object are lit per fragment by its probes
    /// (lmax clipped to 4).
    #[arg(long, value_name = "FILE.shvol")]
    pub volume: Option<PathBuf>,
    /// With --volume: the dynamic object moved through the volume (OBJ,
    /// PLY, OFF, glTF/GLB) [default: the Stanford bunny, meshes/bunny.obj,
    /// built into shlight].
    #[arg(long, value_name = "MESH")]
    pub object: Option<PathBuf>,
    /// With --volume: where the object's bounding-box centre goes, X,Y,Z
    /// [default: the volume's centre].
    #[arg(long, value_parser = crate::values::parse_vec3_f32, allow_hyphen_values = true)]
    pub at: Option<Vec3>,
    /// With --volume: the object's bounding-box diagonal, in scene units
    /// [default: a third of the volume box's shortest side].
    #[arg(long)]
    pub object_size: Option<f32>,
}

impl VolumeShadingArgs {
    /// Refuses the object options without `--volume`, a volume that is not
    /// a `.shvol` file, an `--lmax` beyond [`SHADED_MAX_LMAX`] and a
    /// size that is not positive.
    ///
    /// # Errors
    /// As above, naming the option or the file.
    pub fn check(&self, lmax: Option<usize>) -> Result<()> {
        let Some(path) = &self.volume else {
            for (given, name) in [
                (self.object.is_some(), "--object"),
                (self.at.is_some(), "--at"),
                (self.object_size.is_some(), "--object-size"),
            ] {
                if given {
                    bail!(
                        "{name} places an object in an irradiance volume: it needs --volume FILE.shvol"
                    );
                }
            }
            return Ok(());
        };
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("shvol"))
        {
            bail!(
                "{}: --volume takes a .shvol file (bake one with shlight volume SCENE --env LIGHT -o FILE.shvol)",
                path.display()
            );
        }
        if let Some(l) = lmax.filter(|&l| l > SHADED_MAX_LMAX) {
            bail!("--lmax {l}: volumes are shaded to lmax {SHADED_MAX_LMAX} at most");
        }
        if let Some(s) = self.object_size
            && !(s.is_finite() && s > 0.0)
        {
            bail!("--object-size {s}: expected a positive length");
        }
        Ok(())
    }
}

#[cfg(feature = "gpu")]
pub use gpu::{VolumeInput, VolumeLight};

#[cfg(feature = "gpu")]
mod gpu {
    use std::path::{Path, PathBuf};
    use std::time::{Duration, Instant};

    use anyhow::{Result, bail};
    use glam::{DVec3, Vec3};
    use shlight_baked::VolumeView;
    use shlight_core::sh::ShCoeffs;
    use shlight_format::ShvolFile;
    use shlight_gpu::{GpuContext, VolumeRenderer, place, wgpu};
    use shlight_mesh::Mesh;

    use super::VolumeShadingArgs;
    use crate::progress::Ui;

    /// Whether the probes follow the environment.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum VolumeLight {
        /// Relit from the transfer matrices under the (turned) environment.
        Relit,
        /// `--static`: the stored SH, whatever the environment does.
        Stored,
    }

    /// A volume read and checked, with its object, before the GPU.
    pub struct VolumeInput {
        /// The `.shvol` file (its radiance replaced when relit).
        pub file: ShvolFile,
        /// Its path.
        pub path: PathBuf,
        /// The object and its name.
        pub object: Mesh,
        /// The object's file name (or the bundled bunny's).
        pub object_name: String,
        /// Where the object's bounding-box centre is.
        pub at: Vec3,
        /// The object's bounding-box diagonal.
        pub size: f32,
    }

    impl VolumeInput {
        /// Reads `--volume` and `--object`, warns when `scene` is not the
        /// mesh the volume was baked in and notes a volume above the
        /// shading lmax.
        ///
        /// # Errors
        /// An unreadable or invalid file.
        pub fn load(
            args: &VolumeShadingArgs,
            scene: &Mesh,
            scene_name: &Path,
            ui: &Ui,
        ) -> Result<Self> {
            let path = args
                .volume
                .clone()
                .expect("VolumeInput::load is called with --volume");
            if !path.exists() {
                bail!("{}: no such volume file", path.display());
            }
            let file = ShvolFile::read(&path)?;
            let name = path.display();
            if file.scene_hash != scene.content_hash() {
                ui.warn(format!(
                    "{name} was baked in {} (fnv1a64:{:016x}), not in {} (fnv1a64:{:016x}): its light does not match this scene",
                    file.scene,
                    file.scene_hash,
                    scene_name.display(),
                    scene.content_hash()
                ));
            }
            if file.lmax > shlight_baked::SHADED_MAX_LMAX {
                ui.note(format!(
                    "{name} holds lmax {}; the GPU shades volumes to lmax {}",
                    file.lmax,
                    shlight_baked::SHADED_MAX_LMAX
                ));
            }
            let (object, object_name) = match &args.object {
                Some(p) => (shlight_mesh::load(p)?, p.display().to_string()),
                None => (
                    crate::bundled::mesh()?,
                    crate::bundled::MESH_NAME.to_string(),
                ),
            };
            let (lo, hi) = (file.grid().min, file.grid().max);
            let at = args.at.unwrap_or((lo + hi) * 0.5);
            if !at.is_finite() {
                bail!("--at {at}: expected finite coordinates");
            }
            let size = args.object_size.unwrap_or((hi - lo).min_element() / 3.0);
            let valid = file.valid.iter().filter(|v| **v).count();
            ui.note(format!(
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
        pub fn light(&self) -> VolumeLight {
            if self.file.transfer.is_some() {
                VolumeLight::Relit
            } else {
                VolumeLight::Stored
            }
        }

        /// The grid box.
        pub fn bounds(&self) -> (Vec3, Vec3) {
            let grid = self.file.grid();
            (grid.min, grid.max)
        }

        /// Relights a relightable volume under `env` (radiance SH in the
        /// world frame, already turned), returning the time it took;
        /// `None` for a static one (left as stored).
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
        pub fn probes(&self) -> VolumeView<'_> {
            self.file.view()
        }

        /// The object's placement at `at`.
        pub fn placement(&self, at: Vec3) -> shlight_gpu::VolumeInstance {
            place(self.object.bounds(), at, self.size)
        }

        /// The volume pass for colour targets of `format`: `scene` (if
        /// any) and the object, both of `albedo` where they have no
        /// colours.
        ///
        /// # Errors
        /// Probes the GPU cannot take.
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(feature = "gpu")]
    #[test]
    fn object_options_need_a_volume_and_a_volume_needs_its_extension() {
        let object = VolumeShadingArgs {
            object: Some("bunny.obj".into()),
            ..Default::default()
        };
        let e = object.check(None).unwrap_err().to_string();
        assert!(e.contains("--object") && e.contains("--volume"), "{e}");
        let wrong = VolumeShadingArgs {
            volume: Some("room.json".into()),
            ..Default::default()
        };
        let e = wrong.check(None).unwrap_err().to_string();
        assert!(e.contains("room.json") && e.contains(".shvol"), "{e}");
        let right = VolumeShadingArgs {
            volume: Some("room.shvol".into()),
            ..Default::default()
        };
        assert!(right.check(Some(4)).is_ok());
        let e = right.check(Some(5)).unwrap_err().to_string();
        assert!(e.contains("--lmax 5") && e.contains("lmax 4"), "{e}");
    }
}
