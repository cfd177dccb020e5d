//! A memory hint: ask Linux to back the dense grid with huge pages.
//!
//! The second `unsafe` block in the crate. It pays: the grid and the point
//! vector are tens of megabytes read at random (each pick lands anywhere),
//! so with 4 KiB pages nearly every such read also misses the TLB and walks
//! the page tables. Transparent huge pages (2 MiB) cut those walks
//! (`docs/performance-journal.md` has the paired runs). Most distributions
//! set THP to `madvise` mode, where only memory marked with `madvise`
//! gets huge pages; in `always` mode the kernel does it anyway, in `never`
//! it refuses. A no-op off Linux, and for buffers that hold no whole
//! 2 MiB-aligned huge page (all under 2 MiB, and some up to 4 MiB).

/// The huge page size asked for (x86-64 and most ARM64 kernels).
#[cfg(target_os = "linux")]
const HUGE_PAGE: usize = 1 << 21;

/// Asks the kernel to back the whole 2 MiB-aligned pages inside `buffer`'s
/// allocation (its capacity, not just its length) with huge pages. Only a
/// hint: contents and layout stay as they are, and a refusal is ignored.
pub(crate) fn advise<T>(buffer: &Vec<T>) {
    #[cfg(target_os = "linux")]
    {
        let start = buffer.as_ptr() as usize;
        let bytes = buffer.capacity().saturating_mul(size_of::<T>());
        let first = start
            .checked_next_multiple_of(HUGE_PAGE)
            .unwrap_or(usize::MAX);
        let end = start.saturating_add(bytes) / HUGE_PAGE * HUGE_PAGE;
        if end > first {
            // SAFETY: `MADV_HUGEPAGE` neither reads, writes nor frees
            // memory, and the kernel keeps the contents when it moves them
            // to huge pages: nothing observable to this process changes.
            // The range is page-aligned and lies inside `buffer`'s live
            // allocation, which the borrow keeps from being freed or moved
            // during the call. Its result is only a hint's, so it is
            // ignored.
            #[expect(unsafe_code, reason = "a paging hint; see the SAFETY comment")]
            unsafe {
                libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = buffer;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contents_survive_the_hint() {
        // Empty, small (no whole huge page) and 12 MiB buffers, written
        // before and after the hint.
        let value = |i: u32| (i ^ 0x5a5a).wrapping_mul(7);
        for len in [0u32, 1000, 3 << 20] {
            let mut v: Vec<u32> = (0..len).map(value).collect();
            advise(&v);
            assert!(
                v.iter().zip(0..).all(|(&x, i)| x == value(i)),
                "len {len}: contents changed"
            );
            v.iter_mut().for_each(|x| *x = x.wrapping_mul(3));
            advise(&v);
            assert!(
                v.iter()
                    .zip(0..)
                    .all(|(&x, i)| x == value(i).wrapping_mul(3)),
                "len {len}: writes after the hint lost"
            );
        }
    }
}
