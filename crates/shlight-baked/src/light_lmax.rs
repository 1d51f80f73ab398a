//! [`LIGHT_MAX_LMAX`]: the highest degree of the distant light that the
//! renderers shade with.

/// Highest SH degree of a distant light the renderers evaluate: the GPU's
/// shaders (written out per lmax up to it), its projection, and the light a
/// `.shprt` file is shaded with. Here, not in the GPU crate, so that builds
/// without a GPU (`shlight sample`) keep the light to the same lmax.
pub const LIGHT_MAX_LMAX: usize = 8;
