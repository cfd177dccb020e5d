//! The set bank: for one sample count `n`, a fixed collection of periodic
//! Poisson disk sets of exactly `n` points, in the plane and on the line,
//! built once and shared by every pixel.
//!
//! Each set comes from the crate's own sampler on the periodic unit box,
//! run at a radius that gives a few more than `n` points, then thinned to
//! exactly `n` by weighted elimination. Points are stored as
//! 32-bit fixed point (`x · 2³²`), so that a toroidal shift is an integer
//! wrapping add: it moves no point off the torus, rounds nothing, and keeps
//! every toroidal distance bit for bit.

use super::eliminate::{eliminate, max_min_distance, min_distance};
use super::hash::mix;
use crate::{Domain, Error, PoissonDisk};
use core::fmt;

/// Sets per dimension kind (plane, line) in a bank.
pub(crate) const SETS: usize = 32;

/// A little under the relative radius ρ a Bridson set reaches at `k = 30`
/// (about 0.75 in 2-D; in 1-D, where ρ is the count
/// times the radius, gaps fall between `r` and `2r`, so about 0.67), so that
/// a run planned for `c` points gives about `c` or a few more. A short run
/// is simply repeated at a smaller radius.
fn bridson_rho<const N: usize>() -> f64 {
    if N == 1 { 0.66 } else { 0.74 }
}

/// Tries at the planned radius and then at smaller ones before the set is
/// made up with hashed points (which has never been needed).
const TRIES: u64 = 8;

/// Seeds every set of every bank: the banks are a pure function of `n`.
const BANK_SEED: u64 = 0x5eed_ba4c_0000_0001;

/// `2⁻³²`: from 32-bit fixed point to `[0, 1)`, exactly.
pub(crate) const FIXED_TO_UNIT: f64 = 1.0 / 4_294_967_296.0;

/// The periodic exact-count sets for one sample count.
pub(crate) struct Bank {
    spp: u32,
    /// `SETS` sets of `spp` points, set-major, in fixed point.
    plane: Vec<[u32; 2]>,
    /// `SETS` sets of `spp` values, set-major, in fixed point.
    line: Vec<u32>,
    /// The smallest toroidal minimum distance over the plane sets.
    min_distance_2d: Option<f64>,
    /// The same over the line sets.
    min_distance_1d: Option<f64>,
}

impl fmt::Debug for Bank {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Bank")
            .field("spp", &self.spp)
            .field("sets", &SETS)
            .field("min_distance_2d", &self.min_distance_2d)
            .field("min_distance_1d", &self.min_distance_1d)
            .finish_non_exhaustive()
    }
}

impl Bank {
    /// Builds the bank for `spp` points per set (`spp >= 1`, checked by the
    /// caller).
    ///
    /// # Errors
    /// Only those of [`Domain`] and [`PoissonDisk`] construction, which the
    /// unit box and the planned radius never trigger.
    pub(crate) fn build(spp: u32) -> Result<Self, Error> {
        let n = spp as usize;
        let mut plane = Vec::with_capacity(SETS * n);
        let mut line = Vec::with_capacity(SETS * n);
        let mut min_2d: Option<f64> = None;
        let mut min_1d: Option<f64> = None;
        for set in 0..SETS as u64 {
            let seed = mix(BANK_SEED ^ (u64::from(spp) << 32) ^ (set << 1));
            let points = periodic_set::<2>(n, seed)?;
            let unit: Vec<[f64; 2]> = points.iter().map(|p| p.map(to_unit)).collect();
            min_2d = lower(min_2d, min_distance(&unit));
            plane.extend_from_slice(&points);

            let seed = mix(BANK_SEED ^ (u64::from(spp) << 32) ^ (set << 1 | 1));
            let values = periodic_set::<1>(n, seed)?;
            let unit: Vec<[f64; 1]> = values.iter().map(|p| p.map(to_unit)).collect();
            min_1d = lower(min_1d, min_distance(&unit));
            line.extend(values.iter().map(|&[x]| x));
        }
        Ok(Self {
            spp,
            plane,
            line,
            min_distance_2d: min_2d,
            min_distance_1d: min_1d,
        })
    }

    /// The number of points per set.
    pub(crate) fn spp(&self) -> u32 {
        self.spp
    }

    /// Point `index` of plane set `set`, in fixed point. Out-of-range
    /// arguments (which the sampler never passes) give the origin.
    #[inline(always)]
    pub(crate) fn point_2d(&self, set: usize, index: u32) -> [u32; 2] {
        self.plane
            .get(set * self.spp as usize + index as usize)
            .copied()
            .unwrap_or_default()
    }

