//! `shlight convert`: coefficient files to engine formats and back
//! (docs/exporters.md).
//!
//! Reads a shlight coefficient file (JSON), or a file written by an exporter
//! that keeps enough to recover the coefficients: three.js LightProbe JSON
//! (radiance), glTF `EXT_lights_image_based` (irradiance), shlight's Unity
//! JSON (irradiance), Filament sh.txt (pre-scaled irradiance, or radiance).
//! Writes any `--format`; `json` writes a shlight coefficient file.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::coeff_file::CoeffFile;
use crate::export::{self, ExportFormat};

/// Arguments of `shlight convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Input: a shlight coefficient file (JSON), three.js LightProbe JSON, a
    /// glTF (fragment) with EXT_lights_image_based, shlight's Unity JSON, or
    /// a Filament sh.txt.
    pub input: PathBuf,
    /// Output file (written atomically); without it the result goes to
    /// stdout and --format is needed.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Output format; by default inferred from the output's extension where
    /// only one format writes it (.wgsl, .glsl/.frag/.vert, .hlsl, .c/.h,
    /// .gltf).
    #[arg(long, value_enum)]
    pub format: Option<ExportFormat>,
}

/// Reads any file `convert` understands as a coefficient file.
pub fn read_any(path: &std::path::Path) -> Result<CoeffFile> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).with_context(|| format!("{name}: cannot read"))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| anyhow::anyhow!("{name}: not a text file (not UTF-8)"))?;
    match export::read_back(&text, &name)? {
        None => CoeffFile::from_json_str(&text, &name),
        Some(imported) => {
            let mut file = CoeffFile::new(imported.coeffs, imported.frame, imported.quantity);
            file.provenance.input = name;
            file.provenance.layout = imported.source.to_string();
            file.provenance.method = "convert".to_string();
            file.provenance.window = "unknown".to_string();
            Ok(file)
        }
    }
}

/// Runs `shlight convert`.
pub fn run(args: &ConvertArgs) -> Result<()> {
    let format = match (args.format, &args.output) {
        (Some(f), _) => f,
        (None, Some(path)) => ExportFormat::from_path(path)?,
        (None, None) => bail!("writing to stdout needs --format (or give -o FILE)"),
    };
    let file = read_any(&args.input)?;
    let out = crate::project::format_output(&file, format)
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
