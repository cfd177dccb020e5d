//! The rolling window of the streaming mode: the few pixel rows around the
//! current one, with their points, their active points and a background
//! grid, in ring buffers that are reused as the scan moves down the image.
//!
//! Memory is proportional to the image width times the window height
//! (`ceil(r)` rows above the current row for the minimum-distance checks,
//! the current row, and `ceil(8r) + 1` rows below for points made ahead of
//! their pixel, each count capped at the image height; see
//! `WindowPlan::new`), never to the image height.

use crate::grid::rounding_margin;
use crate::vector::distance_squared;

/// An empty grid cell: a point at infinity, so the scan never branches on
/// emptiness (as in the dense batch grid).
const FAR: [f64; 2] = [f64::INFINITY; 2];

/// Points and active points of one pixel, in generation order.
#[derive(Debug, Default, Clone)]
pub(crate) struct Slot {
    /// Points not yet handed out (emptied when the pixel is emitted).
    pub(crate) points: Vec<[f64; 2]>,
    pub(crate) active: Vec<[f64; 2]>,
    /// Points ever stored in the pixel, emitted or not.
    pub(crate) count: usize,
    /// Exact mode: the pixel's final points, kept after emission for the
    /// next rows' elimination weights.
    pub(crate) kept: Vec<[f64; 2]>,
}

/// Geometry of the window, decided (and checked) up front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WindowPlan {
    pub(crate) width: usize,
    pub(crate) height: usize,
    /// Grid cells per pixel side: the cell side is `1 / cells_per_pixel`,
    /// at most `r / √2`, and cell rows line up with pixel rows.
    pub(crate) cells_per_pixel: usize,
    /// Pixel rows kept above the current one.
    pub(crate) rows_above: usize,
    /// Pixel rows kept below the current one.
    pub(crate) rows_below: usize,
    /// Cells searched on each side of a candidate's cell.
    pub(crate) reach: usize,
    /// Rounding margin on cell indices, in cells.
    pub(crate) eta: f64,
    pub(crate) bytes: u64,
}

impl WindowPlan {
    /// `None` if a size overflows.
    pub(crate) fn new(width: usize, height: usize, radius: f64) -> Option<Self> {
        // Cells per pixel: the smallest c with 1/c <= r/√2.
        let c = (core::f64::consts::SQRT_2 / radius).ceil().max(1.0);
        if c.is_nan() || c > 65_536.0 {
            return None;
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "1 <= c <= 65536"
        )]
        let cells_per_pixel = c as usize;
        let whole = |x: f64| -> Option<usize> {
            if (0.0..=1e9).contains(&x) {
                #[expect(
                    clippy::cast_possible_truncation,
                    clippy::cast_sign_loss,
                    reason = "checked to be in 0..=1e9"
                )]
                let n = x.ceil() as usize;
                Some(n)
            } else {
                None
            }
        };
        let rows_above = whole(radius)?.min(height);
        // The sweep works keys up to y + 1 + 2r + J (J = 4r) while finishing
        // row y; such a parent lies at most J below its key, and its children
        // 2r below it: 8r below the row, plus the row itself.
        let rows_below = (whole(8.0 * radius)? + 1).min(height);
        let side = 1.0 / c;
        // Rounding margin on the cell index, as for the batch grid.
        #[expect(clippy::cast_precision_loss, reason = "a bound, not a count")]
        let eta = rounding_margin(width.max(height) as f64 * c);
        // Beyond the raster there is nothing to find: the reach never needs
        // to exceed it, which also bounds the stencil for huge radii.
        let raster_cells = width.max(height).checked_mul(cells_per_pixel)?;
        let reach = whole(radius / side + eta)?.min(raster_cells);
        let columns = width.checked_mul(cells_per_pixel)?.checked_add(2 * reach)?;
        let ring_rows = rows_above.checked_add(rows_below)?.checked_add(1)?;
        let cell_rows = ring_rows.checked_mul(cells_per_pixel)?;
        let cells = columns.checked_mul(cell_rows)?;
        let grid_bytes = cells.checked_mul(size_of::<[f64; 2]>())?;
        let slot_bytes = width
            .checked_mul(ring_rows)?
            .checked_mul(size_of::<Slot>())?;
        // The cell stencil and the table of nearby pixels (both squares of
        // their reach) are allocated too; a huge radius on a wide raster
        // must be an error, not an abort.
        let side_cells = reach.checked_mul(2)?.checked_add(1)?;
        let stencil_bytes =
            side_cells
                .checked_mul(side_cells)?
                .checked_mul(size_of::<(f64, usize, isize, isize)>())?;
        let near = whole(2.0 * radius)?.min(width.max(height));
        let near_side = near.checked_mul(2)?.checked_add(1)?;
        let near_bytes = near_side
            .checked_mul(near_side)?
            .checked_mul(size_of::<(isize, isize)>())?;
        let bytes = grid_bytes
            .checked_add(slot_bytes)?
            .checked_add(stencil_bytes)?
            .checked_add(near_bytes)?;
        let bytes = u64::try_from(bytes).ok()?;
        Some(Self {
            width,
            height,
            cells_per_pixel,
            rows_above,
            rows_below,
            reach,
            eta,
            bytes,
        })
    }

    fn ring_rows(&self) -> usize {
        self.rows_above + self.rows_below + 1
    }
}

