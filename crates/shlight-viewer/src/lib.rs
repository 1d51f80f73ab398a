//! What shlight shows on the GPU beyond a single renderer: the window of
//! `shlight view` (winit events, the wgpu surface, shlight-gpu's renderers
//! and an egui overlay) and the scenes `render-mesh` and the viewer hand the
//! GPU.
//!
//! - [`run`]: opens the window on a [`ViewerScene`] with the
//!   [`ViewerOptions`] and runs its event loop until it closes (or, with
//!   `screenshot`, until the frame is saved). Left drag orbits the camera
//!   (shlight-gpu's `OrbitCamera`), right drag (or shift + left drag, or
//!   the arrow keys) turns the environment: its radiance coefficients
//!   rotated on the CPU every frame (`ShRotation`, lmax 8) and the map
//!   background with them. Keys: `0`-`8` lmax, `m` mode, `e` the light's
//!   encoding (each compiled into the fragment shader as its WGSL snippet,
//!   the normal turned back by the environment's rotation), `b`
//!   background, `w` window, `t` tone map, `+`/`-` exposure, `p`
//!   screenshot, `h` panel, `Esc`/`q` quit; with a volume, `j`/`l`,
//!   `u`/`o`, `i`/`k` move the object and `g` shows the probes.
//! - [`VolumeScene`]: an irradiance volume with the object moved through
//!   it, relit from its transfer matrices under the turned environment
//!   (`L_probe = M R(L_env) + L_emitted`, shlight-volume's `relight_file`)
//!   or kept as stored (`--static`, [`VolumeLight`]).
//! - [`renderer`], [`background_renderer`], [`shading_lmax`],
//!   [`check_lmax`]: a mesh, its PRT transfer and an environment made into
//!   shlight-gpu's `Renderer`, as both commands do.
//!
//! Files: `app.rs` (the window, the surface and the event loop),
//! `controls.rs` (what the panel and keys change), `panel.rs` (the egui
//! overlay), `screenshot.rs` (the swapchain image read back to PNG),
//! `view_volume.rs` (the volume in the window), `volume_scene.rs`,
//! `scene_renderer.rs`.
//!
//! **Architecture invariant:** no command line: options come in as
//! values, and nothing is printed; files are read by the caller.

mod app;
mod controls;
mod panel;
mod scene_renderer;
mod screenshot;
mod view_volume;
mod volume_scene;

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use shlight_core::encoding::Encoding;
use shlight_io::ToneMap;
use shlight_mesh::Mesh;
use shlight_pipeline::Environment;

pub use scene_renderer::{background_renderer, check_lmax, renderer, shading_lmax};
pub use volume_scene::{VolumeLight, VolumeScene};

/// How the viewer starts (each can be changed in the window but the size).
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// Highest SH degree shown at start [default: 2; with PRT, the
    /// transfer's lmax, at most 8; with a volume, its lmax, at most 4].
    pub lmax: Option<usize>,
    /// The light's encoding at start.
    pub encoding: Encoding,
    /// Exposure in stops at start.
    pub exposure: f32,
    /// Tone map at start.
    pub tone_map: ToneMap,
    /// Window size in pixels, `(width, height)`.
    pub size: (usize, usize),
    /// Render `frames` frames, save the last to this PNG and close.
    pub screenshot: Option<PathBuf>,
    /// Frames rendered before `screenshot` saves.
    pub frames: u32,
    /// Start with the overlay panel hidden.
    pub hide_panel: bool,
    /// Lambertian albedo, linear RGB [default: 0.8 each]; with a glossy
    /// PRT file, the diffuse base under its glossy layer [default: none,
    /// the glossy layer alone], as `shlight render-mesh --albedo`.
    pub albedo: Option<[f32; 3]>,
}

/// What the viewer shows.
pub struct ViewerScene {
    /// The mesh.
    pub mesh: Mesh,
    /// Its PRT transfer, checked against the mesh.
    pub transfer: Option<shlight_format::ShprtFile>,
    /// The light.
    pub env: Environment,
    /// An irradiance volume lighting the mesh and an object moving through
    /// it.
    pub volume: Option<VolumeScene>,
}

/// Opens the window and runs its event loop until it closes.
///
/// # Errors
/// No display to open a window on, no GPU adapter, a failure while
/// rendering or saving a screenshot.
pub fn run(options: &ViewerOptions, scene: ViewerScene) -> Result<()> {
    use winit::event_loop::{ControlFlow, EventLoop};

    let event_loop = EventLoop::new()
        .map_err(|e| anyhow!("cannot open a window ({e}); is a display available (DISPLAY)?"))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = app::App::new(options, scene.mesh, scene.transfer, scene.env, scene.volume);
    event_loop
        .run_app(&mut app)
        .map_err(|e| anyhow!("window event loop: {e}"))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
