//! The allocator policy of large solves (glibc; elsewhere these do
//! nothing).
//!
//! glibc hands every block above 32 MB back to the kernel on `free` and
//! takes fresh, zeroed pages on the next `malloc`. The eigen solver of a
//! large model allocates blocks of about 20 MB again and again (Krylov
//! blocks, products, solves), each one fresh pages the kernel must fault in
//! and zero. [`tune_allocator`] keeps blocks up to 64 MB in the heap, where they
//! are reused, and maps larger ones (the factor, the Krylov basis, the
//! copies of `K` and `M`) so that freeing them returns their memory.
//! Freed heap memory stays resident until [`release_free_memory`] hands it
//! back, which the solver does between its phases (after the Lanczos run,
//! before the next factorisation) and the command line after loading a
//! model. A factor's storage can also be touched ahead, by a thread that
//! would otherwise wait (`touch_until`), and fitted to the factor (`fit`).
//!
//! Before a factor's storage is taken, [`Budget::ensure`] compares it with
//! the memory this process can still take ([`Budget::room`]): a factor
//! larger than that is an error at once, not the kernel's out-of-memory
//! kill minutes into the factorisation.

use crate::LinalgError;
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

/// The memory a solve may take: the machine's and the cgroup's room,
/// and a cap the user set on this process's resident memory (the command
/// line's `--max-memory`). A value handed to the solvers with their
/// matrices ([`crate::ldlt::SymbolicLdlt::with_budget`],
/// [`crate::pencil::Pencil::with_budget`]); the default has no cap.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Budget {
    cap: Option<u64>,
}

impl Budget {
    /// The machine's and the cgroup's room only.
    pub const MACHINE: Budget = Budget { cap: None };

    /// At most `cap` bytes resident (`None`: [`Budget::MACHINE`]).
    pub fn at_most(cap: Option<u64>) -> Self {
        Self { cap }
    }

    /// The cap on resident memory in bytes, if one was set.
    pub fn cap(&self) -> Option<u64> {
        self.cap
    }

    /// The room of this process, from `/proc/meminfo`, its memory cgroup
    /// (v2 or v1) and the cap; `None` where none of these is known.
    pub fn room(&self) -> Option<Room> {
        room_under(self.cap)
    }

    /// `needed` more bytes for `what`, or an error when [`Self::room`] is
    /// smaller.
    pub fn ensure(&self, needed: u64, what: &str) -> Result<(), LinalgError> {
        check_room(needed, self.room(), what)
    }

    /// [`Self::ensure`] for the `entries` values of an `LDL^T` factor of
    /// `equations` equations, `resident` of them in storage already.
    pub(crate) fn ensure_factor(
        &self,
        equations: usize,
        entries: usize,
        resident: usize,
    ) -> Result<(), LinalgError> {
        let missing = entries.saturating_sub(resident);
        if missing < TRIVIAL_FACTOR {
            return Ok(());
        }
        self.ensure(
            (missing * std::mem::size_of::<f64>()) as u64,
            &format!("the LDL^T factor of {equations} equations ({entries} entries of L)"),
        )
    }
}

/// Memory this process can still take, and what bounds it.
#[derive(Clone, Debug, PartialEq)]
pub struct Room {
    /// Bytes.
    pub bytes: u64,
    /// The tightest bound, in words (`MemAvailable + SwapFree`, the
    /// cgroup's limit, or the [`Budget`]'s cap).
    pub bound: String,
}

