//! The arguments of `shlight project`.

use std::path::PathBuf;

use clap::builder::{PossibleValuesParser, TypedValueParser};
use clap::{Args, ValueEnum};
use shlight_core::map::montecarlo::SamplerKind;
use shlight_format::{ExportFormat, Quantity};
use shlight_io::{ReadOptions, ToneMap};

use crate::input::{InputLayout, parse_input_layout};
use crate::values::parse_size;

/// Arguments of `shlight project`.
#[derive(Args, Debug)]
pub struct ProjectArgs {
    /// Environment maps (OpenEXR, Radiance .hdr, PNG, JPEG) in any layout
    /// (--layout); `NAME_{face}.exr` reads six cube-face files.
    /// Several need `-o DIR`.
    #[arg(required = true, value_name = "INPUT")]
    pub inputs: Vec<PathBuf>,
    /// Highest SH degree kept (lmax 2 = 9 coefficients).
    #[arg(long, default_value_t = 2)]
    pub lmax: usize,
    /// Which world axis the top row of the map faces.
    #[arg(long, default_value = "y", value_parser = ["y", "z"])]
    pub up: String,
    /// Read a map made for the mirrored pbrt / google mapping.
    #[arg(long)]
    pub mirror: bool,
    /// Layout of the input maps: auto (by aspect ratio: 2:1 equirect, 4:3
    /// cross-h, 3:4 cross-v, 6:1 strip, 1:1 angular), equirect, cross-h,
    /// cross-v, strip, angular, mirror-ball, or faces (six square files: an
    /// INPUT holding `{face}`, which becomes px nx py ny pz nz).
    #[arg(long, default_value = "auto", value_parser = parse_input_layout)]
    pub layout: InputLayout,
    /// How the coefficients are computed: exact texel-solid-angle
    /// quadrature, or Monte Carlo integration of the bilinearly interpolated
    /// map (with a standard error per coefficient in the file).
    #[arg(long, value_enum, default_value_t)]
    pub method: Method,
    /// Monte Carlo: directions to draw [default: 65536]. Stratified and
    /// sobol round to whole grids; the count used is recorded.
    #[arg(long, value_name = "N", value_parser = parse_samples, allow_negative_numbers = true)]
    pub samples: Option<usize>,
    /// Monte Carlo: how directions are drawn [default: sobol]. importance
    /// follows the map's luminance.
    #[arg(long, value_parser = sampler_parser())]
    pub sampler: Option<SamplerKind>,
    /// Monte Carlo: seed of the random streams (equal seeds give identical
    /// files) [default: 6001130381083431937].
    #[arg(long, allow_negative_numbers = true)]
    pub seed: Option<u64>,
    /// What the coefficients hold.
    #[arg(long, value_parser = crate::values::quantity(), default_value = "radiance")]
    pub quantity: Quantity,
    /// Ringing window: none, hanning:W, lanczos:W, laplacian:LAMBDA, or auto
    /// (per colour channel, the weakest Hanning window that makes that
    /// channel's result non-negative).
    #[arg(long, default_value = "none")]
    pub window: String,
    /// Rotate the coefficients: yaw:DEG (about the frame's up axis,
    /// right-handed), quat:X,Y,Z,W, or euler:X,Y,Z (degrees; about world X,
    /// then Y, then Z). A light from a comes from R a afterwards.
    #[arg(long, allow_hyphen_values = true)]
    pub rotate: Option<String>,
    /// How to keep the lighting (docs/coefficient-file.md, `encoding`):
    /// sh, dominant+sh (SH to --lmax of the map without its lights),
    /// sloan+sh, zh3, zh3-hallucinated, l1-nonlinear, ambient-cube. The
    /// encodings other than sh take radiance by quadrature, without
    /// --window, --rotate or --gpu, into the JSON file.
    #[arg(long, value_parser = crate::values::encoding(), default_value = "sh")]
    pub encoding: shlight_core::encoding::Encoding,
    /// Project on the GPU (equirect maps, quadrature, lmax up to 8): the
    /// same sums in f32 by a compute shader, within 1e-4 of the CPU.
    #[arg(long)]
    pub gpu: bool,
    /// Replace NaN and -inf with 0, +inf with the largest finite value, and
    /// negatives with 0, instead of refusing NaN/inf and keeping negatives.
    #[arg(long)]
    pub sanitize: bool,
    /// EXR layer to read (default: the first with R, G, B).
    #[arg(long)]
    pub layer: Option<String>,
    /// Refuse inputs with more pixels than this (judged from the header).
    #[arg(long, default_value_t = ReadOptions::DEFAULT_MAX_PIXELS)]
    pub max_pixels: usize,
    /// Output file, or with several inputs (or an existing directory) a
    /// directory for one file per input, NAME.json (the extension follows
    /// --format); without it, and without --format, a readable table goes to
    /// a terminal and JSON to a pipe.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Output format [default: json]: shlight's coefficient file, or an
    /// engine or shader format (docs/exporters.md).
    #[arg(long, value_parser = crate::values::export_format())]
    pub format: Option<ExportFormat>,
    /// With --format gltf: the face size of the light's specular cube (a
    /// power of two; its mips run down to 1 pixel).
    #[arg(long, default_value_t = shlight_pipeline::GLTF_SPECULAR_SIZE)]
    pub specular_size: usize,
    /// With --format gltf: GGX samples per texel of the specular cube's mips
    /// 0 and 1, doubled per mip after.
    #[arg(long, default_value_t = shlight_specular::PrefilterSettings::DEFAULT_SAMPLES)]
    pub specular_samples: u32,
    /// Write a preview image: input | SH radiance | SH irradiance/π, side
    /// by side. With several inputs, a directory for one NAME.png each.
    #[arg(long, value_name = "FILE.png")]
    pub preview: Option<PathBuf>,
    /// Size of each preview panel, WIDTHxHEIGHT (2:1).
    #[arg(long, default_value = "512x256", value_parser = parse_size)]
    pub preview_size: (usize, usize),
    /// Preview exposure in stops (default: the mean radiance at 0.18).
    #[arg(long, allow_negative_numbers = true)]
    pub preview_exposure: Option<f32>,
    /// Preview tone map: clamp, reinhard or aces.
    #[arg(long, default_value = "aces")]
    pub preview_tone_map: ToneMap,
}

