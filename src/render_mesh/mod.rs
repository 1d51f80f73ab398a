//! `shlight render-mesh`: a mesh lit by SH coefficients, rendered on the
//! GPU without a window.
//!
//! Each fragment shows the Lambertian radiance `ρ/π Σ_l A_l w_l Σ_m L_lm
//! Y_lm(n)` at its interpolated unit normal (`--mode sh`), the per-vertex
//! PRT radiance `T_v · L` of a `.shprt` file, interpolated (`--mode prt`),
//! or the world normal itself (`--mode normals`, background 0). The frame is rendered in
//! linear `f32`: EXR output holds those values untouched (no exposure, no
//! tone map); PNG output gets `--exposure` and `--tone-map` on the CPU, as
//! `shlight render` does.

use std::path::PathBuf;

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, ValueEnum};
use glam::Vec3;
use shlight_core::Window;
use shlight_gpu::{
    Background, Camera, DEFAULT_FOV_Y_DEGREES, DEFAULT_VIEW_FROM, GpuContext, HEADLESS_FORMAT,
    Mode, Shading, render_frame,
};
use shlight_io::{Format, Image, ToneMap, WriteOptions, write_image};

use crate::environment::{Environment, frame_of};
use crate::progress::Ui;
use crate::texels::parse_size;

/// Arguments of `shlight render-mesh`.
#[derive(Args, Debug)]
pub struct RenderMeshArgs {
    /// The mesh (OBJ, PLY, OFF, glTF/GLB).
    pub mesh: PathBuf,
    /// The light: an equirect map (projected to lmax 8) or a radiance
    /// coefficient file (.json).
    #[arg(long)]
    pub env: PathBuf,
    /// Which world axis a map's top row faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// What the mesh shows: SH irradiance shading, PRT (needs --prt), or
    /// world unit normals [default: prt with --prt, else sh].
    #[arg(long, value_enum)]
    pub mode: Option<RenderMode>,
    /// PRT transfer baked for this mesh by `shlight prt` (.shprt): each
    /// vertex shows transfer · light (albedo is in the transfer).
    #[arg(long, value_name = "FILE.shprt")]
    pub prt: Option<PathBuf>,
    /// Highest SH degree of the light used (0..=8) [default: 2; with --prt,
    /// the transfer's lmax, at most 8].
    #[arg(long)]
    pub lmax: Option<usize>,
    /// Ringing window on the light: none, hanning:W, lanczos:W, laplacian:LAMBDA.
    #[arg(long, default_value = "none")]
    pub window: Window,
    /// Lambertian albedo, R,G,B (linear).
    #[arg(long, default_value = "0.8,0.8,0.8", value_parser = parse_vec3)]
    pub albedo: Vec3,
    /// Behind the mesh: none (0), map (the --env map) or sh (its SH reconstruction).
    #[arg(long, value_enum, default_value_t = BackgroundArg::None)]
    pub background: BackgroundArg,
    /// Camera position X,Y,Z [default: framing the mesh from the front, +Z, a little above].
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub camera: Option<Vec3>,
    /// The point the camera looks at [default: the centre of the mesh's bounds].
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long, default_value_t = DEFAULT_FOV_Y_DEGREES)]
    pub fov: f32,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1024x768", value_parser = parse_size)]
    pub size: (usize, usize),
    /// PNG only: exposure in stops.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// PNG only: tone map (clamp, reinhard, aces).
    #[arg(long, default_value = "aces")]
    pub tone_map: ToneMap,
    /// The image to write: .exr (linear) or .png.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `--mode` of `render-mesh`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RenderMode {
    /// Per-fragment SH irradiance, times albedo / π.
    Sh,
    /// Per-vertex PRT transfer · light (`--prt`), interpolated.
    Prt,
    /// World-space unit normals (background 0).
    Normals,
}

/// `--background`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BackgroundArg {
    /// Nothing (0).
    None,
    /// The environment map (needs a map, not a coefficient file).
    Map,
    /// The SH reconstruction of the light to --lmax.
    Sh,
}

/// `X,Y,Z` as a vector (`synth`'s parser, in f32).
pub fn parse_vec3(s: &str) -> std::result::Result<Vec3, String> {
    crate::synth::parse_vec3(s).map(|v| v.as_vec3())
}

