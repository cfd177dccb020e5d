//! Exact mode's step 2: a pixel of the row left short gets darts that keep
//! the sweep's radius, each taking its room from points of other pixels
//! (its *blockers*) in stages, and a top-up only if every stage fails
//! (the module docs of `exact` have the rules).

use super::{DartScratch, Exact, columns_around};
use crate::random::unit;
use crate::tiled::window::Window;
use crate::vector::distance_squared;
use rand::Rng;

/// Darts thrown per point a short pixel needs, first and at most.
const DARTS: usize = 32;
const DARTS_MORE: usize = 256;
/// Further rounds of [`DARTS_MORE`] fresh darts, taking from any pixel the
/// pass allows, before a short pixel gets a top-up: its room can be a
/// sliver. At exact mode's `k = 10` the last stage's 256 darts missed it
/// about once per 10⁶ points (ten top-ups in sixteen runs of 512² at
/// `n = 4`); with 2 048 darts in all, none in fourteen.
const RESCUE_ROUNDS: usize = 7;

/// A dart with more blockers than this is not taken.
const MAX_BLOCKERS: usize = 4;

/// Uniform darts in the pixel whose corner is `(fx, fy)`.
fn throw_darts<R: Rng + ?Sized>(darts: &mut [[f64; 2]], (fx, fy): (f64, f64), rng: &mut R) {
    for d in darts {
        *d = [fx + unit(rng), fy + unit(rng)];
        // Rounding onto the far edge: the pixel's corner instead.
        if d[0] >= fx + 1.0 || d[1] >= fy + 1.0 {
            *d = [fx, fy];
        }
    }
}

/// Passes over a row that mend short pixels (see [`Take::Any`]).
const MEND_PASSES: usize = 4;

/// Which pixels a dart may take points from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Take {
    /// Pixels that keep at least `n` points afterwards.
    Excess,
    /// Those, and pixels not yet mended (right of the dart's in its row,
    /// or in the row below), which may fall short: they get darts in turn.
    Unsettled,
    /// Any other pixel of the band; a pixel of the row left short is
    /// mended on the next pass.
    Any,
}

/// What a dart would cost: the band points closer than `r` to it.
#[derive(Clone, Copy, Debug)]
struct Blockers {
    count: usize,
    items: [u32; MAX_BLOCKERS],
}

impl Exact {
    /// Step 2: darts for every short pixel of row `y`, left to right, in
    /// up to [`MEND_PASSES`] passes. Returns the number of top-ups.
    pub(super) fn mend_row<R: Rng + ?Sized>(
        &mut self,
        window: &mut Window,
        y: usize,
        (width, band_rows): (usize, usize),
        rng: &mut R,
    ) -> usize {
        let mut top_ups = 0;
        self.cleared.clear();
        // A dart may, as a last resort, take a point from a pixel of the
        // row already mended, which then gets mended again on the next
        // pass; the last pass may not, so it ends the row.
        for pass in 0..MEND_PASSES {
            let mut short = false;
            for x in 0..width {
                while self.count.get(x).is_some_and(|&c| c < self.n) {
                    short = true;
                    let settled_ok = pass + 1 < MEND_PASSES;
                    top_ups += self.add_dart(window, (x, y), (width, band_rows), settled_ok, rng);
                }
            }
            if !short {
                break;
            }
        }
        top_ups
    }

