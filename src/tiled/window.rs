//! The rolling window of the streaming mode: the few pixel rows around the
//! current one, in ring buffers reused as the scan moves down the image (a
//! count per pixel and, for the paper's scheme and exact mode, per-pixel
//! lists), and a background grid whose rows slide with it
//! (`tiled/grid.rs`). The sweep keeps its points in the grid only and
//! gathers a row's points from it when the row is emitted: per-pixel lists
//! cost a cache miss and a growing allocation per point, and at 16 384
//! pixels wide about 25 MB.
//!
//! Memory is proportional to the image width times the window height
//! (`ceil(r)` rows above the current row for the minimum-distance checks,
//! the current row, and `ceil(8r) + 1` rows below for points made ahead of
//! their pixel, each count capped at the image height; see
//! `WindowPlan::new`), never to the image height.

use super::grid::RollingGrid;
use crate::grid::rounding_margin;
use smallvec::SmallVec;

/// Points a pixel's list holds inline, beside its slot, before it moves
/// to the heap: exact mode at `n = 4` oversamples to about 4.6 a pixel,
/// and a list on the heap cost a second cache miss per stored point on
/// wide rasters.
const INLINE: usize = 8;

/// Points and active points of one pixel (the paper's scheme and exact
/// mode).
#[derive(Debug, Default, Clone)]
pub(crate) struct Slot {
    /// The paper's scheme: points not yet handed out (emptied when the
    /// pixel is emitted). Exact mode: the sweep's points, until the row is
    /// settled.
    pub(crate) points: SmallVec<[[f64; 2]; INLINE]>,
    pub(crate) active: Vec<[f64; 2]>,
    /// Exact mode: the pixel's final points, emitted and kept for the next
    /// rows' checks and elimination weights.
    pub(crate) kept: Vec<[f64; 2]>,
}

/// Geometry of the window, decided (and checked) up front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct WindowPlan {
    pub(crate) width: usize,
    pub(crate) height: usize,
    /// Grid cell side, `r/√2` as in the batch grid (cells need not line
    /// up with pixels: the grid slides by cell rows).
    pub(crate) side: f64,
    /// Grid cells across the raster, and cell rows the window spans at
    /// most.
    pub(crate) cells_x: usize,
    pub(crate) cells_y: usize,
    pub(crate) live_rows: usize,
    /// Pixel rows kept above the current one.
    pub(crate) rows_above: usize,
    /// Pixel rows kept below the current one.
    pub(crate) rows_below: usize,
    /// Cells searched on each side of a candidate's cell.
    pub(crate) reach: usize,
    /// Rounding margin on cell indices, in cells.
    pub(crate) eta: f64,
    pub(crate) bytes: u64,
    pub(crate) lists: bool,
    /// Whether the live rows' cells overflow the L2 cache
    /// ([`WIDE_WINDOW`]): then the sweep prefetches each pick's cells.
    pub(crate) wide: bool,
    /// Wide windows, plain sweep: rows made per round of blocks of columns
    /// (`tiled::BLOCK_CELLS`); 0 otherwise.
    pub(crate) rows_per_round: usize,
}

/// Bytes of the live rows' cells above which a window is wide: half the
/// L2 cache of the machines measured (1 MiB a core), leaving room for the
/// queue and the conflict cache. Narrower windows stay in cache as they
/// are: the sweep works them across their whole width, without
/// prefetching (which was 1–3 % slower there).
const WIDE_WINDOW: usize = 1 << 19;

impl WindowPlan {
    /// `None` if a size overflows.
    /// `lists`: whether the window keeps per-pixel lists (the paper's
    /// scheme and exact mode).
    pub(crate) fn new(width: usize, height: usize, radius: f64, lists: bool) -> Option<Self> {
        Self::sized(width, height, radius, lists, WIDE_WINDOW)
    }

