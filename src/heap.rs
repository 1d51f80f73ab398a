//! The binary's memory policy: large buffers on transparent huge pages,
//! freed memory kept for reuse (Linux with glibc; elsewhere the system
//! allocator as it is).
//!
//! A projection allocates and frees buffers of 2 to 25 MB in turn (the
//! file's bytes, the image, the ring transform's rows and weights,
//! coefficient copies, the JSON text), each of them touched once from
//! start to end. Served in 4 KiB pages, every buffer costs one page fault
//! per page: at lmax 512 on a 2048x1024 map, 20 000 faults and about a
//! third of the run's CPU time in the kernel (docs/benchmarks.md).
//!
//! - [`Heap`], the global allocator: requests of [`BIG`] bytes or more get
//!   anonymous mappings of their own, aligned to and a multiple of 2 MiB
//!   and advised `MADV_HUGEPAGE`, so the kernel backs them with 2 MiB pages
//!   where it can (one fault per 2 MiB; the system's `transparent_hugepage`
//!   setting `madvise` or `always` allows it, `never` leaves 4 KiB pages
//!   and nothing else changes). Freed ones are kept (up to 1 GiB) and
//!   handed out again, split when larger than asked, so their pages are
//!   faulted in and zeroed once. Smaller requests go to the system
//!   allocator.
//! - [`keep_freed_memory`]: glibc's malloc keeps what it serves from its
//!   heap (up to its largest mmap threshold) and does not trim it, so a
//!   freed medium buffer's pages back the next one.

#[cfg(all(target_os = "linux", target_env = "gnu"))]
pub use big_blocks::Heap;

/// Requests this large or larger get a mapping of their own on huge pages.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
pub const BIG: usize = 2 << 20;

#[cfg(all(target_os = "linux", target_env = "gnu"))]
mod big_blocks {
    use std::alloc::{GlobalAlloc, Layout, System};
    use std::ptr;
    use std::sync::{Mutex, PoisonError};

    use super::BIG;

    /// The size and alignment of a transparent huge page on x86-64 and
    /// aarch64 with 4 KiB base pages.
    const HUGE_PAGE: usize = 2 << 20;

    /// The global allocator of [the module](super).
    pub struct Heap;

    fn is_big(size: usize, align: usize) -> bool {
        size >= BIG && align <= HUGE_PAGE
    }

    /// `size` rounded up to whole huge pages (what a big block maps).
    fn mapped_len(size: usize) -> Option<usize> {
        size.checked_add(HUGE_PAGE - 1)
            .map(|s| s & !(HUGE_PAGE - 1))
    }

    /// Most freed big blocks kept for reuse.
    const SLOTS: usize = 64;
    /// Most bytes kept in freed big blocks; past it they are unmapped.
    const KEPT_MAX: usize = 1 << 30;

    /// Freed big blocks: `(address, mapped length)`, unsorted; `(0, 0)` is
    /// an empty slot.
    struct Cache {
        blocks: [(usize, usize); SLOTS],
        kept: usize,
    }

    static CACHE: Mutex<Cache> = Mutex::new(Cache {
        blocks: [(0, 0); SLOTS],
        kept: 0,
    });

    /// Takes the smallest kept block of at least `len` bytes, its tail past
    /// `len` kept as a block of its own (both stay 2 MiB aligned).
    fn take(len: usize) -> Option<*mut u8> {
        let mut cache = CACHE.lock().unwrap_or_else(PoisonError::into_inner);
        let (slot, &(addr, cap)) = cache
            .blocks
            .iter()
            .enumerate()
            .filter(|(_, b)| b.1 >= len)
            .min_by_key(|(_, b)| b.1)?;
        cache.blocks[slot] = if cap > len {
            (addr + len, cap - len)
        } else {
            (0, 0)
        };
        cache.kept -= len;
        Some(addr as *mut u8)
    }

    /// Keeps a freed block for reuse; false when the cache is full.
    fn keep(addr: usize, len: usize) -> bool {
        let mut cache = CACHE.lock().unwrap_or_else(PoisonError::into_inner);
        if cache.kept + len > KEPT_MAX {
            return false;
        }
        let Some(slot) = cache.blocks.iter().position(|b| b.1 == 0) else {
            return false;
        };
        cache.blocks[slot] = (addr, len);
        cache.kept += len;
        true
    }

    /// A mapping of `mapped_len(size)` bytes at a multiple of 2 MiB,
    /// advised to be backed by huge pages, and whether it is known to be
    /// zero-filled (a fresh mapping) or not (a kept block); null if the
    /// kernel refuses.
    unsafe fn map(size: usize) -> (*mut u8, bool) {
        let Some(len) = mapped_len(size) else {
            return (ptr::null_mut(), true);
        };
        if let Some(p) = take(len) {
            return (p, false);
        }
        // SAFETY: `len` is a whole number of huge pages.
        (unsafe { map_aligned(len) }, true)
    }

