//! `shlight volume`: bake an irradiance volume (SH probes on a grid) through
//! a scene.
//!
//! The arguments made into shlight-pipeline's `VolumeRequest` and its
//! `volume` job run: the scene and the light read, the probes baked, a
//! `.shvol` file or another form written (docs/shvol.md).

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};
use shlight_baked::ProbeGrid;
use shlight_format::VolumeFormat;
use shlight_format::threejs_volume::Precision;
use shlight_mesh::LightUnits;
use shlight_pipeline::{Spelling, VolumeRequest, visibility_size, volume};
use shlight_volume::{VolumeBakeSettings, VolumeOptions};

use crate::progress::{Reporter, Ui};

/// `--precision` of the three.js export.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PrecisionArg {
    /// Half floats (HalfFloatType).
    Half,
    /// 32-bit floats (FloatType).
    F32,
}

impl From<PrecisionArg> for Precision {
    fn from(p: PrecisionArg) -> Self {
        match p {
            PrecisionArg::Half => Precision::Half,
            PrecisionArg::F32 => Precision::F32,
        }
    }
}

/// Arguments of `shlight volume`.
#[derive(Args, Debug)]
pub struct VolumeArgs {
    /// The scene: .obj (+ .mtl: Kd albedo, Ke emission), .ply, .off, .gltf
    /// or .glb (baseColorFactor x COLOR_0 albedo, emissiveFactor x
    /// KHR_materials_emissive_strength emission).
    pub scene: PathBuf,
    /// Output file (.shvol, .json with --format json or threejs, .ktx2
    /// with --format bevy).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Output format [default: json for a .json name, bevy for .ktx2, else
    /// shvol].
    #[arg(long, value_parser = crate::values::volume_format())]
    pub format: Option<VolumeFormat>,
    /// Numbers of the --format threejs atlas.
    #[arg(long, value_enum, default_value = "half")]
    pub precision: PrecisionArg,
    /// The distant light: an equirect map (projected to --lmax, its top row
    /// facing +Y) or a radiance coefficient file (`shlight project -o
    /// FILE.json`).
    #[arg(long)]
    pub env: PathBuf,
    /// Probes along x, y and z, NXxNYxNZ.
    #[arg(long, default_value = "8x4x8")]
    pub resolution: String,
    /// The grid's box, X0,Y0,Z0:X1,Y1,Z1 [default: the scene's bounding box,
    /// padded by 2% of its diagonal].
    #[arg(long, allow_hyphen_values = true)]
    pub bounds: Option<String>,
    /// Highest SH degree of the probes (up to 8).
    #[arg(long, default_value_t = 2)]
    pub lmax: usize,
    /// Rays per probe (a stratified set of about this many, shared by all
    /// probes).
    #[arg(long, default_value_t = 1024)]
    pub samples: usize,
    /// Interreflection bounces of the surfaces' light.
    #[arg(long, default_value_t = 2)]
    pub bounces: u32,
    /// Directions per surface vertex for the surfaces' own light.
    #[arg(long, default_value_t = 512)]
    pub surface_samples: usize,
    /// Surface light is held at the surfaces' vertices: edges longer than
    /// this (scene units) are split first, so that the vertices are close
    /// enough to hold shadows and patches of light [default: the scene's
    /// bounding-box diagonal / 32].
    #[arg(long, value_name = "LENGTH")]
    pub max_edge: Option<f32>,
    /// Diffuse albedo of surfaces without colours, linear: one value or
    /// R,G,B.
    #[arg(long, default_value = "0.8", value_parser = crate::values::parse_albedo)]
    pub albedo: [f32; 3],
    /// A probe is invalid (kept out of interpolation) when more than this
    /// fraction of its rays hit back faces.
    #[arg(long, default_value_t = 0.5)]
    pub invalid_backfaces: f32,
    /// How the intensities of the scene's punctual lights (glTF's
    /// KHR_lights_punctual) become the units of --env's radiance: blender
    /// divides glTF's candela and lux by 683, undoing Blender's exporter,
    /// so a scene bakes to what Cycles renders.
    #[arg(long, default_value = "blender", value_parser = crate::values::light_units())]
    pub light_units: LightUnits,
    /// Seed of the ray directions (the same seed gives the same file at any
    /// thread count).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Keep the probes at their cells' centres: do not move probes inside
    /// geometry, or nearer a surface than a fifth of a cell, to free space
    /// within their cell.
    #[arg(long)]
    pub no_relocate: bool,
    /// Store no distance maps: the file is shaded by trilinear
    /// interpolation of the valid probes, which leaks light through thin
    /// walls (docs/shvol.md, "Visibility").
    #[arg(long)]
    pub no_visibility: bool,
    /// Keep only the probes' SH for --env (no transfer matrices: smaller,
    /// but the volume cannot be relit).
    #[arg(long = "static")]
    pub static_only: bool,
    /// Also write a picture of the probes (PNG, EXR or HDR): each a white
    /// diffuse ball lit by its light, z layers side by side, invalid probes
    /// grey.
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Diameter of each probe's ball in the preview, in pixels.
    #[arg(long, default_value_t = 32)]
    pub preview_ball: usize,
}

/// Runs `shlight volume`.
pub fn run(args: &VolumeArgs, ui: &Ui) -> Result<()> {
    let plan = VolumeRequest {
        scene: &args.scene,
        env: &args.env,
        output: Some(&args.output),
        format: args.format,
        precision: args.precision.into(),
        bake: VolumeBakeSettings {
            resolution: ProbeGrid::parse_resolution(&args.resolution)?,
            bounds: args
                .bounds
                .as_deref()
                .map(ProbeGrid::parse_bounds)
                .transpose()?,
            options: VolumeOptions {
                lmax: args.lmax,
                samples: args.samples,
                bounces: args.bounces,
                surface_samples: args.surface_samples,
                max_edge: args.max_edge,
                albedo: args.albedo,
                invalid_backfaces: args.invalid_backfaces,
                seed: args.seed,
                relocate: !args.no_relocate,
                visibility_size: visibility_size(!args.no_visibility),
                light_units: args.light_units,
            },
            relightable: !args.static_only,
        },
        preview: args.preview.as_deref(),
        preview_ball: args.preview_ball,
    }
    .check(Spelling::CommandLine)?;
    volume(&plan, &Reporter::new(ui))?;
    Ok(())
}
