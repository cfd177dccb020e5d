//! Exact mode: exactly `n` points in every pixel, thinned from a sweep run
//! at a radius that gives about `s·n` points per pixel (`s`, the
//! oversampling, [`DEFAULT_OVERSAMPLE`] unless set), one row at a time.
//!
//! When row `y` is complete, the points of rows `y` and `y + 1` (the band)
//! are gathered, and row `y` is settled in three steps:
//!
//! 1. **Dead points.** A band point closer than the sweep's radius `r` to a
//!    final point of the rows above (a dart placed there, step 2) is out.
//! 2. **Short pixels.** A pixel of row `y` left with fewer than `n` points
//!    gets darts. A dart is valid only if it lies at least `r` from every
//!    point that stays: of 32 uniform darts in the pixel, the one with the
//!    fewest *blockers* (band points closer than `r`, at most four) is
//!    taken and its blockers removed. Every blocker must lie in another
//!    pixel, and a final point of a row above or another dart is never
//!    removed. Which pixels may lose a blocker widens in stages, each
//!    tried only if the previous found no dart: a pixel that keeps at
//!    least `n` points; or one not yet mended, right of it in row `y` or in
//!    row `y + 1`, which gets its own darts in turn (then with 256 darts);
//!    then any pixel, a pixel of row `y` left short being mended on the
//!    next pass over the row (up to four passes). So points move across a
//!    pixel border, one out near it on one side and one in near it on the
//!    other: the density along the borders is kept. The dart goes into the
//!    sweep's grid, so that points the sweep still makes below keep their
//!    distance from it too. If all that fails, the pixel is hemmed in by
//!    points that never go: on any pass but the last, every point of the
//!    pixel is taken out (once a row) and darts place all `n` again, the
//!    pixels they rob mended on the next pass. Only if that fails too
//!    (about once in 10⁹ points at the default oversampling before the
//!    re-placing; `examples/stream.rs` reports it) the best of the darts by
//!    distance is taken: a *top-up*, which may come closer than `r`;
//!    [`Pixels::top_ups`] counts them.
//! 3. **Excess.** Pixels of row `y` with more than `n` points lose the
//!    excess, by the [`ExactMethod`]:
//!    - [`ExactMethod::Eliminate`]: weighted sample elimination (Yuksel
//!      2015, "Sample Elimination for Generating Poisson Disk Sample
//!      Sets") of row `y`: the point with the largest weight
//!      `Σ sⱼ·(1 - d/2rₑ)⁸` over neighbours `j` closer than `2rₑ` is
//!      removed, again and again, except from pixels already down to `n`,
//!      where `rₑ = sqrt(1 / (2√3·n))` is the spacing of `n` points per
//!      pixel on a hexagonal lattice. The neighbours are the band's live
//!      points and the final points above. Row `y + 1` is thinned later,
//!      so a term from one of its points counts with `sⱼ = n / c`, the
//!      share of its pixel's `c` points that will stay (`sⱼ = 1` for the
//!      others). Eliminating both rows together and throwing row
//!      `y + 1`'s result away gives the same image error at more cost
//!      (`docs/performance-journal.md`, "Exact mode: one row eliminated").
//!    - [`ExactMethod::Random`]: the excess points of each pixel are picked
//!      uniformly at random, blind to where they lie.
//!
//! Every kept point is a sweep point or a valid dart, so the set's minimum
//! distance is at least the sweep's radius, [`Tiled::radius`], except
//! around top-ups. The scratch arrays live in [`Exact`] and are reused from
//! row to row: after the first rows, thinning allocates nothing.
//!
//! This file settles a row (gathering the band, step 1, storing the row);
//! each other step has a file of its own, all of them `impl Exact` blocks
//! over the one set of scratch arrays:
//! - `mend.rs`: step 2, the darts;
//! - `elimination.rs` and `dropping.rs`: step 3 by each [`ExactMethod`];
//! - `calibration.rs`: the edge correction both methods weigh points by;
//! - `feedback.rs`: that correction trimmed after each row from the
//!   in-pixel harmonics the rows settled so far kept, so that no residual
//!   of the table builds up into a pixel pattern over a frame;
//! - `waves.rs`: the correction's waves at the pixel lattice's higher
//!   frequencies, trimmed the same way, measured from a histogram of the
//!   points in their pixels and read from a table;
//! - `cells.rs`: the band's local grid, which elimination and top-ups
//!   search.
//!
//! [`Pixels::top_ups`]: super::Pixels::top_ups
//! [`Tiled::radius`]: super::Tiled::radius

