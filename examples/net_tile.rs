//! The offline generator of `src/render/net_tile.rs`: the toroidal tiles of
//! per-pixel keys that make `bridson::NetPixelSampler`'s error blue noise
//! across pixels (Heitz and Belcour's route, on the crate's own nets).
//!
//! ```text
//! cargo run --release --example net_tile -- --out src/render/net_tile.rs
//! cargo run --release --example net_tile -- --min-m 4 --max-m 4   # a quick look, no file
//! ```
//!
//! # What it makes
//! For every `m` in `0..=max_m` (`N = 2^m` samples per pixel), a `32 × 32`
//! tile of keys, one per pixel: a bank entry, a symmetry of the square (the
//! 32 of the sampler: half shifts and reflections on each axis, the x↔y
//! swap) and an offset inside the cells (8 bits on each axis). At run time
//! the sampler reads the tile at the pixel plus a toroidal offset hashed
//! from the seed and the dimension, and composes the key with moves shared
//! by the whole image for that seed and dimension: a uniform symmetry
//! (applied after the tile's), a uniform offset added to the tile's (mod
//! one cell) and, for shift-invariant banks, a uniform column shift.
//!
//! # Why the estimator stays unbiased
//! Each bank entry fills the same number of the tile's pixels, so over the
//! uniform tile offset every pixel's entry is uniform; the shared symmetry,
//! offset and shift are uniform group elements composed with the tile's,
//! so they are uniform and independent of the entry whatever the tile
//! holds. That is exactly the distribution of moves the sampler's balance
//! tests enumerate. Every move the annealing makes keeps the entry counts
//! (entries only swap places).
//!
//! # The objective
//! Training scenarios: an integrand of the pixel's film offset (a step
//! across the pixel at a random angle and position, or a disk), and the
//! shared moves drawn at random. For each, the error of every pixel's
//! estimate; the objective is the tile's periodogram power below 0.125
//! cycles per pixel (radius < 4 of 32), summed over scenarios, over the
//! total power (issue 51's measure). Simulated annealing over three moves:
//! swap two pixels' keys, draw a pixel's symmetry anew, draw or nudge its
//! offset. A held-out family (other steps and disks, other shared moves)
//! is reported at the end; a tile of random keys reads about 1.
//!
//! Single-threaded and deterministic: the same flags give the same table.

#![allow(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    clippy::cast_precision_loss,
    reason = "an offline tool on small grids: cells, counts and levels fit every type"
)]
#![allow(
    clippy::needless_range_loop,
    reason = "index loops over parallel arrays read more plainly here"
)]

#[path = "../src/render/net_table.rs"]
#[allow(dead_code, reason = "only the bank is used")]
mod net_table;
#[path = "common/step_area.rs"]
#[allow(
    dead_code,
    reason = "the held-out steps serve the tracer and its test, not training"
)]
mod step_area;

use net_table::{NETS, SHIFTED};
use std::fmt::Write as _;
use std::process::ExitCode;
use step_area::step_area;

/// Side of the tile, in pixels.
const SIDE: usize = 32;
const PIXELS: usize = SIDE * SIDE;

/// The low band: radial frequency index below this (0.125 · 32).
const LOW_RADIUS2: i64 = 16;

/// splitmix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next()) * n as u128) >> 64) as usize
    }
}

/// One pixel's key.
#[derive(Clone, Copy, Debug)]
struct Key {
    set: u32,
    /// Bits 0-1: x class (bit 0 half shift, bit 1 reflection), 2-3: y, 4: swap.
    sym: u32,
    /// Offsets inside the cell, 8 bits each.
    ox: u32,
    oy: u32,
}

impl Key {
    fn pack(self) -> u32 {
        self.sym | self.set << 5 | self.ox << 16 | self.oy << 24
    }

    fn unpack(key: u32) -> Self {
        Self {
            set: key >> 5 & 63,
            sym: key & 31,
            ox: key >> 16 & 255,
            oy: key >> 24,
        }
    }
}

