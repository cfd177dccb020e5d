//! Hashing for the pixel samplers: a 64-bit mixer, and a keyed permutation
//! of `0..n` for any `n`.
//!
//! Both are integer-only, so they give the same bits on every platform, and
//! stateless, so a value depends only on its inputs: that is what lets a
//! sampler hand out the same sample whatever order or thread asks for it.

/// A bijective 64-bit mixer with full avalanche: every input bit flips
/// about half the output bits. Two xor-shift-multiply rounds and a final
/// xor-shift, with the constants of SplitMix64's output function.
#[inline(always)]
pub(crate) fn mix(mut x: u64) -> u64 {
    x ^= x >> 30;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x ^= x >> 27;
    x = x.wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// A uniform index in `0..len` from the high bits of `hash` (multiply-high:
/// bias below `len / 2⁶⁴`).
#[inline(always)]
pub(crate) fn below(hash: u64, len: usize) -> usize {
    let wide = u128::from(hash) * len as u128;
    #[expect(
        clippy::cast_possible_truncation,
        reason = "the high word is < len, which is a usize"
    )]
    let index = (wide >> 64) as usize;
    index
}

/// Rounds of [`permute_each`]: 10 make the position of an element, and the
/// joint position of two, uniform over keys to within a chi-square test's
/// resolution at 12 000 keys (see the tests). Each round costs about ten
/// cycles of latency; the permutation is most of a draw's cost.
const PERMUTE_ROUNDS: u32 = 10;

/// The element at `index` of the permutation of `0..n` chosen by each of
/// `K` keys.
///
/// For a fixed `(n, key)` the map `index -> permute_each(index, n, [key])`
/// is a bijection of `0..n` for every `n >= 1`, not only powers of two, by
/// construction: it is Hoang, Morris and Rogaway's swap-or-not shuffle
/// (2012). Each round pairs `x` with `K - x (mod n)` for a round key `K`
/// and swaps to the partner if a hashed bit of the pair says so; a round is
/// its own inverse, so the whole is a bijection, with no cycle walking and
/// a fixed cost. Round keys follow from `key` by a xorshift step, the
/// pair's bit is the top bit of a 32-bit multiplicative hash. `index` must
/// be `< n`; an `n` of 0 or 1 gives 0.
///
/// The `K` permutations run round by round side by side, so their
/// dependency chains overlap: a camera sample's three draws cost little
/// more than one.
#[inline(always)]
pub(crate) fn permute_each<const K: usize>(index: u32, n: u32, keys: [u64; K]) -> [u32; K] {
    if n <= 1 {
        return [0; K];
    }
    let mut x = [index; K];
    let mut round_keys = keys.map(|k| k | 1);
    for _ in 0..PERMUTE_ROUNDS {
        for (x, round_key) in x.iter_mut().zip(&mut round_keys) {
            *round_key ^= *round_key << 13;
            *round_key ^= *round_key >> 7;
            *round_key ^= *round_key << 17;
            *x = swap_or_not(*x, n, *round_key);
        }
    }
    x
}

