//! The offline generator of `src/render/net_table.rs`: the bank of
//! well-spaced (0,m,2)-nets behind `bridson::NetPixelSampler`.
//!
//! ```text
//! cargo run --release --example net_bank -- --out src/render/net_table.rs
//! cargo run --release --example net_bank -- --max-m 6     # a quick look, no file
//! cargo run --release --example net_bank -- --min-m 8 --max-m 8 --shift-from 7
//! ```
//!
//! # What it makes
//! For every `m` in `0..=max_m` (`N = 2^m` points), a bank of nets on the
//! `N × N` grid of cells: net `s` puts the point of column `c` in row
//! `rows[s][c]`. A set of cells is a (0,m,2)-net when every elementary
//! interval of area `1/N` (`2^-k` wide, `2^-(m-k)` tall, any `k`) holds one
//! point; the sampler then moves every point by the same offset inside its
//! cell, so the spacing of the sampled set is exactly that of the cells.
//!
//! # Balanced banks (`m < --shift-from`)
//! `S = spread · max(1, N/16)` nets. Simulated annealing, all `S` nets of
//! one `N` at once, over one move that keeps the net property: the two
//! points sharing an elementary interval of area `2/N` (shape
//! `2^-a × 2^-(m-1-a)`) swap rows. Every other interval keeps its count, so
//! the set stays a net (the generator checks it after every run too). The
//! energy is
//! - spacing: the sum over pairs closer than `R = 1.25 d_hex` of
//!   `(R²/d² - 1)³` (toroidal distance on the grid of cells);
//! - balance, weighted up as the run cools: the sampler's moves (half
//!   shifts and the reflections on each axis, the x↔y swap) map a cell to
//!   an orbit of 16 or 32 cells named by the pair of column and row
//!   classes; for every sample index to be equally likely in every cell,
//!   the bank must put `S·|orbit|/N` of its points in each orbit. The
//!   penalty is the total distance from those counts, and a bank is
//!   written only when it is 0.
//!
//! # Shift-invariant banks (`m >= --shift-from`)
//! Nets whose every cyclic shift of the columns is a net as well:
//! Hammersley's `(c, reverse(c))` with the rows Owen-scrambled and the
//! columns left alone. The sampler shifts the columns by a uniform number
//! of cells, so every cell is equally likely for every sample without any
//! balance from the bank; that is what lets the bank reach 256 points and
//! beyond (a balanced bank of 256 did not converge). By default one net
//! per `m`, in closed form: the row of column `c` is
//! `reverse(c ^ (c << 1) mod 2^m)`. `--shift-sets K` makes `K` (halved for
//! every doubling above 256 points) and `--shift-steps K` anneals each
//! net's flip flags from there, `K` flips tried per point.
//!
//! Single-threaded and deterministic: the same flags give the same table.

#![allow(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    clippy::cast_precision_loss,
    reason = "an offline tool on small grids: cells, counts and levels fit every type"
)]
#![allow(
    clippy::type_complexity,
    clippy::needless_range_loop,
    reason = "index loops over parallel arrays read more plainly here"
)]

use std::fmt::Write as _;
use std::process::ExitCode;
use std::time::Instant;

/// Improving moves a repair step collects before it picks the cheapest.
const REPAIR_CANDIDATES: usize = 64;

/// SplitMix64: the generator's random stream.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next()) * n as u128) >> 64) as usize
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The hexagonal packing distance of `n` points on the unit torus.
fn d_hex(n: usize) -> f64 {
    (2.0 / (3f64.sqrt() * n as f64)).sqrt()
}

/// The class of column (or row) `c` of `2^m` under the moves x -> x ^ top,
/// x -> !x: `0..2^(m-2)` for `m >= 2`, 0 below.
fn class(c: usize, m: u32) -> usize {
    if m < 3 {
        return 0;
    }
    let mask = (1usize << (m - 1)) - 1;
    let mut low = c & mask;
    if low & 1 == 1 {
        low ^= mask;
    }
    low >> 1
}

/// One `m`'s bank under construction.
struct Bank {
    m: u32,
    n: usize,
    sets: usize,
    rows: Vec<Vec<usize>>,
    cols: Vec<Vec<usize>>,
    /// Cells within `reach` columns are scanned for neighbours.
    reach: usize,
    r2: f64,
    /// Points of the bank per orbit, and the counts wanted.
    counts: Vec<i64>,
    targets: Vec<i64>,
    classes: usize,
}