/// [`Budget::room`] under `cap`.
fn room_under(cap: Option<u64>) -> Option<Room> {
    let read = |path: &str| std::fs::read_to_string(path).ok();
    let mut best: Option<Room> = None;
    let mut take = |bytes: u64, bound: String| {
        if best.as_ref().is_none_or(|b| bytes < b.bytes) {
            best = Some(Room { bytes, bound });
        }
    };
    if let Some(bytes) = read("/proc/meminfo").as_deref().and_then(system_room) {
        take(bytes, "MemAvailable + SwapFree of /proc/meminfo".into());
    }
    // The memory controller: cgroup v2 (`0::path`) or v1 (`N:memory:path`).
    let cgroups = read("/proc/self/cgroup").unwrap_or_default();
    for line in cgroups.lines() {
        let mut fields = line.splitn(3, ':');
        let (Some(_), Some(controllers), Some(path)) =
            (fields.next(), fields.next(), fields.next())
        else {
            continue;
        };
        let (dir, files) = match controllers {
            "" => (format!("/sys/fs/cgroup{path}"), CGROUP_V2),
            "memory" => (format!("/sys/fs/cgroup/memory{path}"), CGROUP_V1),
            _ => continue,
        };
        let [max, current, cache] = files;
        let bytes = cgroup_room(
            &read(&format!("{dir}/{max}")).unwrap_or_default(),
            &read(&format!("{dir}/{current}")).unwrap_or_default(),
            &read(&format!("{dir}/memory.stat")).unwrap_or_default(),
            cache,
        );
        if let Some(bytes) = bytes {
            take(bytes, format!("the cgroup's {max}"));
        }
    }
    if let Some(limit) = cap {
        let resident = process_memory().map_or(0, |(now, _)| now);
        let Room { bytes, bound } = under_limit(limit, resident);
        take(bytes, bound);
    }
    best
}

/// Resident and peak resident memory of this process in bytes (`VmRSS`,
/// `VmHWM` of Linux's `/proc/self/status`); `None` elsewhere.
pub fn process_memory() -> Option<(u64, u64)> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    Some((kib_field(&status, "VmRSS:")?, kib_field(&status, "VmHWM:")?))
}

/// Factors of fewer entries (1 MiB) are not checked: reading `/proc` costs
/// more than factorising them, and a time integration factorises small
/// Jacobians thousands of times.
const TRIVIAL_FACTOR: usize = 1 << 17;

/// The room under a budget of `limit` bytes with `resident` bytes in use.
fn under_limit(limit: u64, resident: u64) -> Room {
    Room {
        bytes: limit.saturating_sub(resident),
        bound: format!(
            "--max-memory {} with {} resident",
            bytes_text(limit),
            bytes_text(resident)
        ),
    }
}

/// [`ensure_room`] against a given room (`None`: unknown, nothing refused).
fn check_room(needed: u64, room: Option<Room>, what: &str) -> Result<(), LinalgError> {
    match room {
        Some(room) if needed > room.bytes => Err(LinalgError::OutOfMemory {
            what: what.to_string(),
            needed: bytes_text(needed),
            room: bytes_text(room.bytes),
            bound: room.bound,
        }),
        _ => Ok(()),
    }
}

/// Bytes for messages: `16.80 GiB`, or `12.3 MiB` below a GiB.
pub fn bytes_text(bytes: u64) -> String {
    let b = bytes as f64;
    if bytes >= 1 << 30 {
        format!("{:.2} GiB", b / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MiB", b / (1u64 << 20) as f64)
    }
}

/// `MemAvailable + SwapFree` of a `/proc/meminfo` text, in bytes.
fn system_room(meminfo: &str) -> Option<u64> {
    Some(kib_field(meminfo, "MemAvailable:")? + kib_field(meminfo, "SwapFree:").unwrap_or(0))
}

/// The value of a `Name:   123 kB` line, in bytes.
fn kib_field(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kib * 1024)
}

/// A cgroup's limit, usage and the page-cache line of its `memory.stat`,
/// for v2 and v1.
const CGROUP_V2: [&str; 3] = ["memory.max", "memory.current", "file "];
const CGROUP_V1: [&str; 3] = [
    "memory.limit_in_bytes",
    "memory.usage_in_bytes",
    "total_cache ",
];

/// Limit minus usage of a cgroup in bytes, its page cache (the `cache`
/// line of `memory.stat`) counted as free; `None` without a limit (`max`).
fn cgroup_room(max: &str, current: &str, stat: &str, cache: &str) -> Option<u64> {
    let max: u64 = max.trim().parse().ok()?;
    let current: u64 = current.trim().parse().ok()?;
    let cache: u64 = stat
        .lines()
        .find_map(|l| l.strip_prefix(cache))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(0);
    Some(max.saturating_sub(current.saturating_sub(cache)))
}

