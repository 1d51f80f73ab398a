//! [`VolumeFetch`]: the two ways the volume pass interpolates the probes'
//! texels, and which an adapter runs. Apart from [`crate::volume`] so that
//! the shader text (`volume_expansion.rs`) and the pass both depend on it
//! and not on each other. The highest degree the pass shades is
//! [`shlight_baked::SHADED_MAX_LMAX`].

use crate::GpuContext;

/// How the volume pass interpolates the probes' texels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeFetch {
    /// One trilinear sample per texel by the sampler (needs
    /// `wgpu::Features::FLOAT32_FILTERABLE`). The sampler computes the
    /// weights: in f32 on lavapipe (within rounding of the CPU's); GPUs
    /// round them to their sub-texel precision (8 bits on most: weights
    /// in steps of 1/256).
    Filtered,
    /// Eight `textureLoad`s per texel, weighted in the shader exactly as
    /// [`shlight_baked::ProbeGrid::trilinear`] weighs them (any adapter).
    Loads,
}

impl VolumeFetch {
    /// Whether `ctx`'s device filters `Rgba32Float` (wgpu's
    /// `FLOAT32_FILTERABLE`), which [`VolumeFetch::Filtered`] needs.
    #[must_use]
    pub fn can_filter(ctx: &GpuContext) -> bool {
        ctx.device
            .features()
            .contains(wgpu::Features::FLOAT32_FILTERABLE)
    }

    /// What `ctx` runs best without losing exactness: [`VolumeFetch::Filtered`]
    /// on a CPU adapter (lavapipe) that can filter ([`VolumeFetch::can_filter`]),
    /// where the sampler weighs in f32 and is the faster path by far; else
    /// [`VolumeFetch::Loads`]: hardware GPUs round the sampler's weights to
    /// 8 bits, and serve the eight loads per texel cheaply.
    #[must_use]
    pub fn best(ctx: &GpuContext) -> Self {
        let cpu = ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
        if cpu && Self::can_filter(ctx) {
            Self::Filtered
        } else {
            Self::Loads
        }
    }
}
