//! The streaming window's background grid: Bridson's dense grid over the
//! few cell rows the sweep can still touch, in one flat array whose rows
//! slide down the image.
//!
//! Cells have side `1/c <= r/√2` (`c` cells per pixel, so cell rows line up
//! with pixel rows) and hold the point itself (`[f64; 2]`, or [`FAR`] when
//! empty): the window is small enough to sit in cache, so inline
//! coordinates save the batch grid's second load, and in 2-D about half the
//! cells are occupied. The rows live in a flat array with a fixed stride,
//! so a neighbour search is the batch grid's: linear offsets, nearest
//! first, with the stencil of the quarter of the cell the candidate lies in
//! (`grid::dense::Stencil`, the same construction and rounding margin).
//! Instead of addressing rows modulo the window height (a division per
//! cell), the array holds about twice the window's rows; when the window
//! reaches its end, the live rows are copied back to its start. That costs
//! one row copy per row of the image, amortised.

use crate::grid::dense::{Stencil, StencilShape, locate, parts, wide_seed};
use crate::vector::distance_squared;

/// An empty cell: a point at infinity, so the scan never branches on
/// emptiness.
pub(crate) const FAR: [f64; 2] = [f64::INFINITY; 2];

/// The bits of an empty cell's first coordinate (no point has it: points
/// are finite).
const FAR_X_BITS: u64 = f64::INFINITY.to_bits();

/// How many occupied cells [`RollingGrid::seed`] gathers at most (its 44
/// cells hold about 14 points).
const SEED_MAX: usize = 32;

/// Cells scanned together before branching on a conflict (as the batch
/// grid's `SCAN_CHUNK`).
const SCAN_CHUNK: usize = 8;

#[derive(Debug)]
pub(crate) struct RollingGrid {
    /// `rows × columns` cells; array row `a` holds global cell row
    /// `first + a - reach`.
    cells: Vec<[f64; 2]>,
    columns: usize,
    rows: usize,
    /// Cells searched on each side; also the padding, in cells, left, right
    /// and above the first live row.
    reach: usize,
    /// The global cell row at array row `reach`.
    first: usize,
    /// The array index of cell key 0 ([`Self::key`]), wrapping: `reach`
    /// rows and columns of padding, less the rows slid past.
    origin: usize,
    /// Cells per axis inside the raster.
    cells_x: usize,
    cells_y: usize,
    inv_side: f64,
    radius_squared: f64,
    /// Stencils of the four quarters of a cell.
    parts: Vec<Stencil>,
    /// The whole cell's stencil without the centre, in address order, as
    /// runs of adjacent cells `(first offset, length)`: the seed's cells,
    /// read a run (a slice) at a time, with one bounds check a run instead
    /// of a cell.
    seed_runs: Vec<(isize, usize)>,
    /// The cache lines of the block around a pick's parent that its
    /// candidates search first (`r` from the parent's cell, plus the
    /// reach): what [`Self::prefetch`] asks for.
    block: Block,
}

/// A square block of cells around a pick's cell, as [`RollingGrid::prefetch`]
/// walks it: `rows` rows of cells, the first at offset `first` from the
/// pick's cell, and in each row a cache line at each of the offsets
/// `lines` (no rows: no prefetch). Row by row, with the offsets along a
/// row fixed, a line costs an add and the hint: about 60 instructions a
/// pick for 21 lines, where a list of 21 offsets cost about 130
/// (`docs/performance-journal.md`).
#[derive(Debug, Default)]
struct Block {
    rows: usize,
    first: isize,
    lines: Vec<isize>,
}

