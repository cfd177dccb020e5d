//! The rolling window of the streaming mode: the few pixel rows around the
//! current one, with their points and active points in a ring buffer of
//! pixel slots that is reused as the scan moves down the image, and a
//! background grid whose rows slide with it (`tiled/grid.rs`).
//!
//! Memory is proportional to the image width times the window height
//! (`ceil(r)` rows above the current row for the minimum-distance checks,
//! the current row, and `ceil(8r) + 1` rows below for points made ahead of
//! their pixel, each count capped at the image height; see
//! `WindowPlan::new`), never to the image height.

use super::grid::RollingGrid;
use crate::grid::rounding_margin;

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
        // row y, or a bucket height (r/4) more (`tiled/queue.rs`); such a
        // parent lies at most J below its key, and its children 2r below
        // it: 8.25r below the row, plus the row itself.
        let rows_below = (whole((8.0 + super::queue::BUCKET) * radius)? + 1).min(height);
        let side = 1.0 / c;
        // Rounding margin on the cell index, as for the batch grid.
        #[expect(clippy::cast_precision_loss, reason = "a bound, not a count")]
        let eta = rounding_margin(width.max(height) as f64 * c);
        // Beyond the raster there is nothing to find: the reach never needs
        // to exceed it, which also bounds the stencil for huge radii.
        let raster_cells = width.max(height).checked_mul(cells_per_pixel)?;
        let reach = whole(radius / side + eta)?.min(raster_cells);
        let ring_rows = rows_above.checked_add(rows_below)?.checked_add(1)?;
        let cell_rows = ring_rows.checked_mul(cells_per_pixel)?;
        height.checked_mul(cells_per_pixel)?;
        let grid_bytes = RollingGrid::bytes(width.checked_mul(cells_per_pixel)?, cell_rows, reach)?;
        let slot_bytes = width
            .checked_mul(ring_rows)?
            .checked_mul(size_of::<Slot>())?;
        // The table of nearby pixels (a square of its reach) is allocated
        // too; a huge radius on a wide raster must be an error, not an
        // abort.
        let near = whole(2.0 * radius)?.min(width.max(height));
        let near_side = near.checked_mul(2)?.checked_add(1)?;
        let near_bytes = near_side
            .checked_mul(near_side)?
            .checked_mul(size_of::<(isize, isize)>())?;
        let bytes = u64::try_from(slot_bytes.checked_add(near_bytes)?)
            .ok()?
            .checked_add(grid_bytes)?;
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
    grid: RollingGrid,
    /// The lowest pixel row still held (rows above it were dropped).
    top: usize,
}

impl Window {
    /// The window for `plan`, whose sizes [`WindowPlan::new`] checked.
    pub(crate) fn new(plan: WindowPlan, radius: f64) -> Self {
        let c = plan.cells_per_pixel;
        #[expect(clippy::cast_precision_loss, reason = "c <= 65536")]
        let side = 1.0 / c as f64;
        let grid = RollingGrid::new(
            (plan.width * c, plan.height.saturating_mul(c)),
            plan.ring_rows() * c,
            side,
            (radius, plan.reach, plan.eta),
        )
        .unwrap_or_else(RollingGrid::empty);
        Self {
            plan,
            slots: vec![Slot::default(); plan.ring_rows() * plan.width],
            grid,
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
            self.top += 1;
        }
        let c = self.plan.cells_per_pixel;
        self.grid.slide_to(self.top * c, self.plan.ring_rows() * c);
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

    /// A stored point closer than `r` to `p` (a point inside the raster,
    /// in a row at or below the current one), if any.
    #[inline(always)]
    pub(crate) fn conflict(&self, p: &[f64; 2]) -> Option<[f64; 2]> {
        self.grid.conflict(p)
    }

    /// Asks the cache for the grid cells around `p`.
    #[inline(always)]
    pub(crate) fn prefetch(&self, p: &[f64; 2]) {
        self.grid.prefetch(p);
    }

    /// Hands up to `limit` stored points near `p` to `take`.
    #[inline(always)]
    pub(crate) fn seed(&self, p: &[f64; 2], limit: usize, take: impl FnMut(&[f64; 2])) {
        self.grid.seed(p, limit, take);
    }

    /// Stores exact mode's dart `p` in the grid only (see
    /// `RollingGrid::replace`), so that the sweep keeps its distance from it.
    pub(crate) fn replace(&mut self, p: [f64; 2]) {
        self.grid.replace(p);
    }

    /// Stores `p` in the grid and in its pixel's points, and in its
    /// pixel's active list if `active` (the paper's scheme keeps one per
    /// pixel; the sweep's queue holds its own). Returns `false` (storing nothing) if its cell is taken, which only
    /// rounding can cause; the caller treats it as a failed attempt.
    pub(crate) fn insert(&mut self, p: [f64; 2], pixel: (usize, usize), active: bool) -> bool {
        let index = self.slot_index(pixel.0, pixel.1);
        if index >= self.slots.len() || !self.grid.insert(p) {
            return false;
        }
        let Some(slot) = self.slots.get_mut(index) else {
            return false;
        };
        slot.points.push(p);
        if active {
            slot.active.push(p);
        }
        slot.count += 1;
        true
    }
}
