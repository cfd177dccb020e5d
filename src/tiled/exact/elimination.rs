//! Exact mode's step 3 by [`ExactMethod::Eliminate`]: weighted sample
//! elimination (Yuksel 2015) of the row settled, the row below counted as
//! it will be once thinned (the module docs of `exact` have the rule).

#[cfg(doc)]
use super::ExactMethod;
use super::{ByCell, Entry, Exact, columns_around};
use crate::tiled::window::Window;
use crate::vector::distance_squared;

/// Exponent of the elimination weight (Yuksel's α).
const ALPHA: i32 = 8;

/// The sign bit of an `f64`'s bits.
const SIGN: u64 = 1 << 63;

impl Entry {
    fn new(weight: f64, index: u32) -> Self {
        // `total_cmp`'s order as unsigned integers: negative weights have
        // every bit flipped, the others only the sign bit.
        let bits = weight.to_bits();
        let key = if bits & SIGN == 0 { bits | SIGN } else { !bits };
        Self((u128::from(key) << 32) | u128::from(u32::MAX - index))
    }

    fn parts(self) -> (f64, u32) {
        #[expect(clippy::cast_possible_truncation, reason = "the two halves")]
        let (key, low) = ((self.0 >> 32) as u64, self.0 as u32);
        let bits = if key & SIGN == 0 { !key } else { key & !SIGN };
        (f64::from_bits(bits), u32::MAX - low)
    }
}

impl Exact {
    fn weight_of(&self, d2: f64) -> f64 {
        if d2 < self.reach * self.reach {
            self.weight_in_reach(d2)
        } else {
            0.0
        }
    }

    /// [`Self::weight_of`] for `d2` below the reach squared.
    #[inline(always)]
    fn weight_in_reach(&self, d2: f64) -> f64 {
        (1.0 - d2.sqrt() * self.inv_reach).powi(ALPHA)
    }