impl RollingGrid {
    /// A grid for a raster of `cells_x × cells_y` cells of side `side`, of
    /// which at most `live_rows` rows are in use at once, searched `reach`
    /// cells around with rounding margin `eta`; with `prefetch`,
    /// [`Self::prefetch`] asks for a pick's cells. `None` if a size
    /// overflows.
    pub(crate) fn new(
        (cells_x, cells_y): (usize, usize),
        live_rows: usize,
        side: f64,
        (radius, reach, eta): (f64, usize, f64),
        prefetch: bool,
    ) -> Option<Self> {
        let (columns, rows) = Self::size(cells_x, live_rows, reach)?;
        let shape = StencilShape {
            reach: [reach; 2],
            side: [side; 2],
            eta,
            radius,
        };
        let stride = [1, columns];
        let full = Stencil::new(&shape, &stride, &[0, 0], 1)?;
        // The cells within `2r`, as the batch grid's 2-D seed, where the
        // reach is 2 (always, but for a raster of one or two cells a side,
        // or cells narrower than `r/√2`).
        let mut seed_offsets: Vec<isize> = if reach == 2 {
            wide_seed(&stride)?
        } else {
            full.offsets.iter().copied().filter(|&o| o != 0).collect()
        };
        seed_offsets.sort_unstable();
        let seed_runs = runs(&seed_offsets);
        // Within the L2 cache, a pick's cells are near at hand already and
        // their prefetch only costs instructions.
        let block = if prefetch {
            block(radius, side, reach, columns)
        } else {
            Block::default()
        };
        let count = parts(2) * parts(2);
        let parts = (0..count)
            .map(|k| Stencil::new(&shape, &stride, &[k % parts(2), k / parts(2)], parts(2)))
            .collect::<Option<Vec<_>>>()?;
        Some(Self {
            cells: vec![FAR; columns.checked_mul(rows)?],
            columns,
            rows,
            reach,
            first: 0,
            origin: origin(reach, columns, 0),
            cells_x,
            cells_y,
            inv_side: 1.0 / side,
            radius_squared: radius * radius,
            parts,
            seed_runs,
            block,
        })
    }

    /// A grid with no cells, where nothing conflicts and nothing can be
    /// stored: what [`Self::new`]'s caller falls back to if a size it
    /// checked beforehand still fails (it cannot), so that the stream ends
    /// empty instead of panicking.
    pub(crate) fn empty() -> Self {
        Self {
            cells: Vec::new(),
            columns: 0,
            rows: 0,
            reach: 0,
            first: 0,
            origin: 0,
            cells_x: 1,
            cells_y: 1,
            inv_side: 1.0,
            radius_squared: 0.0,
            parts: Vec::new(),
            seed_runs: Vec::new(),
            block: Block::default(),
        }
    }

    /// Columns and array rows: the live rows and their padding, and half
    /// as many again, so that a copy back is needed once per half a
    /// window of rows: about two rows copied per row of the image, which
    /// is cheap next to sampling it, where doubling would cost memory
    /// (16 MB more at 16 384 pixels wide and 4 a pixel).
    fn size(cells_x: usize, live_rows: usize, reach: usize) -> Option<(usize, usize)> {
        let columns = cells_x.checked_add(reach.checked_mul(2)?)?;
        let padded = live_rows.checked_add(reach.checked_mul(2)?)?;
        let rows = padded.checked_add(padded / 2 + 1)?;
        Some((columns, rows))
    }

    /// Heap bytes of a grid built with these sizes (cells and stencils; the
    /// stencils are bounded by the `(2·reach + 1)²` block they are cut
    /// from, as the batch grid counts them).
    pub(crate) fn bytes(cells_x: usize, live_rows: usize, reach: usize) -> Option<u64> {
        let (columns, rows) = Self::size(cells_x, live_rows, reach)?;
        let cells = columns
            .checked_mul(rows)?
            .checked_mul(size_of::<[f64; 2]>())?;
        let side = reach.checked_mul(2)?.checked_add(1)?;
        let block = side.checked_mul(side)?;
        let per_cell = usize::try_from(crate::grid::dense::stencil_bytes_per_cell(2)).ok()?;
        let stencils = block.checked_mul(per_cell)?;
        u64::try_from(cells.checked_add(stencils)?).ok()
    }

