//! The sampling domain: an axis-aligned, half-open box, each axis optionally
//! periodic.

use crate::error::Error;
use crate::vector::zip_map;

/// An axis-aligned box `lo <= x < hi`, each axis optionally periodic.
///
/// Every emitted point lies in the half-open box: a coordinate can equal
/// `lo` but never `hi`. On a periodic (toroidal) axis distances wrap: the
/// difference between two coordinates is `min(|Δ|, L - |Δ|)` with
/// `L = hi - lo`, so the pattern tiles seamlessly.
///
/// # Example: a periodic unit square
/// ```
/// use bridson::Domain;
/// let d = Domain::new([0.0, 0.0], [1.0, 1.0])?.with_periodic([true, true]);
/// assert!(d.contains(&[0.0, 0.5]));
/// assert!(!d.contains(&[1.0, 0.5]));
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "DomainRepr<N>"))]
pub struct Domain<const N: usize> {
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_array"))]
    lo: [f64; N],
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_array"))]
    hi: [f64; N],
    #[cfg_attr(feature = "serde", serde(with = "crate::serde_array"))]
    periodic: [bool; N],
}

impl<const N: usize> Domain<N> {
    /// The box `lo <= x < hi`, no axis periodic.
    ///
    /// # Errors
    /// [`Error::ZeroDimension`] if `N == 0`; [`Error::NonFiniteBound`] if a
    /// bound is NaN or infinite; [`Error::EmptyBox`] if `lo >= hi` on some
    /// axis; [`Error::ExtentOverflow`] if `hi - lo` overflows.
    pub fn new(lo: [f64; N], hi: [f64; N]) -> Result<Self, Error> {
        if N == 0 {
            return Err(Error::ZeroDimension);
        }
        for (axis, (&l, &h)) in lo.iter().zip(&hi).enumerate() {
            if !l.is_finite() || !h.is_finite() {
                return Err(Error::NonFiniteBound { axis });
            }
            if l >= h {
                return Err(Error::EmptyBox { axis });
            }
            if !(h - l).is_finite() {
                return Err(Error::ExtentOverflow { axis });
            }
        }
        Ok(Self {
            lo,
            hi,
            periodic: [false; N],
        })
    }

    /// The box from the origin: `0 <= x < extent`.
    ///
    /// # Errors
    /// As [`Domain::new`].
    pub fn from_extent(extent: [f64; N]) -> Result<Self, Error> {
        Self::new([0.0; N], extent)
    }

    /// The same box with the given axes made periodic (`true`) or bounded.
    #[must_use]
    pub fn with_periodic(mut self, periodic: [bool; N]) -> Self {
        self.periodic = periodic;
        self
    }

    /// Lower corner (inclusive).
    pub fn lo(&self) -> [f64; N] {
        self.lo
    }

    /// Upper corner (exclusive).
    pub fn hi(&self) -> [f64; N] {
        self.hi
    }

    /// Which axes are periodic.
    pub fn periodic(&self) -> [bool; N] {
        self.periodic
    }

    /// Whether any axis is periodic.
    pub fn any_periodic(&self) -> bool {
        self.periodic.iter().any(|&p| p)
    }

    /// `hi - lo` on every axis (finite and positive by construction).
    pub fn extent(&self) -> [f64; N] {
        zip_map(&self.hi, &self.lo, |h, l| h - l)
    }

    /// The period of each axis: its extent if periodic, `0.0` if bounded.
    pub(crate) fn periods(&self) -> [f64; N] {
        zip_map(&self.extent(), &self.periodic, |l, periodic| {
            if periodic { l } else { 0.0 }
        })
    }

    /// The box's volume (length, area, …); may overflow to infinity for
    /// enormous boxes.
    pub fn volume(&self) -> f64 {
        self.extent().iter().product()
    }

    /// Whether `lo <= p < hi` on every axis.
    pub fn contains(&self, p: &[f64; N]) -> bool {
        p.iter()
            .zip(self.lo.iter().zip(&self.hi))
            .all(|(x, (lo, hi))| lo <= x && x < hi)
    }

    /// Whether no two points of the box can be `radius` apart, so that any
    /// one point is a maximal set: the largest distance between two points
    /// (the diagonal, with half the period on periodic axes) is below
    /// `radius` with a margin far above rounding.
    pub(crate) fn holds_one_point(&self, radius: f64) -> bool {
        let diameter_squared: f64 = self
            .extent()
            .iter()
            .zip(&self.periodic)
            .map(|(&e, &periodic)| if periodic { e / 2.0 } else { e })
            .map(|d| d * d)
            .sum();
        diameter_squared * (1.0 + 1e-9) < radius * radius
    }