impl Bank {
    fn new(m: u32, spread: usize, rng: &mut Rng) -> Self {
        let n = 1usize << m;
        let sets = (n / 16).max(1) * spread;
        // The Hammersley net (c, reverse(c)), then a random Owen scramble of
        // each axis: a net, different for every set.
        let mut rows: Vec<Vec<usize>> = Vec::new();
        for s in 0..sets {
            // Nets come in pairs that start alike: a swap changes a net's
            // Walsh sums sum_p chi_u(x_p) chi_v(y_p) by multiples of 4, so
            // each net's sums are fixed mod 4, and balance needs the bank's
            // to vanish; two nets with the same residues always cancel.
            if s % 2 == 1 {
                rows.push(rows[s - 1].clone());
                continue;
            }
            rows.push(scrambled_hammersley(m, rng));
        }
        Self::with_rows(m, rows)
    }

    /// A bank of the given nets, with its orbit counts and targets.
    fn with_rows(m: u32, rows: Vec<Vec<usize>>) -> Self {
        let n = 1usize << m;
        let sets = rows.len();
        let classes = if m < 3 { 1 } else { n / 4 };
        let cols: Vec<Vec<usize>> = rows
            .iter()
            .map(|row| {
                let mut col = vec![0; n];
                for (c, &r) in row.iter().enumerate() {
                    col[r] = c;
                }
                col
            })
            .collect();
        let r = 1.25 * d_hex(n) * n as f64;
        let reach = (r.ceil() as usize).min(n / 2);
        let mut bank = Self {
            m,
            n,
            sets,
            rows,
            cols,
            reach,
            r2: r * r,
            counts: vec![0; classes * classes],
            targets: vec![0; classes * classes],
            classes,
        };
        // Targets: S·|orbit|/N per orbit, kept at its lowest-index cell
        // pair (a <= b); the other entries stay 0.
        for a in 0..classes {
            for b in a..classes {
                let size = if m < 2 {
                    (n * n) as i64
                } else if a == b {
                    16
                } else {
                    32
                };
                let size = size.min((n * n) as i64);
                bank.targets[a * classes + b] = sets as i64 * size / n as i64;
            }
        }
        for s in 0..sets {
            for c in 0..n {
                let o = bank.orbit(c, bank.rows[s][c]);
                bank.counts[o] += 1;
            }
        }
        bank
    }

    fn orbit(&self, c: usize, r: usize) -> usize {
        let (a, b) = (class(c, self.m), class(r, self.m));
        a.min(b) * self.classes + a.max(b)
    }

    fn penalty(&self) -> i64 {
        self.counts
            .iter()
            .zip(&self.targets)
            .map(|(c, t)| (c - t).abs())
            .sum()
    }

    /// Squared toroidal distance between the cells of columns `a` and `b`.
    fn dist2(&self, s: usize, a: usize, b: usize) -> usize {
        let n = self.n;
        let dx = a.abs_diff(b);
        let dx = dx.min(n - dx);
        let dy = self.rows[s][a].abs_diff(self.rows[s][b]);
        let dy = dy.min(n - dy);
        dx * dx + dy * dy
    }

    fn pair_energy(&self, d2: usize) -> f64 {
        let d2 = d2 as f64;
        if d2 >= self.r2 {
            0.0
        } else {
            let t = self.r2 / d2 - 1.0;
            t * t * t
        }
    }

    /// The spacing energy of column `c`'s point with its neighbours.
    fn local(&self, s: usize, c: usize) -> f64 {
        let n = self.n;
        let mut e = 0.0;
        for dc in 1..=self.reach {
            for other in [(c + dc) % n, (c + n - dc) % n] {
                e += self.pair_energy(self.dist2(s, c, other));
                if self.reach * 2 >= n && dc * 2 == n {
                    break;
                }
            }
        }
        e
    }

    /// The column sharing an elementary interval of shape
    /// `2^-a × 2^-(m-1-a)` with column `c`.
    fn partner(&self, s: usize, c: usize, a: u32) -> usize {
        let m = self.m;
        let b = m - 1 - a;
        let r = self.rows[s][c];
        // Columns with the same top a bits; rows with the same top b bits.
        let col_shift = m - a;
        let row_shift = m - b;
        if (1usize << col_shift) <= (1usize << row_shift) {
            let start = (c >> col_shift) << col_shift;
            (start..start + (1 << col_shift))
                .find(|&o| o != c && self.rows[s][o] >> row_shift == r >> row_shift)
                .expect("a net has a partner in every interval")
        } else {
            let start = (r >> row_shift) << row_shift;
            (start..start + (1 << row_shift))
                .map(|o| self.cols[s][o])
                .find(|&o| o != c && o >> col_shift == c >> col_shift)
                .expect("a net has a partner in every interval")
        }
    }

