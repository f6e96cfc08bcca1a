//! A process-wide memory limit that every planner honours through the deadline it already polls.
//!
//! The binary installs [`CountingAlloc`] as its global allocator; it keeps the number of heap
//! bytes live (allocated and not yet freed) in one atomic counter. With a limit set
//! ([`set_limit`]), [`crate::Deadline::expired`] also answers `true` while the live bytes exceed
//! it, so every search that stops at its deadline (CBS, EECBS, space-time A*, SIPP, LaCAM, the
//! formation exact search, every other planner) stops there too, and [`crate::solve`] reports
//! [`crate::Unsolved::MemoryLimit`] instead of a time limit. Without the counting allocator (a
//! library user's program, unit tests) the live count stays 0 and no limit ever trips.
//!
//! Live heap bytes, not the resident set, are counted: freed memory counts at once, so a sweep
//! that runs many jobs in one process is not charged for a job that has ended (the allocator may
//! keep pages resident that it no longer uses).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Heap bytes allocated through [`CountingAlloc`] and not yet freed.
static LIVE: AtomicUsize = AtomicUsize::new(0);
/// The most heap bytes live at once since the last [`reset_peak`].
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// The limit in bytes (`usize::MAX`: none).
static LIMIT: AtomicUsize = AtomicUsize::new(usize::MAX);
/// Whether [`over_limit`] has answered `true` since [`reset_tripped`].
static TRIPPED: AtomicBool = AtomicBool::new(false);

/// The system allocator, counting live bytes for the memory limit. Install it in a binary with
/// `#[global_allocator] static A: mrpp_core::memory::CountingAlloc = mrpp_core::memory::CountingAlloc;`.
pub struct CountingAlloc;

// SAFETY: every call is forwarded to `System` with the same arguments; the counter is only
// bookkeeping.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded as is.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded as is.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded as is.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: forwarded as is.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            let old = layout.size();
            if new_size >= old {
                grew(new_size - old);
            } else {
                LIVE.fetch_sub(old - new_size, Ordering::Relaxed);
            }
        }
        p
    }
}

/// Counts `bytes` more live and raises the peak when passed (a relaxed load on most calls).
#[inline]
fn grew(bytes: usize) {
    let now = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    if now > PEAK.load(Ordering::Relaxed) {
        PEAK.fetch_max(now, Ordering::Relaxed);
    }
}

/// The most heap bytes live at once since the last [`reset_peak`] (0 without
/// [`CountingAlloc`]). Process-wide: with several planners running at once it is their sum.
pub fn peak_bytes() -> usize {
    PEAK.load(Ordering::Relaxed)
}

/// Starts a new peak at the bytes live now (e.g. before one benchmark run; [`peak_bytes`] minus
/// the live bytes at the reset is then that run's peak heap, when it runs alone).
pub fn reset_peak() {
    PEAK.store(LIVE.load(Ordering::Relaxed), Ordering::Relaxed);
}

/// Sets the limit on live heap bytes (`None`: no limit).
pub fn set_limit(bytes: Option<usize>) {
    LIMIT.store(bytes.unwrap_or(usize::MAX), Ordering::Relaxed);
}

/// The limit in bytes, if one is set.
pub fn limit() -> Option<usize> {
    Some(LIMIT.load(Ordering::Relaxed)).filter(|&l| l != usize::MAX)
}

/// Heap bytes live now (0 without [`CountingAlloc`]).
pub fn live_bytes() -> usize {
    LIVE.load(Ordering::Relaxed)
}

/// Whether the live heap bytes exceed the limit now; a `true` is remembered ([`tripped`]).
/// Two relaxed atomic loads: cheap enough for every deadline poll.
#[inline]
pub fn over_limit() -> bool {
    let over = LIVE.load(Ordering::Relaxed) > LIMIT.load(Ordering::Relaxed);
    if over {
        TRIPPED.store(true, Ordering::Relaxed);
    }
    over
}

/// Whether [`over_limit`] has answered `true` since the last [`reset_tripped`].
pub fn tripped() -> bool {
    TRIPPED.load(Ordering::Relaxed)
}

/// Forgets an earlier trip (called by [`crate::solve`] before each planner run).
pub fn reset_tripped() {
    TRIPPED.store(false, Ordering::Relaxed);
}

/// A default limit: three quarters of the machine's memory (`MemTotal` of `/proc/meminfo`),
/// or `None` where that cannot be read.
pub fn default_limit() -> Option<usize> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kb: usize = info
        .lines()
        .find_map(|l| l.strip_prefix("MemTotal:"))?
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb / 4 * 3 * 1024)
}
