//! Everything `shlight project` decides from its arguments before reading
//! any input: the pipeline's settings (checked by shlight-pipeline's
//! `ProjectOptions::check`, as the Python package's are), the GPU and the
//! preview's panels.

use anyhow::{Result, anyhow};
use shlight_core::map::{Layout, MapOrientation};
use shlight_io::ReadOptions;
use shlight_pipeline::{
    CpuProjector, PreviewOptions, ProjectOptions, Projector, ReadSettings, Spelling, output_grid,
};

use super::args::{Method, ProjectArgs};

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
        let pipeline = ProjectOptions {
            read: ReadSettings {
                layout: args.layout,
                read: ReadOptions {
                    layer: args.layer.clone(),
                    max_pixels: args.max_pixels,
                },
                sanitize: args.sanitize,
            },
            lmax: args.lmax,
            orientation: MapOrientation {
                frame: crate::input::frame_of(&args.up),
                mirror: args.mirror,
            },
            monte_carlo: args.method == Method::MonteCarlo,
            samples: args.samples,
            sampler: args.sampler,
            seed: args.seed,
            window: &args.window,
            rotate: args.rotate.as_deref(),
            quantity: args.quantity,
            encoding: args.encoding,
            gpu: args.gpu,
            format: args.format,
        }
        .check(Spelling::CommandLine)?;
        #[cfg(not(feature = "gpu"))]
        if args.gpu {
            return Err(crate::gpu_feature::needs_gpu("project --gpu"));
        }
        #[cfg(feature = "gpu")]
        let gpu = if args.gpu {
            if pipeline.project.method != shlight_pipeline::Method::Quadrature {
                anyhow::bail!(
                    "--gpu computes the quadrature; it does not apply to --method montecarlo"
                );
            }
            if args.lmax > shlight_baked::LIGHT_MAX_LMAX {
                anyhow::bail!(
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
        Ok(Self {
            args,
            pipeline,
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