/// The tiles of a file this tool wrote, by `m` (for `--keep`).
fn read_tiles(path: &str) -> Result<Vec<Vec<Key>>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut tiles = Vec::new();
    for (m, part) in text.split("static TILE_").skip(1).enumerate() {
        let body = part.split('[').nth(2).and_then(|b| b.split(']').next());
        let keys: Vec<Key> = body
            .unwrap_or_default()
            .split(',')
            .filter_map(|v| u32::from_str_radix(v.trim().trim_start_matches("0x"), 16).ok())
            .map(Key::unpack)
            .collect();
        if keys.len() != PIXELS {
            return Err(format!("{path}: tile {m} has {} keys", keys.len()));
        }
        tiles.push(keys);
    }
    Ok(tiles)
}

/// `g` after `t`, both symmetries in the sampler's 5-bit code.
fn compose(g: u32, t: u32) -> u32 {
    let (xt, yt, st) = (t & 3, t >> 2 & 3, t >> 4 & 1);
    let (xg, yg, sg) = (g & 3, g >> 2 & 3, g >> 4 & 1);
    let (x, y) = if st == 1 {
        (xt ^ yg, yt ^ xg)
    } else {
        (xt ^ xg, yt ^ yg)
    };
    x | y << 2 | (st ^ sg) << 4
}

/// An integrand of the film offset, with its exact (or very fine) integral.
#[derive(Clone, Copy, Debug)]
enum Shape {
    /// `1` where `a·x + b·y < c`.
    Step { a: f64, b: f64, c: f64 },
    /// `1` inside the disk of centre `(cx, cy)`, radius `r` (not wrapped).
    Disk { cx: f64, cy: f64, r: f64 },
}

impl Shape {
    #[inline(always)]
    fn eval(self, x: f64, y: f64) -> f64 {
        match self {
            Shape::Step { a, b, c } => f64::from(u8::from(a * x + b * y < c)),
            Shape::Disk { cx, cy, r } => {
                f64::from(u8::from((x - cx).powi(2) + (y - cy).powi(2) < r * r))
            }
        }
    }

    /// The integral over the unit square: the step's by clipping the
    /// square, the disk's by a 2048² midpoint grid.
    fn integral(self) -> f64 {
        match self {
            Shape::Step { a, b, c } => step_area([a, b, c]),
            Shape::Disk { .. } => {
                let g = 2048;
                let mut sum = 0.0;
                for i in 0..g {
                    for j in 0..g {
                        let x = (i as f64 + 0.5) / g as f64;
                        let y = (j as f64 + 0.5) / g as f64;
                        sum += self.eval(x, y);
                    }
                }
                sum / (g * g) as f64
            }
        }
    }

    fn random(rng: &mut Rng, disks: f64) -> Self {
        if rng.unit() < disks {
            Shape::Disk {
                cx: rng.unit(),
                cy: rng.unit(),
                r: 0.15 + 0.35 * rng.unit(),
            }
        } else {
            let theta = std::f64::consts::TAU * rng.unit();
            let (a, b) = (theta.cos(), theta.sin());
            // Through a uniform point of the square.
            let (px, py) = (rng.unit(), rng.unit());
            Shape::Step {
                a,
                b,
                c: a * px + b * py,
            }
        }
    }
}

/// One training (or held-out) scenario: an integrand and the shared moves.
#[derive(Clone, Copy, Debug)]
struct Scenario {
    shape: Shape,
    truth: f64,
    sym: u32,
    sx: u32,
    sy: u32,
    shift: u32,
}

fn scenarios(rng: &mut Rng, count: usize, disks: f64, n: u32, shifted: bool) -> Vec<Scenario> {
    (0..count)
        .map(|_| {
            let shape = Shape::random(rng, disks);
            Scenario {
                shape,
                truth: shape.integral(),
                sym: rng.below(32) as u32,
                sx: rng.next() as u32,
                sy: rng.next() as u32,
                shift: if shifted {
                    rng.below(n as usize) as u32
                } else {
                    0
                },
            }
        })
        .collect()
}

/// One count's bank and the sets' geometry.
struct Bank {
    n: u32,
    rows: &'static [u16],
    sets: u32,
}