mod calibration;
mod cells;
mod dropping;
mod elimination;
mod feedback;
mod mend;
mod turn;
mod waves;

use super::window::Window;
use crate::vector::distance_squared;
use feedback::Feedback;
use rand::Rng;
use std::collections::BinaryHeap;

/// Points per pixel the sweep makes, relative to the `n` kept, unless
/// [`TiledBuilder::exact_oversample`](super::TiledBuilder::exact_oversample)
/// says otherwise. The kept set's ρ is about the sweep's over `√s`: 0.705
/// at [`EXACT_ATTEMPTS`], so 0.655 here, the radius of the former default
/// (`s = 1.25` at `k = 30`, where the sweep's ρ is 0.73) to within 0.3 %.
/// A larger `s` gives elimination more to choose from at the cost of the
/// minimum distance and of speed (`docs/performance-journal.md` has the
/// trade-off).
pub(crate) const DEFAULT_OVERSAMPLE: f64 = 1.16;

/// The attempts `k` exact mode's sweep runs with unless
/// [`TiledBuilder::attempts`](super::TiledBuilder::attempts) says
/// otherwise. A third of the usual 30: thinning, not the sweep's
/// saturation, shapes the kept set, and the sweep's retiring picks (their
/// `k` failed throws) are a third of its time. At `k = 10` the sweep makes
/// 0.93 of the points per `r²` it makes at 30; `DEFAULT_OVERSAMPLE` is
/// counted at this `k`. The journal has the measurements (exact mode at
/// `k = 6` to `30`).
pub const EXACT_ATTEMPTS: u32 = 10;

/// How exact mode chooses, in a pixel with more than `n` points, which
/// points to drop. Set with
/// [`TiledBuilder::exact_method`](super::TiledBuilder::exact_method); both
/// methods give exactly `n` points per pixel with the same minimum distance
/// and mend short pixels the same way (see [`Tiled`](super::Tiled)).
///
/// They differ in what the set looks like. Elimination spreads the kept
/// points best; random dropping adds a little white noise (a thinned
/// Poisson disk set). With either, exactly `n` a pixel would draw the
/// points a little toward the middles of the pixel's halves at small `n`
/// (at `n = 4` the density across a pixel rippled by about ±2.5 % at half
/// a pixel); the edge correction and its feedback hold every frequency of
/// the pixel lattice up to two cycles a pixel flat (`(1, 0)`, `(2, 0)`,
/// `(1, ±1)`, `(2, ±1)`, …). `docs/streaming.md` measures both.
///
/// In renders, elimination gives the lower error, hence the default: in
/// the tracer study (`examples/trace.rs`, `docs/rendering.md`: four scenes
/// at 4, 16 and 64 samples per pixel, one exact stream over the image as a
/// renderer runs it), random dropping's RMSE is up to 8 % higher, beyond
/// the noise on the checkerboard, the moving sphere and the lit figure,
/// level on the depth-of-field scene. Random dropping samples faster; a
/// renderer whose sampling costs more than its shading may prefer it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
#[non_exhaustive]
pub enum ExactMethod {
    /// Weighted sample elimination (Yuksel 2015) of each row, the row
    /// below counted as it will be once thinned: the most crowded point
    /// goes first.
    #[default]
    Eliminate,
    /// Drops each pixel's excess points uniformly at random.
    Random,
}

