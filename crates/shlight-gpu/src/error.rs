//! Errors of the GPU crate.

/// Why a GPU operation failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GpuError {
    /// No adapter (GPU or software rasteriser) could be opened.
    #[error(
        "no GPU adapter found ({0}); install a Vulkan driver (a GPU's, or Mesa's software \
         rasteriser lavapipe: apt install mesa-vulkan-drivers libvulkan1)"
    )]
    NoAdapter(String),
    /// The adapter refused to open a device.
    #[error("the GPU adapter {adapter} refused a device: {reason}")]
    Device {
        /// The adapter's name and backend.
        adapter: String,
        /// wgpu's reason.
        reason: String,
    },
    /// Input the GPU path cannot take (sizes, degrees, array lengths).
    #[error("{0}")]
    Invalid(String),
    /// A GPU operation failed while running (validation, out of memory, lost device).
    #[error("GPU error: {0}")]
    Runtime(String),
}