    fn swap(&mut self, s: usize, a: usize, b: usize) {
        let (ra, rb) = (self.rows[s][a], self.rows[s][b]);
        self.rows[s][a] = rb;
        self.rows[s][b] = ra;
        self.cols[s][ra] = b;
        self.cols[s][rb] = a;
    }

    /// The change in balance penalty if columns `a` and `b` of set `s`
    /// swapped rows.
    fn penalty_delta(&self, s: usize, a: usize, b: usize) -> i64 {
        let (ra, rb) = (self.rows[s][a], self.rows[s][b]);
        let changes = [
            (self.orbit(a, ra), -1),
            (self.orbit(b, rb), -1),
            (self.orbit(a, rb), 1),
            (self.orbit(b, ra), 1),
        ];
        let mut touched = [(usize::MAX, 0i64); 4];
        let mut len = 0;
        for (o, d) in changes {
            match touched[..len].iter_mut().find(|(t, _)| *t == o) {
                Some((_, acc)) => *acc += d,
                None => {
                    touched[len] = (o, d);
                    len += 1;
                }
            }
        }
        touched[..len]
            .iter()
            .map(|&(o, d)| {
                let (c, t) = (self.counts[o], self.targets[o]);
                (c + d - t).abs() - (c - t).abs()
            })
            .sum()
    }

    fn apply_counts(&mut self, s: usize, a: usize, b: usize) {
        let (ra, rb) = (self.rows[s][a], self.rows[s][b]);
        let (o1, o2, o3, o4) = (
            self.orbit(a, ra),
            self.orbit(b, rb),
            self.orbit(a, rb),
            self.orbit(b, ra),
        );
        self.counts[o1] -= 1;
        self.counts[o2] -= 1;
        self.counts[o3] += 1;
        self.counts[o4] += 1;
    }

    /// Smallest squared toroidal distance of set `s`, in cells².
    fn min_dist2(&self, s: usize) -> usize {
        let mut best = usize::MAX;
        for a in 0..self.n {
            for b in a + 1..self.n {
                best = best.min(self.dist2(s, a, b));
            }
        }
        best
    }

    fn rho(&self, s: usize) -> f64 {
        if self.n < 2 {
            return f64::NAN;
        }
        (self.min_dist2(s) as f64).sqrt() / self.n as f64 / d_hex(self.n)
    }

    /// Every elementary interval of area `1/N` holds one point.
    fn is_net(&self, s: usize) -> bool {
        let m = self.m;
        (0..=m).all(|k| {
            let mut seen = vec![false; self.n];
            (0..self.n).all(|c| {
                let cell = (c >> (m - k)) << (m - k) | self.rows[s][c] >> k;
                !std::mem::replace(&mut seen[cell], true)
            })
        })
    }

