//! Counting heap bytes against the memory budget as containers grow.
//!
//! The budget (`max_grid_bytes`) bounds the memory a run holds, measured as
//! it grows, not a worst case planned up front. Every growable container of
//! a run (the grid's point storage, its hash table, the active list) grows
//! through these helpers: the growth is checked before it is allocated, and
//! counted at its peak, when the old and the new block are both held.

/// Heap bytes of a vector's allocation: its capacity, not its length, since
/// that is what the allocator handed out.
pub(crate) fn vec_bytes<T>(v: &Vec<T>) -> u64 {
    bytes_of::<T>(v.capacity())
}

/// Bytes of `count` values of `T`, saturating.
pub(crate) fn bytes_of<T>(count: usize) -> u64 {
    u64::try_from(count)
        .unwrap_or(u64::MAX)
        .saturating_mul(size_of::<T>() as u64)
}

/// Makes room in `v` for one more element, if the new block fits in
/// `spare` bytes (the old block is still held while the new one is filled,
/// so the new block alone must fit what is left). Doubles the capacity (at
/// least 8 elements), or grows by as much as fits. Returns how many bytes
/// the vector holds more than before, or `None` if not even one more
/// element fits, or the allocation fails.
pub(crate) fn reserve_one<T>(v: &mut Vec<T>, spare: u64) -> Option<u64> {
    let (len, capacity) = (v.len(), v.capacity());
    if len < capacity {
        return Some(0);
    }
    let size = (size_of::<T>() as u64).max(1);
    let fits = usize::try_from(spare / size).unwrap_or(usize::MAX);
    let wanted = capacity.saturating_mul(2).max(8).min(fits);
    if wanted <= capacity {
        return None;
    }
    v.try_reserve_exact(wanted - len).ok()?;
    Some(vec_bytes(v).saturating_sub(bytes_of::<T>(capacity)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grows_by_doubling_within_the_spare_bytes() {
        let mut v: Vec<u64> = Vec::new();
        assert_eq!(reserve_one(&mut v, 1 << 20), Some(64), "8 elements first");
        v.extend([0; 8]);
        assert_eq!(reserve_one(&mut v, 1 << 20), Some(64), "then doubles");
        assert_eq!(v.capacity(), 16, "capacity");
        v.extend([0; 8]);
        assert_eq!(reserve_one(&mut v, 17 * 8), Some(8), "only one more fits");
        assert_eq!(v.capacity(), 17, "capacity");
        v.push(0);
        assert_eq!(reserve_one(&mut v, 17 * 8), None, "no new block fits");
        assert_eq!(reserve_one(&mut v, 0), None, "nothing spare");
        v.pop();
        assert_eq!(reserve_one(&mut v, 0), Some(0), "room already");
    }
}
