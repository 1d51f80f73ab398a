//! `shlight prefilter`: an environment map GGX-prefiltered into cube mips
//! for an engine's specular lighting, by shlight-pipeline's `prefilter`
//! job.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use shlight_pipeline::{PrefilterRequest, Spelling, prefilter};
use shlight_specular::{PrefilterSettings, TargetEngine};

use crate::input::MapInputArgs;
use crate::progress::{Reporter, Ui};

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
    pub engine: TargetEngine,
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
    let plan = PrefilterRequest {
        input: &args.input,
        output: &args.output,
        read: args.map.read_settings(),
        orientation: args.map.orientation(),
        settings: PrefilterSettings {
            engine: args.engine,
            size: args.size,
            mips: args.mips,
            samples: args.samples,
        },
    }
    .check(Spelling::CommandLine)?;
    prefilter(&plan, &Reporter::new(ui))?;
    Ok(())
}