    /// Value `index` of line set `set`, in fixed point (0 out of range).
    #[inline(always)]
    pub(crate) fn point_1d(&self, set: usize, index: u32) -> u32 {
        self.line
            .get(set * self.spp as usize + index as usize)
            .copied()
            .unwrap_or_default()
    }

    /// The smallest toroidal minimum distance over the plane sets; `None`
    /// for one point per set.
    pub(crate) fn min_distance_2d(&self) -> Option<f64> {
        self.min_distance_2d
    }

    /// The same over the line sets.
    pub(crate) fn min_distance_1d(&self) -> Option<f64> {
        self.min_distance_1d
    }
}

/// The smaller of two optional distances (`None` is "no pair").
fn lower(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, None) => x,
        (None, y) => y,
    }
}

/// A fixed-point coordinate as an `f64` in `[0, 1)` (exact).
#[inline(always)]
pub(crate) fn to_unit(q: u32) -> f64 {
    f64::from(q) * FIXED_TO_UNIT
}

/// `x` in `[0, 1)` as 32-bit fixed point, rounding down.
fn to_fixed(x: f64) -> u32 {
    // x · 2³² is exact (a power-of-two scale) and below 2³².
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "0 <= x < 1, so 0 <= x * 2^32 < 2^32: truncation is floor"
    )]
    let q = (x * 4_294_967_296.0) as u32;
    q
}

/// A periodic set of exactly `n` points on the unit torus `[0, 1)^N`, in
/// fixed point.
///
/// A Bridson set planned for a few more than `n` points (`n + n/16 + 2`),
/// run again at a 5 % smaller radius should it come out short, thinned to
/// exactly `n` by weighted elimination. Removing points never brings two
/// closer, so the set keeps Bridson's minimum distance `r`: its ρ is that
/// of the Bridson set times `sqrt(n / count)`, about 0.72 in 2-D.
fn periodic_set<const N: usize>(n: usize, seed: u64) -> Result<Vec<[u32; N]>, Error> {
    let domain = Domain::from_extent([1.0; N])?.with_periodic([true; N]);
    let planned = n + n / 16 + 2;
    let mut radius = bridson_rho::<N>() * max_min_distance::<N>(planned);
    let mut points: Vec<[f64; N]> = Vec::new();
    for attempt in 0..TRIES {
        points = PoissonDisk::new(domain, radius)?
            .iter_seeded(mix(seed ^ attempt))
            .collect();
        if points.len() >= n {
            break;
        }
        radius *= 0.95;
    }
    // Should every try fall short, hashed uniform points make up the
    // number and the elimination spreads them; the bank's measured minimum
    // distance then says what was achieved.
    let mut counter = seed;
    while points.len() < n {
        points.push(core::array::from_fn(|_| {
            counter = counter.wrapping_add(0x9e37_79b9_7f4a_7c15);
            to_unit(fixed_from_hash(mix(counter)))
        }));
    }
    Ok(eliminate(&points, n)
        .iter()
        .map(|p| p.map(to_fixed))
        .collect())
}

/// The high 32 bits of a hash.
#[inline(always)]
pub(crate) fn fixed_from_hash(h: u64) -> u32 {
    (h >> 32) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::relative_radius;

    #[test]
    fn every_set_has_exactly_n_points() {
        for spp in [1, 2, 3, 7, 16, 33] {
            let bank = Bank::build(spp).unwrap();
            assert_eq!(bank.plane.len(), SETS * spp as usize, "spp {spp}");
            assert_eq!(bank.line.len(), SETS * spp as usize, "spp {spp}");
        }
    }

    #[test]
    fn banks_are_a_function_of_the_count() {
        let a = Bank::build(12).unwrap();
        let b = Bank::build(12).unwrap();
        assert_eq!(a.plane, b.plane, "plane sets differ between builds");
        assert_eq!(a.line, b.line, "line sets differ between builds");
        let c = Bank::build(13).unwrap();
        assert_ne!(a.plane.first(), c.plane.first(), "counts share sets");
    }

    #[test]
    fn sets_are_well_spread() {
        for spp in [16, 64, 256] {
            let bank = Bank::build(spp).unwrap();
            let n = spp as usize;
            let d2 = bank.min_distance_2d().unwrap();
            let rho2 = relative_radius::<2>(d2, n, 1.0).unwrap();
            let d1 = bank.min_distance_1d().unwrap();
            let rho1 = relative_radius::<1>(d1, n, 1.0).unwrap();
            eprintln!("spp {spp}: ρ 2-D {rho2:.3}, 1-D {rho1:.3}");
            assert!(rho2 > 0.6, "spp {spp}: 2-D ρ {rho2}");
            assert!(rho1 > 0.5, "spp {spp}: 1-D ρ {rho1}");
        }
    }
}
