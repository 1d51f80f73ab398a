//! Keeping freed memory for reuse (glibc only).
//!
//! A projection allocates and frees buffers of 6 to 25 MB in turn (the
//! file's bytes, its compressed blocks, the image, the ring transform's
//! weights, coefficient copies, the JSON text). glibc's malloc serves such
//! sizes with `mmap` and returns them with `munmap`, so every buffer is
//! faulted in and zeroed page by page by the kernel again: at lmax 512 on a
//! 2048x1024 map that was 37 000 page faults and about 40% of the run's CPU
//! time in the kernel. Serving them from the heap and never trimming it
//! lets a freed buffer's pages back the next one (docs/benchmarks.md).

/// Tells glibc's malloc to serve allocations up to its largest threshold
/// (32 MiB on 64-bit targets) from the heap and not to give freed heap
/// memory back to the kernel while the process runs. Elsewhere, nothing.
pub fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // glibc's <malloc.h>.
        const M_TRIM_THRESHOLD: i32 = -1;
        const M_MMAP_THRESHOLD: i32 = -3;
        unsafe extern "C" {
            fn mallopt(param: i32, value: i32) -> i32;
        }
        // The largest threshold glibc accepts: 4 MiB * sizeof(long).
        let mmap_max = 4 * 1024 * 1024 * std::mem::size_of::<std::ffi::c_long>() as i32;
        // SAFETY: mallopt only sets malloc's parameters; it is called
        // before any thread exists. A refused value leaves the default.
        unsafe {
            mallopt(M_MMAP_THRESHOLD, mmap_max);
            mallopt(M_TRIM_THRESHOLD, i32::MAX);
        }
    }
}
