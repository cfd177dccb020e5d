//! The batch sampler's 2-D and 3-D annulus offsets: [`WIDE`] at a time, in
//! `f32`, in units of `r`.
//!
//! The quick check of the conflict cache runs in `f32` on the offset in
//! units of `r` (`ConflictCache::block_relative`), and it turns away most
//! candidates. So the batch draws that offset directly in `f32`, twice the
//! lanes of `f64` to a vector and shorter series, and a candidate is its
//! active point plus the same offset widened to `f64` and scaled by `r`:
//! the quick check sees the candidate's own offset (to `2⁻⁵³` relative, the
//! product's rounding), and the grid's exact `f64` test decides as before.
//! This is faster than the same draws in `f64`
//! (`docs/performance-journal.md`, "Offsets in `f32`").
//!
//! **The law** is the `f64` draw's to within `f32` rounding: radius
//! `r·√(1 + 3u)` (2-D) or `r·∛(1 + 7u)` (3-D) from 24 bits of `u`, a
//! uniform angle from 32 bits (a 256-entry table and a rotation), in 3-D a
//! height uniform in `[-1, 1)` from 24 bits (Archimedes). An offset's
//! length is within a few `2⁻²⁴` relative of `r..2r`; one a hair under `r`
//! is turned away by the exact test against its active point, like any
//! other conflict.

use rand::Rng;

use super::tables::{CUBE_ROOTS_F32, DIRECTIONS_F32, TABLE_BITS};

/// Offsets a wide batch draws at once (`WIDE_IF_DIRECT`: the batch
/// sampler in 2-D and 3-D), and the room every batch has for its `f32`
/// offsets: 32 × `N` coordinates, 8 KiB at the largest `N` that reads
/// ahead (63), where eight would do; the type cannot size itself by `N`
/// on stable Rust. 32 is faster than 8: four times the independent chains
/// in one vector loop (`docs/performance-journal.md`, "Offsets drawn 8
/// ahead"). The same 32 drawn as four fills of 8 gain next to nothing in
/// 3-D, so the width of the loop is what pays, not fewer refills.
pub(super) const WIDE: usize = 32;

/// `2⁻²⁴`: a 24-bit integer as a fraction of one.
const TWO_POW_M24: f32 = 1.0 / 16_777_216.0;

/// [`WIDE`] annulus offsets in units of `r`, 2-D or 3-D by `N` (other
/// dimensions are not drawn here: `units` is left as it is). The generator
/// words are drawn first, in the order the `f64` draws took them (2-D one
/// a draw, 3-D two), then each step runs over all lanes at once.
#[inline(always)]
pub(super) fn fill<R: Rng + ?Sized, const N: usize>(rng: &mut R, units: &mut [[f32; N]; WIDE]) {
    if N == 2 {
        let mut words = [0u64; WIDE];
        for w in &mut words {
            *w = rng.next_u64();
        }
        let mut x = [0.0f32; WIDE];
        let mut y = [0.0f32; WIDE];
        for ((x, y), &w) in x.iter_mut().zip(&mut y).zip(&words) {
            let rho = (1.0 + 3.0 * fraction(w)).sqrt();
            #[expect(clippy::cast_possible_truncation, reason = "the word's low half")]
            let (c, s) = direction(w as u32);
            (*x, *y) = (rho * c, rho * s);
        }
        for ((unit, &x), &y) in units.iter_mut().zip(&x).zip(&y) {
            if let [ux, uy] = unit.as_mut_slice() {
                (*ux, *uy) = (x, y);
            }
        }
    } else if N == 3 {
        let mut first = [0u64; WIDE];
        let mut second = [0u64; WIDE];
        for (a, b) in first.iter_mut().zip(&mut second) {
            *a = rng.next_u64();
            *b = rng.next_u64();
        }
        let mut x = [0.0f32; WIDE];
        let mut y = [0.0f32; WIDE];
        let mut z = [0.0f32; WIDE];
        let words = first.iter().zip(&second);
        for (((x, y), z), (&a, &b)) in x.iter_mut().zip(&mut y).zip(&mut z).zip(words) {
            let rho = cube_root(a);
            #[expect(clippy::cast_possible_truncation, reason = "the word's low half")]
            let h = height(a as u32);
            let ring = rho * ring(h);
            let (c, s) = direction((b >> 32) as u32);
            (*x, *y, *z) = (ring * c, ring * s, rho * h);
        }
        for (((unit, &x), &y), &z) in units.iter_mut().zip(&x).zip(&y).zip(&z) {
            if let [ux, uy, uz] = unit.as_mut_slice() {
                (*ux, *uy, *uz) = (x, y, z);
            }
        }
    }
}

