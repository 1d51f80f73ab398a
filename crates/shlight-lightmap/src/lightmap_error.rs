//! Why a scene's lightmap was not baked.

use shlight_mesh::MeshError;
use shlight_volume::VolumeError;

/// Why [`bake_scene_lightmap`](crate::bake_scene_lightmap) refused.
#[derive(Debug, thiserror::Error)]
pub enum LightmapError {
    /// A primitive has no such UV set.
    #[error("{label} has no UV set {uv_set} (TEXCOORD_{uv_set}) to lay a lightmap on")]
    NoUvs {
        /// The primitive, as the scene names it.
        label: String,
        /// The UV set asked for.
        uv_set: usize,
    },
    /// A mesh's lightmap UVs cannot hold a lightmap.
    #[error("{label}: {message}")]
    Uv {
        /// The primitive, as the scene names it.
        label: String,
        /// What is wrong.
        message: String,
    },
    /// The size, density or padding asked for.
    #[error("{0}")]
    Settings(String),
    /// The scene could not be laid out (a transform, no triangles).
    #[error(transparent)]
    Scene(MeshError),
    /// The light could not be gathered.
    #[error(transparent)]
    Gather(VolumeError),
}