/// `capacity` zeros whose pages are touched (in steps of 2 MiB, the
/// first `touch` values at most) until `done` is set: fresh memory made
/// resident ahead, on a thread that would otherwise wait. The rest stays
/// untouched (the allocator's zero pages). A first touch of fresh memory
/// is a page fault; the shift-invert pencil takes those of part of its
/// first factor's storage while METIS orders.
///
/// Returns the storage and how many of its values were touched.
pub(crate) fn touch_until(done: &AtomicBool, capacity: usize, touch: usize) -> (Vec<f64>, usize) {
    const STEP: usize = 1 << 18;
    const PAGE: usize = 512;
    let Some(mut v) = zeros(capacity) else {
        return (Vec::new(), 0);
    };
    let mut touched = 0;
    for chunk in v[..touch.min(capacity)].chunks_mut(STEP) {
        if done.load(AtomicOrdering::Acquire) {
            break;
        }
        touched += chunk.len();
        for x in chunk.iter_mut().step_by(PAGE) {
            // SAFETY: a write of the value the slot holds; volatile so that
            // it is not elided as a store of zero into zeroed memory.
            unsafe { std::ptr::write_volatile(x, 0.0) };
        }
    }
    (v, touched)
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
    fn room_is_read_from_meminfo_and_the_cgroup() {
        let meminfo = "MemTotal:       24000000 kB\nMemFree:         1000 kB\n\
                       MemAvailable:   20000000 kB\nSwapTotal:  0 kB\nSwapFree:        1000 kB\n";
        assert_eq!(system_room(meminfo), Some((20_000_000 + 1000) * 1024));
        assert_eq!(system_room("MemTotal: 5 kB\n"), None);
        // v2: a limit or none; the page cache counts as free.
        assert_eq!(cgroup_room("max\n", "123\n", "", "file "), None);
        assert_eq!(cgroup_room("1000\n", "400\n", "", "file "), Some(600));
        let stat = "anon 300\nfile 100\n";
        assert_eq!(cgroup_room("1000\n", "400\n", stat, "file "), Some(700));
        assert_eq!(
            cgroup_room("1000", "4000", "file_mapped 5\n", "file "),
            Some(0)
        );
        // v1: the hierarchy's page cache; "unlimited" is a huge limit that
        // never binds, an unreadable one is none.
        let stat = "cache 7\nrss 2\ntotal_cache 100\ntotal_rss 300\n";
        assert_eq!(cgroup_room("1000", "400", stat, "total_cache "), Some(700));
        let unlimited = cgroup_room("9223372036854771712", "400", stat, "total_cache ");
        assert!(unlimited > Some(1 << 60));
        assert_eq!(cgroup_room("", "400", stat, "total_cache "), None);
    }

    #[test]
    fn a_factor_beyond_the_room_is_refused_with_its_size() {
        let room = under_limit(2 << 30, 1 << 29);
        assert_eq!(room.bytes, 3 << 29);
        assert_eq!(room.bound, "--max-memory 2.00 GiB with 512.0 MiB resident");
        let refused = check_room(3 << 30, Some(room.clone()), "the factor");
        let message = refused.unwrap_err().to_string();
        assert!(
            message.starts_with(
                "the factor needs 3.00 GiB more memory, but only 1.50 GiB are left (--max-memory"
            ),
            "{message}"
        );
        assert!(check_room(3 << 29, Some(room), "a factor that fits").is_ok());
        // Unknown room refuses nothing; a budget below what is resident
        // leaves none.
        assert!(check_room(u64::MAX, None, "anything").is_ok());
        assert_eq!(under_limit(1, 1 << 20).bytes, 0);
    }

    #[test]
    fn touched_storage_is_zeros_fitted_to_a_factor() {
        // Touched in full when nothing stops it, not at all when done.
        let running = AtomicBool::new(false);
        let (v, touched) = touch_until(&running, 3 << 18, 1 << 20);
        assert_eq!((v.len(), touched), (3 << 18, 3 << 18));
        assert!(v.iter().all(|&x| x == 0.0));
        let done = AtomicBool::new(true);
        assert_eq!(touch_until(&done, 1000, 1000), (vec![0.0; 1000], 0));
        assert!(touch_until(&done, 0, 0).0.is_empty());
        // Fitting keeps what it keeps, and adds zeros.
        let mut values: Vec<f64> = (0..10).map(f64::from).collect();
        fit(&mut values, 4);
        assert_eq!(values, [0.0, 1.0, 2.0, 3.0]);
        fit(&mut values, 6);
        assert_eq!(values, [0.0; 6]);
    }
}
