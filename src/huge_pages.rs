//! The global allocator of the command line and the Python extension: the
//! system allocator, asking the kernel for transparent huge pages (2 MiB)
//! on large blocks. A program that links the library chooses it with
//! `#[global_allocator] static A: HugePages = HugePages;`.
//!
//! A model of 3e5 DOFs allocates several GB over a run (the factor, the
//! Lanczos basis, blocks of right-hand sides), and the system allocator
//! hands large blocks back to the kernel when they are freed: in 4 KiB pages
//! that is hundreds of thousands of page faults per `flexbody modes` run.
//! Where the kernel grants huge pages only on request (`madvise`
//! mode, the usual default), this allocator makes that request; elsewhere
//! (`always`, `never`, not Linux) it changes nothing.

use std::alloc::{GlobalAlloc, Layout, System};

/// Blocks from this size on are advised.
const LARGE: usize = 4 << 20;

/// A huge page of x86-64 and aarch64 Linux.
const HUGE_PAGE: usize = 2 << 20;

pub struct HugePages;

// Safety: every call is the system allocator's; `advise` only gives the
// kernel a hint about memory the block owns.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        advise(p, layout.size());
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        advise(p, new_size);
        p
    }
}

/// Marks the whole huge pages inside `[p, p + size)` for huge pages.
#[cfg(target_os = "linux")]
fn advise(p: *mut u8, size: usize) {
    if p.is_null() || size < LARGE {
        return;
    }
    let start = (p as usize).next_multiple_of(HUGE_PAGE);
    let end = (p as usize + size) / HUGE_PAGE * HUGE_PAGE;
    if end > start {
        // Safety: the range lies inside the block just allocated. A failure
        // (a kernel without THP) leaves ordinary pages, which is fine.
        unsafe {
            libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_: *mut u8, _: usize) {}
