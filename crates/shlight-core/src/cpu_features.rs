//! Which vector kernels the processor runs: the ring transform's and the
//! quarter turn's AVX + FMA code is chosen at run time.

/// Tests set this to run the portable code on CPUs that have AVX and FMA.
#[cfg(test)]
pub(crate) static FORCE_PORTABLE: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Whether the AVX + FMA kernels can run (and are not switched off by a
/// test).
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn avx_fma() -> bool {
    #[cfg(test)]
    if FORCE_PORTABLE.load(std::sync::atomic::Ordering::Relaxed) {
        return false;
    }
    std::arch::is_x86_feature_detected!("avx") && std::arch::is_x86_feature_detected!("fma")
}
