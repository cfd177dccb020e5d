//! Exact mode: exactly `n` points in every pixel, by weighted sample
//! elimination (Yuksel 2015, "Sample Elimination for Generating Poisson Disk
//! Sample Sets") applied to an oversampled sweep, a row at a time.
//!
//! The sweep runs at the radius that gives about [`OVERSAMPLE`]`·n` points
//! per pixel. When row `y` is complete, the points of rows `y` and `y + 1`
//! are thinned *together*: the point with the largest weight
//! `Σ (1 - d/2rₑ)⁸` over neighbours closer than `2rₑ` is removed, again and
//! again, except from pixels already down to `n`, where
//! `rₑ = sqrt(1 / (2√3·n))` is the spacing of `n` points per pixel on a
//! hexagonal lattice. The neighbours are the band's remaining points and
//! the final points of the rows above. Row `y` keeps its result; row
//! `y + 1`'s is thrown away and done again with row `y` fixed. So every row
//! is thinned with thinned rows on both sides and jointly along its length:
//! no pixel border is favoured; thinning pixel by pixel favours some
//! (`docs/performance-journal.md` has the bands it left).
//!
//! Measured with `examples/stream.rs --pixels 160x160 --exact N`, the
//! density in 0.1-pixel bands along the pixel edges relative to the pixel
//! interior is 0.95–1.01 for `n = 8`, 0.91–0.96 for `n = 4` and 0.72–0.74
//! for `n = 1`. Part of this is inherent: the best-spread set with exactly
//! one point per pixel draws its points toward the pixel centres, like a
//! jittered lattice; exact counts and edge-blind density pull against each
//! other as `n` gets small.
//!
//! Elimination only removes points, so the set keeps the minimum distance of
//! the oversampled sweep. A pixel left with fewer than `n` points (rare at
//! this oversampling) is topped up with best-candidate darts: of 32 uniform
//! darts in the pixel, the one farthest from every point near it. Those may
//! come closer than the sweep's radius; [`Pixels::top_ups`] counts them.
//!
//! [`Pixels::top_ups`]: super::Pixels::top_ups

use super::window::Window;
use crate::random::unit;
use crate::vector::distance_squared;
use core::cmp::Ordering;
use rand::Rng;
use std::collections::BinaryHeap;

/// Points per pixel the sweep makes, relative to the `n` kept.
pub(crate) const OVERSAMPLE: f64 = 2.0;

/// Exponent of the elimination weight (Yuksel's α).
const ALPHA: i32 = 8;

/// Darts per best-candidate top-up.
const DARTS: usize = 32;

/// Elimination settings for `n` points per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Thinning {
    n: usize,
    /// `2rₑ`: the reach of the weight.
    reach: f64,
    /// Pixels searched on each side for neighbours.
    pixels: usize,
}

/// A heap entry: a point's weight when pushed (stale if it changed since).
#[derive(Clone, Copy, Debug)]
struct Entry(f64, usize);

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(other.1.cmp(&self.1))
    }
}