/// The rolling window itself.
#[derive(Debug)]
pub(crate) struct Window {
    plan: WindowPlan,
    /// `ring_rows × width` pixel slots; pixel row `y` lives in ring row
    /// `y % ring_rows`.
    slots: Vec<Slot>,
    /// `ring_rows · c` cell rows of `columns` cells, padded by `reach`
    /// empty cells left and right; cell row `j` lives in ring row
    /// `j % (ring_rows · c)`.
    cells: Vec<[f64; 2]>,
    columns: usize,
    cell_rows: usize,
    inv_side: f64,
    radius_squared: f64,
    /// Cell offsets `(dx, dy)` that can hold a point closer than `r`,
    /// nearest first.
    stencil: Vec<(isize, isize)>,
    /// The lowest pixel row still held (rows above it were dropped).
    top: usize,
}

impl Window {
    pub(crate) fn new(plan: WindowPlan, radius: f64) -> Self {
        let c = plan.cells_per_pixel;
        let columns = plan.width * c + 2 * plan.reach;
        let cell_rows = plan.ring_rows() * c;
        #[expect(clippy::cast_precision_loss, reason = "c <= 65536")]
        let side = 1.0 / c as f64;
        Self {
            plan,
            slots: vec![Slot::default(); plan.ring_rows() * plan.width],
            cells: vec![FAR; columns * cell_rows],
            columns,
            cell_rows,
            inv_side: 1.0 / side,
            radius_squared: radius * radius,
            stencil: stencil(plan.reach, side, radius, plan.eta),
            top: 0,
        }
    }

    /// Drops the pixel rows above `row - rows_above`, freeing their ring
    /// rows for the rows below.
    pub(crate) fn advance_to_row(&mut self, row: usize) {
        let keep_from = row.saturating_sub(self.plan.rows_above);
        while self.top < keep_from {
            let ring = self.top % self.plan.ring_rows();
            let width = self.plan.width;
            let row = self.slots.get_mut(ring * width..(ring + 1) * width);
            for slot in row.into_iter().flatten() {
                slot.points.clear();
                slot.active.clear();
                slot.kept.clear();
                slot.count = 0;
            }
            let c = self.plan.cells_per_pixel;
            for j in self.top * c..(self.top + 1) * c {
                let r = j % self.cell_rows;
                if let Some(cells) = self.cells.get_mut(r * self.columns..(r + 1) * self.columns) {
                    cells.fill(FAR);
                }
            }
            self.top += 1;
        }
    }

    /// Whether pixel row `y` is inside the window (so it may hold points).
    pub(crate) fn holds_row(&self, y: usize) -> bool {
        y >= self.top && y < self.top + self.plan.ring_rows()
    }

    /// The slot of pixel `(x, y)`, `x < width`; an empty one if `x` is
    /// out of range (callers never ask for that).
    pub(crate) fn slot(&self, x: usize, y: usize) -> &Slot {
        static NONE: Slot = Slot {
            points: Vec::new(),
            active: Vec::new(),
            count: 0,
            kept: Vec::new(),
        };
        self.slots.get(self.slot_index(x, y)).unwrap_or(&NONE)
    }

