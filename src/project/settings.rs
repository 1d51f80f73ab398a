//! Everything `shlight project` decides from its arguments before reading
//! any input: frame, window, rotation, Monte Carlo options, the GPU.

use anyhow::{Result, anyhow, bail};
use shlight_core::map::montecarlo::{DEFAULT_SEED, McOptions};
use shlight_core::map::{Layout, MapOrientation};
use shlight_core::sh::Window;
use shlight_format::RotationRecord;
use shlight_io::ReadOptions;
use shlight_pipeline::{
    CpuProjector, PreviewOptions, ProjectSettings, Projector, ReadSettings, output_grid,
};

use super::args::{DEFAULT_SAMPLES, Method, ProjectArgs};

/// The library's method for `--method`.
type LibMethod = shlight_pipeline::Method;

/// Everything decided from the arguments before any input is read.
pub struct Settings<'a> {
    pub args: &'a ProjectArgs,
    /// The pipeline's settings for every input (the preview is set per
    /// input).
    pub pipeline: shlight_pipeline::Settings,
    pub preview: PreviewOptions,
    /// The device and pipelines of `--gpu`.
    #[cfg(feature = "gpu")]
    pub gpu: Option<super::gpu::GpuProjection>,
}

impl<'a> Settings<'a> {
    pub fn new(args: &'a ProjectArgs) -> Result<Self> {
        let frame = crate::input::frame_of(&args.up);
        if args.encoding != shlight_core::encoding::Encoding::Sh {
            let e = args.encoding;
            let clash = [
                (
                    args.quantity != shlight_format::Quantity::Radiance,
                    "--quantity irradiance",
                ),
                (args.rotate.is_some(), "--rotate"),
                (args.gpu, "--gpu"),
                (args.method != Method::Quadrature, "--method montecarlo"),
                (args.window.trim() != "none", "--window"),
                (
                    args.format.is_some_and(|f| !f.takes_encodings()),
                    "--format other than json, wgsl, glsl, hlsl or c",
                ),
            ];
            if let Some((_, what)) = clash.iter().find(|(c, _)| *c) {
                bail!(
                    "--encoding {e} keeps radiance projected by quadrature in shlight's JSON file; it cannot be combined with {what}"
                );
            }
        }
        let window = match args.window.trim() {
            "auto" => None,
            spec => Some(
                spec.parse::<Window>()
                    .map_err(|e| anyhow!("--window {spec}: {e}"))?,
            ),
        };
        let rotation = match &args.rotate {
            None => None,
            Some(spec) => {
                let matrix = shlight_pipeline::parse_rotation(spec, frame)?;
                let record = RotationRecord {
                    spec: spec.trim().to_string(),
                    matrix: matrix.transpose().to_cols_array_2d(),
                };
                Some((record, matrix))
            }
        };
        let method = match args.method {
            Method::MonteCarlo => LibMethod::MonteCarlo {
                options: McOptions {
                    lmax: args.lmax,
                    samples: args.samples.unwrap_or(DEFAULT_SAMPLES),
                    seed: args.seed.unwrap_or(DEFAULT_SEED),
                    ..McOptions::default()
                },
                sampler: args.sampler.unwrap_or_default(),
            },
            Method::Quadrature => {
                let given: Vec<&str> = [
                    ("--samples", args.samples.is_some()),
                    ("--sampler", args.sampler.is_some()),
                    ("--seed", args.seed.is_some()),
                ]
                .into_iter()
                .filter_map(|(flag, given)| given.then_some(flag))
                .collect();
                if !given.is_empty() {
                    bail!(
                        "{} only apply to --method montecarlo (the method is quadrature)",
                        given.join(", ")
                    );
                }
                LibMethod::Quadrature
            }
        };
        #[cfg(not(feature = "gpu"))]
        if args.gpu {
            return Err(crate::gpu_feature::needs_gpu("project --gpu"));
        }
        #[cfg(feature = "gpu")]
        let gpu = if args.gpu {
            if method != LibMethod::Quadrature {
                bail!("--gpu computes the quadrature; it does not apply to --method montecarlo");
            }
            if args.lmax > shlight_baked::LIGHT_MAX_LMAX {
                bail!(
                    "--gpu projects to lmax {} at most (asked: {})",
                    shlight_baked::LIGHT_MAX_LMAX,
                    args.lmax
                );
            }
            let ctx = anyhow::Context::context(shlight_gpu::GpuContext::headless(), "--gpu")?;
            let projector = shlight_gpu::GpuProjector::new(&ctx);
            Some(super::gpu::GpuProjection { ctx, projector })
        } else {
            None
        };
        if args.preview.is_some() {
            output_grid(
                Layout::Equirect,
                args.preview_size,
                MapOrientation::default(),
            )
            .map_err(|e| anyhow!("--preview-size: {e}"))?;
        }
        let orientation = MapOrientation {
            frame,
            mirror: args.mirror,
        };
        Ok(Self {
            args,
            pipeline: shlight_pipeline::Settings {
                read: ReadSettings {
                    layout: args.layout,
                    read: ReadOptions {
                        layer: args.layer.clone(),
                        max_pixels: args.max_pixels,
                    },
                    sanitize: args.sanitize,
                },
                project: ProjectSettings {
                    lmax: args.lmax,
                    orientation,
                    method,
                    window,
                    rotation,
                    quantity: args.quantity,
                },
                encoding: args.encoding,
                preview: None,
            },
            preview: PreviewOptions {
                panel: args.preview_size,
                exposure: args.preview_exposure,
                tone_map: args.preview_tone_map,
            },
            #[cfg(feature = "gpu")]
            gpu,
        })
    }

    /// The projection step: the GPU's for `--gpu`, else the library's.
    pub fn projector(&self) -> &dyn Projector {
        #[cfg(feature = "gpu")]
        if let Some(gpu) = &self.gpu {
            return gpu;
        }
        &CpuProjector
    }
}
