//! The invariants every flexbody fuzz target checks, and the bundle that
//! turns one fuzz input into the files a reader takes.
//!
//! A target unpacks its input into files in a private tmpfs folder
//! ([`Bundle`]), calls the reader on their paths (the same entry point the
//! command uses) and then checks:
//!
//! - no panic, abort or overflow (the release profile of this crate keeps
//!   debug assertions and overflow checks);
//! - no allocation beyond the bound: [`LimitedAlloc`] refuses any request
//!   that would take the live heap past [`memory_limit`], which aborts the
//!   run (libFuzzer records the input as a crash); libFuzzer's `-timeout`
//!   and `-rss_limit_mb` bound the time and the resident memory;
//! - an error names a location: [`error_located`];
//! - an accepted input gives finite numbers: [`finite_debug`] over the
//!   whole returned value, and [`finite_values`] over assembled matrices.

pub mod alloc_limit;
pub mod bundle;
pub mod invariants;

pub use alloc_limit::{memory_limit, LimitedAlloc};
pub use bundle::Bundle;
pub use invariants::{error_located, finite_debug, finite_values, Lines};

/// The heap of every fuzz target: the system allocator under the bound.
#[global_allocator]
static ALLOC: LimitedAlloc = LimitedAlloc;
