//! `shlight convert`: coefficient files to engine formats and back
//! (docs/exporters.md).
//!
//! Reads a shlight coefficient file (JSON), or a file written by an exporter
//! that keeps enough to recover the coefficients (shlight-format's
//! `read_coefficients`), and writes any `--format`; `json` writes a shlight
//! coefficient file. A `.shvol` volume converts to `--format threejs`, the
//! atlas of three.js's `LightProbeGridWebGL` (shlight-format's
//! `threejs_volume`), or to a WGSL or GLSL snippet of its lookup with its
//! textures (`volume_shader`).

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use shlight_format::gltf;
use shlight_format::{ExportFormat, ExportInput, export, read_coefficients};

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
pub fn run(args: &ConvertArgs) -> Result<()> {
    let is_volume = args
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("shvol"));
    if is_volume {
        return volume(args);
    }
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

/// `shlight convert VOLUME.shvol --format threejs -o grid.json`: the
/// volume as three.js's `LightProbeGridWebGL` document; `-o NAME.wgsl` or
/// `NAME.glsl`: the visibility-weighted lookup as a shader snippet, its
/// textures beside it (shlight-format's `volume_shader`; docs/shvol.md,
/// "Engines' shaders").
fn volume(args: &ConvertArgs) -> Result<()> {
    use shlight_format::{ShaderLanguage, VolumeFormat, write_volume_shader};
    let input = args.input.display();
    if args.into.is_some() {
        bail!("{input}: --into adds a light to a glTF asset; a volume is not one light");
    }
    let Some(output) = &args.output else {
        bail!(
            "{input}: converting a volume needs -o (FILE.json with --format threejs, or FILE.wgsl / FILE.glsl)"
        );
    };
    let format = match args.format {
        Some(f) => f,
        None => match ExportFormat::from_path(output) {
            Ok(f @ (ExportFormat::Wgsl | ExportFormat::Glsl)) => f,
            _ => bail!("{input}: converting a volume needs --format threejs, or -o FILE.wgsl|glsl"),
        },
    };
    let language = match format {
        ExportFormat::Threejs => None,
        ExportFormat::Wgsl => Some(ShaderLanguage::Wgsl),
        ExportFormat::Glsl => Some(ShaderLanguage::Glsl),
        f => bail!(
            "{input}: a volume converts to --format threejs (three.js's LightProbeGrid), wgsl or \
             glsl (a shader snippet and its textures), not {}",
            f.name()
        ),
    };
    crate::output_path::refuse_overwriting(output, std::slice::from_ref(&args.input))?;
    let file = shlight_format::ShvolFile::read(&args.input)?;
    let Some(language) = language else {
        for note in file.write_as(output, VolumeFormat::Threejs, args.precision.into())? {
            eprintln!("note: {note}");
        }
        return Ok(());
    };
    let written = write_volume_shader(&file, language, output)
        .with_context(|| format!("{input}: converting"))?;
    for note in &written.notes {
        eprintln!("note: {note}");
    }
    for path in &written.paths {
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}
