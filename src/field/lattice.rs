//! The field's lattice of level-0 cells: per axis an origin, a side and a
//! kind (bounded, periodic or unbounded), and the windows of cells a query
//! works in.

#![expect(
    clippy::indexing_slicing,
    reason = "indices are axes `< N` of `[_; N]` arrays"
)]

use crate::domain::Domain;
use crate::error::Error;

/// Level-0 cells are a little under `r/√N` on a side, so that a cell's
/// diagonal is below `r` by a margin far above rounding: two points in one
/// cell would be closer than `r`, so a cell holds at most one point.
const SIDE_SHRINK: f64 = 1.0 - 1.0 / (1u64 << 40) as f64;

/// The widest span of cells on one axis: coordinates up to 2⁴⁰ radii from
/// the origin keep `(i + u)·h` exact to far below the radius.
pub(crate) const MAX_CELLS: i64 = 1 << 41;

/// How one axis of the field is laid out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Axis {
    /// `lo <= x < hi`, cells `0..n` from `lo`, nothing outside.
    Bounded { lo: f64, hi: f64, n: i64 },
    /// `lo <= x < hi` with wrap-around: `n` cells of side `(hi - lo)/n`.
    Periodic { lo: f64, hi: f64, n: i64 },
    /// The whole line, cells from the absolute origin.
    Unbounded,
}

/// The lattice: per axis its layout, origin and cell side.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lattice<const N: usize> {
    pub(crate) axes: [Axis; N],
    pub(crate) origin: [f64; N],
    pub(crate) side: [f64; N],
}

/// The plain side: `r/√N` shrunk by [`SIDE_SHRINK`]. Correctly rounded
/// operations only (`sqrt` is), so the same on every machine.
fn plain_side<const N: usize>(radius: f64) -> f64 {
    #[expect(clippy::cast_precision_loss, reason = "a small dimension")]
    let n = N as f64;
    radius / n.sqrt() * SIDE_SHRINK
}

impl<const N: usize> Lattice<N> {
    /// The unbounded lattice: origin 0, side from `r` alone.
    pub(crate) fn unbounded(radius: f64) -> Self {
        Self {
            axes: [Axis::Unbounded; N],
            origin: [0.0; N],
            side: [plain_side::<N>(radius); N],
        }
    }

    /// The lattice of a box: cells from `lo`; a periodic axis has a whole
    /// number of cells per period.
    pub(crate) fn of_domain(domain: &Domain<N>, radius: f64) -> Result<Self, Error> {
        let h = plain_side::<N>(radius);
        let mut axes = [Axis::Unbounded; N];
        let mut side = [h; N];
        let (lo, hi, periodic) = (domain.lo(), domain.hi(), domain.periodic());
        for axis in 0..N {
            let (l, u) = (lo[axis], hi[axis]);
            let cells = ((u - l) / h).ceil();
            #[expect(clippy::cast_precision_loss, reason = "a power of two")]
            if cells.is_nan() || cells >= MAX_CELLS as f64 {
                return Err(Error::BoxTooWide { axis });
            }
            #[expect(clippy::cast_possible_truncation, reason = "a whole number under 2^41")]
            let n = (cells as i64).max(1);
            if periodic[axis] {
                #[expect(clippy::cast_precision_loss, reason = "n < 2^41")]
                let s = (u - l) / n as f64;
                side[axis] = s.min(h);
                axes[axis] = Axis::Periodic { lo: l, hi: u, n };
            } else {
                axes[axis] = Axis::Bounded { lo: l, hi: u, n };
            }
        }
        Ok(Self {
            axes,
            origin: lo,
            side,
        })
    }

    /// Coordinate `axis` of the point at fraction `t` (in cells, `t >= 0`
    /// within the cell's level-0 span) of level-0 cell `i`: one fixed
    /// formula, so every window computes the same bits.
    #[inline(always)]
    pub(crate) fn coord(&self, axis: usize, i: i64, t: f64) -> f64 {
        #[expect(clippy::cast_precision_loss, reason = "|i| < 2^41: exact")]
        let i = i as f64;
        self.origin[axis] + (i + t) * self.side[axis]
    }

    /// The canonical level-0 index of cell `i` on `axis`: wrapped into
    /// `0..n` on a periodic axis.
    #[inline(always)]
    pub(crate) fn canonical(&self, axis: usize, i: i64) -> i64 {
        match self.axes[axis] {
            Axis::Periodic { n, .. } => i.rem_euclid(n),
            _ => i,
        }
    }

    /// The level-0 cells `[a, b)` on each axis whose span meets the
    /// half-open interval `[lo, hi)`, with one cell of slack for rounding;
    /// `None` if the query box leaves the lattice's reach.
    pub(crate) fn cells_of(&self, lo: &[f64; N], hi: &[f64; N]) -> Option<([i64; N], [i64; N])> {
        let mut a = [0; N];
        let mut b = [0; N];
        for axis in 0..N {
            let s = self.side[axis];
            let fa = ((lo[axis] - self.origin[axis]) / s).floor() - 1.0;
            let fb = ((hi[axis] - self.origin[axis]) / s).floor() + 2.0;
            #[expect(clippy::cast_precision_loss, reason = "a power of two")]
            let limit = MAX_CELLS as f64;
            if !(fa.abs() < limit && fb.abs() < limit) {
                return None;
            }
            #[expect(clippy::cast_possible_truncation, reason = "checked above")]
            let (ia, ib) = (fa as i64, fb as i64);
            a[axis] = ia;
            b[axis] = ib;
        }
        Some((a, b))
    }

    /// Distance squared between two points of the lattice's space: on a
    /// periodic axis the difference is `min(|Δ|, L - |Δ|)`, axes summed in
    /// order.
    #[inline(always)]
    pub(crate) fn dist2(&self, a: &[f64; N], b: &[f64; N]) -> f64 {
        let mut s = 0.0;
        for axis in 0..N {
            let mut d = (a[axis] - b[axis]).abs();
            if let Axis::Periodic { lo, hi, .. } = self.axes[axis] {
                d = d.min((hi - lo) - d);
            }
            s += d * d;
        }
        s
    }

    /// Whether `x` lies in the domain on every bounded or periodic axis
    /// (`lo <= x < hi`).
    #[inline(always)]
    pub(crate) fn inside(&self, x: &[f64; N]) -> bool {
        self.axes.iter().zip(x).all(|(ax, &v)| match *ax {
            Axis::Bounded { lo, hi, .. } | Axis::Periodic { lo, hi, .. } => lo <= v && v < hi,
            Axis::Unbounded => true,
        })
    }
}
