//! `shlight view`'s screenshots: the rendered texture read back
//! (`shlight_gpu::read_srgb8_texture`) and written as PNG.

use std::path::Path;

use anyhow::{Context, Result};
use shlight_gpu::{GpuContext, read_srgb8_texture, wgpu};
use shlight_io::{WriteOptions, write_image};

/// Reads an 8-bit RGBA or BGRA texture back and writes it as PNG.
pub fn save_screenshot(ctx: &GpuContext, texture: &wgpu::Texture, path: &Path) -> Result<()> {
    let image = read_srgb8_texture(ctx, texture).context("screenshot")?;
    write_image(path, &image, &WriteOptions::default())
        .with_context(|| format!("{}: writing the screenshot", path.display()))?;
    Ok(())
}
