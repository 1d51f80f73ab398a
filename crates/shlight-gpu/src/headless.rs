//! Rendering without a window: a frame into an offscreen `Rgba32Float`
//! texture, read back to the CPU.

use crate::pipeline::DEPTH_FORMAT;
use crate::readback::TextureReadback;
use crate::{Camera, GpuContext, GpuError, Renderer, Shading};

/// Colour format of headless frames: linear 32-bit float RGBA.
pub const HEADLESS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// A frame read back: `width x height` RGBA, row 0 at the top. Alpha is 1
/// where the mesh or the background was drawn and 0 elsewhere.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` RGBA values, rows from the top.
    pub pixels: Vec<[f32; 4]>,
}

impl Frame {
    /// The RGB of each pixel.
    #[must_use]
    pub fn rgb(&self) -> Vec<[f32; 3]> {
        self.pixels.iter().map(|p| [p[0], p[1], p[2]]).collect()
    }
}

/// An offscreen colour and depth target with its read-back buffer.
#[derive(Debug)]
pub struct Offscreen {
    width: u32,
    height: u32,
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    readback: TextureReadback<[f32; 4]>,
}

impl Offscreen {
    /// Targets of `width x height` pixels.
    ///
    /// # Errors
    /// [`GpuError::Invalid`] for a zero size or one beyond the device's
    /// texture limit.
    pub fn new(ctx: &GpuContext, width: usize, height: usize) -> Result<Self, GpuError> {
        let max = ctx.device.limits().max_texture_dimension_2d as usize;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(GpuError::Invalid(format!(
                "image size {width}x{height} is outside 1..={max} on this GPU"
            )));
        }
        let size = wgpu::Extent3d {
            width: width as u32,
            height: height as u32,
            depth_or_array_layers: 1,
        };
        let texture = |format, usage| {
            ctx.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("offscreen"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = texture(
            HEADLESS_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        Ok(Self {
            width: width as u32,
            height: height as u32,
            color_view: color.create_view(&Default::default()),
            depth_view: depth_view(ctx, width as u32, height as u32),
            color,
            readback: TextureReadback::new(&ctx.device, size),
        })
    }

    /// Width / height.
    #[must_use]
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// A command encoder holding one frame's draw into the colour and depth
    /// targets.
    fn encode_draw(
        &self,
        ctx: &GpuContext,
        renderer: &Renderer,
        camera: &Camera,
        shading: &Shading,
    ) -> Result<wgpu::CommandEncoder, GpuError> {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        renderer.draw(
            ctx,
            &mut encoder,
            &self.color_view,
            &self.depth_view,
            camera,
            self.aspect(),
            shading,
        )?;
        Ok(encoder)
    }

    /// Draws one frame and waits for it, without reading it back (for timing).
    ///
    /// # Errors
    /// As [`Renderer::draw`], and GPU errors raised while drawing.
    pub fn draw(
        &self,
        ctx: &GpuContext,
        renderer: &Renderer,
        camera: &Camera,
        shading: &Shading,
    ) -> Result<(), GpuError> {
        let encoder = self.encode_draw(ctx, renderer, camera, shading)?;
        ctx.checked(|| ctx.queue.submit([encoder.finish()]))?;
        ctx.wait()
    }

    /// Draws one frame and reads it back.
    ///
    /// # Errors
    /// As [`Offscreen::draw`], and a failed read-back.
    pub fn render(
        &self,
        ctx: &GpuContext,
        renderer: &Renderer,
        camera: &Camera,
        shading: &Shading,
    ) -> Result<Frame, GpuError> {
        if renderer.color_format() != HEADLESS_FORMAT {
            return Err(GpuError::Invalid(format!(
                "headless frames need a renderer for {HEADLESS_FORMAT:?}"
            )));
        }
        let encoder = self.encode_draw(ctx, renderer, camera, shading)?;
        self.read_back(ctx, encoder)
    }

    /// Draws one frame recorded by `record` (given the encoder, the colour
    /// view and the depth view, e.g. a [`Renderer::draw`] then a
    /// [`VolumeRenderer::draw`](crate::VolumeRenderer::draw)) and waits for
    /// it; with `read_back`, returns the frame.
    ///
    /// # Errors
    /// What `record` returns, GPU errors while drawing, a failed read-back.
    pub fn render_with(
        &self,
        ctx: &GpuContext,
        read_back: bool,
        record: impl FnOnce(
            &mut wgpu::CommandEncoder,
            &wgpu::TextureView,
            &wgpu::TextureView,
        ) -> Result<(), GpuError>,
    ) -> Result<Option<Frame>, GpuError> {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        record(&mut encoder, &self.color_view, &self.depth_view)?;
        if read_back {
            return self.read_back(ctx, encoder).map(Some);
        }
        ctx.checked(|| ctx.queue.submit([encoder.finish()]))?;
        ctx.wait()?;
        Ok(None)
    }

    /// Submits `encoder` with a copy of the colour target and reads it back.
    fn read_back(
        &self,
        ctx: &GpuContext,
        encoder: wgpu::CommandEncoder,
    ) -> Result<Frame, GpuError> {
        Ok(Frame {
            width: self.width as usize,
            height: self.height as usize,
            pixels: self.readback.read(ctx, encoder, &self.color)?,
        })
    }
}

/// Renders one frame of `renderer`'s mesh and light at `width x height`.
///
/// # Errors
/// As [`Offscreen::new`] and [`Offscreen::render`].
pub fn render_frame(
    ctx: &GpuContext,
    renderer: &Renderer,
    camera: &Camera,
    shading: &Shading,
    width: usize,
    height: usize,
) -> Result<Frame, GpuError> {
    Offscreen::new(ctx, width, height)?.render(ctx, renderer, camera, shading)
}

/// A depth target of `width x height` in [`DEPTH_FORMAT`], for
/// [`Renderer::draw`].
#[must_use]
pub fn depth_view(ctx: &GpuContext, width: u32, height: u32) -> wgpu::TextureView {
    ctx.device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&Default::default())
}
