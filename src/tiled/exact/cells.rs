//! The band's local grid: its live points sorted by cells about half the
//! elimination's search distance wide, and the searches over it
//! (elimination's neighbours, a top-up's nearest point) and over the few
//! pixels around a dart.

use super::{Exact, columns_around};

impl Exact {
    /// The local grid cell of `p` (band row `y` at the top).
    fn cell_of(&self, p: &[f64; 2], y: usize, width: usize, band_rows: usize) -> (usize, usize) {
        #[expect(clippy::cast_precision_loss, reason = "small counts")]
        let (m, top) = (self.cells as f64, y as f64);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "saturating casts, clamped to the band"
        )]
        let cx = ((p[0] * m) as usize).min(width * self.cells - 1);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "saturating casts, clamped to the band"
        )]
        let cy = (((p[1] - top) * m).max(0.0) as usize).min(band_rows * self.cells - 1);
        (cx, cy)
    }

    /// Sorts the live points by local grid cell (a counting sort).
    pub(super) fn index_cells(&mut self, y: usize, width: usize, band_rows: usize) {
        self.indexed = true;
        let columns = width * self.cells;
        let cells = columns * band_rows * self.cells;
        // Each point's cell, or `usize::MAX` for a dead one.
        let mut cell_of = core::mem::take(&mut self.cell_of);
        cell_of.clear();
        cell_of.extend(self.points.iter().zip(&self.alive).map(|(p, &alive)| {
            if alive {
                let (cx, cy) = self.cell_of(p, y, width, band_rows);
                cy * columns + cx
            } else {
                usize::MAX
            }
        }));
        // A counting sort: each cell's count at its own index, summed into
        // its end, then the points placed from the last one back, each
        // cell's end moving down to its start (so a cell keeps its points
        // in index order, and `cell_start[cells]` stays the total).
        let starts = &mut self.cell_start;
        starts.clear();
        starts.resize(cells + 1, 0);
        for &c in &cell_of {
            if let Some(count) = starts.get_mut(c) {
                *count += 1;
            }
        }
        let mut sum = 0;
        for s in starts.iter_mut() {
            sum += *s;
            *s = sum;
        }
        self.cell_items.clear();
        self.cell_items.resize(sum, 0);
        for (i, &c) in cell_of.iter().enumerate().rev() {
            if let Some(end) = starts.get_mut(c) {
                *end -= 1;
                #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
                if let Some(slot) = self.cell_items.get_mut(*end) {
                    *slot = i as u32;
                }
            }
        }
        self.cell_of = cell_of;
    }

    /// Calls `visit` with the index of every gathered band point (dead
    /// ones included, darts not) in the band pixels of columns `x - 1` to
    /// `x + 1`, until it returns `false`: all that can lie within `r` of a point of column `x` in row
    /// `y`, as `r < 1`. The darts' search: a short pixel's darts look
    /// through these few pixels' points directly, where sorting the band
    /// into the local grid first cost more (3 % of exact mode's
    /// instructions at `n = 4`, random dropping).
    pub(super) fn near_pixel(
        &self,
        x: usize,
        width: usize,
        band_rows: usize,
        mut visit: impl FnMut(u32) -> bool,
    ) {
        let columns = columns_around(x, width);
        for row in 0..band_rows {
            let first = row * width + columns.start();
            let last = row * width + columns.end();
            let (Some(&a), Some(&b)) = (self.start.get(first), self.start.get(last + 1)) else {
                continue;
            };
            #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
            for i in a..b {
                if !visit(i as u32) {
                    return;
                }
            }
        }
    }

    /// Calls `visit` with the index of every point indexed in the local
    /// grid within `cell_reach` cells of `p`'s cell (dead ones included:
    /// points die after indexing).
    pub(super) fn near(
        &self,
        p: &[f64; 2],
        y: usize,
        width: usize,
        band_rows: usize,
        mut visit: impl FnMut(u32),
    ) {
        let (cx, cy) = self.cell_of(p, y, width, band_rows);
        let columns = width * self.cells;
        let rows = band_rows * self.cells;
        let k = self.cell_reach;
        for yy in cy.saturating_sub(k)..=(cy + k).min(rows - 1) {
            let first = yy * columns + cx.saturating_sub(k);
            let last = yy * columns + (cx + k).min(columns - 1);
            let (Some(&a), Some(&b)) = (self.cell_start.get(first), self.cell_start.get(last + 1))
            else {
                continue;
            };
            for &i in self.cell_items.get(a..b).unwrap_or(&[]) {
                visit(i);
            }
        }
    }
}