    /// [`Self::new`], with the live rows' bytes above which the window
    /// counts as wide (tests force the wide path on small rasters).
    pub(crate) fn sized(
        width: usize,
        height: usize,
        radius: f64,
        lists: bool,
        wide_above: usize,
    ) -> Option<Self> {
        // Cells of side r/√2; more than 65 536 a pixel side is refused.
        let side = radius * core::f64::consts::FRAC_1_SQRT_2;
        if side.is_nan() || side < 1.0 / 65_536.0 {
            return None;
        }
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
        let below = whole((8.0 + super::queue::BUCKET) * radius)?;
        let cells = |pixels: usize| -> Option<usize> {
            #[expect(clippy::cast_precision_loss, reason = "pixel counts < 2^32")]
            let n = (pixels as f64 / side).ceil().max(1.0);
            whole(n)
        };
        let (cells_x, cells_y) = (cells(width)?, cells(height)?);
        // Rounding margin on the cell index, as for the batch grid.
        #[expect(clippy::cast_precision_loss, reason = "a bound, not a count")]
        let eta = rounding_margin(cells_x.max(cells_y) as f64);
        // Beyond the raster there is nothing to find: the reach never needs
        // to exceed it, which also bounds the stencil for huge radii.
        let reach = whole(radius / side + eta)?.min(cells_x.max(cells_y));
        // The grid holds only the rows the searches can reach, not whole
        // pixel rows: from `r` above the current row (its first cell row,
        // less one for rounding) to the lowest row a child can land in,
        // `1 + (8 + BUCKET)·r` below the current row's top, plus the reach;
        // and `rows_per_round - 1` rows more below on wide windows, whose
        // rounds work that many rows ahead.
        let live = |extra: usize| -> Option<usize> {
            #[expect(clippy::cast_precision_loss, reason = "a few rows")]
            let extra = extra as f64;
            Some(
                whole((1.0 + extra + (9.0 + super::queue::BUCKET) * radius) / side)?
                    .checked_add(3)?
                    .min(cells_y.checked_add(1)?),
            )
        };
        let live_bytes = cells_x
            .checked_add(reach.checked_mul(2)?)?
            .checked_mul(live(0)?.checked_add(reach.checked_mul(2)?)?)?
            .checked_mul(size_of::<[f64; 2]>())?;
        let wide = live_bytes > wide_above;
        // A round makes about `J = 4r` of rows: its blocks' cells are
        // loaded about `(J + 7r + rows) / rows` times, and more rows cost
        // window memory. The plain sweep only: exact mode's thinning is
        // calibrated on the sweep worked across the whole width.
        let rows_per_round = if wide && !lists {
            whole((super::SWEEP_BAND * radius - 0.5).max(0.0))?.clamp(1, height)
        } else {
            0
        };
        let extra = rows_per_round.saturating_sub(1);
        let rows_below = below.checked_add(1)?.checked_add(extra)?.min(height);
        let ring_rows = rows_above.checked_add(rows_below)?.checked_add(1)?;
        let live_rows = live(extra)?;
        let grid_bytes = RollingGrid::bytes(cells_x, live_rows, reach)?;
        let per_pixel = size_of::<u32>() + if lists { size_of::<Slot>() } else { 0 };
        let slot_bytes = width.checked_mul(ring_rows)?.checked_mul(per_pixel)?;
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
            side,
            cells_x,
            cells_y,
            live_rows,
            rows_above,
            rows_below,
            reach,
            eta,
            bytes,
            lists,
            wide,
            rows_per_round,
        })
    }

    /// How far below the current row's bottom the sweep's children can
    /// land: `(8 + BUCKET)·r`, and the rows a round works ahead.
    pub(crate) fn lead(&self, radius: f64) -> f64 {
        #[expect(clippy::cast_precision_loss, reason = "a few rows")]
        let extra = self.rows_per_round.saturating_sub(1) as f64;
        (8.0 + super::queue::BUCKET) * radius + extra
    }

    fn ring_rows(&self) -> usize {
        self.rows_above + self.rows_below + 1
    }
}

/// The rolling window itself.
#[derive(Debug)]
pub(crate) struct Window {
    plan: WindowPlan,
    /// `ring_rows × width` pixel slots, or none for the plain sweep;
    /// pixel row `y` lives in ring row `y % ring_rows`.
    slots: Vec<Slot>,
    /// Points ever stored in each pixel, emitted or not, in the same ring.
    counts: Vec<u32>,
    grid: RollingGrid,
    /// An empty slot, for [`Self::slot`] out of range.
    none: Slot,
    /// The sweep's gathered row: its points by pixel, pixel `x`'s at
    /// `row[starts[x]..starts[x + 1]]`.
    row: Vec<[f64; 2]>,
    starts: Vec<usize>,
    /// Where [`Self::gather_row`] puts each pixel's next point (kept
    /// between rows for its allocation).
    cursor: Vec<usize>,
    /// The lowest pixel row still held (rows above it were dropped), and
    /// its ring row (`top % ring_rows`, kept so that a pixel's slot needs
    /// no division: a 64-bit division per stored point showed).
    top: usize,
    top_ring: usize,
    radius: f64,
}