    /// A fresh anonymous mapping of `len` bytes at a multiple of 2 MiB,
    /// advised to be backed by huge pages; null if the kernel refuses.
    unsafe fn map_aligned(len: usize) -> *mut u8 {
        let Some(over) = len.checked_add(HUGE_PAGE) else {
            return ptr::null_mut();
        };
        // SAFETY: an anonymous private mapping owned by nobody else; the
        // slack before and after the aligned range is unmapped again.
        unsafe {
            let raw = libc::mmap(
                ptr::null_mut(),
                over,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            );
            if raw == libc::MAP_FAILED {
                return ptr::null_mut();
            }
            let start = raw as usize;
            let aligned = (start + HUGE_PAGE - 1) & !(HUGE_PAGE - 1);
            let head = aligned - start;
            if head > 0 {
                libc::munmap(raw, head);
            }
            let tail = over - head - len;
            if tail > 0 {
                libc::munmap((aligned + len) as *mut libc::c_void, tail);
            }
            // Only advice: a kernel without THP leaves base pages.
            libc::madvise(aligned as *mut libc::c_void, len, libc::MADV_HUGEPAGE);
            aligned as *mut u8
        }
    }

    /// Releases a block that [`map`] returned for `size` bytes: kept for
    /// reuse, or unmapped when the cache is full.
    unsafe fn unmap(p: *mut u8, size: usize) {
        if let Some(len) = mapped_len(size)
            && !keep(p as usize, len)
        {
            // SAFETY: `p` and `len` are what `map` returned.
            unsafe {
                libc::munmap(p.cast(), len);
            }
        }
    }

    // SAFETY: big blocks are mappings (fresh, or kept and handed to one
    // owner at a time under the cache's lock) at least `size` bytes long
    // and aligned to 2 MiB (hence to any `align <= HUGE_PAGE`), zeroed when
    // asked, and released with the length they were given (a pure function
    // of the layout's size, which the caller passes back unchanged);
    // everything else is the system allocator's.
    unsafe impl GlobalAlloc for Heap {
        unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
            if is_big(layout.size(), layout.align()) {
                unsafe { map(layout.size()).0 }
            } else {
                unsafe { System.alloc(layout) }
            }
        }

        unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
            if is_big(layout.size(), layout.align()) {
                let (p, zeroed) = unsafe { map(layout.size()) };
                if !p.is_null() && !zeroed {
                    // SAFETY: a kept block of at least `size` bytes.
                    unsafe { ptr::write_bytes(p, 0, layout.size()) };
                }
                p
            } else {
                unsafe { System.alloc_zeroed(layout) }
            }
        }

        unsafe fn dealloc(&self, p: *mut u8, layout: Layout) {
            if is_big(layout.size(), layout.align()) {
                unsafe { unmap(p, layout.size()) }
            } else {
                unsafe { System.dealloc(p, layout) }
            }
        }

        unsafe fn realloc(&self, p: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
            let align = layout.align();
            let (old_big, new_big) = (is_big(layout.size(), align), is_big(new_size, align));
            if !old_big && !new_big {
                return unsafe { System.realloc(p, layout, new_size) };
            }
            if old_big && new_big && mapped_len(layout.size()) == mapped_len(new_size) {
                // The same mapping holds the new size.
                return p;
            }
            // SAFETY: `new_size` with the old alignment is a valid layout
            // (the caller's contract); the old block is copied up to the
            // smaller size and released with its own layout.
            unsafe {
                let new_layout = Layout::from_size_align_unchecked(new_size, align);
                let q = self.alloc(new_layout);
                if !q.is_null() {
                    ptr::copy_nonoverlapping(p, q, layout.size().min(new_size));
                    self.dealloc(p, layout);
                }
                q
            }
        }
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        /// Big blocks are aligned to 2 MiB, zeroed, writable to their last
        /// byte, keep their bytes through growth and shrinking across the
        /// threshold, and small blocks still work.
        #[test]
        fn blocks_keep_their_bytes_across_the_threshold() {
            let heap = Heap;
            unsafe {
                let small = Layout::from_size_align(1000, 8).unwrap();
                let p = heap.alloc(small);
                assert!(!p.is_null());
                for i in 0..1000 {
                    *p.add(i) = (i % 251) as u8;
                }
                let big = 3 * BIG + 5;
                let q = heap.realloc(p, small, big);
                assert_eq!(q as usize % HUGE_PAGE, 0, "big blocks start on a huge page");
                for i in 0..1000 {
                    assert_eq!(*q.add(i), (i % 251) as u8);
                }
                *q.add(big - 1) = 7;
                // Growing within the same mapping keeps the address.
                let big_layout = Layout::from_size_align(big, 8).unwrap();
                let r = heap.realloc(q, big_layout, big + 100);
                assert_eq!(r, q);
                // Shrinking below the threshold copies back to the system
                // allocator.
                let s = heap.realloc(r, Layout::from_size_align(big + 100, 8).unwrap(), 500);
                for i in 0..500 {
                    assert_eq!(*s.add(i), (i % 251) as u8);
                }
                heap.dealloc(s, Layout::from_size_align(500, 8).unwrap());

                let z = Layout::from_size_align(BIG * 2, 64).unwrap();
                let zp = heap.alloc_zeroed(z);
                assert!((0..z.size()).step_by(4093).all(|i| *zp.add(i) == 0));
                heap.dealloc(zp, z);
            }
        }

        #[test]
        fn sizes_round_to_whole_huge_pages() {
            assert_eq!(mapped_len(BIG), Some(HUGE_PAGE));
            assert_eq!(mapped_len(BIG + 1), Some(2 * HUGE_PAGE));
            assert_eq!(mapped_len(usize::MAX), None);
            assert!(!is_big(BIG - 1, 8));
            assert!(!is_big(BIG, 2 * HUGE_PAGE));
        }
    }
}

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
