//! What the processor can do, detected at run time.

/// Whether the processor has AVX2 and FMA (detected at run time; `false`
/// off `x86_64`): what the packet traversal needs, and the summing kernels
/// of the bakes.
#[must_use]
pub fn has_avx2_and_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}