impl Thinning {
    pub(crate) fn new(n: usize) -> Self {
        #[expect(clippy::cast_precision_loss, reason = "a count per pixel")]
        let r_e = (1.0 / (2.0 * 3f64.sqrt() * n as f64)).sqrt();
        let reach = 2.0 * r_e;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "reach <= 2 / sqrt(2√3) < 2 pixels"
        )]
        let pixels = reach.ceil() as usize;
        Self { n, reach, pixels }
    }

    fn weight(&self, d2: f64) -> f64 {
        if d2 < self.reach * self.reach {
            (1.0 - d2.sqrt() / self.reach).powi(ALPHA)
        } else {
            0.0
        }
    }

    /// Thins row `y` to exactly `n` points per pixel, jointly with row
    /// `y + 1` (whose thinning is discarded), against the final points of
    /// the rows above; stores the result as the row's points and final
    /// points. Returns the number of top-up darts placed.
    pub(crate) fn thin_row<R: Rng + ?Sized>(
        &self,
        window: &mut Window,
        y: usize,
        (width, height): (usize, usize),
        rng: &mut R,
    ) -> usize {
        // The band: every point of rows y and y + 1, with its band pixel.
        let band_rows = if y + 1 < height && window.holds_row(y + 1) {
            2
        } else {
            1
        };
        let mut points: Vec<[f64; 2]> = Vec::new();
        let mut pixel_of: Vec<usize> = Vec::new();
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); band_rows * width];
        for row in 0..band_rows {
            for x in 0..width {
                let b = row * width + x;
                for &p in &window.slot(x, y + row).points {
                    if let Some(list) = members.get_mut(b) {
                        list.push(points.len());
                    }
                    points.push(p);
                    pixel_of.push(b);
                }
            }
        }
        // Final points of the rows above row y within reach of the band
        // pixel at row offset `row`, column `x`.
        let window_ref: &Window = window;
        let above = |row: usize, x: usize| {
            ((y + row).saturating_sub(self.pixels)..y)
                .filter(|&yy| window_ref.holds_row(yy))
                .flat_map(move |yy| {
                    (x.saturating_sub(self.pixels)..=(x + self.pixels).min(width - 1))
                        .flat_map(move |xx| window_ref.slot(xx, yy).kept.iter())
                })
        };
        // Band pixels within reach of band pixel b.
        let reach = self.pixels;
        let near = |b: usize| {
            let (row, x) = (b / width, b % width);
            (row.saturating_sub(reach)..=(row + reach).min(band_rows - 1)).flat_map(move |r| {
                (x.saturating_sub(reach)..=(x + reach).min(width - 1)).map(move |xx| r * width + xx)
            })
        };
        let mut weight = vec![0.0; points.len()];
        for (i, p) in points.iter().enumerate() {
            let b = pixel_of.get(i).copied().unwrap_or(0);
            let mut w = 0.0;
            for nb in near(b) {
                for &j in members.get(nb).into_iter().flatten() {
                    if j != i
                        && let Some(q) = points.get(j)
                    {
                        w += self.weight(distance_squared(p, q));
                    }
                }
            }
            w += above(b / width, b % width)
                .map(|q| self.weight(distance_squared(p, q)))
                .sum::<f64>();
            if let Some(slot) = weight.get_mut(i) {
                *slot = w;
            }
        }
        let mut count: Vec<usize> = members.iter().map(Vec::len).collect();
        let mut alive = vec![true; points.len()];
        let mut heap: BinaryHeap<Entry> = weight
            .iter()
            .enumerate()
            .map(|(i, &w)| Entry(w, i))
            .collect();
        while let Some(Entry(w, i)) = heap.pop() {
            let (Some(&is_alive), Some(&current), Some(&b)) =
                (alive.get(i), weight.get(i), pixel_of.get(i))
            else {
                continue;
            };
            if !is_alive || w != current || count.get(b).is_none_or(|&c| c <= self.n) {
                continue;
            }
            if let (Some(a), Some(c)) = (alive.get_mut(i), count.get_mut(b)) {
                *a = false;
                *c -= 1;
            }
            let Some(&p) = points.get(i) else { continue };
            for nb in near(b) {
                for &j in members.get(nb).into_iter().flatten() {
                    if alive.get(j) == Some(&true)
                        && let (Some(q), Some(wj)) = (points.get(j), weight.get_mut(j))
                    {
                        let dw = self.weight(distance_squared(&p, q));
                        if dw > 0.0 {
                            *wj -= dw;
                            heap.push(Entry(*wj, j));
                        }
                    }
                }
            }
        }
        // Row y's survivors, in generation order, topped up if short.
        let mut top_ups = 0;
        let mut results: Vec<Vec<[f64; 2]>> = Vec::with_capacity(width);
        for x in 0..width {
            let mut mine: Vec<[f64; 2]> = members
                .get(x)
                .into_iter()
                .flatten()
                .filter(|&&i| alive.get(i) == Some(&true))
                .filter_map(|&i| points.get(i).copied())
                .collect();
            if mine.len() < self.n {
                let others: Vec<[f64; 2]> = near(x)
                    .flat_map(|nb| members.get(nb).into_iter().flatten())
                    .filter(|&&i| alive.get(i) == Some(&true))
                    .filter_map(|&i| points.get(i).copied())
                    .chain(above(0, x).copied())
                    .collect();
                top_ups += self.top_up(&mut mine, &others, (x, y), rng);
            }
            results.push(mine);
        }
        for (x, mine) in results.into_iter().enumerate() {
            if let Some(slot) = window.slot_mut(x, y) {
                slot.kept.clone_from(&mine);
                slot.points = mine;
            }
        }
        top_ups
    }

    /// Adds best-candidate darts to pixel `(x, y)` until it holds `n`.
    fn top_up<R: Rng + ?Sized>(
        &self,
        mine: &mut Vec<[f64; 2]>,
        others: &[[f64; 2]],
        (x, y): (usize, usize),
        rng: &mut R,
    ) -> usize {
        #[expect(clippy::cast_precision_loss, reason = "pixel indices < 2^32")]
        let (fx, fy) = (x as f64, y as f64);
        let mut placed = 0;
        while mine.len() < self.n {
            let mut best = (f64::NEG_INFINITY, [fx, fy]);
            for _ in 0..DARTS {
                let dart = [fx + unit(rng), fy + unit(rng)];
                if dart[0] >= fx + 1.0 || dart[1] >= fy + 1.0 {
                    continue;
                }
                let nearest = mine
                    .iter()
                    .chain(others)
                    .map(|q| distance_squared(&dart, q))
                    .fold(f64::INFINITY, f64::min);
                if nearest > best.0 {
                    best = (nearest, dart);
                }
            }
            mine.push(best.1);
            placed += 1;
        }
        placed
    }
}