/// The top 24 bits of `w` as a fraction in `[0, 1)`, exactly.
#[inline(always)]
fn fraction(w: u64) -> f32 {
    let top = (w >> 40) as i32;
    #[expect(clippy::cast_precision_loss, reason = "24 bits convert exactly")]
    let u = top as f32;
    u * TWO_POW_M24
}

/// `∛(1 + 7u)` for `u` the top 24 bits of `w`: uniform in volume over
/// `1..2`. The top 8 bits pick a [`CUBE_ROOTS_F32`] entry (the root at the
/// middle of their range), the other 16 the step from it, `t` below
/// `0.0137` in size, whose binomial series to `t³` is exact to `2·10⁻⁹`.
#[inline(always)]
fn cube_root(w: u64) -> f32 {
    let top = (w >> 40) as u32;
    let (root, scale) = CUBE_ROOTS_F32
        .get((top >> 16) as usize)
        .copied()
        .unwrap_or((1.0, 0.0));
    #[expect(clippy::cast_possible_wrap, reason = "16 bits fit an i32")]
    let step = (top & 0xFFFF) as i32 - (1 << 15);
    #[expect(clippy::cast_precision_loss, reason = "16 bits convert exactly")]
    let t = step as f32 * scale;
    let q = (1.0 / 3.0) + t * ((-1.0 / 9.0) + t * ((5.0 / 81.0) + t * (-10.0 / 243.0)));
    root + root * (t * q)
}

/// `√(1 - h²)`, the ring's radius at height `h`, as `(1 - h)(1 + h)`: both
/// factors are exact (`h` is a multiple of `2⁻²³`), so only the product
/// and the root round, where `1 - h·h` would lose most of its digits near
/// the poles.
#[inline(always)]
fn ring(h: f32) -> f32 {
    ((1.0 - h) * (1.0 + h)).sqrt()
}

/// A height uniform in `[-1, 1)` from the top 24 bits of `bits`, exactly.
#[inline(always)]
fn height(bits: u32) -> f32 {
    #[expect(clippy::cast_possible_wrap, reason = "the bits as a signed integer")]
    let signed = (bits as i32) >> 8;
    #[expect(clippy::cast_precision_loss, reason = "24 bits convert exactly")]
    let h = signed as f32;
    h * (2.0 * TWO_POW_M24)
}