    /// Makes global cell rows from `row` on addressable, with every row
    /// up to `row + live_rows` (plus the search reach) in the array,
    /// copying the rows still needed to the array's start when the window
    /// has slid past its end. Rows above `row` are no longer needed.
    pub(crate) fn slide_to(&mut self, row: usize, live_rows: usize) {
        // One past the last global row the array holds.
        let end = self.first + self.rows - self.reach;
        if row <= self.first || row + live_rows + self.reach <= end {
            return;
        }
        // Drop the array rows above `row - reach`; the rest move up.
        let start = (row - self.first).saturating_mul(self.columns);
        let kept = self.cells.len().saturating_sub(start);
        if kept > 0 {
            self.cells.copy_within(start.., 0);
        }
        if let Some(rest) = self.cells.get_mut(kept..) {
            rest.fill(FAR);
        }
        self.first = row;
        self.origin = origin(self.reach, self.columns, row);
    }

    /// The array index of cell `(cx, cy)` (global), or `usize::MAX` if it
    /// is above the array.
    #[inline(always)]
    fn index(&self, cx: usize, cy: usize) -> usize {
        match (cy + self.reach).checked_sub(self.first) {
            Some(a) => a * self.columns + cx + self.reach,
            None => usize::MAX,
        }
    }

    /// The key of `p`'s cell (a point inside the raster): its global cell
    /// numbered row by row, `cy·columns + cx`, wrapping. Unlike an array
    /// index it stays valid as the rows slide: the candidate's search finds
    /// it for the insert, and the sweep's queue names its points by it.
    #[inline(always)]
    pub(crate) fn key(&self, p: &[f64; 2]) -> usize {
        let (cx, cy, _) = self.locate(p);
        self.key_of(cx, cy)
    }

    /// The key of global cell `(cx, cy)`.
    #[inline(always)]
    fn key_of(&self, cx: usize, cy: usize) -> usize {
        cy.wrapping_mul(self.columns).wrapping_add(cx)
    }

    /// The array index of the cell with key `key` (wrapping: a cell above
    /// the array wraps below zero, past the array's end).
    #[inline(always)]
    fn at(&self, key: usize) -> usize {
        key.wrapping_add(self.origin)
    }

    /// The global cell of a point inside the raster, and the quarter of the
    /// cell it lies in.
    #[inline(always)]
    fn locate(&self, p: &[f64; 2]) -> (usize, usize, usize) {
        let last = [self.cells_x, self.cells_y].map(|m| m.saturating_sub(1));
        let ([cx, cy], part) = locate(p, &[0.0; 2], &[self.inv_side; 2], &last, parts(2));
        (cx, cy, part)
    }

    /// A stored point closer than `r` to `p` (inside the raster, in a row
    /// the window holds), if any: the nearest cells first, eight at a time.
    /// Also `p`'s cell key ([`Self::key`]), found on the way.
    #[inline(always)]
    pub(crate) fn conflict(&self, p: &[f64; 2]) -> (usize, Option<[f64; 2]>) {
        let (cx, cy, part) = self.locate(p);
        let key = self.key_of(cx, cy);
        let base = self.at(key);
        let Some(stencil) = self.parts.get(part) else {
            return (key, None);
        };
        for chunk in stencil.offsets.chunks(SCAN_CHUNK) {
            let mut hit = false;
            for &off in chunk {
                let q = self
                    .cells
                    .get(base.wrapping_add_signed(off))
                    .unwrap_or(&FAR);
                hit |= distance_squared(p, q) < self.radius_squared;
            }
            if hit {
                let found = chunk
                    .iter()
                    .filter_map(|&off| self.cells.get(base.wrapping_add_signed(off)))
                    .find(|q| distance_squared(p, q) < self.radius_squared)
                    .copied();
                return (key, found);
            }
        }
        (key, None)
    }

