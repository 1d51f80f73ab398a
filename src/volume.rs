//! `shlight volume`: bake an irradiance volume (SH probes on a grid) through
//! a scene.
//!
//! Loads the scene (shlight-mesh, with albedo and emission from its
//! materials), the environment (an equirect map projected to the bake's
//! lmax, or a radiance coefficient file), bakes the probes (shlight-volume's
//! `bake_file`, which the Python package calls too; in parallel with progress
//! bars) and writes a `.shvol` file or its JSON form (shlight-format;
//! docs/shvol.md).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use glam::DVec3;
use shlight_baked::ProbeGrid;
use shlight_core::sh::{Frame, ShCoeffs};
use shlight_format::VolumeFormat;
use shlight_format::threejs_volume::Precision;
use shlight_pipeline::Environment;
use shlight_volume::{
    BakedVolume, Stage, VolumeOptions, VolumeRequest, bake_file, check_environment,
};

use crate::progress::{StageBars, Ui};

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
    /// Diffuse albedo of surfaces without colours, linear: one value or
    /// R,G,B.
    #[arg(long, default_value = "0.8", value_parser = crate::values::parse_albedo)]
    pub albedo: [f32; 3],
    /// A probe is invalid (kept out of interpolation) when more than this
    /// fraction of its rays hit back faces.
    #[arg(long, default_value_t = 0.5)]
    pub invalid_backfaces: f32,
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
    let resolution = ProbeGrid::parse_resolution(&args.resolution)?;
    let bounds = args
        .bounds
        .as_deref()
        .map(ProbeGrid::parse_bounds)
        .transpose()?;
    let format = args
        .format
        .unwrap_or_else(|| VolumeFormat::from_path(&args.output));
    for out in std::iter::once(&args.output).chain(&args.preview) {
        crate::output_path::refuse_overwriting(out, &[args.scene.clone(), args.env.clone()])?;
    }
    if args.lmax > shlight_baked::MAX_LMAX {
        bail!(
            "--lmax {} is beyond {}, the most a volume holds",
            args.lmax,
            shlight_baked::MAX_LMAX
        );
    }
    let request = VolumeRequest {
        resolution,
        bounds,
        options: VolumeOptions {
            lmax: args.lmax,
            samples: args.samples,
            bounces: args.bounces,
            surface_samples: args.surface_samples,
            max_edge: None,
            albedo: args.albedo,
            invalid_backfaces: args.invalid_backfaces,
            seed: args.seed,
            relocate: !args.no_relocate,
            visibility_size: if args.no_visibility {
                0
            } else {
                shlight_baked::visibility::VISIBILITY_SIZE
            },
        },
        relightable: !args.static_only,
    };
    // The light first: a bad file fails before a long bake.
    let env = environment(&args.env, args.lmax, ui)?;
    let scene = shlight_mesh::load(&args.scene)?;
    let name = args.scene.display().to_string();
    if scene.report.degenerate_triangles > 0 {
        ui.warn(format!(
            "{name}: skipped {} degenerate triangles",
            scene.report.degenerate_triangles
        ));
    }
    let grid = request.grid(&scene)?;
    ui.note(format!(
        "{name}: {} triangles, {}; grid {}x{}x{} over {}:{}",
        scene.triangle_count(),
        match (&scene.colors, &scene.emission) {
            (Some(_), Some(_)) => "albedo and emission from its materials",
            (Some(_), None) => "albedo from its colours",
            (None, Some(_)) => "emission from its materials",
            (None, None) => "constant albedo",
        },
        resolution[0],
        resolution[1],
        resolution[2],
        grid.min,
        grid.max
    ));

    let bars = StageBars::new(ui, |stage| match stage {
        Stage::Surface(shlight_prt::Stage::Rays) => "surface rays".to_string(),
        Stage::Surface(shlight_prt::Stage::Bounce(k)) => format!("bounce {k}"),
        Stage::Surface(shlight_prt::Stage::Matrices) => "matrices".to_string(),
        Stage::Relocate => "relocate".to_string(),
        Stage::Probes => "probes".to_string(),
    });
    let start = Instant::now();
    let BakedVolume { volume, file } = bake_file(
        &scene,
        &args.scene,
        &env,
        &args.env,
        &request,
        &|stage, done, total| {
            bars.update(stage, done, total);
        },
    )?;
    bars.finish();
    let seconds = start.elapsed().as_secs_f64();
    let invalid = volume.invalid_count();
    ui.note(format!(
        "{} probes ({} invalid: inside geometry; {} moved out of geometry, at most {:.2} of a cell), {} rays in {seconds:.2} s ({:.1} M rays/s)",
        volume.probe_count(),
        invalid,
        volume.relocated_count(),
        volume.largest_move(),
        volume.rays,
        volume.rays as f64 / seconds.max(1e-9) / 1e6
    ));
    if let Some(path) = &args.preview {
        let (w, h, pixels) = shlight_volume::probe_sheet(
            &grid,
            &file.valid,
            &file.radiance,
            args.lmax,
            args.preview_ball,
        );
        let exposure = shlight_volume::probe_sheet_exposure(&pixels);
        let image = shlight_io::Image::new(w, h, pixels)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let options = shlight_io::WriteOptions {
            exposure_ev: exposure,
            ..shlight_io::WriteOptions::default()
        };
        shlight_io::write_image(path, &image, &options)?;
    }
    for note in file.write_as(&args.output, format, args.precision.into())? {
        ui.note(note);
    }
    Ok(())
}

/// The environment's radiance coefficients to `lmax`, in the y-up frame
/// (`shlight_pipeline::Environment`), refusing a coefficient file that
/// stops below `lmax`.
fn environment(path: &Path, lmax: usize, ui: &Ui) -> Result<ShCoeffs<DVec3>> {
    let env = Environment::load(path, Frame::YUp, lmax)?;
    env.warnings.iter().for_each(|w| ui.warn(w));
    check_environment(&env.radiance, path, lmax)?;
    Ok(env.radiance_in(Frame::YUp))
}