    /// Step 3's starting weights, without the final points above: for
    /// every point elimination may remove (`over`), the sum of its weight
    /// terms over the live points closer than `2rₑ`, each scaled by the
    /// other end's pixel's `scale`, added in the order of the local grid
    /// (`cell_items`), which is the order [`Self::near`] meets them in.
    /// Each pair is found once, from the end that comes first in that
    /// order, looking only forward: the rest of its own cell row, then the
    /// cell rows below; its term (`distance_squared` is the same both ways
    /// round, bit for bit) is added to both ends at once. Each end still
    /// gets its terms in grid order: first those of the pairs where it is
    /// the later end, as the earlier ends come, then its own. Points of row
    /// `y + 1` are never removed here, so the pairs found from them (all
    /// within row `y + 1`, which comes last in the grid) are not looked for.
    fn pair_weights(&mut self, width: usize, band_rows: usize) {
        let n = self.n;
        self.over.clear();
        self.over
            .extend(self.alive.iter().zip(&self.pixel).map(|(&a, &b)| {
                a && (b as usize) < width && self.count.get(b as usize).is_some_and(|&c| c > n)
            }));
        self.scale.clear();
        self.scale
            .extend(self.count.iter().enumerate().map(|(b, &c)| {
                if b >= width && c > n {
                    #[expect(clippy::cast_precision_loss, reason = "counts per pixel")]
                    let share = n as f64 / c as f64;
                    share
                } else {
                    1.0
                }
            }));
        let reach2 = self.reach * self.reach;
        let columns = width * self.cells;
        let rows = band_rows * self.cells;
        let k = self.cell_reach;
        // The live points in grid order, so that a cell row's points are
        // read in sequence, without the two indirections (point, pixel).
        let mut by_cell = core::mem::take(&mut self.by_cell);
        by_cell.clear();
        by_cell.extend(self.cell_items.iter().map(|&i| {
            let i = i as usize;
            let p = self.points.get(i).copied().unwrap_or([0.0; 2]);
            let over = self.over.get(i) == Some(&true);
            let scale = self
                .pixel
                .get(i)
                .and_then(|&b| self.scale.get(b as usize))
                .copied()
                .unwrap_or(1.0);
            ByCell {
                p,
                over,
                scale,
                weight: 0.0,
            }
        }));
        for (a, &i) in self.cell_items.iter().enumerate() {
            let Some(&c) = self.cell_of.get(i as usize) else {
                continue;
            };
            let (cx, cy) = (c % columns, c / columns);
            if cy >= self.cells {
                // Row `y + 1` from here on.
                break;
            }
            let Some(&ByCell {
                p, over: over_i, ..
            }) = by_cell.get(a)
            else {
                continue;
            };
            let (x0, x1) = (cx.saturating_sub(k), (cx + k).min(columns - 1));
            for yy in cy..=(cy + k).min(rows - 1) {
                let first = if yy == cy {
                    a + 1
                } else {
                    self.cell_start.get(yy * columns + x0).copied().unwrap_or(0)
                };
                let last = self
                    .cell_start
                    .get(yy * columns + x1 + 1)
                    .copied()
                    .unwrap_or(0);
                let Some((head, tail)) = by_cell.split_at_mut_checked(first) else {
                    continue;
                };
                let (Some(this), Some(others)) =
                    (head.get_mut(a), tail.get_mut(..last.saturating_sub(first)))
                else {
                    continue;
                };
                // `i` lies in row `y`, so its own terms count in full on
                // its neighbours' weights (scale 1). Without a branch: a
                // pair out of reach, or with neither end removable, adds a
                // term of +0.0, which leaves every sum's bits as they are
                // (sums of terms >= 0 are never -0.0).
                let mut w = this.weight;
                for q in others {
                    let d2 = distance_squared(&p, &q.p);
                    let term = self.weight_in_reach(d2);
                    let t = if d2 < reach2 && (over_i || q.over) {
                        term
                    } else {
                        0.0
                    };
                    w += t * q.scale;
                    q.weight += t;
                }
                this.weight = w;
            }
        }
        // Back to the points' order; only removable points' weights are
        // read again.
        let mut weight = core::mem::take(&mut self.weight);
        for (&i, q) in self.cell_items.iter().zip(&by_cell) {
            if q.over
                && let Some(slot) = weight.get_mut(i as usize)
            {
                *slot = q.weight;
            }
        }
        self.by_cell = by_cell;
        self.weight = weight;
    }

    /// The live points elimination may remove (`over`) closer than `2rₑ`
    /// to point `i` (one of them), with their weight terms, into
    /// `neighbours`: what `i`'s removal takes from their weights (the same
    /// terms, bit for bit, as [`Self::pair_weights`] added: `i`'s scale
    /// is 1).
    fn neighbours_of(&mut self, i: usize, y: usize, width: usize, band_rows: usize) {
        let mut found = core::mem::take(&mut self.neighbours);
        found.clear();
        if let Some(&p) = self.points.get(i) {
            let reach2 = self.reach * self.reach;
            self.near(&p, y, width, band_rows, |j| {
                if j as usize != i
                    && self.alive.get(j as usize) == Some(&true)
                    && self.over.get(j as usize) == Some(&true)
                    && let Some(q) = self.points.get(j as usize)
                {
                    let d2 = distance_squared(&p, q);
                    if d2 < reach2 {
                        found.push((j, self.weight_of(d2)));
                    }
                }
            });
        }
        self.neighbours = found;
    }