impl Bank {
    /// The error of the estimate of `sc`'s integrand by the pixel of key `k`.
    #[inline(always)]
    fn error(&self, k: Key, sc: &Scenario) -> f64 {
        let n = self.n;
        let h = compose(sc.sym, k.sym);
        let flip = |bits: u32| ((n >> 1) * (bits & 1)) ^ ((n - 1) * (bits >> 1 & 1));
        let (fx, fy) = (flip(h & 3), flip(h >> 2 & 3));
        let mut ox = (k.ox << 24).wrapping_add(sc.sx);
        let mut oy = (k.oy << 24).wrapping_add(sc.sy);
        if h & 2 != 0 {
            ox = !ox;
        }
        if h & 8 != 0 {
            oy = !oy;
        }
        let (ox, oy) = (
            f64::from(ox) / 4_294_967_296.0,
            f64::from(oy) / 4_294_967_296.0,
        );
        let scale = 1.0 / f64::from(n);
        let base = (k.set * n) as usize;
        let mut sum = 0.0;
        for c in 0..n {
            let x = ((c + sc.shift) & (n - 1)) ^ fx;
            let y = u32::from(self.rows[base + c as usize]) ^ fy;
            let (px, py) = ((f64::from(x) + ox) * scale, (f64::from(y) + oy) * scale);
            sum += if h & 16 != 0 {
                sc.shape.eval(py, px)
            } else {
                sc.shape.eval(px, py)
            };
        }
        sum * scale - sc.truth
    }
}

/// The low frequencies, half of them (the other half mirrors): `(kx, ky,
/// weight)`, weight 1 for DC and 2 for the rest.
fn low_band() -> Vec<(i64, i64, f64)> {
    let mut out = Vec::new();
    for ky in -4i64..=4 {
        for kx in -4i64..=4 {
            if kx * kx + ky * ky >= LOW_RADIUS2 {
                continue;
            }
            if ky > 0 || (ky == 0 && kx > 0) {
                out.push((kx, ky, 2.0));
            } else if kx == 0 && ky == 0 {
                out.push((0, 0, 1.0));
            }
        }
    }
    out
}

/// The annealing state for one count.
struct State<'a> {
    bank: &'a Bank,
    sc: Vec<Scenario>,
    keys: Vec<Key>,
    /// `errors[s * PIXELS + p]`.
    errors: Vec<f64>,
    /// `spectrum[s * band + f]`: the low-band DFT of each scenario's errors.
    spectrum: Vec<[f64; 2]>,
    /// `waves[p * band + f]`: `exp(-2πi k·p / 32)`.
    waves: Vec<[f64; 2]>,
    weights: Vec<f64>,
    low: f64,
    all: f64,
}

impl<'a> State<'a> {
    fn new(bank: &'a Bank, sc: Vec<Scenario>, keys: Vec<Key>) -> Self {
        let band = low_band();
        let mut waves = Vec::with_capacity(PIXELS * band.len());
        for p in 0..PIXELS {
            let (x, y) = ((p % SIDE) as f64, (p / SIDE) as f64);
            for &(kx, ky, _) in &band {
                let phase = -std::f64::consts::TAU * (kx as f64 * x + ky as f64 * y) / SIDE as f64;
                waves.push([phase.cos(), phase.sin()]);
            }
        }
        let mut s = Self {
            bank,
            keys,
            errors: vec![0.0; sc.len() * PIXELS],
            spectrum: vec![[0.0; 2]; sc.len() * band.len()],
            sc,
            waves,
            weights: band.iter().map(|b| b.2).collect(),
            low: 0.0,
            all: 0.0,
        };
        s.recompute();
        s
    }

    fn recompute(&mut self) {
        let b = self.weights.len();
        self.all = 0.0;
        for i in 0..self.sc.len() {
            let sc = self.sc[i];
            for p in 0..PIXELS {
                let e = self.bank.error(self.keys[p], &sc);
                self.errors[i * PIXELS + p] = e;
            }
            for f in 0..b {
                let mut acc = [0.0; 2];
                for p in 0..PIXELS {
                    let e = self.errors[i * PIXELS + p];
                    let w = self.waves[p * b + f];
                    acc[0] += e * w[0];
                    acc[1] += e * w[1];
                }
                self.spectrum[i * b + f] = acc;
            }
        }
        self.all = self.errors.iter().map(|e| e * e).sum();
        self.low = self.low_power(&self.spectrum);
    }

    fn low_power(&self, spectrum: &[[f64; 2]]) -> f64 {
        let b = self.weights.len();
        spectrum
            .iter()
            .enumerate()
            .map(|(i, z)| self.weights[i % b] * (z[0] * z[0] + z[1] * z[1]))
            .sum()
    }

