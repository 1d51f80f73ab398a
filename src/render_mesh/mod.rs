//! `shlight render-mesh`: a mesh lit by SH coefficients, rendered on the
//! GPU without a window.
//!
//! Each fragment shows the Lambertian radiance `ρ/π Σ_l A_l w_l Σ_m L_lm
//! Y_lm(n)` at its interpolated unit normal (`--mode sh`), or `ρ/π E(n)`
//! with `E` the irradiance of another encoding of the light
//! (`--encoding`), the per-vertex
//! PRT radiance `T_v · L` of a `.shprt` file (plus a glTF scene's static
//! term `S_v`), interpolated (`--mode prt`),
//! or the world normal itself (`--mode normals`, background 0); a
//! lightmapped scene's baked nodes `ρ/π E` with `E` its lightmap's
//! irradiance (without `--env`, or with `--lightmap`). The frame is rendered in
//! linear `f32`: EXR output holds those values untouched (no exposure, no
//! tone map); PNG output gets `--exposure` and `--tone-map` on the CPU, as
//! `shlight render` does.
//!
//! The arguments become shlight-gpu's `RenderMeshRequest`, checked by its
//! `check` and run by its `render_mesh` (the scene read, drawn and
//! written); this module only converts them and reports.

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};
use glam::Vec3;
use shlight_core::sh::Window;
use shlight_io::ToneMap;

use crate::progress::Ui;
use crate::values::{parse_size, parse_vec3_f32 as parse_vec3};

/// `--fov`'s default in degrees: the GPU crate's
/// `shlight_gpu::DEFAULT_FOV_Y_DEGREES`, here so that builds without the
/// `gpu` feature parse the same arguments (a test keeps the two equal).
const DEFAULT_FOV: f32 = 35.0;

