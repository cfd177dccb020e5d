//! The varying radius's coarse grid: cells of side `r_max` (slightly more),
//! so that two points closer than `r_max` are never more than one cell
//! apart on an axis. Both indexes hang their per-cell data on it: the lists
//! of [`Lists`](super::lists::Lists), the level masks and largest radii of
//! [`Levels`](super::levels::Levels).

use crate::domain::Domain;
use crate::error::Error;

/// Cells are this much wider than `r_max`, so that a pair closer than
/// `r_max` is never more than one cell apart on an axis, whatever the
/// rounding of the cell index (its error is far below 1e-6 of a cell with
/// at most [`MAX_CELLS_PER_AXIS`] cells, multiplied by a rounded inverse
/// of the side).
const CELL_SLACK: f64 = 1.0 + 1e-6;
/// The most cells on one axis.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 20) as f64;

#[derive(Debug)]
pub(super) struct Coarse<const N: usize> {
    lo: [f64; N],
    /// `1 / side`, where the side is `r_max·(1 + 1e-6)`.
    inv_side: f64,
    cells_per_axis: [u32; N],
    periodic: [bool; N],
    /// The 3^N neighbours of a cell away from every face, as linear
    /// offsets, its own first.
    deltas: Vec<isize>,
    /// Of those, the ones not offset along axis 0: the middles of the
    /// 3^(N-1) rows of three cells.
    rows: Vec<isize>,
    /// Cells in all.
    count: usize,
}

impl<const N: usize> Coarse<N> {
    /// The grid over `domain` for radii up to `r_max`.
    ///
    /// # Errors
    /// [`Error::BoxTooWide`] past 2²⁰ cells on an axis;
    /// [`Error::GridTooLarge`] if the cell count overflows.
    pub(super) fn new(domain: &Domain<N>, r_max: f64) -> Result<Self, Error> {
        let side = r_max * CELL_SLACK;
        let mut cells_per_axis = [1u32; N];
        for (axis, (count, extent)) in cells_per_axis.iter_mut().zip(domain.extent()).enumerate() {
            let cells = (extent / side).floor();
            if cells.is_nan() || cells > MAX_CELLS_PER_AXIS {
                return Err(Error::BoxTooWide { axis });
            }
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a whole number in 0..=2^20"
            )]
            let whole = cells as u32;
            *count = whole.max(1);
        }
        let count = cells_per_axis
            .iter()
            .try_fold(1_usize, |n, &m| n.checked_mul(m as usize))
            .ok_or(Error::GridTooLarge {
                needed: u64::MAX,
                budget: 0,
            })?;
        let mut deltas = Vec::new();
        let mut rows = Vec::new();
        for t in 0..3_usize.pow(u32::try_from(N).unwrap_or(0)) {
            if t % 3 == 0 {
                // Digit 0 of axis 0: no offset along it.
                rows.push(t);
            }
            let (mut digits, mut delta, mut stride) = (t, 0_isize, 1_isize);
            for &m in &cells_per_axis {
                // Digit 0 is offset 0, so that t = 0 is the cell itself.
                let o = match digits % 3 {
                    0 => 0,
                    1 => 1,
                    _ => -1,
                };
                digits /= 3;
                delta += o * stride;
                stride = stride.saturating_mul(isize::try_from(m).unwrap_or(isize::MAX));
            }
            deltas.push(delta);
        }
        let rows = rows
            .into_iter()
            .filter_map(|t| deltas.get(t).copied())
            .collect();
        Ok(Self {
            lo: domain.lo(),
            inv_side: 1.0 / side,
            cells_per_axis,
            periodic: domain.periodic(),
            deltas,
            rows,
            count,
        })
    }

    /// How many cells the grid has.
    pub(super) const fn count(&self) -> usize {
        self.count
    }

    /// The cell of a point of the box (clamped against rounding).
    pub(super) fn cell_of(&self, p: &[f64; N]) -> [u32; N] {
        let mut cell = [0u32; N];
        let axes = p.iter().zip(&self.lo).zip(&self.cells_per_axis);
        for (c, ((&x, &l), &m)) in cell.iter_mut().zip(axes) {
            // Through i64, saturating (truncation is the floor: `x >= l`
            // in the box), then clamped: no libm `floor` call.
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a saturating cast, clamped to 0..m, m <= 2^20"
            )]
            let i = (((x - l) * self.inv_side) as i64).clamp(0, i64::from(m - 1)) as u32;
            *c = i;
        }
        cell
    }

    /// The linear index of a cell (axis 0 fastest).
    pub(super) fn linear(&self, cell: &[u32; N]) -> usize {
        cell.iter()
            .zip(&self.cells_per_axis)
            .rev()
            .fold(0, |acc, (&c, &m)| acc * m as usize + c as usize)
    }

    /// The linear index of the middle cell of each row of three (along
    /// axis 0) around `cell`, away from the faces: what a prefetch of the
    /// data hung on the 3^N cells around asks for (near a face, indices
    /// that may lie outside the grid, which a prefetch ignores).
    pub(super) fn rows_around(&self, cell: &[u32; N]) -> impl Iterator<Item = usize> + '_ {
        let base = self.linear(cell);
        self.rows.iter().map(move |&d| base.wrapping_add_signed(d))
    }

    /// Calls `f` on the linear index of each of the (up to) 3^N cells
    /// around `cell`, its own first, each once, until `f` returns `Some`:
    /// periodic axes wrap, bounded ones stop at the faces.
    #[inline]
    pub(super) fn find_around<T>(
        &self,
        cell: &[u32; N],
        mut f: impl FnMut(usize) -> Option<T>,
    ) -> Option<T> {
        // Away from every face, the neighbours are fixed offsets.
        let inner = cell
            .iter()
            .zip(&self.cells_per_axis)
            .all(|(&c, &m)| c >= 1 && c + 2 <= m);
        let base = self.linear(cell);
        if inner {
            for &delta in &self.deltas {
                if let Some(found) = base.checked_add_signed(delta).and_then(&mut f) {
                    return Some(found);
                }
            }
            return None;
        }
        let neighbourhood = 3_usize.pow(u32::try_from(N).unwrap_or(u32::MAX));
        'cells: for t in 0..neighbourhood {
            let mut at = [0u32; N];
            // Digit 1 is offset 0: shifting by the centre's index visits the
            // centre cell first.
            let mut digits = (t + neighbourhood / 2) % neighbourhood;
            let axes = cell.iter().zip(&self.cells_per_axis).zip(&self.periodic);
            for (slot, ((&c, &m), &periodic)) in at.iter_mut().zip(axes) {
                // The offset on this axis, -1, 0 or 1.
                let o = i64::try_from(digits % 3).unwrap_or(0) - 1;
                digits /= 3;
                let (c, m) = (i64::from(c), i64::from(m));
                let j = if periodic {
                    // Fewer than 3 cells around: each is visited once.
                    if (m == 1 && o != 0) || (m == 2 && o == -1) {
                        continue 'cells;
                    }
                    (c + o).rem_euclid(m)
                } else {
                    c + o
                };
                let Ok(j) = u32::try_from(j) else {
                    continue 'cells;
                };
                if i64::from(j) >= m {
                    continue 'cells;
                }
                *slot = j;
            }
            if let Some(found) = f(self.linear(&at)) {
                return Some(found);
            }
        }
        None
    }
}
