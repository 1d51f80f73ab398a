//! The scene `shlight render-mesh` and `shlight view` shade, read from
//! shlight's files and checked once for every front end, and its headless
//! frame.
//!
//! - [`SceneOptions`]: the settings as a front end was given them;
//!   [`SceneOptions::check`] refuses those that do not go together before
//!   any file is read (a volume with a transfer, PRT mode without one, an
//!   encoding outside SH mode, lmax beyond what the GPU shades, ...),
//!   naming them as the front end spells them
//!   ([`shlight_pipeline::Spelling`]), and makes the [`SceneSettings`].
//! - [`Scene`]: [`Scene::read`] reads the mesh (a `.gltf`/`.glb` file as
//!   a [`GltfScene`]: its primitives, instances, materials and textures,
//!   and their flattening, the mesh the baked files are checked against),
//!   its `.shprt` transfer
//!   (checked against the mesh), the light (shlight-pipeline's
//!   [`Environment`](shlight_pipeline::Environment): a map projected, or a
//!   coefficient file) and a [`SceneVolume`] (a `.shvol` file and the
//!   object moved through it, relit by shlight-volume's `relight_file`),
//!   and refuses what the files rule out (a map background or
//!   `dominant+sh` without a map, a static volume turned). [`BuiltIn`]
//!   holds the mesh and map a front end uses when none is named.
//! - [`scene_renderer`], [`mesh_renderer`], [`gltf_renderer`] and
//!   [`light_renderer`]: the [`Renderer`](crate::Renderer) of the scene, of
//!   a mesh, its transfer (diffuse vectors with a scene's static term,
//!   [`static_radiance`], or glossy matrices with their lobe from
//!   shlight-prt's `Brdf`) and a light, of a glTF scene (its primitives
//!   per instance with their materials; flattened under a diffuse
//!   transfer, taken per unit albedo: [`per_unit_albedo`]), or of
//!   the light alone; [`SceneVolume::renderer`] the volume's pass over a
//!   [`SceneGeometry`].
//! - [`Scene::render_headless`]: one frame as a [`Shot`] sees it;
//!   [`RenderMeshRequest`] and [`render_mesh`]: read, render and write
//!   (every step of `render-mesh`), progress, warnings and notes told to
//!   shlight-pipeline's `Hooks`.
//!
//! Files: `scene_options.rs`, `scene.rs`, `gltf_scene.rs`, `scene_volume.rs`,
//! `transfer_file.rs` (a `.shprt` file on its mesh), `scene_renderers.rs`,
//! `shot.rs`, `render_mesh.rs`, `built_in.rs`,
//! `scene_error.rs`. The renderers outside this module know no file
//! format: they take meshes, texel slices and shlight-baked's views.

mod built_in;
mod gltf_scene;
mod render_mesh;
#[allow(clippy::module_inception)]
mod scene;
mod scene_error;
mod scene_options;
mod scene_renderers;
mod scene_volume;
mod shot;
mod transfer_file;

pub use built_in::BuiltIn;
pub use gltf_scene::{GltfScene, SceneGeometry};
pub use render_mesh::{RenderMeshRequest, RenderMeshSettings, render_mesh, write_frame};
pub use scene::{Scene, SceneLightmap};
pub use scene_error::SceneError;
pub use scene_options::{SceneOptions, SceneSettings};
pub use scene_renderers::{gltf_renderer, light_renderer, mesh_renderer, scene_renderer};
pub use scene_volume::{SceneVolume, VolumeLight};
pub use shot::Shot;
pub use transfer_file::{per_unit_albedo, read_transfer, set_transfer, static_radiance};
