//! Reading a mappable buffer back to the CPU.

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