/// Arguments of `shlight render-mesh`.
#[derive(Args, Debug)]
pub struct RenderMeshArgs {
    /// The mesh (OBJ, PLY, OFF), or a glTF/GLB scene, drawn with its
    /// materials (base colour textures, cut-outs, double-sided faces) and
    /// instances.
    pub mesh: PathBuf,
    /// The light: an equirect map (projected to lmax 8) or a radiance
    /// coefficient file (.json). Needed unless MESH is a lightmapped scene
    /// (`shlight lightmap -o OUT.glb`), which is then drawn by its lightmap
    /// alone (the nodes it skipped black).
    #[arg(long)]
    pub env: Option<PathBuf>,
    /// Draw a lightmapped scene (`shlight lightmap -o OUT.glb`) by its
    /// lightmap even with --env given: each baked node shows albedo/pi x
    /// the lightmap's irradiance, read as `shlight sample` reads it; the
    /// nodes it skipped keep --env's light. Without --env, a lightmapped
    /// scene is drawn so anyway. Not with --prt, --volume, --mode
    /// prt/normals or --encoding.
    #[arg(long)]
    pub lightmap: bool,
    /// Which world axis a map's top row faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// What the mesh shows: SH irradiance shading, PRT (needs --prt), or
    /// world unit normals [default: prt with --prt, else sh].
    #[arg(long, value_enum)]
    pub mode: Option<RenderMode>,
    /// PRT transfer baked for this mesh by `shlight prt` (.shprt): each
    /// vertex shows transfer · light (albedo is in the transfer), plus a
    /// glTF scene's lamps and emission where the file holds them; a glossy
    /// file's vertices their exit radiance toward the camera (--albedo: a
    /// diffuse base under the glossy layer).
    #[arg(long, value_name = "FILE.shprt")]
    pub prt: Option<PathBuf>,
    /// Highest SH degree of the light used (0..=8) [default: 2; with --prt,
    /// the transfer's lmax, at most 8].
    #[arg(long)]
    pub lmax: Option<usize>,
    /// Shade with this encoding of the light (docs/coefficient-file.md,
    /// `encoding`), its SH part to --lmax; from the map's texels when --env
    /// is a map (dominant+sh needs one). Not with --prt, --mode
    /// prt/normals or --volume.
    #[arg(long, value_parser = crate::values::encoding(), default_value = "sh")]
    pub encoding: shlight_core::encoding::Encoding,
    /// Ringing window on the light: none, hanning:W, lanczos:W, laplacian:LAMBDA.
    #[arg(long, default_value = "none")]
    pub window: Window,
    /// Lambertian albedo, R,G,B (linear) [default: 0.8,0.8,0.8]; with a
    /// glossy --prt file, the diffuse base under its glossy layer
    /// [default: none, the glossy layer alone].
    #[arg(long, value_parser = parse_vec3)]
    pub albedo: Option<Vec3>,
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
    #[arg(long, default_value_t = DEFAULT_FOV)]
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
    /// Turn the environment: yaw:DEG (about the --up axis), quat:X,Y,Z,W or
    /// euler:X,Y,Z (degrees); with --volume, a relightable volume is relit
    /// under the turned light (a --static one refuses).
    #[arg(long, allow_hyphen_values = true)]
    pub rotate: Option<String>,
    #[command(flatten)]
    pub volume: crate::volume_shading::VolumeShadingArgs,
    /// The image to write: .exr (linear) or .png.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// `--mode` of `render-mesh`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum RenderMode {
    /// Per-fragment SH irradiance, times albedo / π.
    Sh,
    /// Per-vertex PRT transfer · light (`--prt`; glossy files toward the
    /// camera), interpolated.
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

/// Runs `shlight render-mesh`.
pub fn run(args: &RenderMeshArgs, ui: &Ui) -> Result<()> {
    #[cfg(feature = "gpu")]
    {
        if args.env.is_none() {
            let lightmapped = shlight_mesh::read_lightmap_pages_if_any(&args.mesh)?.is_some();
            if !lightmapped {
                anyhow::bail!(
                    "{}: holds no lightmap, so render-mesh needs --env LIGHT (a map or a coefficient file)",
                    args.mesh.display()
                );
            }
        }
        let settings = request(args).check(shlight_pipeline::Spelling::CommandLine)?;
        let reporter = crate::progress::Reporter::new(ui);
        shlight_gpu::render_mesh(&settings, &crate::bundled::BUILT_IN, &reporter)?;
        Ok(())
    }
    #[cfg(not(feature = "gpu"))]
    {
        let _ = (args, ui);
        Err(crate::gpu_feature::needs_gpu("render-mesh"))
    }
}

/// The arguments as shlight-gpu's request.
#[cfg(feature = "gpu")]
fn request(args: &RenderMeshArgs) -> shlight_gpu::RenderMeshRequest {
    use shlight_gpu::{Background, Mode};
    shlight_gpu::RenderMeshRequest {
        scene: shlight_gpu::SceneOptions {
            mesh: Some(args.mesh.clone()),
            prt: args.prt.clone(),
            env: args.env.clone(),
            lightmap: args.lightmap,
            up: crate::input::frame_of(&args.up),
            mode: args.mode.map(|m| match m {
                RenderMode::Sh => Mode::Sh,
                RenderMode::Prt => Mode::Prt,
                RenderMode::Normals => Mode::Normals,
            }),
            lmax: args.lmax,
            encoding: args.encoding,
            albedo: args.albedo.map(|a| a.to_array()),
            background: Some(match args.background {
                BackgroundArg::None => Background::None,
                BackgroundArg::Map => Background::Map,
                BackgroundArg::Sh => Background::Sh,
            }),
            rotate: args.rotate.clone(),
            ..args.volume.options()
        },
        shot: shlight_gpu::Shot {
            camera: args.camera,
            target: args.target,
            fov_degrees: args.fov,
            size: args.size,
            window: args.window,
        },
        exposure: args.exposure,
        tone_map: args.tone_map,
        output: args.output.clone(),
    }
}

#[cfg(all(test, feature = "gpu"))]
mod tests {
    #[test]
    fn the_fov_default_is_the_renderers() {
        assert_eq!(super::DEFAULT_FOV, shlight_gpu::DEFAULT_FOV_Y_DEGREES);
    }
}
