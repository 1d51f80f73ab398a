//! Reading GPU memory back to the CPU: a mappable buffer
//! ([`read_buffer`]), a texture through a buffer of padded rows
//! (`TextureReadback`: headless frames, screenshots), and an 8-bit sRGB
//! colour texture as linear RGB ([`read_srgb8_texture`], a window's
//! screenshot).

use std::marker::PhantomData;

use shlight_io::{Image, srgb_to_linear};

use crate::{GpuContext, GpuError};

/// Maps `buffer` (`MAP_READ`) after the queue's work, copies its bytes out
/// and unmaps it.
///
/// # Errors
/// A lost device or a failed mapping.
pub fn read_buffer(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    ctx.wait()?;
    rx.recv()
        .map_err(|_| GpuError::Runtime("buffer mapping was dropped".into()))?
        .map_err(|e| GpuError::Runtime(format!("cannot map a buffer: {e}")))?;
    let bytes = buffer
        .get_mapped_range(..)
        .map_err(|e| GpuError::Runtime(format!("cannot read a mapped buffer: {e}")))?
        .to_vec();
    buffer.unmap();
    Ok(bytes)
}

/// A mappable buffer that a 2D texture of one size, with texels of type
/// `T` (e.g. `[f32; 4]` for `Rgba32Float`, `[u8; 4]` for `Rgba8Unorm`), is
/// copied into, rows padded to [`wgpu::COPY_BYTES_PER_ROW_ALIGNMENT`], and
/// read back without the padding.
#[derive(Debug)]
pub(crate) struct TextureReadback<T> {
    buffer: wgpu::Buffer,
    size: wgpu::Extent3d,
    padded_row: u32,
    texel: PhantomData<T>,
}

impl<T: bytemuck::Pod> TextureReadback<T> {
    /// A buffer for one layer of `size`.
    pub(crate) fn new(device: &wgpu::Device, size: wgpu::Extent3d) -> Self {
        let row = size.width * std::mem::size_of::<T>() as u32;
        let padded_row = row.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("texture readback"),
            size: u64::from(padded_row) * u64::from(size.height),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            buffer,
            size,
            padded_row,
            texel: PhantomData,
        }
    }

    /// Appends the copy of `texture` (of this size and texel type, with
    /// `COPY_SRC`) into the buffer to `encoder`, submits it, waits, and
    /// returns the texels, rows from the top.
    ///
    /// # Errors
    /// [`GpuError::Runtime`] when the work is invalid (e.g. a texture
    /// without `COPY_SRC`, or of another size), a lost device or a failed
    /// mapping.
    pub(crate) fn read(
        &self,
        ctx: &GpuContext,
        mut encoder: wgpu::CommandEncoder,
        texture: &wgpu::Texture,
    ) -> Result<Vec<T>, GpuError> {
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: None,
                },
            },
            self.size,
        );
        ctx.checked(|| ctx.queue.submit([encoder.finish()]))?;
        let bytes = read_buffer(ctx, &self.buffer)?;
        let (w, h) = (self.size.width as usize, self.size.height as usize);
        let mut texels = vec![T::zeroed(); w * h];
        let row = w * std::mem::size_of::<T>();
        let rows = bytemuck::cast_slice_mut::<T, u8>(&mut texels).chunks_exact_mut(row);
        for (dst, src) in rows.zip(bytes.chunks_exact(self.padded_row as usize)) {
            dst.copy_from_slice(&src[..row]);
        }
        Ok(texels)
    }
}

/// Reads a `Rgba8`/`Bgra8` texture (unorm or unorm-sRGB, `COPY_SRC`, one
/// layer) back as linear RGB: copied to a buffer ([`wgpu::Texture::format`]
/// says which of the four), mapped, and decoded by `srgb8_to_linear` (a
/// window's surface holds sRGB-encoded values, which the image writers
/// encode again from linear ones). Alpha is dropped.
///
/// # Errors
/// [`GpuError::Invalid`] for a texture of another format;
/// [`GpuError::Runtime`] for one that cannot be copied (without
/// `COPY_SRC`), a lost device or a failed mapping.
pub fn read_srgb8_texture(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<Image, GpuError> {
    let bgra = match texture.format() {
        wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb => false,
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb => true,
        other => {
            return Err(GpuError::Invalid(format!(
                "cannot read a {other:?} texture as 8-bit sRGB: it must be Rgba8Unorm, \
                 Rgba8UnormSrgb, Bgra8Unorm or Bgra8UnormSrgb"
            )));
        }
    };
    let size = texture.size();
    let (w, h) = (size.width as usize, size.height as usize);
    let encoder = ctx.device.create_command_encoder(&Default::default());
    let texels: Vec<[u8; 4]> =
        TextureReadback::new(&ctx.device, size).read(ctx, encoder, texture)?;
    let pixels = srgb8_to_linear(bytemuck::cast_slice(&texels), w, h, w * 4, bgra);
    Image::new(w, h, pixels).map_err(|e| GpuError::Runtime(e.to_string()))
}

/// `width x height` texels of 8-bit sRGB-encoded RGBA (or BGRA when
/// `bgra`), rows `bytes_per_row` apart, as linear RGB: each channel
/// `srgb_to_linear(v / 255)`, alpha dropped.
///
/// # Panics
/// If `bytes` holds fewer than `height` rows or a row fewer than
/// `4 width` bytes.
#[must_use]
fn srgb8_to_linear(
    bytes: &[u8],
    width: usize,
    height: usize,
    bytes_per_row: usize,
    bgra: bool,
) -> Vec<[f32; 3]> {
    let mut pixels = Vec::with_capacity(width * height);
    for row in bytes.chunks_exact(bytes_per_row).take(height) {
        for p in row[..width * 4].chunks_exact(4) {
            let (r, g, b) = if bgra {
                (p[2], p[1], p[0])
            } else {
                (p[0], p[1], p[2])
            };
            pixels.push([r, g, b].map(|v| srgb_to_linear(f32::from(v) / 255.0)));
        }
    }
    pixels
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two rows of two texels, padded to 12 bytes: channels swizzled for
    /// BGRA, the padding and alpha skipped, sRGB decoded (0 and 255 exact,
    /// 188 about half).
    #[test]
    fn srgb_bytes_decode_to_linear_texels() {
        #[rustfmt::skip]
        let bytes = [
            255, 0, 188, 7,   0, 0, 0, 255,   9, 9, 9, 9,
            0, 255, 0, 0,     1, 2, 3, 4,     9, 9, 9, 9,
        ];
        let rgba = srgb8_to_linear(&bytes, 2, 2, 12, false);
        assert_eq!(rgba.len(), 4);
        assert_eq!(rgba[0][0], 1.0);
        assert_eq!(rgba[0][1], 0.0);
        assert!((rgba[0][2] - 0.5).abs() < 0.01, "{:?}", rgba[0]);
        assert_eq!(rgba[1], [0.0; 3]);
        assert_eq!(rgba[2], [0.0, 1.0, 0.0]);
        assert_eq!(rgba[3], [1, 2, 3].map(|v| srgb_to_linear(v as f32 / 255.0)));
        let bgra = srgb8_to_linear(&bytes, 2, 2, 12, true);
        assert_eq!(bgra[0], [rgba[0][2], rgba[0][1], rgba[0][0]]);
        assert_eq!(bgra[3], [3, 2, 1].map(|v| srgb_to_linear(v as f32 / 255.0)));
    }
}
