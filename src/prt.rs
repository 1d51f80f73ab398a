//! `shlight prt`: bake precomputed radiance transfer for a mesh.
//!
//! Loads the mesh (OBJ, PLY, OFF, glTF/GLB; shlight-mesh), bakes per-vertex
//! transfer vectors (shlight-prt, in parallel with a progress bar), and
//! writes a `.shprt` file (docs/shprt.md) or a glTF with `_SH_TRANSFER_k`
//! attributes; with `--light` and `--preview`, shades the vertices under a
//! coefficient file's radiance and rasterises them to a PNG.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use glam::DVec3;
use shlight_format::ShprtFile;
use shlight_io::{ToneMap, WriteOptions, write_image};
use shlight_mesh::Mesh;
use shlight_prt::{
    Albedo, BakeRequest, Brdf, DEFAULT_BOUNCES, MAX_BAKE_LMAX, MAX_GLOSSY_BYTES, Mode, Stage,
    bake_file, bake_glossy_file, glossy_bytes, glossy_channels,
};

use crate::progress::{StageBars, Ui};
use crate::values::{parse_albedo, parse_size};
use shlight_format::CoeffFile;

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

/// Arguments of `shlight prt`.
#[derive(Args, Debug)]
pub struct PrtArgs {
    /// The mesh: .obj, .ply, .off, .gltf or .glb.
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
    /// Diffuse albedo, linear: one value or R,G,B [default: the mesh's vertex
    /// colours if it has them, otherwise 0.8].
    #[arg(long, value_parser = parse_albedo)]
    pub albedo: Option<[f32; 3]>,
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
    let mode = match (args.mode, args.bounces) {
        (ModeArg::Interreflected, b) => Mode::Interreflected {
            bounces: b.unwrap_or(DEFAULT_BOUNCES),
        },
        (ModeArg::Glossy, None | Some(0)) => Mode::Shadowed,
        (ModeArg::Glossy, Some(bounces)) => Mode::Interreflected { bounces },
        (_, Some(_)) => bail!("--bounces needs --mode interreflected or --mode glossy"),
        (ModeArg::Unshadowed, None) => Mode::Unshadowed,
        (ModeArg::Shadowed, None) => Mode::Shadowed,
    };
    let glossy = args.mode == ModeArg::Glossy;
    let brdf = match (&args.brdf, glossy) {
        (Some(text), true) => Some(Brdf::parse(text).map_err(|e| anyhow::anyhow!("--brdf: {e}"))?),
        (None, true) => {
            bail!("--mode glossy needs --brdf phong:S or ggx:ALPHA[,F0] (e.g. --brdf phong:32)")
        }
        (Some(_), false) => bail!("--brdf is the BRDF of --mode glossy"),
        (None, false) => None,
    };
    let compress = match (&args.compress, glossy) {
        (Some(text), true) => {
            Some(shlight_prt::parse_cpca(text).map_err(|e| anyhow::anyhow!("--compress: {e}"))?)
        }
        (Some(_), false) => bail!("--compress compresses the matrices of --mode glossy"),
        (None, _) => None,
    };
    if glossy && args.preview.is_some() {
        bail!(
            "--preview shades diffuse transfer; a glossy file is shaded view by view: \
             shlight sample FILE.shprt --light LIGHT --view X,Y,Z"
        );
    }
    if args.samples == 0 {
        bail!("--samples must be at least 1");
    }
    if args.lmax > MAX_BAKE_LMAX {
        bail!(
            "--lmax {} is beyond {MAX_BAKE_LMAX} (diffuse transfer needs 2 to 6)",
            args.lmax
        );
    }
    let output_kind = args.output.as_deref().map(output_kind).transpose()?;
    if let (Some(brdf), Some(Output::Gltf), Some(out)) = (brdf, output_kind, &args.output) {
        bail!(
            "{}: glTF cannot carry glossy transfer ({brdf}): a matrix per vertex is beyond \
             what glTF vertex attributes hold; write a .shprt file, or bake without \
             --mode glossy for glTF's transfer vectors",
            out.display()
        );
    }
    for out in args.output.iter().chain(&args.preview) {
        crate::output_path::refuse_overwriting(out, std::slice::from_ref(&args.mesh))?;
    }
    // Read the light first: a bad light file fails before a long bake.
    let light = args
        .light
        .as_deref()
        .map(|path| {
            CoeffFile::read_radiance(path, "PRT shading", "project without --quantity irradiance")
                .map(|f| f.coeffs)
        })
        .transpose()?;