/// The camera for a mesh of `bounds`: `--camera`/`--target`, or framed.
pub fn camera_for(
    bounds: (Vec3, Vec3),
    eye: Option<Vec3>,
    target: Option<Vec3>,
    fov_degrees: f32,
    aspect: f32,
) -> Result<Camera> {
    if !(fov_degrees > 1.0 && fov_degrees < 179.0) {
        bail!("--fov {fov_degrees}: expected degrees between 1 and 179");
    }
    let fov = fov_degrees.to_radians();
    let centre = (bounds.0 + bounds.1) * 0.5;
    let radius = (bounds.1 - bounds.0).length() * 0.5;
    let target = target.unwrap_or(centre);
    Ok(match eye {
        None if target == centre => Camera::framing(bounds, DEFAULT_VIEW_FROM, fov, aspect),
        None => {
            let framed = Camera::framing(bounds, DEFAULT_VIEW_FROM, fov, aspect);
            Camera::looking_at(
                framed.eye - centre + target,
                target,
                radius + (target - centre).length(),
                fov,
            )
        }
        Some(eye) => {
            if (eye - target).length() <= 0.0 {
                bail!("--camera and --target are the same point");
            }
            Camera::looking_at(eye, target, radius + (target - centre).length(), fov)
        }
    })
}

/// Runs `shlight render-mesh`.
pub fn run(args: &RenderMeshArgs, ui: &Ui) -> Result<()> {
    let out = args.output.display().to_string();
    let format = Format::from_extension(&args.output);
    if !matches!(format, Some(Format::Exr | Format::Png)) {
        bail!("{out}: render-mesh writes .exr (linear) or .png");
    }
    crate::gpu_scene::check_lmax(args.lmax)?;
    let mode = match (args.mode, &args.prt) {
        (Some(RenderMode::Prt), None) => bail!("--mode prt needs --prt FILE.shprt"),
        (Some(mode), _) => mode,
        (None, Some(_)) => RenderMode::Prt,
        (None, None) => RenderMode::Sh,
    };
    let mut inputs = vec![args.mesh.clone(), args.env.clone()];
    inputs.extend(args.prt.clone());
    crate::project::refuse_overwriting(&args.output, &inputs)?;
    let bar = ui.spinner("reading the mesh");
    let mesh = shlight_mesh::load(&args.mesh)?;
    let transfer = match &args.prt {
        Some(path) => Some(crate::prt_input::load_transfer(path, &mesh, &args.mesh)?),
        None => None,
    };
    bar.set_message("reading the environment");
    let env = Environment::load(&args.env, frame_of(&args.up))?;
    if args.background == BackgroundArg::Map && env.map.is_none() {
        bail!(
            "--background map needs an environment map; {} holds coefficients (use --background sh)",
            env.path.display()
        );
    }
    bar.set_message("opening the GPU");
    let ctx = GpuContext::headless()?;
    let renderer =
        crate::gpu_scene::renderer(&ctx, HEADLESS_FORMAT, &mesh, transfer.as_ref(), &env)?;
    let lmax = crate::gpu_scene::shading_lmax(
        args.lmax,
        transfer.as_ref().filter(|_| mode == RenderMode::Prt),
    );
    let (w, h) = args.size;
    let camera = camera_for(
        mesh.bounds(),
        args.camera,
        args.target,
        args.fov,
        w as f32 / h as f32,
    )?;
    let shading = Shading {
        mode: match mode {
            RenderMode::Sh => Mode::Sh,
            RenderMode::Prt => Mode::Prt,
            RenderMode::Normals => Mode::Normals,
        },
        lmax,
        window: args.window,
        exposure_ev: 0.0,
        tone_map: None,
        albedo: args.albedo.to_array(),
        background: match args.background {
            BackgroundArg::None => Background::None,
            BackgroundArg::Map => Background::Map,
            BackgroundArg::Sh => Background::Sh,
        },
    };
    if env.radiance.lmax() < lmax {
        ui.note(format!(
            "{} holds lmax {}; shading to lmax {}",
            env.path.display(),
            env.radiance.lmax(),
            env.radiance.lmax()
        ));
    }
    bar.set_message(format!("rendering {w}x{h} on {}", ctx.adapter_name()));
    let frame = render_frame(&ctx, &renderer, &camera, &shading, w, h)?;
    bar.finish_and_clear();
    let image = Image::new(w, h, frame.rgb()).map_err(|e| anyhow!("{e}"))?;
    let options = match format {
        Some(Format::Png) => WriteOptions {
            exposure_ev: args.exposure,
            tone_map: args.tone_map,
            ..WriteOptions::default()
        },
        _ => WriteOptions::default(),
    };
    write_image(&args.output, &image, &options).with_context(|| format!("{out}: writing"))?;
    Ok(())
}