/// Pixel column `x` and its neighbours inside a raster `width` wide: all
/// the columns a point of column `x` can be closer than `r` to, as `r < 1`.
fn columns_around(x: usize, width: usize) -> core::ops::RangeInclusive<usize> {
    x.saturating_sub(1)..=(x + 1).min(width.saturating_sub(1))
}

/// A heap entry: a point's weight when pushed (stale if it changed since)
/// and its index, packed into one integer whose order is the weights'
/// `total_cmp`, ties going to the lower index: the heap then compares
/// integers (its pops were 6 % of exact mode's instructions at `n = 4`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry(u128);

/// A live band point in the local grid's order, for
/// [`Exact::pair_weights`].
#[derive(Clone, Copy, Debug)]
struct ByCell {
    p: [f64; 2],
    over: bool,
    scale: f64,
    weight: f64,
}

/// What the darts of one short pixel are checked against
/// ([`Exact::best_dart`]), copied out once since nothing changes until one
/// is placed: the darts already placed in the columns around, the final
/// points above near it, the live points of the short pixel itself (a
/// dart may take none of them: checked first, they turn most darts away
/// in a few distances), and the other live band points of the pixels
/// around with their index and pixel, in [`Exact::near_pixel`]'s order.
#[derive(Debug, Default)]
struct DartScratch {
    darts: Vec<[f64; 2]>,
    above: Vec<[f64; 2]>,
    own: Vec<[f64; 2]>,
    near: Vec<([f64; 2], u32, u32)>,
}

/// Exact mode's settings and its scratch arrays, reused from row to row.
#[derive(Debug)]
pub(crate) struct Exact {
    n: usize,
    method: ExactMethod,
    /// `[βx, βy, γ]` of [`Self::edge_factor`].
    bias: [f64; 3],
    /// Its `δ`: 0 when the caller set the correction.
    top: f64,
    /// Its `ε`: 0 when the caller set the correction.
    side: f64,
    /// Its cross terms `[ζcc, ζss, ζcs, ζsc]`: 0 but for the feedback.
    cross: [f64; 4],
    /// `[βx, βy, γ, ε]` as calibrated, before the feedback's trims, and
    /// the feedback (`feedback.rs`); `None` when the caller set the
    /// correction.
    base: [f64; 4],
    feedback: Option<Feedback>,
    /// `2rₑ`: the reach of the elimination weight, and its inverse.
    reach: f64,
    inv_reach: f64,
    /// The sweep's radius squared: what darts must keep from every point.
    radius_squared: f64,
    /// Cells per pixel side of the band's local grid: cells are about half
    /// the search distance wide (a 5 × 5 block of them is searched, 1.8
    /// pixels² at `n = 4` where whole pixels would search 9), and
    /// neighbours lie within `cell_reach` cells.
    cells: usize,
    cell_reach: usize,
    /// Pixel rows above searched for final points (`ceil(reach)`).
    rows_up: usize,
    /// Band points: gathered pixel by pixel in generation order, darts
    /// appended; their band pixel (`row · width + x`); whether they stay.
    points: Vec<[f64; 2]>,
    pixel: Vec<u32>,
    alive: Vec<bool>,
    /// Where each band pixel's gathered points start in `points`.
    start: Vec<usize>,
    /// Live points per band pixel.
    count: Vec<usize>,
    /// Indices of `points` by local grid cell, and each point's cell.
    cell_start: Vec<usize>,
    cell_of: Vec<usize>,
    cell_items: Vec<u32>,
    /// [`Self::pair_weights`]' copy of the live points in the local grid's
    /// order (`cell_items`): coordinates, whether elimination may remove
    /// it, its pixel's `scale`, and its weight so far.
    by_cell: Vec<ByCell>,
    /// What a short pixel's darts are checked against
    /// ([`Self::gather_blockers`]), reused from pixel to pixel.
    dart_scratch: DartScratch,
    /// Elimination: weights and edge factors ([`Self::edge_factor`]).
    weight: Vec<f64>,
    factor: Vec<f64>,
    /// Whether each point is in a pixel of the row settled that is over
    /// `n` as elimination starts: the points elimination may remove.
    over: Vec<bool>,
    /// What the weight terms of each band pixel's points count for on
    /// the others' weights: `n / c` for a pixel of row `y + 1` with
    /// `c > n` points (the share of them that will stay), else 1.
    scale: Vec<f64>,
    /// A removed point's live neighbours and their weight terms.
    neighbours: Vec<(u32, f64)>,
    heap: BinaryHeap<Entry>,
    /// The weights elimination starts from, largest first.
    sorted: Vec<Entry>,
    /// Darts placed in this band (indices into `points`).
    darts: Vec<u32>,
    /// The same darts by pixel column, for [`Self::blockers`]: a dart
    /// closer than `r` to a point of pixel `x` lies in column `x - 1`,
    /// `x` or `x + 1` (darts are all in row `y`, and `r < 1`: at most
    /// `sqrt(0.88 / (s·n))` with `s, n >= 1`), so a dart is checked
    /// against a few darts, not against every dart of a row as wide as the
    /// image.
    dart_columns: Vec<Vec<u32>>,
    /// Columns of the row being mended whose points were all taken out to
    /// be placed again by darts, before a top-up (at most once a row each).
    cleared: Vec<usize>,
    /// The darts kept in the row settled last, by pixel column: the only
    /// final points a band point can be closer than `r` to (step 1; every
    /// other final point is a sweep point, as the band's points are, and
    /// `r < 1` keeps older rows out of reach).
    darts_above: Vec<Vec<[f64; 2]>>,
    /// The final points of the row settled last (`strip_row`) within
    /// `2rₑ` of its bottom edge (with a margin), by pixel column, in the
    /// order of the pixels' final points: the only ones whose weight
    /// terms on the band's points are not zero, when `2rₑ <= 1` (`rows_up`
    /// 1). Elimination adds their terms in that order, skipping only
    /// zeros, which leaves the sums' bits as they were.
    strip: Vec<Vec<[f64; 2]>>,
    strip_row: Option<usize>,
    /// Whether the local grid holds this band's points.
    indexed: bool,
}

