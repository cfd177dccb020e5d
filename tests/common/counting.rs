//! A global allocator that counts the bytes this thread holds and their
//! peak, for the tests that hold memory to a figure
//! (`tests/memory_budget.rs`, `tests/stream_memory.rs`), each including it
//! by `#[path]`: a test binary gets it as its allocator.
//!
//! The counters are per thread: tests run on parallel threads, and the
//! test harness allocates on its own.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The system allocator, counting the bytes held now and their peak.
struct Counting;

thread_local! {
    /// Bytes this thread holds now (wrapping: a block freed by another
    /// thread than its own would be counted there; no test does that).
    static NOW: Cell<usize> = const { Cell::new(0) };
    /// The most `NOW` has been since the last reset.
    static PEAK: Cell<usize> = const { Cell::new(0) };
}

fn add(bytes: usize) {
    let now = NOW.get().wrapping_add(bytes);
    NOW.set(now);
    PEAK.set(PEAK.get().max(now));
}

fn sub(bytes: usize) {
    NOW.set(NOW.get().wrapping_sub(bytes));
}

// SAFETY: every call forwards to `System` with the caller's arguments
// unchanged; the counters only observe sizes.
#[expect(
    unsafe_code,
    reason = "a global allocator is an unsafe trait; test only"
)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        add(layout.size());
        // SAFETY: forwarded unchanged.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        add(layout.size());
        // SAFETY: forwarded unchanged.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        sub(layout.size());
        // SAFETY: forwarded unchanged.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // Counted as the worst case: the new block while the old is held.
        add(new_size);
        sub(layout.size());
        // SAFETY: forwarded unchanged.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Starts a measurement: the peak so far becomes the bytes held now,
/// which are returned.
pub(crate) fn start() -> usize {
    let now = NOW.get();
    PEAK.set(now);
    now
}

/// The peak since [`start`] returned `before`, above `before`.
pub(crate) fn peak_since(before: usize) -> usize {
    PEAK.get().wrapping_sub(before)
}
