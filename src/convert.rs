//! `shlight convert`: coefficient files to engine formats and back
//! (docs/exporters.md), a light into a glTF asset, a volume to three.js's
//! grid or a shader snippet, by shlight-pipeline's `convert` job.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use shlight_format::ExportFormat;
use shlight_pipeline::{ConvertRequest, Spelling, convert};

use crate::progress::{Reporter, Ui};
use crate::volume::PrecisionArg;

/// Arguments of `shlight convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input: a shlight coefficient file (JSON), three.js LightProbe JSON, a
    /// glTF or GLB with EXT_lights_image_based, shlight's Unity JSON, or
    /// a Filament sh.txt; or an irradiance volume (.shvol), which converts
    /// to --format threejs (three.js's LightProbeGridWebGL), wgsl or glsl
    /// (a snippet of its lookup, its textures beside it).
    pub input: PathBuf,
    /// Output file (written atomically); without it the result goes to
    /// stdout and --format is needed.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Output format; by default inferred from the output's extension where
    /// only one format writes it (.wgsl, .glsl/.frag/.vert, .hlsl, .c/.h,
    /// .gltf).
    #[arg(long, value_parser = crate::values::export_format())]
    pub format: Option<ExportFormat>,
    /// Add the light to this existing glTF asset (.gltf or .glb) in place,
    /// as an EXT_lights_image_based light its default scene uses; nothing
    /// else in the asset changes.
    #[arg(long, value_name = "SCENE.gltf|glb", conflicts_with_all = ["output", "format"])]
    pub into: Option<PathBuf>,
    /// Numbers of the atlas when a volume (.shvol) is converted to
    /// --format threejs.
    #[arg(long, value_enum, default_value = "half")]
    pub precision: PrecisionArg,
    /// Write a glTF light (--format gltf, --into) from the coefficients
    /// alone, without the specularImages the extension requires (a
    /// coefficient file holds no map to prefilter; `shlight project MAP
    /// --format gltf` writes them).
    #[arg(long)]
    pub irradiance_only: bool,
}

/// Runs `shlight convert`.
pub fn run(args: &ConvertArgs, ui: &Ui) -> Result<()> {
    let plan = ConvertRequest {
        input: &args.input,
        output: args.output.as_deref(),
        format: args.format,
        into: args.into.as_deref(),
        precision: args.precision.into(),
        irradiance_only: args.irradiance_only,
    }
    .check(Spelling::CommandLine)?;
    let converted = convert(&plan, &Reporter::new(ui))?;
    for path in &converted.written {
        eprintln!("wrote {}", path.display());
    }
    if let Some(text) = converted.stdout {
        let mut out = std::io::stdout().lock();
        out.write_all(text.as_bytes())
            .and_then(|()| out.flush())
            .context("writing to stdout")?;
    }
    Ok(())
}
