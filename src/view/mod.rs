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
//! The window is shlight-viewer's ([`shlight_viewer::run`]); this module
//! parses the arguments and reads the files.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use shlight_io::ToneMap;

use crate::progress::Ui;
use crate::values::parse_size;

/// Arguments of `shlight view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// The mesh (OBJ, PLY, OFF, glTF/GLB) [default: the Stanford bunny,
    /// meshes/bunny.obj, built into shlight].
    pub mesh: Option<PathBuf>,
    /// PRT transfer baked for this mesh by `shlight prt` (.shprt): starts in
    /// PRT mode (`m` cycles SH, PRT and normals); a glossy file is shaded
    /// toward the camera as the orbit moves it.
    #[arg(long, value_name = "FILE.shprt")]
    pub prt: Option<PathBuf>,
    /// The light: an equirect map or a radiance coefficient file (.json)
    /// [default: envmaps/default.exr, built into shlight].
    #[arg(long)]
    pub env: Option<PathBuf>,
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
    if args.frames == 0 {
        bail!("--frames must be at least 1");
    }
    if let Some(path) = &args.screenshot
        && !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        bail!("{}: --screenshot writes PNG files", path.display());
    }
    args.volume.check(args.lmax)?;
    if args.volume.volume.is_some() && args.mesh.is_none() {
        bail!("--volume lights the scene it was baked in: give that scene as MESH");
    }
    if args.volume.volume.is_some() && args.prt.is_some() {
        bail!("--volume shades by the volume's SH: it takes no --prt");
    }
    if args.volume.volume.is_some() && args.encoding != shlight_core::encoding::Encoding::Sh {
        bail!(
            "--volume shades by the volume's SH probes: it does not take --encoding {}",
            args.encoding
        );
    }
    #[cfg(feature = "gpu")]
    return show(args, ui);
    #[cfg(not(feature = "gpu"))]
    {
        let _ = ui;
        Err(crate::gpu_feature::needs_gpu("view"))
    }
}

/// Opens the window and runs its event loop until it closes.
#[cfg(feature = "gpu")]
fn show(args: &ViewArgs, ui: &Ui) -> Result<()> {
    use crate::input::frame_of;
    use shlight_pipeline::Environment;

    shlight_viewer::check_lmax(args.lmax)?;
    let mesh_path = args
        .mesh
        .clone()
        .unwrap_or_else(|| PathBuf::from(crate::bundled::MESH_NAME));
    let mesh = match &args.mesh {
        Some(path) => shlight_mesh::load(path)?,
        None => crate::bundled::mesh()?,
    };
    let transfer = match &args.prt {
        Some(path) => {
            let t = crate::prt_input::load_transfer(path, &mesh, &mesh_path)?;
            ui.note(format!(
                "{}: {} transfer to lmax {}, {} channel(s)",
                path.display(),
                t.mode,
                t.lmax,
                t.channels
            ));
            Some(t)
        }
        None => None,
    };
    let up = frame_of(&args.up);
    let env = match &args.env {
        Some(path) => Environment::load(path, up, shlight_baked::LIGHT_MAX_LMAX)?,
        None => crate::bundled::environment(up)?,
    };
    env.warnings.iter().for_each(|w| ui.warn(w));
    if args.encoding == shlight_core::encoding::Encoding::DominantSh && env.map.is_none() {
        // The same message as render-mesh's.
        env.encode(args.encoding, 2)?;
    }
    let volume = match &args.volume.volume {
        Some(_) => Some(crate::volume_shading::load_volume(
            &args.volume,
            &mesh,
            &mesh_path,
            ui,
        )?),
        None => None,
    };
    let options = shlight_viewer::ViewerOptions {
        lmax: args.lmax,
        encoding: args.encoding,
        exposure: args.exposure,
        tone_map: args.tone_map,
        size: args.size,
        screenshot: args.screenshot.clone(),
        frames: args.frames,
        hide_panel: args.hide_panel,
        albedo: args.albedo.map(|a| a.to_array()),
    };
    let scene = shlight_viewer::ViewerScene {
        mesh,
        transfer,
        env,
        volume,
    };
    shlight_viewer::run(&options, scene)
}