    /// Step 2: one more point for the short pixel `(x, y)`; 1 if it had to
    /// be a top-up, else 0.
    fn add_dart<R: Rng + ?Sized>(
        &mut self,
        window: &mut Window,
        (x, y): (usize, usize),
        (width, band_rows): (usize, usize),
        settled_ok: bool,
        rng: &mut R,
    ) -> usize {
        #[expect(clippy::cast_precision_loss, reason = "pixel indices < 2^32")]
        let (fx, fy) = (x as f64, y as f64);
        let mut darts = [[0.0; 2]; DARTS_MORE];
        let mut thrown = 0;
        // Filled apart from `self`, which it reads, then put back: the
        // darts below read it there.
        let mut near = core::mem::take(&mut self.dart_scratch);
        self.gather_blockers(window, (x, y), (width, band_rows), &mut near);
        self.dart_scratch = near;
        // Strict with a few darts, then lenient with them, then lenient
        // with many, then (if allowed) taking from any pixel: most short
        // pixels take the first.
        let stages = [
            (Take::Excess, DARTS),
            (Take::Unsettled, DARTS),
            (Take::Unsettled, DARTS_MORE),
            (Take::Any, DARTS_MORE),
        ];
        for (take, count) in stages {
            if take == Take::Any && !settled_ok {
                continue;
            }
            throw_darts(
                darts.get_mut(thrown..count).unwrap_or(&mut []),
                (fx, fy),
                rng,
            );
            thrown = thrown.max(count);
            let found = self.best_dart(darts.get(..count).unwrap_or(&[]), (x, y), take);
            if let Some((d, b)) = found {
                self.take_dart(window, d, b, x);
                return 0;
            }
        }
        let take = if settled_ok {
            Take::Any
        } else {
            Take::Unsettled
        };
        for _ in 0..RESCUE_ROUNDS {
            throw_darts(&mut darts, (fx, fy), rng);
            if let Some((d, b)) = self.best_dart(&darts, (x, y), take) {
                self.take_dart(window, d, b, x);
                return 0;
            }
        }
        // Hemmed in by points that never go (its own, darts, final points
        // above): before a top-up, take every point of the pixel out, once
        // a row, and let darts place all `n` again, each taking its room
        // from other pixels as above. At oversampling 1.0 (128², seeds 1 to
        // 3, `n` = 2 to 16) this cut the top-ups from 148 to 20; at the
        // default oversampling it is the one a 1024² run (`n = 4`, seed 2)
        // needed. A pixel robbed here is mended on the next pass, so it
        // is not done on the last.
        if settled_ok && !self.cleared.contains(&x) {
            self.cleared.push(x);
            self.clear_pixel(x);
            return 0;
        }
        // A top-up: the dart farthest from every point that stays, looked
        // for as far as the local grid reaches (built for the first top-up
        // of the band: they are rare).
        if !self.indexed {
            self.index_cells(y, width, band_rows);
        }
        let mut best = (f64::NEG_INFINITY, [fx, fy]);
        for d in &darts {
            let mut nearest = self
                .final_above(window, y, x, width)
                .map(|q| distance_squared(d, q))
                .fold(f64::INFINITY, f64::min);
            self.near(d, y, width, band_rows, |i| {
                if self.alive.get(i as usize) == Some(&true)
                    && let Some(q) = self.points.get(i as usize)
                {
                    nearest = nearest.min(distance_squared(d, q));
                }
            });
            for &i in &self.darts {
                if let Some(q) = self.points.get(i as usize) {
                    nearest = nearest.min(distance_squared(d, q));
                }
            }
            if nearest > best.0 {
                best = (nearest, *d);
            }
        }
        self.push_dart(best.1, x);
        1
    }

    /// The dart of `darts` with the fewest blockers that `take` may remove
    /// (at most [`MAX_BLOCKERS`]), the first such; `None` if none can go.
    fn best_dart(
        &self,
        darts: &[[f64; 2]],
        (x, y): (usize, usize),
        take: Take,
    ) -> Option<([f64; 2], Blockers)> {
        let mut best: Option<([f64; 2], Blockers)> = None;
        for d in darts {
            // Only a dart with fewer blockers than the best so far can be
            // taken: the search gives up on the others early.
            let cap = best.map_or(MAX_BLOCKERS, |(_, c)| c.count.saturating_sub(1));
            if let Some(b) = self.blockers(d, (x, y), (take, cap))
                && best.is_none_or(|(_, c)| b.count < c.count)
            {
                best = Some((*d, b));
                if b.count == 0 {
                    break;
                }
            }
        }
        best
    }

    /// What the darts of the short pixel `(x, y)` are checked against, into
    /// `near` ([`DartScratch`]): gathered once per dart placed, since
    /// nothing it holds changes until one is.
    fn gather_blockers(
        &self,
        window: &Window,
        (x, y): (usize, usize),
        (width, band_rows): (usize, usize),
        near: &mut DartScratch,
    ) {
        near.darts.clear();
        near.darts.extend(
            self.dart_columns
                .get(columns_around(x, width))
                .unwrap_or(&[])
                .iter()
                .flatten()
                .filter(|&&i| self.alive.get(i as usize) == Some(&true))
                .filter_map(|&i| self.points.get(i as usize).copied()),
        );
        near.above.clear();
        near.above
            .extend(self.final_above(window, y, x, width).copied());
        near.own.clear();
        near.near.clear();
        self.near_pixel(x, width, band_rows, |i| {
            if self.alive.get(i as usize) == Some(&true)
                && let (Some(&q), Some(&b)) =
                    (self.points.get(i as usize), self.pixel.get(i as usize))
            {
                if b as usize == x {
                    near.own.push(q);
                } else {
                    near.near.push((q, i, b));
                }
            }
            true
        });
    }