    /// Step 3, [`ExactMethod::Eliminate`]: weighted sample elimination of
    /// row `y` until each of its pixels is down to `n`, the band's other
    /// points and the final points above counted as neighbours.
    pub(super) fn eliminate(&mut self, window: &Window, y: usize, width: usize, band_rows: usize) {
        #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
        let top = y as f64;
        let total = self.points.len();
        self.weight.clear();
        self.weight.resize(total, 0.0);
        self.factor.clear();
        self.factor.resize(total, 1.0);
        self.pair_weights(width, band_rows);
        let mut entries = core::mem::take(&mut self.sorted);
        entries.clear();
        self.heap.clear();
        for i in 0..total {
            let (Some(&p), Some(true), Some(&b), Some(&w)) = (
                self.points.get(i),
                self.over.get(i).copied(),
                self.pixel.get(i),
                self.weight.get(i),
            ) else {
                continue;
            };
            let mut w = w;
            if p[1] - top < self.reach {
                let x = b as usize % width;
                w += if y > 0 && self.strip_row == Some(y - 1) && window.holds_row(y - 1) {
                    self.strip
                        .get(columns_around(x, width))
                        .unwrap_or(&[])
                        .iter()
                        .flatten()
                        .map(|q| self.weight_of(distance_squared(&p, q)))
                        .sum::<f64>()
                } else {
                    self.final_above(window, y, x, width)
                        .map(|q| self.weight_of(distance_squared(&p, q)))
                        .sum::<f64>()
                };
            }
            let f = self.edge_factor(i);
            if let (Some(slot), Some(g)) = (self.weight.get_mut(i), self.factor.get_mut(i)) {
                *slot = w;
                *g = f;
            }
            #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
            entries.push(Entry::new(w * f, i as u32));
        }
        // Largest first. Most entries are popped before row `y` is done
        // (about 1.1 pops an entry at `n = 4`): sorting them once costs
        // less than a heap of them all; the heap holds only the weights
        // lowered since, and each pop takes the larger of the two fronts.
        // All keys differ (the index is part of them), so the pops come in
        // the order one heap of everything gave.
        entries.sort_unstable_by(|a, b| b.cmp(a));
        self.sorted = entries;
        let mut next = 0;
        // Pixels of row `y` still over `n`: the loop ends when none is.
        let mut left = self
            .count
            .get(..width)
            .unwrap_or(&[])
            .iter()
            .filter(|&&c| c > self.n)
            .count();
        while left > 0
            && let Some(entry) = match (self.sorted.get(next), self.heap.peek()) {
                (Some(&e), Some(&h)) if e > h => {
                    next += 1;
                    Some(e)
                }
                (Some(&e), None) => {
                    next += 1;
                    Some(e)
                }
                _ => self.heap.pop(),
            }
        {
            let (w, i) = entry.parts();
            let i = i as usize;
            let (Some(&is_alive), Some(&current), Some(&f), Some(&b)) = (
                self.alive.get(i),
                self.weight.get(i),
                self.factor.get(i),
                self.pixel.get(i),
            ) else {
                continue;
            };
            if !is_alive
                || w != current * f
                || self.count.get(b as usize).is_none_or(|&c| c <= self.n)
            {
                continue;
            }
            self.kill(i);
            if (b as usize) < width && self.count.get(b as usize) == Some(&self.n) {
                left -= 1;
            }
            // Its neighbours are looked up again, rather than kept from
            // the start: about one point in five is removed.
            self.neighbours_of(i, y, width, band_rows);
            for &(j32, t) in &self.neighbours {
                let j = j32 as usize;
                if let Some(wj) = self.weight.get_mut(j) {
                    *wj -= t;
                    let wj = *wj;
                    let still_over = self
                        .pixel
                        .get(j)
                        .and_then(|&c| self.count.get(c as usize))
                        .is_some_and(|&c| c > self.n);
                    if still_over && let Some(&f) = self.factor.get(j) {
                        self.heap.push(Entry::new(wj * f, j32));
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Entry, Exact, ExactMethod};
    use crate::random::{below, seeded_rng, unit};
    use crate::vector::distance_squared;

    /// Elimination's starting weights are, for each point of an over-full
    /// pixel of row `y`, the sum over the live band points closer than
    /// `2rₑ` of their terms, scaled by `n / c` for those of row `y + 1`
    /// (`c` their pixel's live points, when over `n`); and nothing else
    /// gets a weight. A brute-force sum over every pair, against
    /// `pair_weights`' grid search, which looks forward from row `y` only.
    #[test]
    fn starting_weights_are_the_scaled_sums_over_the_band() {
        let (n, width, y, band_rows) = (4, 12, 7, 2);
        let mut exact = Exact::new(n, ExactMethod::Eliminate, 0.3, None);
        let mut rng = seeded_rng(11);
        // Pixels with 2 to 9 points, so some are short, some at n, most over.
        for row in 0..band_rows {
            for x in 0..width {
                exact.start.push(exact.points.len());
                let m = 2 + below(&mut rng, 8);
                for _ in 0..m {
                    #[expect(clippy::cast_precision_loss, reason = "small")]
                    let p = [x as f64 + unit(&mut rng), (y + row) as f64 + unit(&mut rng)];
                    exact.points.push(p);
                    #[expect(clippy::cast_possible_truncation, reason = "small")]
                    exact.pixel.push((row * width + x) as u32);
                }
            }
        }
        exact.start.push(exact.points.len());
        let total = exact.points.len();
        // Every seventh point dead, as a dart's blocker would be.
        exact.alive = (0..total).map(|i| i % 7 != 3).collect();
        exact.count = vec![0; band_rows * width];
        for (i, &b) in exact.pixel.iter().enumerate() {
            if exact.alive[i] {
                exact.count[b as usize] += 1;
            }
        }
        exact.index_cells(y, width, band_rows);
        exact.weight = vec![0.0; total];
        exact.pair_weights(width, band_rows);
        let (mut checked, mut scaled) = (0, 0);
        for i in 0..total {
            let b = exact.pixel[i] as usize;
            let over = exact.alive[i] && b < width && exact.count[b] > n;
            assert_eq!(exact.over[i], over, "point {i}");
            if !over {
                assert_eq!(exact.weight[i], 0.0, "point {i}");
                continue;
            }
            let mut sum = 0.0;
            for j in (0..total).filter(|&j| j != i && exact.alive[j]) {
                let c = exact.pixel[j] as usize;
                let t = exact.weight_of(distance_squared(&exact.points[i], &exact.points[j]));
                #[expect(clippy::cast_precision_loss, reason = "small counts")]
                let s = if c >= width && exact.count[c] > n {
                    n as f64 / exact.count[c] as f64
                } else {
                    1.0
                };
                if t > 0.0 && s < 1.0 {
                    scaled += 1;
                }
                sum += t * s;
            }
            assert!(
                (exact.weight[i] - sum).abs() <= 1e-12 * sum.max(1.0),
                "point {i}: {} against {sum}",
                exact.weight[i]
            );
            checked += 1;
        }
        assert!(
            checked > 30 && scaled > 10,
            "{checked} weights, {scaled} scaled terms"
        );
    }

    /// The packed heap entry orders as `total_cmp` on the weight, the
    /// lower index first on ties, and gives back what it was made from.
    #[test]
    fn entry_order_is_the_weights_then_the_lower_index() {
        let weights = [
            f64::NEG_INFINITY,
            -3.5,
            -1e-300,
            -0.0,
            0.0,
            5e-324,
            1e-300,
            0.25,
            0.250_000_000_000_000_06,
            7.0,
            f64::INFINITY,
        ];
        let indices = [0, 1, 7, u32::MAX - 1, u32::MAX];
        let entries: Vec<(f64, u32)> = weights
            .iter()
            .flat_map(|&w| indices.iter().map(move |&i| (w, i)))
            .collect();
        for &(w, i) in &entries {
            let (w2, i2) = Entry::new(w, i).parts();
            assert_eq!((w2.to_bits(), i2), (w.to_bits(), i));
            for &(v, j) in &entries {
                let expected = w.total_cmp(&v).then(j.cmp(&i));
                assert_eq!(
                    Entry::new(w, i).cmp(&Entry::new(v, j)),
                    expected,
                    "{w} {i} {v} {j}"
                );
            }
        }
    }
}
