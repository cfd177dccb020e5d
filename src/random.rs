//! Turning raw generator output into the few draws the sampler needs.
//!
//! Only integer operations and correctly rounded `f64` arithmetic are used,
//! never `sin`, `ln` or `powf`, whose last bit differs between platforms'
//! math libraries. That is what makes a seed give the same points everywhere.

use rand::Rng;
use rand::SeedableRng as _;

/// The generator behind every `*_seeded` convenience: fast, small, and with
/// a stable, documented output stream.
pub type DefaultRng = rand_xoshiro::Xoshiro256PlusPlus;

/// The generator a `*_seeded` call uses: [`DefaultRng`] seeded through
/// SplitMix64, as `rand_xoshiro` documents for `seed_from_u64`.
pub fn seeded_rng(seed: u64) -> DefaultRng {
    DefaultRng::seed_from_u64(seed)
}

/// A uniform `f64` in `[0, 1)` with 53 random bits.
#[inline(always)]
pub(crate) fn unit<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    const SCALE: f64 = 1.0 / (1u64 << 53) as f64;
    // Through i64: one instruction on x86-64, where u64 -> f64 takes several.
    #[expect(
        clippy::cast_possible_wrap,
        clippy::cast_precision_loss,
        reason = "a 53-bit integer fits i64 and converts to f64 exactly"
    )]
    let x = (rng.next_u64() >> 11) as i64 as f64;
    x * SCALE
}

/// Two uniform `f64` in `[-1, 1)` from one 64-bit draw, 32 bits each.
///
/// Used for candidate offsets, where 2⁻³¹ of the annulus width is far finer
/// than anything the pattern can show, and one generator call per two
/// coordinates is a measurable share of the sampler's time.
#[inline(always)]
pub(crate) fn symmetric_pair<R: Rng + ?Sized>(rng: &mut R) -> (f64, f64) {
    const SCALE: f64 = 1.0 / (1u64 << 31) as f64;
    let x = rng.next_u64();
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_possible_wrap,
        reason = "splitting the word into two signed 32-bit halves is the point"
    )]
    let (hi, lo) = ((x >> 32) as u32 as i32, x as u32 as i32);
    (f64::from(hi) * SCALE, f64::from(lo) * SCALE)
}

/// A uniform `f64` in `[-1, 1)`.
#[inline(always)]
pub(crate) fn symmetric<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    2.0 * unit(rng) - 1.0
}

/// A uniform index in `0..len` (`len > 0`), by the multiply-high method.
/// Its bias is below `len / 2^64`, far under anything measurable.
#[inline(always)]
pub(crate) fn below<R: Rng + ?Sized>(rng: &mut R, len: usize) -> usize {
    let wide = u128::from(rng.next_u64()) * len as u128;
    #[expect(
        clippy::cast_possible_truncation,
        reason = "the high word is < len, which is a usize"
    )]
    let index = (wide >> 64) as usize;
    index
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_stay_in_range() {
        let mut rng = seeded_rng(1);
        for _ in 0..10_000 {
            let u = unit(&mut rng);
            assert!((0.0..1.0).contains(&u), "unit draw {u}");
            let s = symmetric(&mut rng);
            assert!((-1.0..1.0).contains(&s), "symmetric draw {s}");
            let (a, b) = symmetric_pair(&mut rng);
            assert!(
                (-1.0..1.0).contains(&a) && (-1.0..1.0).contains(&b),
                "pair {a} {b}"
            );
            let i = below(&mut rng, 7);
            assert!(i < 7, "index {i}");
        }
    }

    #[test]
    fn below_reaches_every_index() {
        let mut rng = seeded_rng(2);
        let mut seen = [false; 5];
        for _ in 0..1000 {
            seen[below(&mut rng, 5)] = true;
        }
        assert!(seen.iter().all(|&s| s), "some index never drawn: {seen:?}");
    }
}