/// How `shlight project` computes coefficients.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Exact texel-solid-angle quadrature over every texel.
    #[default]
    Quadrature,
    /// Monte Carlo integration (--samples, --sampler, --seed), with
    /// standard errors.
    #[value(name = "montecarlo")]
    MonteCarlo,
}

/// `--samples N`: a whole number of at least 1.
fn parse_samples(s: &str) -> std::result::Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(0) => Err("the sample count must be at least 1".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!("{s:?} is not a whole number of samples")),
    }
}

/// `--sampler NAME`: one of the Monte Carlo samplers' names.
fn sampler_parser() -> impl TypedValueParser<Value = SamplerKind> {
    PossibleValuesParser::new(SamplerKind::ALL.map(SamplerKind::name)).map(|name| {
        name.parse::<SamplerKind>()
            .expect("possible values are sampler names")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use shlight_core::map::montecarlo::{DEFAULT_SEED, McOptions};
    use shlight_pipeline::DEFAULT_SAMPLES;

    #[test]
    fn the_help_states_the_library_defaults() {
        use clap::Args as _;
        let cmd = ProjectArgs::augment_args(clap::Command::new("project"));
        let help = |id: &str| {
            cmd.get_arguments()
                .find(|a| a.get_id() == id)
                .and_then(|a| a.get_help())
                .map(|h| h.to_string())
                .unwrap_or_default()
        };
        let d = McOptions::default();
        assert!(help("seed").contains(&format!("[default: {DEFAULT_SEED}]")));
        assert!(help("samples").contains(&format!("[default: {DEFAULT_SAMPLES}]")));
        assert!(help("sampler").contains(&format!("[default: {}]", d.sampler)));
        assert_eq!((d.samples, d.seed), (DEFAULT_SAMPLES, DEFAULT_SEED));
    }
}
