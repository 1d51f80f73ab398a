//! `shlight prt`: bake precomputed radiance transfer for a mesh or a glTF
//! scene, by
//! shlight-pipeline's `prt` job: a `.shprt` file (docs/shprt.md) or a glTF
//! with `_SH_TRANSFER_k` attributes; with `--light` and `--preview`, the
//! vertices shaded under a coefficient file's radiance, rasterised.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use shlight_mesh::LightUnits;
use shlight_pipeline::{PrtMode, PrtRequest, Spelling, prt};

use crate::progress::{Reporter, Ui};
use crate::values::{parse_albedo, parse_size};

/// Light transport to bake.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// Cosine-weighted only: the SH irradiance transfer.
    Unshadowed,
    /// With self-shadowing.
    Shadowed,
    /// With self-shadowing and `--bounces` bounces of diffuse interreflection.
    Interreflected,
    /// Glossy transfer matrices (shadowed, with `--bounces` diffuse
    /// bounces when given) for the view-dependent `--brdf`; .shprt only.
    Glossy,
}

impl From<ModeArg> for PrtMode {
    fn from(m: ModeArg) -> Self {
        match m {
            ModeArg::Unshadowed => PrtMode::Unshadowed,
            ModeArg::Shadowed => PrtMode::Shadowed,
            ModeArg::Interreflected => PrtMode::Interreflected,
            ModeArg::Glossy => PrtMode::Glossy,
        }
    }
}

/// Arguments of `shlight prt`.
#[derive(Args, Debug)]
pub struct PrtArgs {
    /// The mesh (.obj, .ply, .off) or glTF scene (.gltf, .glb: its
    /// materials' albedo and cut-outs, its punctual lights and emission in
    /// a static term).
    pub mesh: PathBuf,
    /// Highest SH degree of the transfer ((lmax+1)^2 coefficients per channel).
    #[arg(long, default_value_t = 4)]
    pub lmax: usize,
    /// Directions per vertex over the whole sphere (a stratified grid of
    /// about this many, shared by all vertices; about half are cast).
    #[arg(long, default_value_t = 1024)]
    pub samples: usize,
    /// Light transport.
    #[arg(long, value_enum, default_value_t = ModeArg::Shadowed)]
    pub mode: ModeArg,
    /// Bounces of interreflection (with --mode interreflected [default: 2],
    /// or --mode glossy [default: 0]).
    #[arg(long)]
    pub bounces: Option<u32>,
    /// The glossy BRDF of --mode glossy: phong:S, the normalised Phong lobe
    /// of exponent S (e.g. phong:32); or ggx:ALPHA or ggx:ALPHA,F0, the GGX microfacet
    /// BRDF of linear roughness ALPHA (0.001 to 1) with Schlick's Fresnel
    /// of reflectance F0 at normal incidence [default F0: 1, no Fresnel]
    /// (e.g. ggx:0.3 or ggx:0.3,0.04).
    #[arg(long)]
    pub brdf: Option<String>,
    /// Compress --mode glossy's matrices: cpca:C,K, clustered PCA with C
    /// clusters of K basis vectors each (e.g. cpca:64,8).
    #[arg(long)]
    pub compress: Option<String>,
    /// Diffuse albedo of every vertex of a mesh, linear: one value or R,G,B
    /// [default: the mesh's vertex colours if it has them, otherwise 0.8];
    /// a glTF scene's albedo is its materials'.
    #[arg(long, value_parser = parse_albedo)]
    pub albedo: Option<[f32; 3]>,
    /// How a glTF scene's punctual lights' intensities become the units of
    /// the light it is shaded with: blender divides glTF's candela and lux
    /// by 683, undoing Blender's exporter [default: blender].
    #[arg(long, value_parser = crate::values::light_units())]
    pub light_units: Option<LightUnits>,
    /// Seed of the direction set (the same seed gives the same file).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output: .shprt (transfer file), .gltf or .glb (mesh with transfer attributes).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// A radiance coefficient file (`shlight project -o FILE.json`) to shade the preview with.
    #[arg(long, requires = "preview")]
    pub light: Option<PathBuf>,
    /// Write a PNG (or EXR/HDR) of the mesh shaded by --light.
    #[arg(long, requires = "light")]
    pub preview: Option<PathBuf>,
    /// Preview size, WIDTHxHEIGHT.
    #[arg(long, value_parser = parse_size, default_value = "512x512")]
    pub preview_size: (usize, usize),
    /// Preview exposure in stops [default: the mean vertex radiance at 0.25].
    #[arg(long, allow_negative_numbers = true)]
    pub preview_exposure: Option<f32>,
}

/// Runs `shlight prt`.
pub fn run(args: &PrtArgs, ui: &Ui) -> Result<()> {
    if args.output.is_none() && args.preview.is_none() {
        bail!(
            "nothing to write: give -o OUT.shprt (or .gltf/.glb) and/or --light L.json --preview P.png"
        );
    }
    let plan = PrtRequest {
        mesh: &args.mesh,
        lmax: args.lmax,
        samples: args.samples,
        mode: args.mode.into(),
        bounces: args.bounces,
        brdf: args.brdf.as_deref(),
        compress: args.compress.as_deref(),
        albedo: args.albedo,
        light_units: args.light_units,
        seed: args.seed,
        output: args.output.as_deref(),
        light: args.light.as_deref(),
        preview: args.preview.as_deref(),
        preview_size: args.preview_size,
        preview_exposure: args.preview_exposure,
    }
    .check(Spelling::CommandLine)?;
    prt(&plan, &Reporter::new(ui))?;
    Ok(())
}