/// The unit direction at angle `2π · bits / 2³²`: the top 8 bits pick a
/// [`DIRECTIONS_F32`] entry, the other 24 a rotation by `δ < 2π/256`, whose
/// cosine and sine polynomials are exact to `10⁻¹⁰`, far below `f32`'s
/// rounding.
#[inline(always)]
fn direction(bits: u32) -> (f32, f32) {
    const DELTA_PER_UNIT: f32 = core::f32::consts::TAU / 4_294_967_296.0;
    let (c, s) = DIRECTIONS_F32
        .get((bits >> (32 - TABLE_BITS)) as usize)
        .copied()
        .unwrap_or((1.0, 0.0));
    #[expect(clippy::cast_possible_wrap, reason = "24 bits fit an i32")]
    let low = (bits & ((1 << (32 - TABLE_BITS)) - 1)) as i32;
    #[expect(clippy::cast_precision_loss, reason = "24 bits convert exactly")]
    let delta = low as f32 * DELTA_PER_UNIT;
    let d2 = delta * delta;
    let cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0));
    let sd = delta * (1.0 - d2 * (1.0 / 6.0));
    (c * cd - s * sd, s * cd + c * sd)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::seeded_rng;

    /// Words that reach the ends of every field, then random ones.
    fn words() -> Vec<u64> {
        let mut rng = seeded_rng(3);
        let mut out = vec![0, u64::MAX, 1 << 63, (1 << 63) - 1, 0xFF00_0000_FF00_0000];
        out.extend((0..20_000).map(|_| rng.next_u64()));
        out
    }

    #[test]
    fn the_fields_match_their_f64_formulas() {
        for w in words() {
            #[expect(clippy::cast_precision_loss, reason = "24 bits")]
            let u = (w >> 40) as f64 / 16_777_216.0;
            let rho = f64::from((1.0 + 3.0 * fraction(w)).sqrt());
            assert!(
                (rho - (1.0 + 3.0 * u).sqrt()).abs() < 4e-7,
                "{w:#x}: √ {rho}"
            );
            let root = f64::from(cube_root(w));
            assert!(
                (root - (1.0 + 7.0 * u).cbrt()).abs() < 4e-7,
                "{w:#x}: ∛ {root}"
            );
            #[expect(clippy::cast_possible_truncation, reason = "low half")]
            let bits = w as u32;
            let theta = f64::from(bits) * core::f64::consts::TAU / 4_294_967_296.0;
            let (c, s) = direction(bits);
            assert!((f64::from(c) - theta.cos()).abs() < 4e-7, "{w:#x}: cos");
            assert!((f64::from(s) - theta.sin()).abs() < 4e-7, "{w:#x}: sin");
            #[expect(clippy::cast_possible_wrap, reason = "signed on purpose")]
            let signed = f64::from(bits as i32) / 2_147_483_648.0;
            let h = f64::from(height(bits));
            assert!((-1.0..1.0).contains(&h), "{w:#x}: height {h}");
            assert!(
                (h - signed).abs() <= 1.0 / 8_388_608.0,
                "{w:#x}: height {h}"
            );
        }
    }

    #[test]
    fn rings_keep_their_digits_at_the_poles() {
        // Heights a few steps from either pole, and some in between.
        let steps = (1..64).chain([1 << 10, 1 << 20, 1 << 22]);
        for k in steps {
            for sign in [-1.0f32, 1.0] {
                let h = sign * (1.0 - k as f32 / 8_388_608.0);
                let want = (1.0 - f64::from(h).powi(2)).sqrt();
                let got = f64::from(ring(h));
                assert!(
                    (got / want - 1.0).abs() < 3e-7,
                    "h = {h}: {got} against {want}"
                );
            }
        }
        assert_eq!(ring(-1.0), 0.0, "the south pole");
    }

    /// Draws batches from the generator and returns the offsets' lengths.
    fn lengths<const N: usize>(batches: usize) -> Vec<f64> {
        let mut rng = seeded_rng(11);
        let mut units = [[0.0f32; N]; WIDE];
        let mut out = Vec::new();
        for _ in 0..batches {
            fill(&mut rng, &mut units);
            for u in &units {
                out.push(u.iter().map(|&x| f64::from(x).powi(2)).sum::<f64>().sqrt());
            }
        }
        out
    }

    #[test]
    fn offsets_stay_in_the_annulus_to_f32_rounding() {
        for len in lengths::<2>(2_000).into_iter().chain(lengths::<3>(2_000)) {
            assert!(len > 1.0 - 1e-6 && len < 2.0 + 1e-6, "length {len}");
        }
    }

    #[test]
    fn offsets_are_uniform_in_area_and_volume() {
        // P(|d| < 1.5) = (1.5² - 1) / 3 in 2-D, (1.5³ - 1) / 7 in 3-D; the
        // share is a mean of 64 000 draws, its standard deviation 0.002.
        let share = |lens: &[f64]| {
            #[expect(clippy::cast_precision_loss, reason = "a count")]
            let n = lens.len() as f64;
            #[expect(clippy::cast_precision_loss, reason = "a count")]
            let inner = lens.iter().filter(|&&l| l < 1.5).count() as f64;
            inner / n
        };
        let two = share(&lengths::<2>(2_000));
        assert!(
            (two - 1.25 / 3.0).abs() < 0.01,
            "2-D share inside 1.5: {two}"
        );
        let three = share(&lengths::<3>(2_000));
        assert!(
            (three - 2.375 / 7.0).abs() < 0.01,
            "3-D share inside 1.5: {three}"
        );
    }

    #[test]
    fn directions_cover_every_octant_evenly() {
        let mut rng = seeded_rng(12);
        let mut units = [[0.0f32; 3]; WIDE];
        let mut octants = [0u32; 8];
        for _ in 0..2_000 {
            fill(&mut rng, &mut units);
            for u in &units {
                let octant: usize = u
                    .iter()
                    .enumerate()
                    .map(|(i, &x)| usize::from(x >= 0.0) << i)
                    .sum();
                if let Some(count) = octants.get_mut(octant) {
                    *count += 1;
                }
            }
        }
        for (i, &count) in octants.iter().enumerate() {
            let share = f64::from(count) / 64_000.0;
            assert!((share - 0.125).abs() < 0.006, "octant {i}: {share}");
        }
    }
}