    /// The slot of pixel `(x, y)`; `None` only if `x >= width`.
    pub(crate) fn slot_mut(&mut self, x: usize, y: usize) -> Option<&mut Slot> {
        let index = self.slot_index(x, y);
        self.slots.get_mut(index)
    }

    fn slot_index(&self, x: usize, y: usize) -> usize {
        if x < self.plan.width {
            (y % self.plan.ring_rows()) * self.plan.width + x
        } else {
            usize::MAX
        }
    }

    /// The global cell of a point inside the raster.
    fn cell_of(&self, p: &[f64; 2]) -> (usize, usize) {
        let c = self.plan.cells_per_pixel;
        let clamp = |v: f64, cells: usize| {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "saturating cast of a non-negative value, then clamped"
            )]
            let i = (v * self.inv_side) as i64 as usize;
            i.min(cells - 1)
        };
        (
            clamp(p[0], self.plan.width * c),
            clamp(p[1], self.plan.height * c),
        )
    }

    /// Whether a stored point is closer than `r` to `p` (inside the raster,
    /// in a row the window holds).
    pub(crate) fn conflicts(&self, p: &[f64; 2]) -> bool {
        let (cx, cy) = self.cell_of(p);
        let c = self.plan.cells_per_pixel;
        // Rows outside the raster or the window hold nothing (and rows
        // past the window's bottom would alias the ring's top).
        let first_row = self.top * c;
        let end_row = ((self.top + self.plan.ring_rows()) * c).min(self.plan.height * c);
        for &(dx, dy) in &self.stencil {
            let Some(gy) = cy.checked_add_signed(dy) else {
                continue;
            };
            if gy < first_row || gy >= end_row {
                continue;
            }
            let column = (cx + self.plan.reach).wrapping_add_signed(dx);
            let index = (gy % self.cell_rows) * self.columns + column;
            if let Some(q) = self.cells.get(index)
                && distance_squared(p, q) < self.radius_squared
            {
                return true;
            }
        }
        false
    }

    /// Stores `p` in the grid and in its pixel's lists (as active too).
    /// Returns `false` (storing nothing) if its cell is taken, which only
    /// rounding can cause; the caller treats it as a failed attempt.
    pub(crate) fn insert(&mut self, p: [f64; 2], pixel: (usize, usize)) -> bool {
        let (cx, cy) = self.cell_of(&p);
        let index = (cy % self.cell_rows) * self.columns + cx + self.plan.reach;
        match self.cells.get_mut(index) {
            Some(cell) if cell[0] == f64::INFINITY => *cell = p,
            _ => return false,
        }
        let Some(slot) = self.slot_mut(pixel.0, pixel.1) else {
            return false;
        };
        slot.points.push(p);
        slot.active.push(p);
        slot.count += 1;
        true
    }
}

/// Offsets `(dx, dy)` of the cells that can hold a point closer than `r` to
/// a point of the centre cell (with a rounding margin), nearest first.
///
/// The same test as the dense grid's whole-cell stencil
/// (`grid/dense.rs`, `Stencil::new` with one part), kept apart on purpose:
/// the window's rows wrap in a ring buffer, so an offset is a `(dx, dy)`
/// pair resolved row by row, not one linear offset into a padded array; and
/// its cells hold lists of points, not one index, so the dense grid's
/// parts-of-a-cell stencils would buy little here.
fn stencil(reach: usize, side: f64, radius: f64, eta: f64) -> Vec<(isize, isize)> {
    let reach = isize::try_from(reach).unwrap_or(0);
    let gap = |d: isize| {
        #[expect(clippy::cast_precision_loss, reason = "small offsets")]
        let a = d.unsigned_abs() as f64;
        (a - 1.0 - eta).max(0.0) * side
    };
    let mut cells = Vec::new();
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            let g2 = gap(dx) * gap(dx) + gap(dy) * gap(dy);
            if g2 < radius * radius {
                cells.push((g2, dx * dx + dy * dy, dx, dy));
            }
        }
    }
    cells.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    cells.into_iter().map(|(_, _, dx, dy)| (dx, dy)).collect()
}