    let name = args.mesh.display().to_string();
    let mesh = shlight_mesh::load(&args.mesh)?;
    if mesh.report.degenerate_triangles > 0 {
        ui.warn(format!(
            "{name}: skipped {} degenerate triangles",
            mesh.report.degenerate_triangles
        ));
    }
    let request = BakeRequest {
        lmax: args.lmax,
        samples: args.samples,
        mode,
        albedo: args.albedo,
        seed: args.seed,
    };
    if matches!(request.albedo(&mesh).0, Albedo::PerVertex(_)) {
        ui.note(format!("{name}: albedo from the mesh's vertex colours"));
    }
    if let Some(brdf) = brdf {
        return glossy_bake(args, ui, &mesh, &request, brdf, compress);
    }
    let bars = StageBars::new(ui, |stage| match stage {
        Stage::Rays => "directions".to_string(),
        Stage::Bounce(k) => format!("bounce {k}"),
        Stage::Matrices => "matrices".to_string(),
    });
    let start = Instant::now();
    let (transfer, file) = bake_file(&mesh, &args.mesh, &request, &|stage, done, total| {
        bars.update(stage, done, total)
    });
    bars.finish();
    let seconds = start.elapsed().as_secs_f64();
    ui.note(format!(
        "{name}: {} vertices, {} triangles, {} transfer, lmax {}, {} directions; {} rays in {seconds:.2} s ({:.1} M rays/s)",
        mesh.vertex_count(),
        mesh.triangle_count(),
        mode.name(),
        args.lmax,
        transfer.samples,
        transfer.rays,
        transfer.rays as f64 / seconds.max(1e-9) / 1e6,
    ));
    if let (Some(out), Some(kind)) = (&args.output, output_kind) {
        match kind {
            Output::Shprt => file.write(out)?,
            Output::Gltf => shlight_prt::write_gltf(out, &mesh, &file)?,
        }
    }
    if let (Some(path), Some(light)) = (&args.preview, &light) {
        write_preview(path, &mesh, &file, light, args)?;
    }
    Ok(())
}

