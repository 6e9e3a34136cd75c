//! What a solver program sets up around its work, the same for the command
//! line and the benches: the C allocator told to keep freed memory, the
//! work on a rayon pool worker, and a global allocator that puts large
//! blocks on huge pages.

use std::alloc::{GlobalAlloc, Layout, System};

/// Ask the C allocator to keep freed memory for reuse instead of handing it
/// back to the system.
///
/// An evaluation allocates and frees some 500 bytes per particle of
/// transient arrays. glibc serves blocks that large with fresh `mmap`s (or
/// trims the heap after them), so every evaluation paid for zeroing new
/// pages in the kernel: 13 % of the CPU time of a 10⁵-particle run on 2
/// cores (docs/performance.md). With mmap off and no trimming the blocks are
/// reused; the price is that the process keeps its peak heap until it ends,
/// which a solver run does anyway. A no-op on other C libraries. Call it once
/// at start-up, before other threads exist.
fn keep_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters; called before any
    // other thread runs.
    unsafe {
        libc::mallopt(libc::M_MMAP_MAX, 0);
        libc::mallopt(libc::M_TRIM_THRESHOLD, i32::MAX);
    }
}

/// The command line's and the benches' global allocator: the system
/// allocator, with every block of 4 MiB or more placed on a 2 MiB boundary
/// and marked for transparent huge pages (`MADV_HUGEPAGE`).
///
/// Linux backs memory with 4 KiB pages unless a region asks for more (the
/// usual `transparent_hugepage=madvise` setting). The solver walks
/// gigabytes of per-particle and per-pair arrays at 10⁷ particles, and with
/// 4 KiB pages nearly every row of the walk misses the address-translation
/// caches. Measured on this project's two-core machine, leapfrog, two
/// threads, alternated with the build before (docs/performance.md): 1.89e6
/// particle-steps/s at 10⁷ particles against 1.42e6, and 1.42–1.99e6
/// against 1.10–1.40e6 at 10⁶. Small blocks, and other systems, are left
/// as they are.
/// Results are the same bits: only where the memory lies changes.
pub struct HugePages;

/// Blocks at least this large are aligned and advised.
const HUGE_MIN: usize = 4 << 20;
/// The x86-64 and AArch64 (4 KiB granule) huge page.
const HUGE_PAGE: usize = 2 << 20;

impl HugePages {
    /// The layout a block is really allocated with.
    #[inline]
    fn placed(l: Layout) -> Layout {
        if cfg!(target_os = "linux") && l.size() >= HUGE_MIN && l.align() < HUGE_PAGE {
            Layout::from_size_align(l.size(), HUGE_PAGE).unwrap_or(l)
        } else {
            l
        }
    }

    /// Ask for huge pages over a block this allocator placed; a hint the
    /// kernel may decline, so its answer is not checked.
    #[inline]
    fn advise(p: *mut u8, placed: Layout, asked: Layout) {
        #[cfg(target_os = "linux")]
        if !p.is_null() && placed != asked {
            // SAFETY: the range is the block just allocated, owned by the
            // caller; MADV_HUGEPAGE changes how it is backed, not what it
            // holds.
            unsafe {
                libc::madvise(p.cast(), placed.size(), libc::MADV_HUGEPAGE);
            }
        }
        #[cfg(not(target_os = "linux"))]
        let _ = (p, placed, asked);
    }
}

// SAFETY: every block comes from `System` and goes back to it with the
// layout it was allocated with (`placed` is a pure function of the
// caller's layout); the advice does not touch the memory.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let placed = Self::placed(l);
        // SAFETY: `placed` has the caller's non-zero size.
        let p = unsafe { System.alloc(placed) };
        Self::advise(p, placed, l);
        p
    }

    unsafe fn alloc_zeroed(&self, l: Layout) -> *mut u8 {
        let placed = Self::placed(l);
        if placed == l {
            // SAFETY: as `alloc`.
            return unsafe { System.alloc_zeroed(l) };
        }
        // Advised before the zeroing touches the pages, so that the first
        // touch faults in huge pages.
        // SAFETY: as `alloc`; the block holds `l.size()` bytes.
        unsafe {
            let p = System.alloc(placed);
            Self::advise(p, placed, l);
            if !p.is_null() {
                std::ptr::write_bytes(p, 0, l.size());
            }
            p
        }
    }

    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        // SAFETY: `p` was allocated by `alloc` with `placed(l)`.
        unsafe { System.dealloc(p, Self::placed(l)) }
    }

    unsafe fn realloc(&self, p: *mut u8, l: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller guarantees `new_size` with `l.align()` is a
        // valid layout.
        let new = unsafe { Layout::from_size_align_unchecked(new_size, l.align()) };
        if Self::placed(l) == l && Self::placed(new) == new {
            // SAFETY: neither block is placed: the system's own realloc.
            return unsafe { System.realloc(p, l, new_size) };
        }
        // SAFETY: a new block, the contents copied, the old one freed.
        unsafe {
            let q = self.alloc(new);
            if !q.is_null() {
                std::ptr::copy_nonoverlapping(p, q, l.size().min(new_size));
                self.dealloc(p, l);
            }
            q
        }
    }
}

