//! A bound on the live heap of a fuzz target.
//!
//! libFuzzer's own `-malloc_limit_mb` works through sanitizer hooks that a
//! build without a sanitizer (the stable toolchain) does not have, so the
//! bound is kept here: [`LimitedAlloc`] counts the bytes in use and fails
//! a request that would take them past [`memory_limit`]. Rust then aborts
//! with "memory allocation of N bytes failed", and libFuzzer writes the
//! input that did it to a `crash-*` file.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Bytes in use now.
static LIVE: AtomicUsize = AtomicUsize::new(0);

/// The bound on the live heap in bytes: `FLEXBODY_FUZZ_MEMORY_MB` MiB
/// (read by [`set_memory_limit_from_env`]), 512 MiB by default. A fuzz
/// input is at most a few hundred kB, so a reader that needs more than
/// that for it has allocated from a number in the input, not from its
/// size.
pub fn memory_limit() -> usize {
    LIMIT.load(Ordering::Relaxed)
}

static LIMIT: AtomicUsize = AtomicUsize::new(512 << 20);

/// Sets [`memory_limit`] from `FLEXBODY_FUZZ_MEMORY_MB` if it is set.
pub fn set_memory_limit_from_env() {
    if let Some(mb) = std::env::var("FLEXBODY_FUZZ_MEMORY_MB")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        LIMIT.store(mb.saturating_mul(1 << 20), Ordering::Relaxed);
    }
}

/// The system allocator, failing requests beyond [`memory_limit`].
pub struct LimitedAlloc;

impl LimitedAlloc {
    /// Reserves `size` bytes of the budget; false if they do not fit.
    fn reserve(size: usize) -> bool {
        let before = LIVE.fetch_add(size, Ordering::Relaxed);
        if before.saturating_add(size) > LIMIT.load(Ordering::Relaxed) {
            LIVE.fetch_sub(size, Ordering::Relaxed);
            return false;
        }
        true
    }
}

// SAFETY: every call forwards to `System` with the same layout; the
// counter only decides whether to forward.
unsafe impl GlobalAlloc for LimitedAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !Self::reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        let p = System.alloc(layout);
        if p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !Self::reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        let p = System.alloc_zeroed(layout);
        if p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !Self::reserve(new_size - old) {
            return std::ptr::null_mut();
        }
        let p = System.realloc(ptr, layout, new_size);
        if p.is_null() {
            if new_size > old {
                LIVE.fetch_sub(new_size - old, Ordering::Relaxed);
            }
        } else if new_size < old {
            LIVE.fetch_sub(old - new_size, Ordering::Relaxed);
        }
        p
    }
}