    fn anneal(&mut self, moves_per_point: usize, l0: f64, l1: f64, rng: &mut Rng) {
        if self.m == 0 {
            return;
        }
        let total = moves_per_point * self.n * self.sets;
        let (t0, t1) = (2.0f64, 0.002f64);
        let mut penalty = self.penalty();
        for step in 0..total {
            let f = step as f64 / total as f64;
            let t = t0 * (t1 / t0).powf(f);
            let lambda = if l1 > 0.0 {
                l0 * (l1 / l0).powf(f)
            } else {
                0.0
            };
            let s = rng.below(self.sets);
            let a = rng.below(self.n);
            let level = rng.below(self.m as usize) as u32;
            let b = self.partner(s, a, level);
            let dp = self.penalty_delta(s, a, b);
            let before =
                self.local(s, a) + self.local(s, b) - self.pair_energy(self.dist2(s, a, b));
            self.swap(s, a, b);
            let after = self.local(s, a) + self.local(s, b) - self.pair_energy(self.dist2(s, a, b));
            let delta = after - before + lambda * dp as f64;
            if delta <= 0.0 || rng.unit() < (-delta / t).exp() {
                self.swap(s, a, b);
                self.apply_counts(s, a, b);
                self.swap(s, a, b);
                penalty += dp;
            } else {
                self.swap(s, a, b);
            }
        }
        // Repair: a swap, or a pair of swaps, starting at a point in an
        // orbit over its count, that lowers the penalty; of those, the one
        // that costs the least spacing energy. Until the penalty is 0.
        let mut kicks = 0;
        while penalty > 0 {
            let Some(best) = self.repair_step(rng) else {
                if std::env::var_os("NET_BANK_DEBUG").is_some() {
                    eprintln!("  repair: stuck at penalty {penalty}, kick {kicks}");
                }
                // A kick: a few random swaps that raise the penalty by at
                // most 2 each, then repair again.
                kicks += 1;
                if kicks > 400 {
                    return;
                }
                let mut done = 0;
                while done < 3 {
                    let s = rng.below(self.sets);
                    let a = rng.below(self.n);
                    let level = rng.below(self.m as usize) as u32;
                    let b = self.partner(s, a, level);
                    let dp = self.penalty_delta(s, a, b);
                    if dp <= 2 {
                        self.apply_counts(s, a, b);
                        self.swap(s, a, b);
                        done += 1;
                    }
                }
                penalty = self.penalty();
                continue;
            };
            if std::env::var_os("NET_BANK_DEBUG").is_some() {
                eprintln!("  repair: penalty {penalty}, {} swaps", best.len());
            }
            for &(s, a, b) in &best {
                self.apply_counts(s, a, b);
                self.swap(s, a, b);
            }
            penalty = self.penalty();
        }
        debug_assert_eq!(penalty, self.penalty(), "penalty bookkeeping");
    }

    /// The cheapest (in spacing energy) one or two swaps that lower the
    /// balance penalty. A swap lowers it only if it takes a point out of an
    /// orbit over its count (of its four ±1 effects at least three must be
    /// gains, and only two are removals... so at least one removal is from
    /// an overfull orbit), so the second swap is sought among those; the
    /// first is any swap that raises the penalty by at most 4.
    fn repair_step(&mut self, rng: &mut Rng) -> Option<Vec<(usize, usize, usize)>> {
        type Found = Option<(i64, f64, Vec<(usize, usize, usize)>)>;
        let mut best: Found = None;
        let mut found = 0usize;
        let consider = |best: &mut Found,
                        found: &mut usize,
                        dp: i64,
                        de: f64,
                        moves: Vec<(usize, usize, usize)>| {
            if dp < 0 {
                *found += 1;
                if best
                    .as_ref()
                    .is_none_or(|(bp, be, _)| dp < *bp || (dp == *bp && de < *be))
                {
                    *best = Some((dp, de, moves));
                }
            }
        };
        // The points of every orbit.
        let mut members: Vec<Vec<(usize, usize)>> = vec![Vec::new(); self.counts.len()];
        for s in 0..self.sets {
            for c in 0..self.n {
                members[self.orbit(c, self.rows[s][c])].push((s, c));
            }
        }
        // Orbits over their count now; a first swap can only add the two
        // orbits its points move to, whose other points are in `members`
        // and whose moved points are tried below.
        let overfull: Vec<usize> = (0..self.counts.len())
            .filter(|&o| self.counts[o] > self.targets[o])
            .collect();
        // First swaps in a random order; the search stops once it has seen
        // REPAIR_CANDIDATES improving moves and takes the cheapest of them
        // (the whole scan is slow at 256 points and beyond).
        let (sets, n) = (self.sets, self.n);
        let (s0, c0) = (rng.below(sets), rng.below(n));
        for s in (0..sets).map(|k| (k + s0) % sets) {
            if found >= REPAIR_CANDIDATES {
                break;
            }
            for c in (0..n).map(|k| (k + c0) % n) {
                for level in 0..self.m {
                    let d = self.partner(s, c, level);
                    if c > d {
                        continue;
                    }
                    let dp1 = self.penalty_delta(s, c, d);
                    if dp1 > 4 {
                        continue;
                    }
                    let e1 = self.swap_energy(s, c, d);
                    if dp1 < 0 {
                        consider(&mut best, &mut found, dp1, e1, vec![(s, c, d)]);
                    }
                    self.apply_counts(s, c, d);
                    self.swap(s, c, d);
                    let moved = [
                        self.orbit(c, self.rows[s][c]),
                        self.orbit(d, self.rows[s][d]),
                    ];
                    let fresh = moved.iter().filter(|o| !overfull.contains(o));
                    for &o in overfull.iter().chain(fresh) {
                        if self.counts[o] <= self.targets[o] {
                            continue;
                        }
                        for &(s2, c2) in &members[o] {
                            if s2 == s && (c2 == c || c2 == d) {
                                continue;
                            }
                            for level2 in 0..self.m {
                                let d2 = self.partner(s2, c2, level2);
                                let dp2 = self.penalty_delta(s2, c2, d2);
                                if dp1 + dp2 < 0 {
                                    let e2 = self.swap_energy(s2, c2, d2);
                                    consider(
                                        &mut best,
                                        &mut found,
                                        dp1 + dp2,
                                        e1 + e2,
                                        vec![(s, c, d), (s2, c2, d2)],
                                    );
                                }
                            }
                        }
                    }
                    // The swapped points themselves, in their new orbits.
                    for c2 in [c, d] {
                        for level2 in 0..self.m {
                            let d2 = self.partner(s, c2, level2);
                            let dp2 = self.penalty_delta(s, c2, d2);
                            if dp1 + dp2 < 0 {
                                let e2 = self.swap_energy(s, c2, d2);
                                consider(
                                    &mut best,
                                    &mut found,
                                    dp1 + dp2,
                                    e1 + e2,
                                    vec![(s, c, d), (s, c2, d2)],
                                );
                            }
                        }
                    }
                    // Undo the first swap: counts back, then rows back.
                    self.apply_counts(s, c, d);
                    self.swap(s, c, d);
                }
            }
        }
        best.map(|(_, _, moves)| moves)
    }

