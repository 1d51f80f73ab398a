//! `shlight convert`: coefficient files to engine formats and back
//! (docs/exporters.md).
//!
//! Reads a shlight coefficient file (JSON), or a file written by an exporter
//! that keeps enough to recover the coefficients (shlight-format's
//! `read_coefficients`), and writes any `--format`; `json` writes a shlight
//! coefficient file.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use shlight_format::gltf;
use shlight_format::{ExportFormat, ExportInput, export, read_coefficients};

/// Arguments of `shlight convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input: a shlight coefficient file (JSON), three.js LightProbe JSON, a
    /// glTF or GLB with EXT_lights_image_based, shlight's Unity JSON, or
    /// a Filament sh.txt.
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
    /// Write a glTF light (--format gltf, --into) from the coefficients
    /// alone, without the specularImages the extension requires (a
    /// coefficient file holds no map to prefilter; `shlight project MAP
    /// --format gltf` writes them).
    #[arg(long)]
    pub irradiance_only: bool,
}

/// Runs `shlight convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    if let Some(scene) = &args.into {
        if !args.irradiance_only {
            bail!("{}: {}", args.input.display(), gltf::MISSING_SPECULAR);
        }
        crate::output_path::refuse_overwriting(scene, std::slice::from_ref(&args.input))?;
        let file = read_coefficients(&args.input)?;
        if file.encoding != shlight_format::FileEncoding::Sh {
            bail!(
                "{}: holds the {} encoding, whose coefficients are not the whole light; \
                 a glTF light keeps plain SH only",
                args.input.display(),
                file.encoding.encoding()
            );
        }
        let input = ExportInput {
            coeffs: &file.coeffs,
            quantity: file.quantity,
            frame: file.frame,
        };
        for note in gltf::add_light_to_file(&input, scene)? {
            eprintln!("note: {note}");
        }
        return Ok(());
    }
    let format = match (args.format, &args.output) {
        (Some(f), _) => f,
        (None, Some(path)) => ExportFormat::from_path(path)?,
        (None, None) => bail!("writing to stdout needs --format (or give -o FILE)"),
    };
    let file = read_coefficients(&args.input)?;
    let out = match format {
        // Without the flag, export refuses a glTF light (after the checks
        // every format shares).
        ExportFormat::Gltf if args.irradiance_only => shlight_format::export_gltf(&file, None),
        _ => export(&file, format),
    }
    .with_context(|| format!("{}: converting", args.input.display()))?;
    for note in &out.notes {
        eprintln!("note: {note}");
    }
    let text = out.text;
    match &args.output {
        Some(path) => shlight_io::write_atomically(path, |out| out.write_all(text.as_bytes()))
            .with_context(|| format!("writing {}", path.display()))?,
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(text.as_bytes())
                .and_then(|()| out.flush())
                .context("writing to stdout")?;
        }
    }
    Ok(())
}