    /// Issue 51's measure: mean low-band power over mean power.
    fn metric(&self) -> f64 {
        metric(self.low, self.all)
    }

    /// The low and total power with pixels `changed` given new keys, and
    /// their new errors in `errs` (nothing applied).
    fn propose(&self, changed: &[(usize, Key)], errs: &mut Vec<f64>) -> (f64, f64) {
        let b = self.weights.len();
        errs.clear();
        let (mut low, mut all) = (self.low, self.all);
        let mut delta = [[0.0f64; 2]; 32];
        for (i, sc) in self.sc.iter().enumerate() {
            delta[..b].fill([0.0; 2]);
            for &(p, k) in changed {
                let old = self.errors[i * PIXELS + p];
                let new = self.bank.error(k, sc);
                errs.push(new);
                all += new * new - old * old;
                let d = new - old;
                for f in 0..b {
                    let w = self.waves[p * b + f];
                    delta[f][0] += d * w[0];
                    delta[f][1] += d * w[1];
                }
            }
            for f in 0..b {
                let z = self.spectrum[i * b + f];
                let (re, im) = (z[0] + delta[f][0], z[1] + delta[f][1]);
                low += self.weights[f] * (re * re + im * im - z[0] * z[0] - z[1] * z[1]);
            }
        }
        (low, all)
    }

    fn apply(&mut self, changed: &[(usize, Key)], errs: &[f64], low: f64, all: f64) {
        let b = self.weights.len();
        let mut at = 0;
        for i in 0..self.sc.len() {
            for &(p, _) in changed {
                let e = &mut self.errors[i * PIXELS + p];
                let d = errs[at] - *e;
                *e = errs[at];
                at += 1;
                for f in 0..b {
                    let w = self.waves[p * b + f];
                    let z = &mut self.spectrum[i * b + f];
                    z[0] += d * w[0];
                    z[1] += d * w[1];
                }
            }
        }
        for &(p, k) in changed {
            self.keys[p] = k;
        }
        self.low = low;
        self.all = all;
    }
}

fn metric(low: f64, all: f64) -> f64 {
    // The periodogram is |DFT|² / PIXELS; its total, by Parseval, `all`.
    let band = 45.0;
    (low / PIXELS as f64 / band) / (all / PIXELS as f64)
}

/// Random keys with every bank entry equally often.
fn random_keys(rng: &mut Rng, sets: u32) -> Vec<Key> {
    let mut keys: Vec<Key> = (0..PIXELS)
        .map(|p| Key {
            set: p as u32 % sets,
            sym: rng.below(32) as u32,
            ox: rng.below(256) as u32,
            oy: rng.below(256) as u32,
        })
        .collect();
    for i in (1..PIXELS).rev() {
        let j = rng.below(i + 1);
        keys.swap(i, j);
    }
    keys
}

/// The held-out measure of `keys`: fresh scenarios, steps only and
/// steps with disks.
fn held_out(bank: &Bank, keys: &[Key], seed: u64, shifted: bool) -> (f64, f64) {
    let mut rng = Rng(seed ^ 0x0dd5_eed5);
    let steps = scenarios(&mut rng, 256, 0.0, bank.n, shifted);
    let disks = scenarios(&mut rng, 64, 1.0, bank.n, shifted);
    let a = State::new(bank, steps, keys.to_vec()).metric();
    let b = State::new(bank, disks, keys.to_vec()).metric();
    (a, b)
}

struct Options {
    min_m: u32,
    max_m: u32,
    steps: usize,
    scenarios: usize,
    disks: f64,
    seed: u64,
    t0: f64,
    t1: f64,
    refresh: usize,
    /// Tiles kept from an earlier run, for the `m` not remade.
    keep: Vec<Vec<Key>>,
    /// The commands that made the kept tiles (from the kept file's head).
    kept_by: Vec<String>,
}

