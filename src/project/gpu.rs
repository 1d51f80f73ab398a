//! `--gpu`: the GPU's projection ([`shlight_gpu::GpuProjector`]) as the
//! pipeline's injected [`Projector`], so the pipeline stays free of wgpu.

use shlight_core::map::{EquirectView, Layout, TexelSource, contiguous_pixels};
use shlight_pipeline::{PipelineError, ProjectSettings, Projection, Projector};

/// The device and pipelines of `--gpu`.
pub struct GpuProjection {
    pub ctx: shlight_gpu::GpuContext,
    pub projector: shlight_gpu::GpuProjector,
}

impl GpuProjection {
    /// A headless device and the projector's pipelines.
    pub fn new() -> anyhow::Result<Self> {
        let ctx = anyhow::Context::context(shlight_gpu::GpuContext::headless(), "--gpu")?;
        let projector = shlight_gpu::GpuProjector::new(&ctx);
        Ok(Self { ctx, projector })
    }
}

impl Projector for GpuProjection {
    /// The quadrature of an equirect map on the GPU; other layouts are
    /// refused.
    fn project(
        &self,
        texels: &dyn TexelSource,
        s: &ProjectSettings,
    ) -> shlight_pipeline::Result<Projection> {
        let layout = texels.layout();
        if layout != Layout::Equirect {
            return Err(PipelineError::new(format!(
                "--gpu projects equirect maps; this one is {}",
                layout.name()
            )));
        }
        let (width, height) = texels.size();
        let pixels = contiguous_pixels(texels);
        let view = EquirectView {
            width,
            height,
            pixels: &pixels,
        };
        let coeffs = self
            .projector
            .project(&self.ctx, view, s.lmax, s.orientation)
            .map_err(|e| PipelineError::new(shlight_pipeline::error_chain(&e)))?;
        Ok(Projection::exact(coeffs))
    }
}
