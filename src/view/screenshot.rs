//! `shlight view`'s screenshots: the rendered texture read back to PNG.

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use shlight_gpu::{GpuContext, wgpu};
use shlight_io::{Image, WriteOptions, srgb_to_linear, write_image};

/// Reads an 8-bit RGBA or BGRA texture back and writes it as PNG.
pub fn save_screenshot(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    format: wgpu::TextureFormat,
    path: &Path,
) -> Result<()> {
    let size = texture.size();
    let (w, h) = (size.width as usize, size.height as usize);
    let padded = (size.width * 4).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("screenshot"),
        size: u64::from(padded) * h as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: None,
            },
        },
        size,
    );
    ctx.queue.submit([encoder.finish()]);
    let bytes = shlight_gpu::read_buffer(ctx, &buffer).context("screenshot")?;
    let bgra = matches!(
        format,
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    );
    let mut pixels = Vec::with_capacity(w * h);
    for row in bytes.chunks_exact(padded as usize).take(h) {
        for p in row[..w * 4].chunks_exact(4) {
            let (r, g, b) = if bgra {
                (p[2], p[1], p[0])
            } else {
                (p[0], p[1], p[2])
            };
            // The target holds sRGB-encoded values; the writer encodes linear ones.
            pixels.push([r, g, b].map(|v| srgb_to_linear(f32::from(v) / 255.0)));
        }
    }
    let image = Image::new(w, h, pixels).map_err(|e| anyhow!("{e}"))?;
    write_image(path, &image, &WriteOptions::default())
        .with_context(|| format!("{}: writing the screenshot", path.display()))?;
    Ok(())
}
