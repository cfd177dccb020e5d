//! The field's randomness: every dart a hash of (seed, cell, level, round),
//! by integer operations only, so that a dart is the same wherever and
//! whenever it is computed.

/// SplitMix64's finaliser (Stafford's "Mix13"): a bijection of `u64` whose
/// outputs pass the usual statistical batteries for consecutive inputs.
#[inline(always)]
pub(crate) fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The odd constant that spaces consecutive words of one dart (2⁶⁴/φ).
const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// The key of one dart: the seed, the level-0 cell (canonical indices), the
/// sub-cell within it, its level and the round. Each word is folded through
/// [`mix`] in turn, so that nearby cells give unrelated keys.
#[inline(always)]
pub(crate) fn dart_key<const N: usize>(
    seed: u64,
    cell: &[i64; N],
    sub: &[u32; N],
    level: u32,
    round: u32,
) -> u64 {
    let mut h = mix(seed ^ 0x6a09_e667_f3bc_c908);
    for (&c, &s) in cell.iter().zip(sub) {
        #[expect(
            clippy::cast_sign_loss,
            reason = "the bits of the index are hashed, not its value"
        )]
        let c = c as u64;
        h = mix(h ^ c);
        h = mix(h ^ u64::from(s));
    }
    mix(h ^ (u64::from(level) << 32 | u64::from(round)))
}

/// Word `j` of the dart with key `key`: `j = 0` is its priority, `1..=N` its
/// coordinates in the cell.
#[inline(always)]
pub(crate) fn word(key: u64, j: u64) -> u64 {
    mix(key.wrapping_add(GOLDEN.wrapping_mul(j + 1)))
}

/// A uniform `f64` in `[0, 1)` from the top 53 bits of a word: exact
/// integer-to-float conversion and a power-of-two scale, so the same bits
/// on every machine.
#[inline(always)]
pub(crate) fn unit(w: u64) -> f64 {
    const SCALE: f64 = 1.0 / (1u64 << 53) as f64;
    #[expect(
        clippy::cast_precision_loss,
        reason = "a 53-bit integer converts to f64 exactly"
    )]
    let x = (w >> 11) as f64;
    x * SCALE
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_differ_by_every_input() {
        let base = dart_key(1, &[3, 4], &[0, 0], 0, 0);
        assert_ne!(base, dart_key(2, &[3, 4], &[0, 0], 0, 0), "seed");
        assert_ne!(base, dart_key(1, &[4, 3], &[0, 0], 0, 0), "cell");
        assert_ne!(base, dart_key(1, &[3, 4], &[1, 0], 1, 0), "sub");
        assert_ne!(base, dart_key(1, &[3, 4], &[0, 0], 1, 0), "level");
        assert_ne!(base, dart_key(1, &[3, 4], &[0, 0], 0, 1), "round");
    }

    #[test]
    fn unit_stays_in_range() {
        assert!(unit(0) == 0.0, "zero word");
        assert!(unit(u64::MAX) < 1.0, "top word");
    }

    #[test]
    fn pinned_words() {
        // Value stability: these hashes define every field's points.
        assert_eq!(mix(0), 0, "mix fixes zero");
        assert_eq!(mix(1), 0x5692_161d_100b_05e5, "mix(1)");
    }
}