fn anneal(m: u32, o: &Options) -> Vec<Key> {
    let n = 1u32 << m;
    let rows = NETS[m as usize];
    let shifted = SHIFTED[m as usize];
    let bank = Bank {
        n,
        rows,
        sets: (rows.len() / n as usize) as u32,
    };
    let mut rng = Rng(o.seed.wrapping_mul(0x1000_0001).wrapping_add(u64::from(m)));
    let train = scenarios(&mut rng, o.scenarios, o.disks, n, shifted);
    let start = random_keys(&mut rng, bank.sets);
    let (h0, d0) = held_out(&bank, &start, o.seed, shifted);
    let mut state = State::new(&bank, train, start);
    let first = state.metric();
    let mut refreshed = 0;
    let mut errs = Vec::new();
    let mut accepted = 0usize;
    let started = std::time::Instant::now();
    for step in 0..o.steps {
        let frac = step as f64 / o.steps as f64;
        let temp = o.t0 * (o.t1 / o.t0).powf(frac);
        let p = rng.below(PIXELS);
        let mut k = state.keys[p];
        let roll = rng.below(10);
        let changed: Vec<(usize, Key)> = match roll {
            0..=3 => {
                // Swap with a pixel anywhere (half the time a near one).
                let q = if rng.below(2) == 0 {
                    rng.below(PIXELS)
                } else {
                    let (x, y) = (p % SIDE, p / SIDE);
                    let dx = rng.below(5) + SIDE - 2;
                    let dy = rng.below(5) + SIDE - 2;
                    (x + dx) % SIDE + (y + dy) % SIDE * SIDE
                };
                if q == p {
                    continue;
                }
                vec![(p, state.keys[q]), (q, state.keys[p])]
            }
            4..=5 => {
                k.sym = rng.below(32) as u32;
                vec![(p, k)]
            }
            6..=7 => {
                k.ox = rng.below(256) as u32;
                k.oy = rng.below(256) as u32;
                vec![(p, k)]
            }
            _ => {
                k.ox = (k.ox + rng.below(33) as u32 + 256 - 16) & 255;
                k.oy = (k.oy + rng.below(33) as u32 + 256 - 16) & 255;
                vec![(p, k)]
            }
        };
        let (low, all) = state.propose(&changed, &mut errs);
        let now = metric(low, all);
        let before = state.metric();
        if now <= before || rng.unit() < (-(now - before) / temp).exp() {
            state.apply(&changed, &errs, low, all);
            accepted += 1;
        }
        if o.refresh > 0 && step % o.refresh == o.refresh - 1 {
            // A few training scenarios are replaced by fresh ones, so that
            // the tile follows the family, not one sample of it.
            let k = state.sc.len();
            for _ in 0..(k / 16).max(1) {
                state.sc[refreshed % k] = scenarios(&mut rng, 1, o.disks, n, shifted)[0];
                refreshed += 1;
            }
            state.recompute();
        }
        if step % (o.steps / 10).max(1) == 0 {
            // Guard against drift of the running sums.
            state.recompute();
            eprintln!(
                "  m {m}: step {step}, T {temp:.2e}, train {:.3}, accepted {accepted}",
                state.metric()
            );
        }
    }
    state.recompute();
    let (h1, d1) = held_out(&bank, &state.keys, o.seed, shifted);
    eprintln!(
        "m {m} ({n} spp): train {first:.3} -> {:.3}; held-out steps {h0:.3} -> {h1:.3}, disks {d0:.3} -> {d1:.3} ({:.1} s)",
        state.metric(),
        started.elapsed().as_secs_f64()
    );
    // The entry counts are what balance rests on.
    let mut counts = vec![0usize; bank.sets as usize];
    for k in &state.keys {
        counts[k.set as usize] += 1;
    }
    assert!(
        counts.iter().all(|&c| c == PIXELS / bank.sets as usize),
        "entry counts"
    );
    state.keys
}

