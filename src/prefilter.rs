//! `shlight prefilter`: an environment map GGX-prefiltered into cube mips
//! for an engine's specular lighting (shlight-pipeline's `prefilter_map`,
//! shlight-specular), written as cmgen's `--ibl-ld` writes them.

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use shlight_pipeline::{
    PrefilterRequest, prefilter_map, write_prefiltered_faces, write_prefiltered_ktx1,
    write_prefiltered_ktx2,
};
use shlight_specular::{Engine, PrefilterSettings};

use crate::input::MapInputArgs;
use crate::output_path::{names_dir, refuse_overwriting};
use crate::progress::Ui;

/// Arguments of `shlight prefilter`.
#[derive(Args, Debug)]
pub struct PrefilterArgs {
    /// The environment map (OpenEXR, Radiance .hdr, PNG, JPEG), any layout.
    pub input: PathBuf,
    /// A directory (`DIR/`): one float EXR per mip and face, named as cmgen's
    /// --ibl-ld names them (m0_px.exr, m0_nx.exr, ... per mip); FILE.ktx: the
    /// KTX 1.1 cube Filament's KtxBundle reads (R11F_G11F_B10F, as cmgen
    /// --format=ktx); or FILE.ktx2: a KTX2 cube with its mips (RGBA16F),
    /// Bevy's EnvironmentMapLight specular map.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The engine whose roughness per mip and cube axes to use.
    #[arg(long = "for", default_value = "filament", value_parser = crate::values::engine())]
    pub engine: Engine,
    /// Face size of mip 0 (a power of two).
    #[arg(long, default_value_t = PrefilterSettings::DEFAULT_SIZE)]
    pub size: usize,
    /// Number of mips (default: the engine's; Filament stops at 16 pixels).
    #[arg(long)]
    pub mips: Option<usize>,
    /// GGX samples per texel at mips 0 and 1, doubled per mip after (cmgen's
    /// --ibl-samples).
    #[arg(long, default_value_t = PrefilterSettings::DEFAULT_SAMPLES)]
    pub samples: u32,
    /// How the map is read.
    #[command(flatten)]
    pub map: MapInputArgs,
}

/// Runs `shlight prefilter`.
pub fn run(args: &PrefilterArgs, ui: &Ui) -> Result<()> {
    let ext = args
        .output
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let (ktx1, ktx2) = (
        ext.as_deref() == Some("ktx"),
        ext.as_deref() == Some("ktx2"),
    );
    if !ktx1 && !ktx2 && !names_dir(&args.output) {
        bail!(
            "{}: -o names a directory for the faces (end it with /, e.g. -o ld/), a .ktx or a .ktx2 file",
            args.output.display()
        );
    }
    refuse_overwriting(&args.output, std::slice::from_ref(&args.input))?;
    let settings = PrefilterSettings {
        engine: args.engine,
        size: args.size,
        mips: args.mips,
        samples: args.samples,
    };
    let request = PrefilterRequest {
        read: args.map.read_settings(),
        orientation: args.map.orientation(),
        settings,
    };
    settings.check()?;
    let bar = ui.bar(settings.rows() as u64, "prefilter");
    let cube = prefilter_map(&args.input, &request, &|m| ui.warn(m), &|n| {
        bar.inc(n as u64);
    });
    bar.finish_and_clear();
    let cube = cube?;
    if ktx1 {
        write_prefiltered_ktx1(&cube, &args.output)?;
    } else if ktx2 {
        write_prefiltered_ktx2(&cube, &args.output)?;
    } else {
        write_prefiltered_faces(&cube, &args.output)?;
    }
    for (k, level) in cube.levels.iter().enumerate() {
        ui.note(format!(
            "mip {k}: {0}x{0}, roughness {1:.4} (perceptual {2:.4}), {3} samples",
            level.cube.size(),
            level.alpha,
            level.alpha.sqrt(),
            level.samples
        ));
    }
    Ok(())
}
