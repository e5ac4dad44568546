//! The allocator policy of large solves (glibc; elsewhere these do
//! nothing).
//!
//! glibc hands every block above 32 MB back to the kernel on `free` and
//! takes fresh, zeroed pages on the next `malloc`. The eigen solver of a
//! large model allocates blocks of about 20 MB again and again (Krylov
//! blocks, products, solves); at 3e5 DOFs, page faults once cost 3 s of
//! 19. [`tune_allocator`] keeps blocks up to 64 MB in the heap, where they
//! are reused, and maps larger ones (the factor, the Krylov basis, the
//! copies of `K` and `M`) so that freeing them returns their memory.
//! Freed heap memory stays resident until [`release_free_memory`] hands it
//! back, which the solver does between its phases (after the Lanczos run,
//! before the next factorisation) and the command line after loading a
//! model. A factor's storage can also be touched ahead, by a thread that
//! would otherwise wait (`touch_until`), and fitted to the factor (`fit`).

use std::sync::atomic::{AtomicBool, Ordering as AtomicOrdering};

/// Sets the thresholds; call once, before any thread starts.
pub fn tune_allocator() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 64 << 20);
        libc::mallopt(libc::M_TRIM_THRESHOLD, 64 << 20);
    }
}

/// Returns the free pages of the heap to the system.
pub fn release_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases memory the allocator holds free.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// `capacity` zeros whose pages are touched (in steps of 2 MiB, the
/// first `touch` values at most) until `done` is set: fresh memory made
/// resident ahead, on a thread that would otherwise wait. The rest stays
/// untouched (the allocator's zero pages). On this machine's VM the first
/// touch of fresh memory costs about 1 s/GiB; the shift-invert pencil
/// touches part of its first factor's storage while METIS orders.
pub(crate) fn touch_until(done: &AtomicBool, capacity: usize, touch: usize) -> Vec<f64> {
    const STEP: usize = 1 << 18;
    const PAGE: usize = 512;
    let Some(mut v) = zeros(capacity) else {
        return Vec::new();
    };
    for chunk in v[..touch.min(capacity)].chunks_mut(STEP) {
        if done.load(AtomicOrdering::Acquire) {
            break;
        }
        for x in chunk.iter_mut().step_by(PAGE) {
            // SAFETY: a write of the value the slot holds; volatile so that
            // it is not elided as a store of zero into zeroed memory.
            unsafe { std::ptr::write_volatile(x, 0.0) };
        }
    }
    v
}

/// `len` zeros, or `None` where the allocator has no room: a reservation
/// that may be larger than memory, of which only the touched pages count.
fn zeros(len: usize) -> Option<Vec<f64>> {
    let layout = std::alloc::Layout::array::<f64>(len).ok()?;
    if layout.size() == 0 {
        return None;
    }
    // SAFETY: the layout has a nonzero size.
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if ptr.is_null() {
        return None;
    }
    // SAFETY: allocated by the global allocator with the layout of `len`
    // f64 values, all of them zero (initialised).
    Some(unsafe { Vec::from_raw_parts(ptr, len, len) })
}

/// `values` at length `len`, its content left as it is where it is kept:
/// a longer one truncated (the tail handed back), a shorter one replaced
/// by zeros (pages touched first by the threads that fill them).
pub(crate) fn fit(values: &mut Vec<f64>, len: usize) {
    if values.len() > len {
        values.truncate(len);
        values.shrink_to_fit();
    } else if values.len() < len {
        *values = Vec::new();
        *values = vec![0.0; len];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touched_storage_is_zeros_fitted_to_a_factor() {
        // Touched in full when nothing stops it, not at all when done.
        let running = AtomicBool::new(false);
        let v = touch_until(&running, 3 << 18, 1 << 20);
        assert_eq!(v.len(), 3 << 18);
        assert!(v.iter().all(|&x| x == 0.0));
        let done = AtomicBool::new(true);
        assert_eq!(touch_until(&done, 1000, 1000), vec![0.0; 1000]);
        assert!(touch_until(&done, 0, 0).is_empty());
        // Fitting keeps what it keeps, and adds zeros.
        let mut values: Vec<f64> = (0..10).map(f64::from).collect();
        fit(&mut values, 4);
        assert_eq!(values, [0.0, 1.0, 2.0, 3.0]);
        fit(&mut values, 6);
        assert_eq!(values, [0.0; 6]);
    }
}