impl Exact {
    /// Settings for `n` points per pixel, thinned by `method` from a sweep
    /// of radius `radius`.
    pub(crate) fn new(n: usize, method: ExactMethod, radius: f64, bias: Option<[f64; 3]>) -> Self {
        // At `n = 1` a quarter of the pixels are short and no term moves
        // the pattern (`calibration.rs`): nothing to feed back.
        let feedback = (bias.is_none() && n >= 2).then(|| Self::feedback(method, n));
        let (bias, top, side) = Self::correction(method, n, bias);
        #[expect(clippy::cast_precision_loss, reason = "a count per pixel")]
        let r_e = (1.0 / (2.0 * 3f64.sqrt() * n as f64)).sqrt();
        let reach = 2.0 * r_e;
        // Both the weight's reach and the darts' radius must fit in the
        // searched cells; the radius is below the reach for any
        // oversampling above 0.54, but take the larger to be sure.
        let search = reach.max(radius);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to 1 ..= 2^16"
        )]
        let cells = ((2.0 / search).floor().clamp(1.0, 65_536.0)) as usize;
        #[expect(clippy::cast_precision_loss, reason = "cells <= 2^16")]
        let cell_side = 1.0 / cells as f64;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "search / side: a few cells (search < 2 pixels here)"
        )]
        let cell_reach = ((search / cell_side).ceil().clamp(1.0, 1e6)) as usize;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a few pixels"
        )]
        let rows_up = (search.ceil().clamp(1.0, 1e6)) as usize;
        Self {
            n,
            method,
            bias,
            top,
            side,
            cross: [0.0; 4],
            base: [bias[0], bias[1], bias[2], side],
            feedback,
            reach,
            inv_reach: 1.0 / reach,
            radius_squared: radius * radius,
            cells,
            cell_reach,
            rows_up,
            points: Vec::new(),
            pixel: Vec::new(),
            alive: Vec::new(),
            start: Vec::new(),
            count: Vec::new(),
            cell_start: Vec::new(),
            cell_of: Vec::new(),
            cell_items: Vec::new(),
            by_cell: Vec::new(),
            dart_scratch: DartScratch::default(),
            weight: Vec::new(),
            factor: Vec::new(),
            over: Vec::new(),
            scale: Vec::new(),
            neighbours: Vec::new(),
            heap: BinaryHeap::new(),
            sorted: Vec::new(),
            darts: Vec::new(),
            dart_columns: Vec::new(),
            cleared: Vec::new(),
            darts_above: Vec::new(),
            strip: Vec::new(),
            strip_row: None,
            indexed: false,
        }
    }

    /// Settles row `y`: exactly `n` points in each of its pixels, stored as
    /// the row's points and final points. Returns the number of top-ups
    /// (darts closer than the sweep's radius) it needed.
    pub(crate) fn thin_row<R: Rng + ?Sized>(
        &mut self,
        window: &mut Window,
        y: usize,
        (width, height): (usize, usize),
        rng: &mut R,
    ) -> usize {
        let band_rows = if y + 1 < height && window.holds_row(y + 1) {
            2
        } else {
            1
        };
        self.gather(window, y, width, band_rows);
        self.kill_conflicts(y, width);
        let top_ups = self.mend_row(window, y, (width, band_rows), rng);
        match self.method {
            ExactMethod::Eliminate => {
                // The local grid serves elimination only: the darts look
                // through the few pixels around theirs.
                self.index_cells(y, width, band_rows);
                self.eliminate(window, y, width, band_rows);
            }
            ExactMethod::Random => self.drop_at_random(width, rng),
        }
        self.store(window, y, width);
        top_ups
    }

    /// Copies the band's points, pixel by pixel.
    fn gather(&mut self, window: &Window, y: usize, width: usize, band_rows: usize) {
        for &i in &self.darts {
            if let Some(list) = self
                .pixel
                .get(i as usize)
                .and_then(|&x| self.dart_columns.get_mut(x as usize))
            {
                list.clear();
            }
        }
        self.darts.clear();
        self.indexed = false;
        self.dart_columns.resize_with(width, Vec::new);
        self.points.clear();
        self.pixel.clear();
        self.start.clear();
        for row in 0..band_rows {
            for x in 0..width {
                let b = row * width + x;
                self.start.push(self.points.len());
                let list = &window.slot(x, y + row).points;
                self.points.extend_from_slice(list);
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "band pixels: 2 · width < 2^32"
                )]
                self.pixel
                    .extend(core::iter::repeat_n(b as u32, list.len()));
            }
        }
        self.start.push(self.points.len());
        self.alive.clear();
        self.alive.resize(self.points.len(), true);
        self.count.clear();
        self.count.extend(self.start.windows(2).map(|w| match w {
            [a, b] => b - a,
            _ => 0,
        }));
    }

    /// The final points of the rows above row `y` near pixel column `x`
    /// (within `rows_up` pixels).
    fn final_above<'w>(
        &self,
        window: &'w Window,
        y: usize,
        x: usize,
        width: usize,
    ) -> impl Iterator<Item = &'w [f64; 2]> + 'w {
        let reach = self.rows_up;
        (y.saturating_sub(reach)..y)
            .filter(move |&yy| window.holds_row(yy))
            .flat_map(move |yy| {
                (x.saturating_sub(reach)..=(x + reach).min(width - 1))
                    .flat_map(move |xx| window.slot(xx, yy).kept.iter())
            })
    }

    /// Step 1: band points closer than `r` to a final point above are out.
    /// Only darts of row `y - 1` can be: two sweep points keep `r`, and
    /// `r < 1` (at most `sqrt(0.88 / (s·n))`, `s, n >= 1`) puts rows above
    /// `y - 1` out of reach; a band point within `r` of a dart lies in the
    /// dart's column or a next one.
    fn kill_conflicts(&mut self, y: usize, width: usize) {
        if self.darts_above.iter().all(Vec::is_empty) {
            return;
        }
        #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
        let top = y as f64;
        let r2 = self.radius_squared;
        let r = r2.sqrt();
        for i in 0..self.points.len() {
            let (Some(&p), Some(&b)) = (self.points.get(i), self.pixel.get(i)) else {
                continue;
            };
            if p[1] - top >= r {
                continue;
            }
            let x = b as usize % width;
            let near = self
                .darts_above
                .get(columns_around(x, width))
                .unwrap_or(&[])
                .iter()
                .flatten()
                .any(|q| distance_squared(&p, q) < r2);
            if near
                && let (Some(a), Some(c)) = (self.alive.get_mut(i), self.count.get_mut(b as usize))
                && *a
            {
                *a = false;
                *c -= 1;
            }
        }
    }

    fn kill(&mut self, i: usize) {
        if let (Some(a), Some(&b)) = (self.alive.get_mut(i), self.pixel.get(i))
            && *a
        {
            *a = false;
            if let Some(c) = self.count.get_mut(b as usize) {
                *c -= 1;
            }
        }
    }

    /// Row `y`'s live points, in generation order (darts last), become its
    /// final points, which are also what the pixels emit.
    fn store(&mut self, window: &mut Window, y: usize, width: usize) {
        for x in 0..width {
            let (Some(&a), Some(&z)) = (self.start.get(x), self.start.get(x + 1)) else {
                continue;
            };
            if let Some(slot) = window.slot_mut(x, y) {
                // The sweep's list is spent; the pixel is emitted from
                // `kept`.
                slot.points.clear();
                slot.kept.clear();
                for i in a..z {
                    if self.alive.get(i) == Some(&true)
                        && let Some(&p) = self.points.get(i)
                    {
                        slot.kept.push(p);
                    }
                }
            }
        }
        for list in &mut self.darts_above {
            list.clear();
        }
        self.darts_above.resize_with(width, Vec::new);
        for &i in &self.darts {
            let i = i as usize;
            if self.alive.get(i) == Some(&true)
                && let (Some(&p), Some(&x)) = (self.points.get(i), self.pixel.get(i))
                && let Some(slot) = window.slot_mut(x as usize, y)
            {
                slot.kept.push(p);
                if let Some(list) = self.darts_above.get_mut(x as usize) {
                    list.push(p);
                }
            }
        }
        if let Some(feedback) = &mut self.feedback {
            // Where each point lies in its pixel: `p - x` is exact, as `p`
            // lies in `[x, x + 1)` (Sterbenz), the bits of `p - floor(p)`.
            #[expect(clippy::cast_precision_loss, reason = "pixel indices < 2^32")]
            let top = y as f64;
            feedback.observe((0..width).flat_map(|x| {
                #[expect(clippy::cast_precision_loss, reason = "pixel indices < 2^32")]
                let left = x as f64;
                window
                    .slot(x, y)
                    .kept
                    .iter()
                    .map(move |p| [p[0] - left, p[1] - top])
            }));
            let [bx, by, g, e, cc, ss, cs, sc] = feedback.trim();
            let [bx0, by0, g0, e0] = self.base;
            self.bias = [bx0 + bx, by0 + by, g0 + g];
            self.side = e0 + e;
            self.cross = [cc, ss, cs, sc];
        }
        self.strip_row = None;
        if self.method == ExactMethod::Eliminate && self.rows_up == 1 {
            // Anything lower lies more than `2rₑ` above every point of the
            // rows below (which start at `y + 1`, up to rounding: hence
            // the margin, far above it).
            #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
            let low = (y + 1) as f64 - self.reach - 1e-6;
            self.strip.resize_with(width, Vec::new);
            for (x, list) in self.strip.iter_mut().enumerate() {
                list.clear();
                list.extend(
                    window
                        .slot(x, y)
                        .kept
                        .iter()
                        .filter(|q| q[1] >= low)
                        .copied(),
                );
            }
            self.strip_row = Some(y);
        }
    }
}