    /// Prints the bank's nonzero symmetrized Walsh sums over the
    /// characters the moves leave alone (top bit clear, even weight).
    fn walsh_report(&self) {
        let m = self.m;
        let inv: Vec<usize> = (1..self.n)
            .filter(|u| u >> (m - 1) == 0 && u.count_ones().is_multiple_of(2))
            .collect();
        let chi = |u: usize, c: usize| {
            if (u & c).count_ones().is_multiple_of(2) {
                1i64
            } else {
                -1
            }
        };
        for &u in &inv {
            for &v in &inv {
                if v < u {
                    continue;
                }
                let mut total = 0i64;
                let mut per_set = Vec::new();
                for s in 0..self.sets {
                    let w: i64 = (0..self.n)
                        .map(|c| {
                            chi(u, c) * chi(v, self.rows[s][c])
                                + chi(v, c) * chi(u, self.rows[s][c])
                        })
                        .sum();
                    per_set.push(w);
                    total += w;
                }
                if total != 0 {
                    eprintln!("  u {u:#b} v {v:#b}: total {total}, per set {per_set:?}");
                }
            }
        }
    }

    /// The spacing energy change if columns `a` and `b` of set `s` swapped
    /// rows.
    fn swap_energy(&mut self, s: usize, a: usize, b: usize) -> f64 {
        let before = self.local(s, a) + self.local(s, b) - self.pair_energy(self.dist2(s, a, b));
        self.swap(s, a, b);
        let after = self.local(s, a) + self.local(s, b) - self.pair_energy(self.dist2(s, a, b));
        self.swap(s, a, b);
        after - before
    }

    /// Greedy polish of each set's minimum distance: a swap is kept when
    /// it brings no pair closer than the set's current minimum, leaves the
    /// balance alone, and does not add pairs at the minimum.
    fn polish(&mut self, moves_per_point: usize, rng: &mut Rng) {
        if self.m == 0 {
            return;
        }
        for s in 0..self.sets {
            let mut floor = self.min_dist2(s);
            for _ in 0..moves_per_point * self.n {
                let a = rng.below(self.n);
                let level = rng.below(self.m as usize) as u32;
                let b = self.partner(s, a, level);
                if self.penalty_delta(s, a, b) != 0 {
                    continue;
                }
                let at_floor = |bank: &Self| bank.near(s, a, floor) + bank.near(s, b, floor);
                let before = at_floor(self);
                let lowest_before = self.nearest(s, a).min(self.nearest(s, b));
                self.swap(s, a, b);
                let after = at_floor(self);
                let lowest_after = self.nearest(s, a).min(self.nearest(s, b));
                let worse = lowest_after < floor
                    || (lowest_after == floor && after > before)
                    || (lowest_after == floor && lowest_before > floor);
                if worse {
                    self.swap(s, a, b);
                } else if lowest_after > floor || after < before {
                    let now = self.min_dist2(s);
                    floor = now;
                }
            }
        }
    }

