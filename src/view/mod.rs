//! `shlight view`: a mesh lit by SH coefficients in a window (winit, wgpu,
//! an egui overlay).
//!
//! Left drag orbits the camera, right drag (or shift + left drag, or the
//! arrow keys) turns the environment: its radiance coefficients are rotated
//! on the CPU every frame (`ShRotation`, lmax 8) and the map background
//! turns with them. Keys: `0`-`8` lmax, `m` mode, `e` the light's encoding
//! (plain SH, dominant lights + SH, ZH3, non-linear L1, ambient cube: each
//! compiled into the fragment shader as its WGSL snippet, the normal turned
//! back by the environment's rotation), `b` background, `w` window, `t`
//! tone map, `+`/`-` exposure, `p` screenshot, `h` panel, `Esc`/`q` quit. `--screenshot FILE.png` renders `--frames` frames, saves
//! the last (overlay included) and exits.
//!
//! The scene is shlight-gpu's (`SceneOptions::check`, then `Scene::read`,
//! as `render-mesh` reads it) and the window shlight-viewer's
//! (`shlight_viewer::run`); this module converts the arguments and calls
//! them.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use shlight_io::ToneMap;

use crate::progress::Ui;
use crate::values::parse_size;

/// Arguments of `shlight view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// The mesh (OBJ, PLY, OFF), or a glTF/GLB scene drawn with its
    /// materials and instances [default: the Stanford bunny,
    /// meshes/bunny.obj, built into shlight].
    pub mesh: Option<PathBuf>,
    /// PRT transfer baked for this mesh by `shlight prt` (.shprt): starts in
    /// PRT mode (`m` cycles SH, PRT and normals); a glossy file is shaded
    /// toward the camera as the orbit moves it.
    #[arg(long, value_name = "FILE.shprt")]
    pub prt: Option<PathBuf>,
    /// The light: an equirect map or a radiance coefficient file (.json)
    /// [default: envmaps/default.exr, built into shlight; none for a
    /// lightmapped scene, drawn by its lightmap, the nodes it skipped
    /// black].
    #[arg(long)]
    pub env: Option<PathBuf>,
    /// Draw a lightmapped scene (`shlight lightmap -o OUT.glb`) by its
    /// lightmap even with --env given (which then lights the nodes the
    /// lightmap skipped). Not with --prt, --volume or --encoding.
    #[arg(long)]
    pub lightmap: bool,
    /// Which world axis a map's top row faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// Highest SH degree shown at start (0..=8) [default: 2; with --prt, the
    /// transfer's lmax, at most 8].
    #[arg(long)]
    pub lmax: Option<usize>,
    /// The light's encoding at start (`e` cycles them): sh, dominant+sh
    /// (needs a map), sloan+sh, zh3, zh3-hallucinated, l1-nonlinear,
    /// ambient-cube; the SH part to the lmax shown.
    #[arg(long, value_parser = crate::values::encoding(), default_value = "sh")]
    pub encoding: shlight_core::encoding::Encoding,
    /// Exposure in stops at start.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Tone map at start: clamp, reinhard or aces.
    #[arg(long, default_value = "aces")]
    pub tone_map: ToneMap,
    /// Window size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x800", value_parser = parse_size)]
    pub size: (usize, usize),
    /// Render --frames frames, save the last to this PNG and exit.
    #[arg(long, value_name = "FILE.png")]
    pub screenshot: Option<PathBuf>,
    /// Frames rendered before --screenshot saves.
    #[arg(long, default_value_t = 3)]
    pub frames: u32,
    /// Start with the overlay panel hidden (`h` toggles it).
    #[arg(long)]
    pub hide_panel: bool,
    /// Lambertian albedo, R,G,B (linear) [default: 0.8,0.8,0.8]; with a
    /// glossy --prt file, the diffuse base under its glossy layer
    /// [default: none, the glossy layer alone].
    #[arg(long, value_parser = crate::values::parse_vec3_f32)]
    pub albedo: Option<glam::Vec3>,
    #[command(flatten)]
    pub volume: crate::volume_shading::VolumeShadingArgs,
}

/// Runs `shlight view`.
pub fn run(args: &ViewArgs, ui: &Ui) -> Result<()> {
    #[cfg(feature = "gpu")]
    {
        use shlight_pipeline::Spelling::CommandLine;
        let options = viewer_options(args);
        options.check(CommandLine)?;
        let settings = scene_options(args).check(CommandLine)?;
        let reporter = crate::progress::Reporter::new(ui);
        let scene = shlight_gpu::Scene::read(&settings, &crate::bundled::BUILT_IN, &reporter)?;
        reporter.finish();
        note_transfer(args, &scene, ui);
        Ok(shlight_viewer::run(&options, scene)?)
    }
    #[cfg(not(feature = "gpu"))]
    {
        let _ = (args, ui);
        Err(crate::gpu_feature::needs_gpu("view"))
    }
}

/// Says what `--prt`'s file holds.
#[cfg(feature = "gpu")]
fn note_transfer(args: &ViewArgs, scene: &shlight_gpu::Scene, ui: &Ui) {
    if let (Some(path), Some(t)) = (&args.prt, &scene.transfer) {
        ui.note(format!(
            "{}: {} transfer to lmax {}, {} channel(s)",
            path.display(),
            t.mode,
            t.lmax,
            t.channels
        ));
    }
}

/// The window's arguments as shlight-viewer's options.
#[cfg(feature = "gpu")]
fn viewer_options(args: &ViewArgs) -> shlight_viewer::ViewerOptions {
    shlight_viewer::ViewerOptions {
        exposure: args.exposure,
        tone_map: args.tone_map,
        size: args.size,
        screenshot: args.screenshot.clone(),
        frames: args.frames,
        hide_panel: args.hide_panel,
    }
}

/// The scene's arguments as shlight-gpu's options.
#[cfg(feature = "gpu")]
fn scene_options(args: &ViewArgs) -> shlight_gpu::SceneOptions {
    shlight_gpu::SceneOptions {
        mesh: args.mesh.clone(),
        prt: args.prt.clone(),
        env: args.env.clone(),
        up: crate::input::frame_of(&args.up),
        lmax: args.lmax,
        encoding: args.encoding,
        albedo: args.albedo.map(|a| a.to_array()),
        lightmap: args.lightmap,
        ..args.volume.options()
    }
}
