//! A cache hint: start loading memory that a later step will read.
//!
//! One of the crate's three `unsafe` blocks (the others are
//! `huge_pages.rs` and `cpu.rs`). It pays: in 3-D the sampler waits
//! on memory (random picks land anywhere in a grid of tens of megabytes),
//! and asking for the next picks' memory while this pick runs hides much of
//! that wait (`docs/performance-journal.md` has the runs).

/// Starts loading the cache line of `slice[index]`. Only a hint: nothing is
/// read and nothing observable changes, so any `index` is harmless, in
/// range or not. A no-op off x86-64.
#[inline(always)]
pub(crate) fn prefetch<T>(slice: &[T], index: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // `wrapping_add`: forming the address is defined for any index.
        let at = slice.as_ptr().wrapping_add(index).cast::<i8>();
        // SAFETY: `prefetch` reads no memory and cannot fault, whatever the
        // address (Intel SDM, PREFETCHh); its only requirement is SSE, which
        // every x86-64 processor has. It is `unsafe` only because the
        // intrinsic carries `#[target_feature(enable = "sse")]`.
        #[expect(unsafe_code, reason = "a cache hint; see the SAFETY comment")]
        #[allow(
            unused_unsafe,
            reason = "a compiler that sees SSE as always on may call this safe"
        )]
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(at);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (slice, index);
    }
}