    /// Pairs of column `c` at squared distance `d2` or less.
    fn near(&self, s: usize, c: usize, d2: usize) -> usize {
        (0..self.n)
            .filter(|&o| o != c && self.dist2(s, c, o) <= d2)
            .count()
    }

    fn nearest(&self, s: usize, c: usize) -> usize {
        (0..self.n)
            .filter(|&o| o != c)
            .map(|o| self.dist2(s, c, o))
            .min()
            .unwrap_or(usize::MAX)
    }
}

/// A net on the `2^m × 2^m` grid that stays a net under every cyclic
/// shift of its columns: the Hammersley net `(c, reverse(c))` with its rows
/// Owen-scrambled (bit `i` from the top of the row of column `c` flipped
/// as the flag of node `(i, c mod 2^i)` says; its columns stay put). The
/// top `j` bits of a row then depend on `c mod 2^j` alone, and do so one
/// to one, which is what every shifted elementary interval needs.
///
/// It starts from the flags `flag(i, q) = bit i-1 of q`, the row of column
/// `c` being `reverse(c ^ (c << 1) mod 2^m)`: ρ 0.658 for even `m` (at 16
/// points no flags do better: an exhaustive search over all 2^15) and
/// 0.670 to 0.736 for odd `m`. With `steps > 0` the flags are then
/// annealed for spacing (a flip moves the `2^(m-i)` points of one node by
/// `2^(m-1-i)` rows), and the result is kept only if its minimum distance
/// is no smaller.
fn shift_invariant_net(m: u32, steps: usize, rng: &mut Rng) -> Vec<usize> {
    let n = 1usize << m;
    // flags[i] holds the 2^i flags of level i.
    let mut flags: Vec<Vec<bool>> = (0..m as usize)
        .map(|i| {
            (0..1usize << i)
                .map(|q| i > 0 && (q >> (i - 1)) & 1 == 1)
                .collect()
        })
        .collect();
    let row_of = |flags: &Vec<Vec<bool>>, c: usize| {
        let mut r = 0;
        for i in 0..m as usize {
            let bit = (c >> i) & 1 ^ usize::from(flags[i][c & ((1 << i) - 1)]);
            r |= bit << (m as usize - 1 - i);
        }
        r
    };
    let rows: Vec<usize> = (0..n).map(|c| row_of(&flags, c)).collect();
    debug_assert!(
        (0..n).all(|c| rows[c] == reverse((c ^ c << 1) & (n - 1), m)),
        "the closed form"
    );
    let mut bank = Bank::with_rows(m, vec![rows]);
    if m < 2 || steps == 0 {
        return bank.rows.swap_remove(0);
    }
    let start = (bank.min_dist2(0), bank.rows[0].clone());
    let (t0, t1) = (0.05f64, 0.002f64);
    let reach = bank.reach;
    for step in 0..steps {
        let f = step as f64 / steps as f64;
        let t = t0 * (t1 / t0).powf(f);
        // Deep levels are cheap and local; shallow ones move many points.
        let i = (m as usize - 1).saturating_sub(rng.below(m as usize).min(rng.below(m as usize)));
        let q = rng.below(1 << i);
        let stride = 1usize << i;
        let delta_row = 1usize << (m as usize - 1 - i);
        // Energy of every pair with at least one moved point: pairs inside
        // the moved set are met twice.
        let energy = |bank: &Bank| {
            let mut e = 0.0;
            for c in (q..n).step_by(stride) {
                e += bank.local(0, c);
                let mut k = stride;
                while k <= reach {
                    for d in [(c + k) % n, (c + n - k) % n] {
                        e -= 0.5 * bank.pair_energy(bank.dist2(0, c, d));
                        if 2 * k == n {
                            break;
                        }
                    }
                    k += stride;
                }
            }
            e
        };
        let flip = |bank: &mut Bank| {
            for c in (q..n).step_by(stride) {
                let r = bank.rows[0][c] ^ delta_row;
                bank.rows[0][c] = r;
                bank.cols[0][r] = c;
            }
        };
        let before = energy(&bank);
        flip(&mut bank);
        let delta = energy(&bank) - before;
        if delta <= 0.0 || rng.unit() < (-delta / t).exp() {
            flags[i][q] = !flags[i][q];
        } else {
            flip(&mut bank);
        }
    }
    debug_assert!(
        (0..n).all(|c| bank.rows[0][c] == row_of(&flags, c)),
        "the rows follow the flags"
    );
    if bank.min_dist2(0) < start.0 {
        return start.1;
    }
    bank.rows.swap_remove(0)
}

