//! Where a field's points may go: [`FieldRegion`], and the regions given by
//! a signed distance ([`SignedDistance`]).
//!
//! A field's rounds need more of a region than the core samplers' point
//! test ([`Region`](crate::Region)): a cell that no point of the region
//! meets must die, or it would split on every round without end. So a
//! field region answers for boxes too, conservatively.

use crate::sampler::Everywhere;

/// The region a [`Field`](crate::Field) places its points in, as a function
/// of place: the field's set is then maximal inside the region (every point
/// of the region is within `r` of a point), and still a pure function of
/// (seed, radius, domain, region, position).
///
/// Implemented for [`Everywhere`] (the plain field) and [`SignedDistance`]
/// (a region given by a signed distance, the usual form of a procedural
/// shape). The box test is what a closure `Fn(&[f64; N]) -> bool` cannot
/// give, which is why the core samplers' [`Region`](crate::Region) does not
/// serve here.
pub trait FieldRegion<const N: usize> {
    /// Whether a point may lie at `p` (a point of the domain, in its
    /// canonical coordinates on periodic axes).
    fn admits(&self, p: &[f64; N]) -> bool;

    /// Whether the closed box `[lo, hi]` may hold a point that
    /// [`admits`](Self::admits) accepts. `false` must mean none: a cell
    /// the answer wrongly drops leaves a hole (the set is no longer maximal
    /// there), though never a pair closer than `r`. `true` where there is
    /// none costs only work, but a region that answers `true` for boxes
    /// ever smaller around places it never admits (a region of zero
    /// volume) makes a query run out of its budget.
    fn meets(&self, lo: &[f64; N], hi: &[f64; N]) -> bool;
}

impl<const N: usize> FieldRegion<N> for Everywhere {
    #[inline(always)]
    fn admits(&self, _p: &[f64; N]) -> bool {
        true
    }

    #[inline(always)]
    fn meets(&self, _lo: &[f64; N], _hi: &[f64; N]) -> bool {
        true
    }
}

/// The region `{p : d(p) <= 0}` of a signed distance `d`: negative inside,
/// positive outside, and never changing faster than the distance between
/// two places (`|d(p) - d(q)| <= |p - q|`, a *1-Lipschitz* function, as
/// every exact or conservative signed distance field is).
///
/// A box meets the region unless `d` at its centre exceeds its
/// half-diagonal. A `d` that grows faster than distance can drop cells that
/// do meet the region, leaving holes near its edge; a `d` that is `NaN`
/// somewhere treats that place as outside.
///
/// # Example: a disk of radius 3 in a 10 × 10 box
/// ```
/// use bridson::{Domain, Field, SignedDistance};
/// let disk = SignedDistance(|p: &[f64; 2]| (p[0] - 5.0).hypot(p[1] - 5.0) - 3.0);
/// let field = Field::new(Domain::from_extent([10.0, 10.0])?, 0.5, 7)?.with_region(disk);
/// let points = field.points()?;
/// assert!(points.iter().all(|p| (p[0] - 5.0).hypot(p[1] - 5.0) <= 3.0));
/// // The same points, asked for in two halves.
/// let mut halves = field.points_in([0.0, 0.0], [5.0, 10.0])?;
/// halves.extend(field.points_in([5.0, 0.0], [10.0, 10.0])?);
/// halves.sort_by(bridson::field_order);
/// assert_eq!(points, halves);
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Clone, Copy, Default)]
pub struct SignedDistance<F>(pub F);

impl<F> core::fmt::Debug for SignedDistance<F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("SignedDistance(..)")
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64> FieldRegion<N> for SignedDistance<F> {
    #[inline]
    fn admits(&self, p: &[f64; N]) -> bool {
        (self.0)(p) <= 0.0
    }

    #[inline]
    fn meets(&self, lo: &[f64; N], hi: &[f64; N]) -> bool {
        let centre: [f64; N] = core::array::from_fn(|a| 0.5 * (lo[a] + hi[a]));
        let half2: f64 = (0..N)
            .map(|a| {
                let h = 0.5 * (hi[a] - lo[a]);
                h * h
            })
            .sum();
        // A margin far above the rounding of the centre and the sum: a box
        // kept by it costs work, never a point.
        (self.0)(&centre) <= half2.sqrt() * (1.0 + 1e-9) + 1e-300
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_meets_a_disk_exactly_when_it_reaches_it() {
        let disk = SignedDistance(|p: &[f64; 2]| p[0].hypot(p[1]) - 1.0);
        assert!(disk.admits(&[0.5, 0.5]));
        assert!(!disk.admits(&[1.0, 0.5]));
        // Centre 1.5 from the origin, half-diagonal √2/2 ≈ 0.707: reaches.
        assert!(disk.meets(&[1.0, -0.5], &[2.0, 0.5]));
        // Centre 2.5 away, the same half-diagonal: does not.
        assert!(!disk.meets(&[2.0, -0.5], &[3.0, 0.5]));
        let nan = SignedDistance(|_: &[f64; 2]| f64::NAN);
        assert!(!nan.admits(&[0.0, 0.0]));
        assert!(!nan.meets(&[0.0, 0.0], &[1.0, 1.0]));
    }
}