impl Window {
    /// The window for `plan`, whose sizes [`WindowPlan::new`] checked.
    pub(crate) fn new(plan: WindowPlan, radius: f64) -> Self {
        let lists = plan.lists;
        let grid = RollingGrid::new(
            (plan.cells_x, plan.cells_y),
            plan.live_rows,
            plan.side,
            (radius, plan.reach, plan.eta),
            plan.wide,
        )
        .unwrap_or_else(RollingGrid::empty);
        let pixels = plan.ring_rows() * plan.width;
        Self {
            plan,
            slots: if lists {
                vec![Slot::default(); pixels]
            } else {
                Vec::new()
            },
            counts: vec![0; pixels],
            grid,
            none: Slot::default(),
            row: Vec::new(),
            starts: Vec::new(),
            cursor: Vec::new(),
            top: 0,
            top_ring: 0,
            radius,
        }
    }

    /// Drops the pixel rows above `row - rows_above`, freeing their ring
    /// rows for the rows below.
    pub(crate) fn advance_to_row(&mut self, row: usize) {
        let keep_from = row.saturating_sub(self.plan.rows_above);
        while self.top < keep_from {
            let ring = self.top_ring;
            let width = self.plan.width;
            let row = self.slots.get_mut(ring * width..(ring + 1) * width);
            for slot in row.into_iter().flatten() {
                slot.points.clear();
                slot.active.clear();
                slot.kept.clear();
            }
            if let Some(counts) = self.counts.get_mut(ring * width..(ring + 1) * width) {
                counts.fill(0);
            }
            self.top += 1;
            self.top_ring += 1;
            if self.top_ring == self.plan.ring_rows() {
                self.top_ring = 0;
            }
        }
        // The first cell row that can hold a point within `r` of row
        // `row` (the same rounding as a point's cell, which is monotonic,
        // less one row for the margin).
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            clippy::cast_precision_loss,
            reason = "a saturating cast of a non-negative row"
        )]
        let first = ((row as f64 - self.radius).max(0.0) / self.plan.side) as usize;
        self.grid
            .slide_to(first.saturating_sub(1), self.plan.live_rows);
    }

    /// Whether pixel row `y` is inside the window (so it may hold points).
    pub(crate) fn holds_row(&self, y: usize) -> bool {
        y >= self.top && y < self.top + self.plan.ring_rows()
    }

    /// The slot of pixel `(x, y)`, `x < width`; an empty one if `x` is
    /// out of range (callers never ask for that).
    pub(crate) fn slot(&self, x: usize, y: usize) -> &Slot {
        self.slots.get(self.slot_index(x, y)).unwrap_or(&self.none)
    }

    /// The slot of pixel `(x, y)`; `None` only if `x >= width`.
    pub(crate) fn slot_mut(&mut self, x: usize, y: usize) -> Option<&mut Slot> {
        let index = self.slot_index(x, y);
        self.slots.get_mut(index)
    }

    /// Points ever stored in pixel `(x, y)` (0 outside the window).
    pub(crate) fn count(&self, x: usize, y: usize) -> u32 {
        self.counts.get(self.slot_index(x, y)).copied().unwrap_or(0)
    }

    /// Gathers pixel row `y`'s points from the grid, by pixel, for
    /// [`Self::pixel_points`]: a counting sort over the row's cells, in
    /// cell order within each pixel.
    pub(crate) fn gather_row(&mut self, y: usize) {
        let width = self.plan.width;
        self.starts.clear();
        self.starts.push(0);
        let mut total = 0;
        for x in 0..width {
            total += self.count(x, y) as usize;
            self.starts.push(total);
        }
        // The spare place's cursor.
        self.starts.push(total);
        // One more place, at the end, for everything that is not a point
        // of the row: every cell is written somewhere, without a branch
        // on whether it is empty (half are, at random).
        self.row.clear();
        self.row.resize(total + 1, [f64::NAN; 2]);
        self.cursor.clone_from(&self.starts);
        let (row, grid, next) = (&mut self.row, &self.grid, &mut self.cursor);
        #[expect(clippy::cast_precision_loss, reason = "pixel counts < 2^32")]
        let (top, w) = (y as f64, width as f64);
        grid.for_each_row_of(y, |cells| {
            for p in cells {
                // Empty cells (at infinity) and points of other rows fail
                // the test and go to the spare place, `width`.
                let inside = p[1] >= top && p[1] < top + 1.0 && p[0] < w;
                #[expect(
                    clippy::cast_possible_truncation,
                    clippy::cast_sign_loss,
                    reason = "a saturating cast; only used when inside the raster"
                )]
                // Through u32, cheaper than f64 -> usize: pixel columns < 2^32.
                let px = if inside { p[0] as u32 as usize } else { width };
                if let Some(at) = next.get_mut(px) {
                    if let Some(slot) = row.get_mut(*at) {
                        *slot = *p;
                    }
                    *at += usize::from(inside);
                }
            }
        });
        self.row.truncate(total);
    }

    /// Pixel `x`'s points of the row last gathered.
    pub(crate) fn pixel_points(&self, x: usize) -> &[[f64; 2]] {
        match (self.starts.get(x), self.starts.get(x + 1)) {
            (Some(&a), Some(&b)) => self.row.get(a..b).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Pixel `(x, y)`'s place in the ring: row `y % ring_rows`, found
    /// from the top row's without a division for the rows the window
    /// holds.
    #[inline(always)]
    fn slot_index(&self, x: usize, y: usize) -> usize {
        if x >= self.plan.width {
            return usize::MAX;
        }
        let rows = self.plan.ring_rows();
        let ahead = y.wrapping_sub(self.top);
        let ring = if ahead < rows {
            let r = self.top_ring + ahead;
            if r >= rows { r - rows } else { r }
        } else {
            y % rows
        };
        ring * self.plan.width + x
    }

    /// A stored point closer than `r` to `p` (a point inside the raster,
    /// in a row at or below the current one), if any; and `p`'s cell key
    /// (`RollingGrid::key`), for [`Self::insert`].
    #[inline(always)]
    pub(crate) fn conflict(&self, p: &[f64; 2]) -> (usize, Option<[f64; 2]>) {
        self.grid.conflict(p)
    }

    /// The cell key of `p`, a point inside the raster.
    pub(crate) fn key(&self, p: &[f64; 2]) -> usize {
        self.grid.key(p)
    }

    /// The point stored in the cell with key `key` (the sweep's queue
    /// names its points by their cells).
    #[inline(always)]
    pub(crate) fn point(&self, key: usize) -> [f64; 2] {
        self.grid.point(key)
    }

    /// Asks the cache for the grid cells around the cell with key `key`
    /// (wide windows).
    #[inline(always)]
    pub(crate) fn prefetch(&self, key: usize) {
        self.grid.prefetch(key);
    }

    /// Hands up to `limit` stored points around the cell with key `key`
    /// to `take`.
    #[inline(always)]
    pub(crate) fn seed(&self, key: usize, limit: usize, take: impl FnMut(&[f64; 2])) {
        self.grid.seed(key, limit, take);
    }

    /// Stores exact mode's dart `p` in the grid only (see
    /// `RollingGrid::replace`), so that the sweep keeps its distance from it.
    pub(crate) fn replace(&mut self, p: [f64; 2]) {
        self.grid.replace(p);
    }

    /// Stores `p` in the grid (its cell's key is `key`, from
    /// [`Self::conflict`]), counts it in its pixel, with `list` adds
    /// it to its pixel's points (the paper's scheme, exact mode) and with
    /// `active` to its active points (the paper's scheme). Returns `false`
    /// (storing nothing) if its cell is taken, which only rounding can
    /// cause; the caller treats it as a failed attempt.
    pub(crate) fn insert(
        &mut self,
        (p, key): ([f64; 2], usize),
        pixel: (usize, usize),
        (list, active): (bool, bool),
    ) -> bool {
        let index = self.slot_index(pixel.0, pixel.1);
        if index >= self.counts.len() || !self.grid.insert(p, key) {
            return false;
        }
        if let Some(count) = self.counts.get_mut(index) {
            *count = count.saturating_add(1);
        }
        if list && let Some(slot) = self.slots.get_mut(index) {
            slot.points.push(p);
            if active {
                slot.active.push(p);
            }
        }
        true
    }
}