/// Whether every cyclic shift of the columns of `row` is a net.
fn shift_invariant(m: u32, row: &[usize]) -> bool {
    let n = 1usize << m;
    let mut seen = vec![false; n];
    (0..n).all(|t| {
        (0..=m).all(|k| {
            seen.fill(false);
            (0..n).all(|c| {
                let cell = (c >> (m - k)) << (m - k) | row[(c + t) % n] >> k;
                !std::mem::replace(&mut seen[cell], true)
            })
        })
    })
}

/// The Hammersley net `(c, reverse(c))` under a random Owen scramble of
/// each axis, as rows by column.
fn scrambled_hammersley(m: u32, rng: &mut Rng) -> Vec<usize> {
    let n = 1usize << m;
    let flips_x = owen_flips(m, rng);
    let flips_y = owen_flips(m, rng);
    let mut row = vec![0; n];
    for c in 0..n {
        let r = reverse(c, m);
        row[scramble(c, m, &flips_x)] = scramble(r, m, &flips_y);
    }
    row
}

fn reverse(c: usize, m: u32) -> usize {
    if m == 0 {
        0
    } else {
        c.reverse_bits() >> (usize::BITS - m)
    }
}

/// Random flip bits for every node of an `m`-level binary tree.
fn owen_flips(m: u32, rng: &mut Rng) -> Vec<bool> {
    (0..(1usize << m)).map(|_| rng.next() & 1 == 1).collect()
}

/// Owen scramble of the `m`-bit `c`: bit `l` (from the top) flips as the
/// tree node of the `l` bits above it says.
fn scramble(c: usize, m: u32, flips: &[bool]) -> usize {
    let mut out = 0;
    let mut node = 1usize;
    for l in 0..m {
        let bit = (c >> (m - 1 - l)) & 1;
        let flipped = bit ^ usize::from(flips[node]);
        out = out << 1 | flipped;
        node = node << 1 | bit;
    }
    out
}

