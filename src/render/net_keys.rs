//! Per-pixel keys for [`NetPixelSampler`](super::NetPixelSampler) from a
//! toroidal tile, so that neighbouring pixels' errors cancel (blue noise
//! across pixels), and the moves shared by a whole image that keep every
//! pixel's key uniform.
//!
//! A key is a bank entry, one of the 32 symmetries and an offset inside the
//! cells. The tile (`net_tile.rs`, made by `examples/net_tile.rs`) holds
//! one key per pixel of a 32 × 32 torus, optimised so that the errors of a
//! family of step and disk integrands shared by all pixels have little
//! power at low frequencies. For a seed and a dimension the sampler reads
//! it at a uniform toroidal offset and composes each key with [`Shared`]
//! moves: a uniform symmetry applied after the tile's, a uniform offset
//! added to the tile's (mod one cell) and, for shift-invariant banks, a
//! uniform column shift.
//!
//! # Balance
//! Every bank entry fills the same number of the tile's pixels, so over the
//! uniform tile offset a pixel's entry is uniform. A uniform group element
//! composed with any fixed one is uniform: the symmetry, offset and shift
//! are uniform and independent of the entry whatever the tile holds. So
//! every pixel draws its moves from exactly the distribution the sampler's
//! balance tests enumerate; only the relation between pixels is chosen.

use super::hash::mix;
use super::net_tile::{TILE_SIDE, TILES};

/// Separates the shared hash from the per-pixel ones.
const SHARED_SALT: u64 = 0x6a09_e667_f3bc_c909;

/// Separates the shared offsets' hash from the shared moves' hash.
const OFFSETS: u64 = 0x3c6e_f372_fe94_f82b;

/// The moves shared by every pixel of an image for one seed, draw kind and
/// dimension.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Shared {
    /// The toroidal offset of the tile, in pixels, x and y.
    pub(crate) tile: [u32; 2],
    /// The symmetry applied after the tile's (the sampler's 5-bit code).
    pub(crate) symmetry: u32,
    /// The column shift, in cells (shift-invariant banks; else unused).
    pub(crate) shift: u32,
    /// Added to the tile's offsets inside the cells, mod 2³².
    pub(crate) offset: [u32; 2],
}

impl Shared {
    /// The shared moves for hash input `input` (the seed's hash with the
    /// draw's kind and dimension): all exactly uniform (the shift over
    /// `0..n` for `n` a power of two up to 2¹²).
    #[inline]
    pub(crate) fn new(input: u64, n: u32) -> Self {
        let h = mix(input ^ SHARED_SALT);
        let o = mix(h ^ OFFSETS);
        let side = TILE_SIDE - 1;
        #[expect(clippy::cast_possible_truncation, reason = "bit fields of the hash")]
        Self {
            tile: [h as u32 & side, (h >> 8) as u32 & side],
            symmetry: (h >> 16) as u32 & 31,
            shift: (h >> 32) as u32 & n.wrapping_sub(1),
            offset: [(o >> 32) as u32, o as u32],
        }
    }
}

/// A pixel's key read from the tile of `2^m` samples, before the shared
/// moves: `(bank entry, symmetry, [offset x, offset y])`, the offsets as
/// 32-bit fractions of a cell.
#[inline(always)]
pub(crate) fn tile_key(tile: &[u32], [x, y]: [u32; 2], shared: &Shared) -> (u32, u32, [u32; 2]) {
    let side = TILE_SIDE - 1;
    let at = (y.wrapping_add(shared.tile[1]) & side) * TILE_SIDE
        + (x.wrapping_add(shared.tile[0]) & side);
    let key = tile.get(at as usize).copied().unwrap_or(0);
    (key >> 5 & 63, key & 31, [key >> 16 & 255, key >> 24])
}

/// The tile for `2^m` samples per pixel, if there is one.
pub(crate) fn tile(m: u32) -> Option<&'static [u32]> {
    TILES.get(m as usize).map(|t| &t[..])
}

/// Symmetry `g` applied after symmetry `t`, both in the sampler's 5-bit
/// code (bits 0-1 the x class: bit 0 a half shift, bit 1 a reflection;
/// bits 2-3 the same for y; bit 4 the x↔y swap, applied last). The 32
/// symmetries form a group and this is its product, so for any fixed `t`,
/// `g ↦ compose(g, t)` is a bijection.
#[inline(always)]
pub(crate) fn compose(g: u32, t: u32) -> u32 {
    let (xt, yt, st) = (t & 3, t >> 2 & 3, t >> 4 & 1);
    let (xg, yg, sg) = (g & 3, g >> 2 & 3, g >> 4 & 1);
    // After t's swap, g's x class lands on what was y, and the reverse.
    let (x, y) = if st == 1 {
        (xt ^ yg, yt ^ xg)
    } else {
        (xt ^ xg, yt ^ yg)
    };
    x | y << 2 | (st ^ sg) << 4
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compose_is_a_group_product() {
        for t in 0..32 {
            let mut seen = [false; 32];
            for g in 0..32 {
                assert!(!std::mem::replace(&mut seen[compose(g, t) as usize], true));
            }
            assert_eq!(compose(0, t), t, "identity");
            assert_eq!(compose(t, 0), t, "identity");
        }
        // Associative.
        for a in 0..32 {
            for b in 0..32 {
                for c in 0..32 {
                    assert_eq!(compose(a, compose(b, c)), compose(compose(a, b), c));
                }
            }
        }
    }

    #[test]
    fn every_tile_fills_each_bank_entry_equally_often() {
        use super::super::net_table::NETS;
        for (m, tile) in TILES.iter().enumerate() {
            let n = 1usize << m;
            let sets = NETS[m].len() / n;
            let mut counts = vec![0usize; sets];
            for &key in tile.iter() {
                let set = (key >> 5 & 63) as usize;
                assert!(set < sets, "m {m}: entry {set} of {sets}");
                counts[set] += 1;
            }
            assert!(
                counts.iter().all(|&c| c * sets == tile.len()),
                "m {m}: {counts:?}"
            );
        }
    }

    #[test]
    fn shared_moves_are_in_range() {
        for k in 0..500 {
            let s = Shared::new(mix(k), 64);
            assert!(s.tile.iter().all(|&t| t < TILE_SIDE));
            assert!(s.symmetry < 32 && s.shift < 64);
        }
    }
}
