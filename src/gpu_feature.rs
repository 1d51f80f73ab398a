//! What the GPU commands say in a build without the `gpu` feature.

/// The error of a GPU command (`render-mesh`, `view`, `project --gpu`) in a
/// build without the `gpu` feature, naming how to get one.
pub fn needs_gpu(command: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{command} needs the gpu feature: cargo install --path . (default features), \
         or cargo build --release --features gpu"
    )
}