    /// Hands the points of the cells around `p` (up to `limit`) to `take`:
    /// its nearest neighbours, which turn away most of its candidates. Two
    /// passes, as the batch grid's seed: the occupied cells' points in
    /// address order without a branch (whether a cell is empty is a coin
    /// toss the predictor loses), then those points. `key` is `p`'s cell's
    /// ([`Self::key`]).
    #[inline(always)]
    pub(crate) fn seed(&self, key: usize, limit: usize, mut take: impl FnMut(&[f64; 2])) {
        let base = self.at(key);
        let mut found = [FAR; SEED_MAX];
        let mut n = 0;
        for &(first, len) in &self.seed_runs {
            let start = base.wrapping_add_signed(first);
            // A run past the padding (the seed reads 3 cells out, the
            // padding is 2) reads another row's cells or none: real points
            // or nothing, which the cache takes without changing a decision.
            let Some(run) = self.cells.get(start..start.saturating_add(len)) else {
                continue;
            };
            for q in run {
                // Past SEED_MAX occupied cells, later ones overwrite earlier
                // ones: any subset suits the cache.
                if let Some(slot) = found.get_mut(n % SEED_MAX) {
                    *slot = *q;
                }
                // Empty is infinity, compared by its bits: one integer
                // compare, where `!=` on floats also tests for NaN.
                n += usize::from(q[0].to_bits() != FAR_X_BITS);
            }
        }
        for q in found.iter().take(n.min(limit)) {
            take(q);
        }
    }

    /// Asks for the cells a pick around the point with cell key `key`
    /// ([`Self::key`]) reads first: the sweep picks its next parent anywhere
    /// along the front, whose width can put the window's live rows past the
    /// nearest caches; its candidates, up to `2r` away, search cells up to
    /// `2r` plus the reach from it, of which the inner block (`r` plus the
    /// reach) is fetched.
    #[inline(always)]
    pub(crate) fn prefetch(&self, key: usize) {
        if self.block.rows == 0 {
            return;
        }
        let mut row = self.at(key).wrapping_add_signed(self.block.first);
        let cells = &self.cells;
        let ask = |at: usize| crate::prefetch::prefetch(cells, at);
        match *self.block.lines.as_slice() {
            // At r/√2 cells: seven cells a row, three lines.
            [a, b, c] => {
                for _ in 0..self.block.rows {
                    ask(row.wrapping_add_signed(a));
                    ask(row.wrapping_add_signed(b));
                    ask(row.wrapping_add_signed(c));
                    row = row.wrapping_add(self.columns);
                }
            }
            ref lines => {
                for _ in 0..self.block.rows {
                    for &line in lines {
                        ask(row.wrapping_add_signed(line));
                    }
                    row = row.wrapping_add(self.columns);
                }
            }
        }
    }

    /// Hands the cells of each cell row that covers pixel row `y` to
    /// `take`, a slice a row, top to bottom, empty cells ([`FAR`]) and the
    /// points of the neighbouring pixel rows included: the caller filters.
    pub(crate) fn for_each_row_of(&self, y: usize, mut take: impl FnMut(&[[f64; 2]])) {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            clippy::cast_precision_loss,
            reason = "saturating casts of non-negative rows, clamped"
        )]
        let (lo, hi) = (
            ((y as f64 * self.inv_side) as usize).min(self.cells_y - 1),
            (((y + 1) as f64 * self.inv_side) as usize).min(self.cells_y - 1),
        );
        for cy in lo..=hi {
            // The row's first (padding) cell; `usize::MAX` above the array.
            if let Some(cells) = self
                .index(0, cy)
                .checked_sub(self.reach)
                .and_then(|a| self.cells.get(a..a.checked_add(self.columns)?))
            {
                take(cells);
            }
        }
    }

    /// The point stored in the cell with key `key` ([`Self::key`]), or
    /// [`FAR`] if the cell is empty or outside the array.
    #[inline(always)]
    pub(crate) fn point(&self, key: usize) -> [f64; 2] {
        self.cells.get(self.at(key)).copied().unwrap_or(FAR)
    }

    /// Stores `p` in its cell, over whatever the cell held: exact mode's
    /// darts, whose cell can only hold a point thinned out (any two points
    /// in one cell are closer than `r`, and a dart keeps `r` from every
    /// point that stays).
    pub(crate) fn replace(&mut self, p: [f64; 2]) {
        let (cx, cy, _) = self.locate(&p);
        let index = self.index(cx, cy);
        if let Some(cell) = self.cells.get_mut(index) {
            *cell = p;
        }
    }

    /// Stores `p` in its cell, whose key ([`Self::key`]) is `key`; `false`
    /// (storing nothing) if the cell is taken, which only rounding can
    /// cause, or lies outside the array.
    #[inline(always)]
    pub(crate) fn insert(&mut self, p: [f64; 2], key: usize) -> bool {
        let index = self.at(key);
        match self.cells.get_mut(index) {
            Some(cell) if cell[0] == f64::INFINITY => {
                *cell = p;
                true
            }
            _ => false,
        }
    }
}