    /// Whether every point within `reach` of `p` is inside the box, so that
    /// [`Self::wrap`] need not run for candidates thrown from `p`. Robust to
    /// rounding: it also asks for coordinates small against `reach` (under
    /// `2^40·reach`), so that `p + d` is within `reach·2⁻¹²` of its exact
    /// value, far inside the margin of `reach` it keeps from every face.
    #[inline(always)]
    pub(crate) fn holds_ball(&self, p: &[f64; N], reach: f64) -> bool {
        const SMALL: f64 = (1u64 << 40) as f64;
        p.iter()
            .zip(self.lo.iter().zip(&self.hi))
            .fold(true, |inside, (&x, (&lo, &hi))| {
                inside
                    & (x - lo >= 2.0 * reach)
                    & (hi - x >= 2.0 * reach)
                    & (x.abs() <= SMALL * reach)
            })
    }

    /// Maps a coordinate that left the box on a periodic axis back into it,
    /// and reports whether the point now lies inside. Bounded axes are only
    /// checked, never moved.
    #[inline(always)]
    pub(crate) fn wrap(&self, p: &mut [f64; N]) -> bool {
        for (((x, &lo), &hi), &periodic) in
            p.iter_mut().zip(&self.lo).zip(&self.hi).zip(&self.periodic)
        {
            if *x < lo || *x >= hi {
                if !periodic {
                    return false;
                }
                *x = lo + (*x - lo).rem_euclid(hi - lo);
                // Rounding can land exactly on `hi`: then the point is
                // dropped rather than moved, keeping the box half-open.
                if !(lo <= *x && *x < hi) {
                    return false;
                }
            }
        }
        true
    }
}

/// The unchecked form read by serde before [`Domain::new`] validates it.
/// `periodic` may be left out (no axis periodic, as [`Domain::new`]); any
/// other field is an error, so a misspelt `"periodc"` is not ignored.
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
#[serde(rename = "Domain", deny_unknown_fields)]
struct DomainRepr<const N: usize> {
    #[serde(with = "crate::serde_array")]
    lo: [f64; N],
    #[serde(with = "crate::serde_array")]
    hi: [f64; N],
    #[serde(with = "crate::serde_array", default = "all_bounded")]
    periodic: [bool; N],
}

/// The default of `periodic`: every axis bounded.
#[cfg(feature = "serde")]
fn all_bounded<const N: usize>() -> [bool; N] {
    [false; N]
}

#[cfg(feature = "serde")]
impl<const N: usize> TryFrom<DomainRepr<N>> for Domain<N> {
    type Error = Error;
    fn try_from(raw: DomainRepr<N>) -> Result<Self, Error> {
        Ok(Self::new(raw.lo, raw.hi)?.with_periodic(raw.periodic))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_keeps_points_half_open() {
        let d = Domain::new([0.0, 0.0], [1.0, 1.0])
            .unwrap()
            .with_periodic([true, false]);
        let mut p = [-0.25, 0.5];
        assert!(d.wrap(&mut p), "periodic axis wraps");
        assert_eq!(p, [0.75, 0.5], "wrapped by one period");
        let mut q = [1.5, 0.5];
        assert!(d.wrap(&mut q), "wraps from above");
        assert_eq!(q, [0.5, 0.5], "wrapped from above");
        let mut outside = [0.5, 1.0];
        assert!(!d.wrap(&mut outside), "bounded axis rejects hi");
        // -1e-300 + 1 rounds to exactly 1 = hi: must be rejected, not kept.
        let mut edge = [-1e-300, 0.5];
        assert!(!d.wrap(&mut edge), "rounding onto hi is rejected");
    }

    #[test]
    fn a_held_ball_keeps_every_near_point_inside() {
        use crate::random::{seeded_rng, symmetric_pair};
        // Parents all over a box (also far from the origin, where rounding
        // is coarse) and offsets up to just over 2r: whenever the ball test
        // passes, parent + offset lies inside.
        let r = 0.01;
        let mut rng = seeded_rng(8);
        for (lo, hi) in [([0.0, 0.0], [1.0, 1.0]), ([1e6, -3.0], [1e6 + 1.0, -2.0])] {
            let d = Domain::new(lo, hi).unwrap();
            let mut held = 0;
            for _ in 0..20_000 {
                let (a, b) = symmetric_pair(&mut rng);
                let p = [lo[0] + (a + 1.0) / 2.0, lo[1] + (b + 1.0) / 2.0];
                if !d.holds_ball(&p, 2.0 * r) {
                    continue;
                }
                held += 1;
                let (u, v) = symmetric_pair(&mut rng);
                let q = [p[0] + u * 2.0 * r * 1.01, p[1] + v * 2.0 * r * 1.01];
                assert!(d.contains(&q), "{p:?} + offset = {q:?}");
            }
            assert!(held > 10_000, "most parents are interior: {held}");
        }
        // Coordinates huge against r: never held, whatever the margins.
        let far = Domain::new([1e12], [1e12 + 1.0]).unwrap();
        assert!(!far.holds_ball(&[1e12 + 0.5], 1e-3), "coarse coordinates");
    }
}
