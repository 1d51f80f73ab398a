//! `shlight lightmap`: bake a glTF scene's lightmap on its second UV set
//! (`TEXCOORD_1`) for an engine.
//!
//! The arguments made into shlight-pipeline's `LightmapRequest` and its
//! `lightmap` job run (docs/lightmaps.md).

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};
use shlight_lightmap::{Engine, LightmapSettings, TexelBasis};
use shlight_mesh::LightUnits;
use shlight_pipeline::{LightmapRequest, Spelling, lightmap, lightmap_size, reconstruction};
use shlight_volume::VolumeOptions;

use crate::progress::{Reporter, Ui};

/// `--basis`: what a texel holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BasisArg {
    /// RGB irradiance for the surface's normal.
    Irradiance,
    /// L0 and L1 per channel: a normal map reshades it.
    ShL1,
    /// RGB L0 and one direction shared by the channels (Bakery's MonoSH).
    Monosh,
}

/// `--for`: the engine that reads the lightmap (units and packing).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EngineArg {
    /// three.js: lightMap texels are irradiance E.
    Threejs,
    /// Bevy: E / pi.
    Bevy,
    /// Godot 4's LightmapGI: E / pi; sh-l1 as L0, then L1 y, z, x.
    Godot,
    /// Unity with Bakery's shaders: E / pi; Bakery's SH and MonoSH.
    Unity,
}

/// Arguments of `shlight lightmap`.
#[derive(Args, Debug)]
pub struct LightmapArgs {
    /// The scene: .gltf or .glb; every mesh needs a second UV set
    /// (TEXCOORD_1) within the unit square, its triangles not overlapping.
    pub scene: PathBuf,
    /// The scene with its lightmaps (.glb).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// The distant light: an equirect map (projected to --lmax, its top row
    /// facing +Y) or a radiance coefficient file.
    #[arg(long)]
    pub env: PathBuf,
    /// What a texel holds.
    #[arg(long, value_enum, default_value = "irradiance")]
    pub basis: BasisArg,
    /// The engine that reads it: its units (three.js E, the others E/pi)
    /// and packing.
    #[arg(long = "for", value_enum, default_value = "threejs")]
    pub engine: EngineArg,
    /// Read SH texels back with Geomerics' non-linear reconstruction
    /// (three.js and Unity).
    #[arg(long)]
    pub non_linear: bool,
    /// Texels a side of the square lightmap, the regions as large as fit
    /// [default: 512 without --texel-density].
    #[arg(long, conflicts_with = "texel_density")]
    pub size: Option<u32>,
    /// Texels per metre on every surface, in the smallest power-of-two
    /// lightmap that holds them.
    #[arg(long)]
    pub texel_density: Option<f64>,
    /// Empty texels around each node's region, filled by dilation.
    #[arg(long, default_value_t = 2)]
    pub padding: u32,
    /// Radius in texels of the edge-aware filter over the baked texels,
    /// guided by their positions and normals (never across a geometric
    /// edge); 0: none.
    #[arg(long, value_name = "TEXELS", default_value_t = shlight_lightmap::DEFAULT_DENOISE)]
    pub denoise: u32,
    /// Rays per texel (a stratified set of about this many).
    #[arg(long, default_value_t = 256)]
    pub samples: usize,
    /// Interreflection bounces of the surfaces' light (a closed room loses
    /// about a tenth of its light with 2; docs/lightmaps.md).
    #[arg(long, default_value_t = 8)]
    pub bounces: u32,
    /// Directions per surface vertex for the surfaces' own light.
    #[arg(long, default_value_t = 512)]
    pub surface_samples: usize,
    /// Longest surface edge before the surfaces' light is split finer
    /// (scene units) [default: the scene's diagonal / 32].
    #[arg(long, value_name = "LENGTH")]
    pub max_edge: Option<f32>,
    /// Highest SH degree of --env read.
    #[arg(long, default_value_t = 2)]
    pub lmax: usize,
    /// Diffuse albedo of primitives without a material: one value or R,G,B.
    #[arg(long, default_value = "0.8", value_parser = crate::values::parse_albedo)]
    pub albedo: [f32; 3],
    /// A texel is inside geometry (filled from its neighbours) when more
    /// than this fraction of its rays hit back faces.
    #[arg(long, default_value_t = 0.5)]
    pub invalid_backfaces: f32,
    /// How the intensities of the scene's punctual lights become the units
    /// of --env's radiance (blender: glTF's candela and lux over 683).
    #[arg(long, default_value = "blender", value_parser = crate::values::light_units())]
    pub light_units: LightUnits,
    /// Seed of the texels' rays (the same seed gives the same file at any
    /// thread count).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// In the written scene, give every baked node its own copy of its
    /// mesh with TEXCOORD_1 moved into its region (for loaders without a
    /// per-node rectangle; always so with --for threejs).
    #[arg(long)]
    pub unshare_instances: bool,
    /// Also write each layer as OpenEXR: PREFIX.LAYER.exr.
    #[arg(long, value_name = "PREFIX")]
    pub exr: Option<PathBuf>,
    /// Also write a picture of the lightmap's irradiance (PNG, EXR or HDR).
    #[arg(long)]
    pub preview: Option<PathBuf>,
}

impl From<BasisArg> for TexelBasis {
    fn from(b: BasisArg) -> Self {
        match b {
            BasisArg::Irradiance => TexelBasis::Irradiance,
            BasisArg::ShL1 => TexelBasis::ShL1,
            BasisArg::Monosh => TexelBasis::MonoSh,
        }
    }
}

impl From<EngineArg> for Engine {
    fn from(e: EngineArg) -> Self {
        match e {
            EngineArg::Threejs => Engine::ThreeJs,
            EngineArg::Bevy => Engine::Bevy,
            EngineArg::Godot => Engine::Godot,
            EngineArg::Unity => Engine::Unity,
        }
    }
}

/// Runs `shlight lightmap`.
pub fn run(args: &LightmapArgs, ui: &Ui) -> Result<()> {
    let size = lightmap_size(args.size, args.texel_density, Spelling::CommandLine)?;
    let plan = LightmapRequest {
        scene: &args.scene,
        env: &args.env,
        output: args.output.as_deref(),
        basis: args.basis.into(),
        engine: args.engine.into(),
        reconstruction: reconstruction(args.non_linear),
        settings: LightmapSettings {
            size,
            padding: args.padding,
            denoise: args.denoise,
            gather: VolumeOptions {
                lmax: args.lmax,
                samples: args.samples,
                bounces: args.bounces,
                surface_samples: args.surface_samples,
                max_edge: args.max_edge,
                invalid_backfaces: args.invalid_backfaces,
                seed: args.seed,
                light_units: args.light_units,
                ..LightmapSettings::default().gather
            },
            ..LightmapSettings::default()
        },
        albedo: args.albedo,
        unshare_instances: args.unshare_instances,
        exr: args.exr.as_deref(),
        preview: args.preview.as_deref(),
    }
    .check(Spelling::CommandLine)?;
    lightmap(&plan, &Reporter::new(ui))?;
    Ok(())
}