fn main() -> ExitCode {
    let mut out: Option<String> = None;
    let mut o = Options {
        min_m: 0,
        max_m: 6,
        steps: 200_000,
        scenarios: 96,
        disks: 0.25,
        seed: 51,
        t0: 3e-3,
        t1: 3e-5,
        refresh: 2000,
        keep: Vec::new(),
        kept_by: Vec::new(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        let value = args.next().unwrap_or_default();
        match flag.as_str() {
            "--out" => out = Some(value),
            "--min-m" => o.min_m = value.parse().unwrap_or(0),
            "--max-m" => o.max_m = value.parse().unwrap_or(6),
            "--steps" => o.steps = value.parse().unwrap_or(200_000),
            "--scenarios" => o.scenarios = value.parse().unwrap_or(96),
            "--disks" => o.disks = value.parse().unwrap_or(0.25),
            "--seed" => o.seed = value.parse().unwrap_or(51),
            "--t0" => o.t0 = value.parse().unwrap_or(3e-3),
            "--t1" => o.t1 = value.parse().unwrap_or(3e-5),
            "--refresh" => o.refresh = value.parse().unwrap_or(2000),
            "--keep" => match read_tiles(&value) {
                Ok(tiles) => {
                    o.keep = tiles;
                    let text = std::fs::read_to_string(&value).unwrap_or_default();
                    o.kept_by = text
                        .lines()
                        .filter_map(|l| l.split('`').nth(1))
                        .filter(|c| c.starts_with("cargo run --release --example net_tile"))
                        .map(str::to_owned)
                        .collect();
                }
                Err(e) => {
                    eprintln!("{e}");
                    return ExitCode::FAILURE;
                }
            },
            _ => {
                eprintln!(
                    "usage: net_tile [--out FILE] [--min-m M] [--max-m M] [--steps K] \
                     [--scenarios K] [--disks P] [--seed S] [--t0 T] [--t1 T] [--refresh K] [--keep FILE]"
                );
                return ExitCode::from(2);
            }
        }
    }
    let max_m = o.max_m.min(NETS.len() as u32 - 1);
    let made: Vec<Vec<Key>> = (o.min_m..=max_m).map(|m| anneal(m, &o)).collect();
    let Some(path) = out else {
        return ExitCode::SUCCESS;
    };
    // Tiles below `min_m` (and above `max_m`) come from `--keep`.
    let count = (max_m as usize + 1).max(o.keep.len());
    let mut tiles = Vec::with_capacity(count);
    for m in 0..count {
        let tile = if (o.min_m as usize..=max_m as usize).contains(&m) {
            made[m - o.min_m as usize].clone()
        } else if let Some(kept) = o.keep.get(m) {
            kept.clone()
        } else {
            eprintln!("--out: no tile for m = {m} (make it or pass --keep)");
            return ExitCode::from(2);
        };
        tiles.push(tile);
    }
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut text = String::new();
    let _ = writeln!(
        text,
        "//! Generated by examples/net_tile.rs; do not edit. Made by, in order (each\n\
         //! run keeps the tiles it does not remake from the file it reads):"
    );
    o.kept_by.push(format!(
        "cargo run --release --example net_tile -- {}",
        args.join(" ")
    ));
    for command in &o.kept_by {
        let _ = writeln!(text, "//! - `{command}`");
    }
    let _ = writeln!(
        text,
        "//!\n\
         //! `TILES[m]` is the {SIDE} × {SIDE}\n\
         //! toroidal tile of per-pixel keys for `2^m` samples per pixel, row by row:\n\
         //! bits 0-4 the symmetry, 5-10 the bank entry, 16-23 and 24-31 the offsets\n\
         //! inside the cells in x and y (the top 8 bits of a 32-bit offset). Every\n\
         //! bank entry fills the same number of pixels.\n"
    );
    let _ = writeln!(
        text,
        "/// Side of every tile, in pixels.\npub(crate) const TILE_SIDE: u32 = {SIDE};\n"
    );
    for (m, keys) in tiles.iter().enumerate() {
        let _ = writeln!(
            text,
            "#[rustfmt::skip]\nstatic TILE_{m}: [u32; {PIXELS}] = ["
        );
        for row in keys.chunks(8) {
            let line: Vec<String> = row.iter().map(|k| format!("0x{:08x}", k.pack())).collect();
            let _ = writeln!(text, "    {},", line.join(", "));
        }
        let _ = writeln!(text, "];\n");
    }
    let names: Vec<String> = (0..tiles.len()).map(|m| format!("&TILE_{m}")).collect();
    let _ = writeln!(
        text,
        "/// The tiles, by `m`.\n#[rustfmt::skip]\npub(crate) static TILES: [&[u32; {PIXELS}]; {}] = [{}];",
        tiles.len(),
        names.join(", ")
    );
    if let Err(e) = std::fs::write(&path, text) {
        eprintln!("{path}: {e}");
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
