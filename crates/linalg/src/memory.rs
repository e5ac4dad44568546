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
//! model.

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