fn main() -> ExitCode {
    let mut out: Option<String> = None;
    let mut max_m = 10u32;
    let mut moves = 400usize;
    let mut seed = 51u64;
    let mut spread = 1usize;
    let mut lambda = 50.0f64;
    let mut lambda0 = 0.05f64;
    let mut min_m = 0u32;
    let mut shift_from = u32::MAX;
    let mut shift_sets = 1usize;
    let mut shift_steps = 0usize;
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().unwrap_or_default();
        match flag.as_str() {
            "--out" => out = Some(value),
            "--max-m" => max_m = value.parse().unwrap_or(10),
            "--moves" => moves = value.parse().unwrap_or(400),
            "--seed" => seed = value.parse().unwrap_or(51),
            "--spread" => spread = value.parse().unwrap_or(1),
            "--lambda" => lambda = value.parse().unwrap_or(50.0),
            "--min-m" => min_m = value.parse().unwrap_or(0),
            "--lambda0" => lambda0 = value.parse().unwrap_or(0.05),
            "--shift-from" => shift_from = value.parse().unwrap_or(u32::MAX),
            "--shift-sets" => shift_sets = value.parse().unwrap_or(1),
            "--shift-steps" => shift_steps = value.parse().unwrap_or(0),
            _ => {
                eprintln!(
                    "usage: net_bank [--out FILE] [--min-m M] [--max-m M] [--moves K] [--seed S] \
                     [--spread K] [--lambda0 L] [--lambda L] [--shift-from M] [--shift-sets K] \
                     [--shift-steps K]"
                );
                return ExitCode::from(2);
            }
        }
    }
    let mut table = String::new();
    let flags: Vec<String> = std::env::args().skip(1).collect();
    let _ = write!(
        table,
        "//! Generated by `cargo run --release --example net_bank -- {}`\n\
         //! (examples/net_bank.rs); do not edit. `NETS[m]` holds \
         (0,m,2)-nets on the\n//! `2^m × 2^m` grid of cells, net after net: \
         entry `c` of a net is the row of\n//! the point in column `c`: \
         `{spread} · max(1, 2^m / 16)` balanced nets below\n//! `m = {shift_from}`, \
         shift-invariant ones from there on (`SHIFTED[m]`).\n\n",
        flags.join(" ")
    );
    let mut names = Vec::new();
    let mut shifted_flags = Vec::new();
    for m in 0..=max_m {
        if m < min_m && out.is_none() {
            continue;
        }
        let started = Instant::now();
        // Fewer moves per point as N grows: the work grows with N·S·reach.
        let k = if m <= 6 {
            moves
        } else {
            moves >> (m - 6).min(3)
        };
        // A run can end in a local minimum of the balance it cannot leave;
        // the next attempt starts from another seed.
        let mut attempt = 0u64;
        let bank = loop {
            let mut rng = Rng(seed ^ u64::from(m) << 32 ^ attempt << 48);
            let mut bank = if m >= shift_from {
                // Fewer sets above 256 points: the column shifts balance
                // any bank, and every entry reaches the same ρ.
                let sets = (shift_sets >> m.saturating_sub(8)).max(1);
                let rows = (0..sets)
                    .map(|_| shift_invariant_net(m, shift_steps << m, &mut rng))
                    .collect();
                Bank::with_rows(m, rows)
            } else {
                let mut bank = Bank::new(m, spread, &mut rng);
                bank.anneal(k, lambda0.min(lambda), lambda, &mut rng);
                bank
            };
            let shifted = m >= shift_from;
            if !shifted {
                bank.polish(k / 4 + 4, &mut rng);
            }
            // Shift-invariant nets need no balance from the bank: the
            // sampler shifts their columns by a uniform whole number of
            // cells, which spreads every point over every cell.
            let penalty = if shifted { 0 } else { bank.penalty() };
            let nets = (0..bank.sets)
                .all(|s| bank.is_net(s) && (!shifted || shift_invariant(m, &bank.rows[s])));
            eprintln!(
                "N {:5}, attempt {attempt}: {} sets, nets {nets}, balance penalty {penalty}, {:.1} s",
                bank.n,
                bank.sets,
                started.elapsed().as_secs_f64()
            );
            if nets && penalty == 0 {
                break bank;
            }
            if std::env::var_os("NET_BANK_DEBUG").is_some() {
                bank.walsh_report();
            }
            attempt += 1;
            if attempt == 8 {
                eprintln!("net_bank: N {} failed; no table written", bank.n);
                return ExitCode::FAILURE;
            }
        };
        if m < min_m {
            continue;
        }
        let mut rhos: Vec<f64> = (0..bank.sets).map(|s| bank.rho(s)).collect();
        rhos.sort_by(f64::total_cmp);
        eprintln!(
            "N {:5}: {:3} sets, ρ min {:.3} median {:.3} max {:.3}",
            bank.n,
            bank.sets,
            rhos[0],
            rhos[rhos.len() / 2],
            rhos[rhos.len() - 1],
        );
        let name = format!("NET_{}", bank.n);
        let len = bank.n * bank.sets;
        let _ = writeln!(table, "#[rustfmt::skip]\nstatic {name}: [u16; {len}] = [");
        for s in 0..bank.sets {
            for chunk in bank.rows[s].chunks(16) {
                let line: Vec<String> = chunk.iter().map(|r| format!("{r},")).collect();
                let _ = writeln!(table, "    {}", line.join(" "));
            }
        }
        table.push_str("];\n\n");
        names.push(name);
        shifted_flags.push(m >= shift_from);
    }
    let _ = writeln!(
        table,
        "/// The bank of `2^m` points per net, for `m` in `0..={max_m}`.\n#[rustfmt::skip]\npub(crate) static NETS: [&[u16]; {}] = [{}];",
        names.len(),
        names
            .iter()
            .map(|n| format!("&{n}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        table,
        "\n/// Whether `NETS[m]` holds shift-invariant nets: every cyclic shift of\n/// an entry's columns is a net too.\n#[rustfmt::skip]\npub(crate) static SHIFTED: [bool; {}] = [{}];",
        shifted_flags.len(),
        shifted_flags
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(path) = out {
        if let Err(e) = std::fs::write(&path, table) {
            eprintln!("net_bank: cannot write {path}: {e}");
            return ExitCode::FAILURE;
        }
        eprintln!("net_bank: wrote {path}");
    }
    ExitCode::SUCCESS
}