/// One swap-or-not round on `0..n` under `round_key`.
#[inline(always)]
fn swap_or_not(x: u32, n: u32, round_key: u64) -> u32 {
    #[expect(
        clippy::cast_possible_truncation,
        reason = "the low and high words of the round key"
    )]
    let (low, high) = (round_key as u32, (round_key >> 32) as u32);
    // K uniform in 0..n by multiply-high; the partner is K - x mod n.
    let k = ((u64::from(low) * u64::from(n)) >> 32) as u32;
    // Branch-free: the swap bit is a coin flip, which a branch predictor
    // would miss half the time (measured: camera samples 4x slower).
    let wrap = n & 0u32.wrapping_sub(u32::from(x > k));
    let partner = k.wrapping_sub(x).wrapping_add(wrap);
    // Both members of a pair see the same bit: it hashes their maximum.
    let h = (partner.max(x) ^ high).wrapping_mul(0x9e37_79b1);
    let swap = 0u32.wrapping_sub(h >> 31);
    x ^ ((x ^ partner) & swap)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn permute(index: u32, n: u32, key: u64) -> u32 {
        let [x] = permute_each(index, n, [key]);
        x
    }

    fn assert_bijection(n: u32, key: u64) {
        let mut seen = vec![false; n as usize];
        for i in 0..n {
            let j = permute(i, n, key);
            assert!(j < n, "permute({i}, {n}, {key:#x}) = {j}, out of range");
            assert!(
                !seen[j as usize],
                "permute(_, {n}, {key:#x}) hits {j} twice"
            );
            seen[j as usize] = true;
        }
    }

    #[test]
    fn permutations_are_bijections_for_every_small_n() {
        for n in 1..=600 {
            for k in 0..4 {
                assert_bijection(n, mix(u64::from(n) << 8 | k));
            }
        }
    }

    #[test]
    fn permutations_are_bijections_for_large_n() {
        for n in [1000, 1023, 1024, 1025, 2047, 2048, 2049, 3000, 4095, 4096] {
            for k in 0..3 {
                assert_bijection(n, mix(u64::from(n) ^ k));
            }
        }
        // The key words hit every mask width, including the full 32 bits.
        assert_bijection(5, u64::MAX);
        assert_bijection(5, 0);
    }

    #[test]
    fn keys_give_different_permutations() {
        // Not a quality measure, a smoke test: 16 elements, 64 keys, and the
        // position of element 0 takes most of its 16 values.
        let mut hit = [0u32; 16];
        for k in 0..64 {
            hit[permute(0, 16, mix(k)) as usize] += 1;
        }
        let distinct = hit.iter().filter(|&&c| c > 0).count();
        assert!(
            distinct >= 12,
            "element 0 lands on {distinct} of 16: {hit:?}"
        );
        // The identity is not what every key gives.
        let moved = (0..64u64)
            .filter(|&k| (0..16).any(|i| permute(i, 16, mix(k)) != i))
            .count();
        assert_eq!(moved, 64, "some key gave the identity");
    }

    #[test]
    fn positions_are_near_uniform() {
        // Over many keys, element i of an n-permutation lands on each slot
        // about equally often (a chi-square bound far in the tail).
        for n in [2u32, 3, 5, 7, 12, 17] {
            positions_are_uniform_for(n);
        }
    }

    fn positions_are_uniform_for(n: u32) {
        let keys = 12_000u64;
        for i in 0..n {
            let mut counts = vec![0u32; n as usize];
            for k in 0..keys {
                counts[permute(i, n, mix(k + 1)) as usize] += 1;
            }
            let expected = keys as f64 / f64::from(n);
            let chi2: f64 = counts
                .iter()
                .map(|&c| (f64::from(c) - expected).powi(2) / expected)
                .sum();
            // n - 1 degrees of freedom; for 1..=16 of them the 1e-5 tail
            // lies below 20 + 3 (n - 1).
            let bound = 20.0 + 3.0 * f64::from(n - 1);
            assert!(
                chi2 < bound,
                "n {n}, element {i}: chi2 {chi2}, counts {counts:?}"
            );
        }
    }

    #[test]
    fn pairs_of_positions_are_near_uniform() {
        // The joint position of elements 0 and 1 of a 5-permutation: 20
        // outcomes, 20 000 keys (19 degrees of freedom: P(chi2 > 55) < 1e-5).
        let (n, keys) = (5u32, 20_000u64);
        let mut counts = vec![0u32; (n * n) as usize];
        for k in 0..keys {
            let key = mix(k + 7);
            counts[(permute(0, n, key) * n + permute(1, n, key)) as usize] += 1;
        }
        let expected = keys as f64 / 20.0;
        let mut chi2 = 0.0;
        for a in 0..n {
            for b in 0..n {
                let c = f64::from(counts[(a * n + b) as usize]);
                if a == b {
                    assert_eq!(c, 0.0, "two elements share position {a}");
                } else {
                    chi2 += (c - expected).powi(2) / expected;
                }
            }
        }
        assert!(chi2 < 55.0, "chi2 {chi2}, counts {counts:?}");
    }

    #[test]
    fn below_stays_in_range() {
        for h in [0, 1, u64::MAX, mix(3), mix(4)] {
            assert!(below(h, 32) < 32, "below({h}, 32)");
        }
        assert_eq!(below(u64::MAX, 32), 31, "the top of the range");
        assert_eq!(below(0, 32), 0, "the bottom of the range");
    }
}
