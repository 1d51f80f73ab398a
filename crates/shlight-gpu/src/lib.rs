//! GPU band-limited shading for shlight (wgpu, WGSL in `shaders/`).
//!
//! - [`GpuContext`]: an adapter and device, headless or for a window;
//! - [`Renderer`]: a mesh lit by SH radiance coefficients `L_lm`, shaded
//!   per fragment as a Lambertian surface, `ρ/π Σ_l A_l w_l Σ_m L_lm Y_lm(n)`
//!   (Ramamoorthi & Hanrahan 2001; `A_l` the clamped-cosine eigenvalues,
//!   `w_l` a run-time window, any lmax up to 8), or by PRT transfer vectors
//!   `Σ_i T_vi L_i` per vertex ([`shlight_baked::TransferView`]), or as world normals; with the
//!   environment map or its SH reconstruction behind; or a glTF scene in
//!   place of the mesh ([`Renderer::set_scene`]: each unique primitive once
//!   per instance, the albedo per fragment from its material, textures
//!   sRGB-decoded and mip-mapped, `MASK` and `BLEND` cut-outs, double-sided
//!   faces; [`Renderer::set_surfaces`], the scene flattened, for PRT);
//! - [`VolumeRenderer`]: a scene and a dynamic object lit per fragment by
//!   trilinear interpolation of an irradiance volume's valid probes (any
//!   lmax up to [`shlight_baked::SHADED_MAX_LMAX`]), each weighted by its
//!   visibility of the point where the volume holds distance maps, and the
//!   probes as spheres;
//! - [`Offscreen`] / [`render_frame`]: frames read back as linear `f32` RGBA;
//!   [`read_srgb8_texture`]: a window's 8-bit sRGB texture as linear RGB;
//! - [`Camera`] (a look-at perspective camera; [`Camera::framing`] and
//!   [`Camera::aimed`] place it for a mesh's bounds) and [`OrbitCamera`]
//!   (yaw, pitch and distance about a target);
//! - [`GpuProjector`]: equirect maps to SH by exact texel-solid-angle
//!   quadrature, the GPU twin of shlight-core's `project_equirect`;
//! - the scene `render-mesh` and the viewer shade (`scene/`): [`SceneOptions`]
//!   and its [`check`](SceneOptions::check), the same refusals for every
//!   front end; [`Scene`] read from shlight's files (a mesh or a glTF
//!   scene, [`GltfScene`], its `.shprt` transfer, a light, a `.shvol`
//!   volume with an object moved through it); [`scene_renderer`],
//!   [`mesh_renderer`], [`gltf_renderer`] and [`light_renderer`];
//!   [`render_mesh`], every step of a headless frame written to an image.
//!
//! The renderers take meshes, texel slices and shlight-baked's views; the
//! scene module alone reads files (shlight-format's `.shprt` and `.shvol`,
//! the light through shlight-pipeline).
//!
//! Conventions are shlight's (docs/conventions.md): real orthonormal SH with
//! the Condon-Shortley phase, index `l(l+1)+m`, world `(x, y, z)`.
//! Only the Vulkan backend is built (a GPU's driver, or Mesa's lavapipe).

mod camera;
mod context;
mod error;
mod glossy_expansion;
mod gpu_material;
mod headless;
mod mip_chain;
mod orbit_camera;
mod pipeline;
mod projector;
mod readback;
mod renderer;
mod ring_sums;
mod scene;
mod scene_draws;
mod sh_expansion;
pub mod shaders;
mod shading;
mod surface_pipelines;
mod volume;
mod volume_expansion;
mod volume_fetch;

pub use camera::{Camera, DEFAULT_FOV_Y_DEGREES, DEFAULT_VIEW_FROM};
pub use context::{GpuContext, new_instance};
pub use error::GpuError;
pub use headless::{Frame, HEADLESS_FORMAT, Offscreen, depth_view, render_frame};
pub use orbit_camera::OrbitCamera;
pub use pipeline::DEPTH_FORMAT;
pub use projector::{GpuProjector, project_equirect};
pub use readback::{read_buffer, read_srgb8_texture};
pub use renderer::{GlossyLobe, LightmapTexels, Renderer};
pub use scene::{
    BuiltIn, GltfScene, RenderMeshRequest, RenderMeshSettings, Scene, SceneError, SceneGeometry,
    SceneLightmap, SceneOptions, SceneSettings, SceneVolume, Shot, VolumeLight, gltf_renderer,
    light_renderer, mesh_renderer, per_unit_albedo, read_transfer, render_mesh, scene_renderer,
    set_transfer, static_radiance, write_frame,
};
pub use shading::{Background, Mode, Shading};
pub use volume::{
    PROBE_SPHERE_RADIUS, ProbeTexels, VolumeInstance, VolumeRenderer, check_visibility_limits,
    pack_texels, place, probe_sphere_instances,
};
pub use volume_fetch::VolumeFetch;
/// wgpu, as this crate uses it (for windows and surfaces).
pub use wgpu;
