//! `shlight view`'s screenshots: the rendered texture read back
//! (`shlight_gpu::read_srgb8_texture`) and written as PNG.

use std::path::Path;

use shlight_gpu::{GpuContext, read_srgb8_texture, wgpu};
use shlight_io::{WriteOptions, write_image};

use crate::ViewerError;

/// Reads an 8-bit RGBA or BGRA texture back and writes it as PNG.
pub fn save_screenshot(
    ctx: &GpuContext,
    texture: &wgpu::Texture,
    path: &Path,
) -> Result<(), ViewerError> {
    let image = read_srgb8_texture(ctx, texture).map_err(ViewerError::ScreenshotRead)?;
    write_image(path, &image, &WriteOptions::default()).map_err(|source| {
        ViewerError::ScreenshotWrite {
            path: path.to_path_buf(),
            source,
        }
    })
}