/// A solver program's set-up around its whole work `f`: freed memory kept
/// (`keep_freed_memory`, before any other thread exists), then `f` on a
/// pool worker (`on_worker`). The command line and the benches both start
/// here, so their figures are taken the same way; pair it with
/// [`HugePages`] as the program's global allocator.
pub fn solver_process<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    keep_freed_memory();
    on_worker(f)
}

/// Run `f` on a worker thread of a rayon pool (the thread count from
/// `RAYON_NUM_THREADS`, else one per core), or in place when the caller is
/// one already.
///
/// A parallel loop entered from a thread outside the pool hands its work to
/// the pool and sleeps until it is done: a futex wake-up each way, for every
/// one of the fifteen or so loops of a step. Measured on a 2-core virtual
/// machine, one thread, 10⁵ particles, leapfrog: 1.1–1.3 s of system time in
/// a 15 s run, and 1.27–1.43e6 particle-steps/s against 1.49–1.53e6 with the
/// loop on a worker (docs/performance.md). A worker that enters a loop runs
/// it itself, waking only idle siblings. Results do not depend on it: every
/// sum's order is fixed by the lists (`neighbours`), not by the threads.
/// Call it once around a whole run: each call outside a pool builds one.
fn on_worker<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() {
        return f();
    }
    // The main thread's stack size: a run on a worker should not meet a
    // smaller stack than a run on the main thread would.
    match rayon::ThreadPoolBuilder::new().stack_size(8 << 20).build() {
        Ok(pool) => pool.install(f),
        // No threads to be had: run where we are, as before.
        Err(_) => f(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The allocator keeps the `GlobalAlloc` contract on both sides of its
    /// threshold: blocks aligned as asked (and large ones on a huge page
    /// boundary on Linux), contents kept through a realloc that crosses
    /// the threshold either way, zeroed blocks zero, and every block freed
    /// with the layout it was placed with.
    #[test]
    fn huge_page_allocator_keeps_the_contract() {
        let a = HugePages;
        for (size, align) in [
            (64, 8),
            (HUGE_MIN - 8, 16),
            (HUGE_MIN, 8),
            (3 * HUGE_MIN + 5, 64),
        ] {
            let l = Layout::from_size_align(size, align).unwrap();
            // SAFETY: non-zero sizes; each block freed once with its layout.
            unsafe {
                let p = a.alloc(l);
                assert!(!p.is_null());
                assert_eq!(p as usize % align, 0, "{size} B aligned to {align}");
                if cfg!(target_os = "linux") && size >= HUGE_MIN {
                    assert_eq!(p as usize % HUGE_PAGE, 0, "{size} B on a huge page");
                }
                for k in 0..size {
                    *p.add(k) = (k % 251) as u8;
                }
                // Across the threshold up, then down, the contents kept.
                let up = a.realloc(p, l, size + HUGE_MIN);
                assert!(!up.is_null());
                for k in 0..size {
                    assert_eq!(*up.add(k), (k % 251) as u8, "byte {k} of {size}, grown");
                }
                let l_up = Layout::from_size_align(size + HUGE_MIN, align).unwrap();
                let down = a.realloc(up, l_up, 40);
                assert!(!down.is_null());
                for k in 0..40 {
                    assert_eq!(*down.add(k), (k % 251) as u8, "byte {k} of {size}");
                }
                a.dealloc(down, Layout::from_size_align(40, align).unwrap());

                let z = a.alloc_zeroed(l);
                assert!(!z.is_null());
                assert_eq!(z as usize % align, 0);
                assert!(std::slice::from_raw_parts(z, size).iter().all(|&b| b == 0));
                a.dealloc(z, l);
            }
        }
    }
}