/// Sorted `offsets` as runs of consecutive values, `(first, length)`.
fn runs(offsets: &[isize]) -> Vec<(isize, usize)> {
    let mut runs: Vec<(isize, usize)> = Vec::new();
    for &off in offsets {
        match runs.last_mut() {
            Some((first, len))
                if first
                    .checked_add_unsigned(*len)
                    .is_some_and(|end| end == off) =>
            {
                *len += 1;
            }
            _ => runs.push((off, 1)),
        }
    }
    runs
}

/// The array index of cell key 0 when global cell row `first` sits at
/// array row `reach`: `reach` padding columns and `reach - first` rows in,
/// wrapping.
fn origin(reach: usize, columns: usize, first: usize) -> usize {
    reach
        .wrapping_sub(first)
        .wrapping_mul(columns)
        .wrapping_add(reach)
}

/// The cache lines (64 bytes, 4 cells) covering the square of cells a
/// pick's first candidates search: `r/side + reach` cells on each side of
/// the parent's, about the inner half of the `2r` its candidates reach.
/// Asking for the whole `2r` square (44 lines a pick) cost more in
/// instructions than it saved in misses (`docs/performance-journal.md`).
fn block(radius: f64, side: f64, reach: usize, columns: usize) -> Block {
    const CELLS_PER_LINE: usize = 64 / size_of::<[f64; 2]>();
    let span = (radius / side).floor();
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a few cells: r / side = √2"
    )]
    let half = (span as usize).saturating_add(reach).min(columns / 2);
    let (Ok(half_i), Ok(columns_i)) = (isize::try_from(half), isize::try_from(columns)) else {
        return Block::default();
    };
    let step = isize::try_from(CELLS_PER_LINE).unwrap_or(1);
    let mut lines = Vec::new();
    let mut dx = -half_i;
    while dx <= half_i {
        lines.push(dx);
        dx += step;
    }
    lines.push(half_i);
    Block {
        rows: half.saturating_mul(2).saturating_add(1),
        first: -half_i.saturating_mul(columns_i),
        lines,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{below, seeded_rng, unit};

    /// Over many slides, so that the rows are copied back to the array's
    /// start many times: every search answers as a brute-force scan of the
    /// stored points does; a seed hands on only points the grid was given,
    /// none more than 3 cells from the candidate's on either axis (it may
    /// read rows the live ones no longer need, which the array keeps until
    /// it slides); a gathered row holds exactly its points; and a row slid
    /// past leaves nothing behind.
    #[test]
    fn the_window_answers_as_a_brute_force_scan_as_it_slides() {
        let (radius, side, reach, live_rows) = (0.39, 0.25, 2, 9);
        let (cells_x, cells_y) = (24, 2_000);
        let mut grid = RollingGrid::new(
            (cells_x, cells_y),
            live_rows,
            side,
            (radius, reach, 1e-9),
            false,
        )
        .unwrap();
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "points of the raster: small non-negative rows"
        )]
        let row_of = |p: &[f64; 2]| (p[1] / side).floor() as usize;
        let mut rng = seeded_rng(7);
        let mut stored: Vec<[f64; 2]> = Vec::new();
        let mut given: Vec<[f64; 2]> = Vec::new();
        let (mut found, mut kept) = (0, 0);
        for first in 0..1_500 {
            grid.slide_to(first, live_rows);
            stored.retain(|p| row_of(p) + reach >= first);
            for _ in 0..8 {
                // A candidate in a live row.
                let cy = first + below(&mut rng, live_rows);
                let c = [
                    unit(&mut rng) * cells_x as f64 * side,
                    (cy as f64 + unit(&mut rng)) * side,
                ];
                let near = stored
                    .iter()
                    .any(|q| distance_squared(&c, q) < radius * radius);
                let (key, hit) = grid.conflict(&c);
                assert_eq!(hit.is_some(), near, "at {c:?}, first row {first}");
                assert_eq!(key, grid.key(&c));
                let mut seeds = Vec::new();
                grid.seed(key, SEED_MAX, |q| seeds.push(*q));
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "cells of the raster: small numbers"
                )]
                let cell = |p: &[f64; 2]| p.map(|x| (x / side).floor() as i64);
                let [cx, cy] = cell(&c);
                assert!(
                    seeds.iter().all(|q| given.contains(q)
                        && (cell(q)[0] - cx).abs() <= 3
                        && (cell(q)[1] - cy).abs() <= 3),
                    "{seeds:?} around {c:?}"
                );
                if near {
                    found += 1;
                } else {
                    if kept % 5 == 0 {
                        grid.replace(c);
                    } else {
                        assert!(grid.insert(c, key));
                    }
                    kept += 1;
                    stored.push(c);
                    given.push(c);
                }
            }
            // The pixel row at the top of the live rows, gathered.
            let y = first.div_ceil(4);
            let (lo, hi) = (4 * y, (4 * y + 4).min(cells_y - 1));
            if hi < first + live_rows {
                let mut gathered = Vec::new();
                grid.for_each_row_of(y, |cells| {
                    gathered.extend(cells.iter().filter(|q| q[0].is_finite()));
                });
                let mut expected: Vec<[f64; 2]> = stored
                    .iter()
                    .filter(|p| (lo..=hi).contains(&row_of(p)))
                    .copied()
                    .collect();
                let order =
                    |a: &[f64; 2], b: &[f64; 2]| a[1].total_cmp(&b[1]).then(a[0].total_cmp(&b[0]));
                gathered.sort_by(order);
                expected.sort_by(order);
                assert_eq!(gathered, expected, "pixel row {y}");
            }
        }
        // Both kinds of answer, many times over.
        assert!(found > 1_000 && kept > 1_000, "{found} found, {kept} kept");
    }

    #[test]
    fn runs_split_sorted_offsets_where_they_jump() {
        assert_eq!(
            runs(&[-9, -8, -7, -1, 1, 2, 3, 40]),
            [(-9, 3), (-1, 1), (1, 3), (40, 1)]
        );
        assert_eq!(runs(&[]), []);
    }

    /// The seed reads its cells a run at a time: the same cells, in the
    /// same (address) order, as offset by offset: the batch grid's 2-D
    /// seed (the cells within `2r`), which holds the whole search stencil.
    #[test]
    fn seed_runs_cover_the_seed_cells_in_address_order() {
        let side = 0.39 * core::f64::consts::FRAC_1_SQRT_2;
        let grid = RollingGrid::new((40, 40), 20, side, (0.39, 2, 1e-9), false).unwrap();
        let cells: Vec<isize> = grid
            .seed_runs
            .iter()
            .flat_map(|&(first, len)| (0..len).map(move |k| first + k as isize))
            .collect();
        let full = {
            let shape = StencilShape {
                reach: [2; 2],
                side: [side; 2],
                eta: 1e-9,
                radius: 0.39,
            };
            Stencil::new(&shape, &[1, grid.columns], &[0, 0], 1).unwrap()
        };
        let mut expected = wide_seed(&[1, grid.columns]).unwrap();
        expected.sort_unstable();
        assert_eq!(expected.len(), 44, "{expected:?}");
        assert_eq!(cells, expected);
        assert!(
            full.offsets.iter().all(|o| *o == 0 || expected.contains(o)),
            "the search stencil is inside"
        );
    }
}
