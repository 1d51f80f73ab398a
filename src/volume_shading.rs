//! `--volume FILE.shvol` of `render-mesh` and `view`: the arguments, as
//! the volume's part of shlight-gpu's `SceneOptions` (the scene lit by its
//! baked irradiance volume and a dynamic object moved through it,
//! docs/shvol.md, "Shading"), which checks and reads them.

use std::path::PathBuf;

use clap::Args;
use glam::Vec3;

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

#[cfg(feature = "gpu")]
impl VolumeShadingArgs {
    /// The scene's options with these volume settings, the others at their
    /// defaults.
    pub fn options(&self) -> shlight_gpu::SceneOptions {
        shlight_gpu::SceneOptions {
            volume: self.volume.clone(),
            object: self.object.clone(),
            at: self.at,
            object_size: self.object_size,
            ..shlight_gpu::SceneOptions::default()
        }
    }
}
