//! Run-time CPU dispatch: the sampling loops compiled a second time for the
//! x86-64-v3 feature set (AVX2, FMA, BMI1/2, LZCNT, POPCNT) and run that way
//! on a processor that has it, which is nearly every x86-64 processor sold
//! since 2015.
//!
//! One of the crate's three `unsafe` blocks (the others are `prefetch.rs`
//! and `huge_pages.rs`). It pays where the time goes in 2-D: the offsets
//! drawn eight at a time and the conflict cache's eight-slot check run four
//! and eight lanes to a vector instead of two and four. That saves
//! instructions and time in 2-D, in the streaming sweep and for a varying
//! radius (the pick), and nothing in memory-bound 3-D with a fixed radius
//! (`docs/performance-journal.md`, "Run-time dispatch to AVX2", has the
//! figures).
//!
//! **The same points.** Only the instructions the compiler may choose
//! change, never the arithmetic: Rust does not contract `a * b + c` into a
//! fused multiply-add on its own (only `mul_add` does, which the sampling
//! code does not call), so every `f64` operation rounds as it does in the
//! portable copy. Unit tests run both copies in one process and compare
//! the bits (`both_copies_*` in `sampler.rs`, `tiled/mod.rs` and
//! `varying/mod.rs`), and
//! `tests/value_stability.rs`, run on such a machine, holds the dispatched
//! copy to the values pinned before it existed.

/// Runs `f`, inlined into a copy compiled for x86-64-v3 when this processor
/// has those features, else as it is. `f` should be a closure marked
/// `#[inline(always)]` whose body calls `#[inline(always)]` code: whatever
/// is not inlined into the copy runs as compiled for the baseline.
#[inline(always)]
pub(crate) fn dispatch<T>(f: impl FnOnce() -> T) -> T {
    #[cfg(target_arch = "x86_64")]
    if has_v3() {
        // SAFETY: `v3` is safe code whose only requirement, as a
        // `#[target_feature]` function, is that the processor supports the
        // features it is compiled with; `has_v3` has just checked every one
        // of them at run time (`is_x86_feature_detected!`).
        #[expect(unsafe_code, reason = "run-time dispatch; see the SAFETY comment")]
        return unsafe { v3(f) };
    }
    f()
}

/// `f`, compiled with the x86-64-v3 features (those [`has_v3`] checks).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn v3<T>(f: impl FnOnce() -> T) -> T {
    f()
}

/// Whether this processor has every feature [`v3`] is compiled with (and
/// the tests have not turned the copy off on this thread). Asked once per
/// process: the loops call this once per point.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn has_v3() -> bool {
    static HAS_V3: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    #[cfg(test)]
    if tests::PORTABLE.with(core::cell::Cell::get) {
        return false;
    }
    *HAS_V3.get_or_init(|| {
        std::is_x86_feature_detected!("avx")
            && std::is_x86_feature_detected!("avx2")
            && std::is_x86_feature_detected!("fma")
            && std::is_x86_feature_detected!("bmi1")
            && std::is_x86_feature_detected!("bmi2")
            && std::is_x86_feature_detected!("lzcnt")
            && std::is_x86_feature_detected!("popcnt")
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use std::cell::Cell;

    thread_local! {
        /// Set: [`super::dispatch`] runs the portable copy on this thread.
        pub(super) static PORTABLE: Cell<bool> = const { Cell::new(false) };
    }

    /// Runs `f` with the portable copies only (on this thread), then as
    /// dispatched, and returns both results.
    pub(crate) fn both_copies<T>(f: impl Fn() -> T) -> (T, T) {
        PORTABLE.with(|p| p.set(true));
        let portable = f();
        PORTABLE.with(|p| p.set(false));
        (portable, f())
    }

    /// Asserts that both copies ([`both_copies`]) made the same list, of
    /// more than `at_least` items; else says where the lists first differ
    /// (an index and both lengths).
    pub(crate) fn assert_same<T: PartialEq>(
        what: &str,
        (portable, dispatched): (Vec<T>, Vec<T>),
        at_least: usize,
    ) {
        assert!(
            portable.len() > at_least,
            "{what}: {} items",
            portable.len()
        );
        let at = portable.iter().zip(&dispatched).position(|(x, y)| x != y);
        let lengths_differ = portable.len() != dispatched.len();
        let first = at.or(lengths_differ.then_some(portable.len().min(dispatched.len())));
        assert!(
            first.is_none(),
            "{what}: first difference at {first:?} (lengths {} and {})",
            portable.len(),
            dispatched.len()
        );
    }

    #[test]
    fn dispatch_runs_the_closure_once() {
        let mut calls = 0;
        let out = super::dispatch(|| {
            calls += 1;
            7
        });
        assert_eq!((out, calls), (7, 1), "the closure's value, from one call");
        let (a, b) = both_copies(|| super::dispatch(|| 3.0_f64.sqrt()));
        assert_eq!(a.to_bits(), b.to_bits(), "both copies round alike");
    }
}