    /// Takes every live point of pixel `x` of the row out: its band points
    /// and its darts.
    fn clear_pixel(&mut self, x: usize) {
        let (a, z) = (
            self.start.get(x).copied().unwrap_or(0),
            self.start.get(x + 1).copied().unwrap_or(0),
        );
        for i in a..z {
            self.kill(i);
        }
        // Column `x`'s darts are pixel `x`'s (`push_dart`); taken out of
        // `self` while `kill` borrows it, then put back.
        let darts = core::mem::take(&mut self.dart_columns);
        for &i in darts.get(x).map_or(&[][..], Vec::as_slice) {
            self.kill(i as usize);
        }
        self.dart_columns = darts;
    }

    /// Places dart `d` in column `x`, its blockers `b` removed.
    fn take_dart(&mut self, window: &mut Window, d: [f64; 2], b: Blockers, x: usize) {
        for &i in b.items.get(..b.count).unwrap_or(&[]) {
            self.kill(i as usize);
        }
        self.push_dart(d, x);
        // The sweep's later points keep their distance from it. Its cell
        // can only hold a point that is out (a blocker, or one thinned
        // before): two points in one cell are closer than r.
        window.replace(d);
    }

    fn push_dart(&mut self, d: [f64; 2], x: usize) {
        #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
        self.darts.push(self.points.len() as u32);
        #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
        if let Some(list) = self.dart_columns.get_mut(x) {
            list.push(self.points.len() as u32);
        }
        self.points.push(d);
        #[expect(clippy::cast_possible_truncation, reason = "x < width < 2^32")]
        self.pixel.push(x as u32);
        self.alive.push(true);
        if let Some(c) = self.count.get_mut(x) {
            *c += 1;
        }
    }

    /// The band points closer than `r` to dart `d` in pixel `(x, y)`, if
    /// they may all be removed: each in another pixel, which `take` allows
    /// to lose it, at most `cap` (and [`MAX_BLOCKERS`]); and no final point
    /// above or dart is that close. They are looked for among what
    /// [`Self::gather_blockers`] put in `dart_scratch`.
    fn blockers(
        &self,
        d: &[f64; 2],
        (x, y): (usize, usize),
        (take, cap): (Take, usize),
    ) -> Option<Blockers> {
        let near = &self.dart_scratch;
        let r2 = self.radius_squared;
        if near.darts.iter().any(|q| distance_squared(d, q) < r2) {
            return None;
        }
        #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
        if d[1] - (y as f64) < r2.sqrt() && near.above.iter().any(|q| distance_squared(d, q) < r2) {
            return None;
        }
        // A point of the dart's own pixel can never go. Whether a dart is
        // refused does not depend on the order the points are checked in.
        if near.own.iter().any(|q| distance_squared(d, q) < r2) {
            return None;
        }
        let mut found = Blockers {
            count: 0,
            items: [0; MAX_BLOCKERS],
        };
        for &(q, i, b32) in &near.near {
            if distance_squared(d, &q) >= r2 {
                continue;
            }
            let b = b32 as usize;
            // Points this dart already takes from pixel b, this one included.
            let taken = 1 + found
                .items
                .get(..found.count)
                .unwrap_or(&[])
                .iter()
                .filter(|&&j| self.pixel.get(j as usize) == Some(&b32))
                .count();
            let left = self.count.get(b).copied().unwrap_or(0);
            // `b != x`: the pixel's own points are in `near.own`, checked
            // above.
            let may = found.count < cap.min(MAX_BLOCKERS)
                && match take {
                    Take::Excess => left >= self.n + taken,
                    Take::Unsettled => left >= self.n + taken || b > x,
                    Take::Any => true,
                };
            match (may, found.items.get_mut(found.count)) {
                (true, Some(slot)) => {
                    *slot = i;
                    found.count += 1;
                }
                _ => return None,
            }
        }
        Some(found)
    }
}