/// `--mode glossy`: says the matrices' bytes (refusing more than shlight
/// bakes), bakes them and writes the `.shprt` file.
fn glossy_bake(
    args: &PrtArgs,
    ui: &Ui,
    mesh: &Mesh,
    request: &BakeRequest,
    brdf: Brdf,
    compress: Option<(usize, usize)>,
) -> Result<()> {
    let name = args.mesh.display().to_string();
    let channels = glossy_channels(&request.options(mesh).0);
    let size = |lmax| glossy_bytes(mesh.vertex_count(), channels, lmax).unwrap_or(u64::MAX);
    let bytes = size(args.lmax);
    let mib = |b: u64| b as f64 / f64::from(1u32 << 20);
    if bytes > MAX_GLOSSY_BYTES {
        let fits = (0..args.lmax).rev().find(|&l| size(l) <= MAX_GLOSSY_BYTES);
        bail!(
            "{name}: --lmax {}: glossy matrices of {} vertices x {channels} channel{} x {}^2 \
             floats would take {:.0} MiB, beyond the {:.0} MiB shlight bakes{}",
            args.lmax,
            mesh.vertex_count(),
            if channels == 1 { "" } else { "s" },
            (args.lmax + 1) * (args.lmax + 1),
            mib(bytes),
            mib(MAX_GLOSSY_BYTES),
            fits.map_or(String::new(), |l| format!(
                " (--lmax {l} takes {:.0} MiB)",
                mib(size(l))
            ))
        );
    }
    let dim = channels * (args.lmax + 1).pow(4);
    if let Some((_, vectors)) = compress.filter(|&(_, k)| k > dim) {
        bail!(
            "--compress: a vertex's matrices hold {dim} values at --lmax {}: at most {dim} basis \
             vectors per cluster, not {vectors}",
            args.lmax
        );
    }
    ui.note(format!(
        "{name}: glossy matrices take {:.1} MiB ({} vertices x {channels} channel{} x {}^2 floats, with positions and normals)",
        mib(bytes),
        mesh.vertex_count(),
        if channels == 1 { "" } else { "s" },
        (args.lmax + 1) * (args.lmax + 1),
    ));
    let bars = StageBars::new(ui, |stage| match stage {
        Stage::Rays => "directions".to_string(),
        Stage::Bounce(k) => format!("bounce {k}"),
        Stage::Matrices => "matrices".to_string(),
    });
    let start = Instant::now();
    let (transfer, mut file) =
        bake_glossy_file(mesh, &args.mesh, request, brdf, &|stage, done, total| {
            bars.update(stage, done, total)
        });
    bars.finish();
    let seconds = start.elapsed().as_secs_f64();
    ui.note(format!(
        "{name}: {} vertices, {} triangles, glossy {} transfer for {brdf}, lmax {}, {} directions; {} rays in {seconds:.2} s",
        mesh.vertex_count(),
        mesh.triangle_count(),
        request.mode.name(),
        args.lmax,
        transfer.samples,
        transfer.rays,
    ));
    if let Some((clusters, vectors)) = compress {
        let bar = ui.spinner("compressing (CPCA)");
        let e = shlight_prt::compress_file(&mut file, clusters, vectors, args.seed)
            .map_err(|e| anyhow::anyhow!("--compress: {e}"))?;
        bar.finish_and_clear();
        ui.note(format!(
            "{name}: cpca:{clusters},{vectors}: {:.1} MiB of matrices in {:.1} MiB; RMS error {:.3e} ({:.2}% of the entries' RMS)",
            mib(e.bytes_before),
            mib(e.bytes_after),
            e.rms,
            100.0 * e.rms / e.rms_entries.max(f64::MIN_POSITIVE),
        ));
    }
    if let Some(out) = &args.output {
        file.write(out)?;
    }
    Ok(())
}

#[derive(Clone, Copy)]
enum Output {
    Shprt,
    Gltf,
}

fn output_kind(path: &Path) -> Result<Output> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("shprt") => Ok(Output::Shprt),
        Some("gltf" | "glb") => Ok(Output::Gltf),
        _ => bail!(
            "{}: unknown output format (use .shprt, .gltf or .glb)",
            path.display()
        ),
    }
}

/// Shades every vertex (`T . L`) and rasterises the mesh to `path`.
fn write_preview(
    path: &Path,
    mesh: &Mesh,
    file: &ShprtFile,
    light: &shlight_core::sh::ShCoeffs<DVec3>,
    args: &PrtArgs,
) -> Result<()> {
    let radiance: Vec<glam::Vec3> = file
        .view()?
        .exit_radiance(light.as_slice())
        .iter()
        .map(|c| c.as_vec3())
        .collect();
    let (w, h) = args.preview_size;
    let image = shlight_prt::render_preview(mesh, &radiance, w, h);
    let exposure = args
        .preview_exposure
        .unwrap_or_else(|| shlight_prt::vertex_exposure(&radiance));
    write_image(
        path,
        &image,
        &WriteOptions {
            exposure_ev: exposure,
            tone_map: ToneMap::Aces,
            ..WriteOptions::default()
        },
    )?;
    Ok(())
}
