//! Streams a Poisson disk set pixel by pixel and prints the figures that
//! matter for a renderer, for both streaming schemes side by side: points/s
//! (against the batch sampler on the same area), per-pixel counts, the
//! density in 0.1-pixel bands along each pixel edge relative to the pixel
//! interior (border bias), the power at the pixel frequency, and peak RSS.
//!
//! ```text
//! cargo run --release --example stream                          # 1024 x 1024, 4 per pixel
//! cargo run --release --example stream -- --pixels 512x512 --radius 0.8 --seed 3
//! cargo run --release --example stream -- --pixels 16384x16384 --per-pixel 4 --scheme sweep --no-batch --progress 512
//! ```
//!
//! Exact mode (`--exact N`, with `--method eliminate|random`,
//! `--oversample S` and `--bias BX,BY,GY` to override the calibrated edge
//! correction) prints the same figures for its kept points, plus the
//! top-ups, the first harmonic of the in-pixel density (what the edge
//! correction is calibrated on), the power at the pixel lattice's other
//! frequencies up to two cycles a pixel with the second harmonic, and ρ of
//! the measured minimum distance.
//! `--chart FILE` charts the trade-off against the oversampling instead:
//!
//! ```text
//! cargo run --release --example stream -- --pixels 160x160 --exact 4 --scheme sweep --no-batch
//! cargo run --release --example stream -- --pixels 160x160 --exact 4 --chart docs/images/exact-tradeoff.png
//! ```
//!
//! Speed is timed in passes of their own that only take the points, as a
//! renderer would (the statistics' minimum-distance check grows with the
//! points per pixel, so it runs in one more, untimed, pass). `--rounds R`
//! times every program R times, alternating them round by round: the
//! streams, with `--exact` the plain sweep at exact mode's radius (unless
//! `--no-sweep`; `--method both` times both methods), and the batch sampler
//! on the same area (unless `--no-batch`); then the medians, and each
//! stream's points/s against the batch sampler's (the median of the
//! rounds' own ratios, in thread CPU time and on the wall clock):
//!
//! ```text
//! cargo run --release --example stream -- --pixels 4096x256 --per-pixel 4 --scheme sweep --rounds 5
//! cargo run --release --example stream -- --pixels 256x256 --exact 16 --method both --rounds 3 --no-batch
//! ```
//!
//! `--progress ROWS` prints, every ROWS rows, the points so far, the rate and
//! the current RSS, so a long run shows its memory staying flat; it times
//! the statistics pass itself (no separate timed rounds), so its rate
//! includes the checks.
//!
//! Peak RSS (`VmHWM`, Linux) covers the whole run; with `--scheme` and
//! `--no-batch` a run measures one configuration only.

#[allow(dead_code, reason = "shared with `plot`, which uses all of it")]
#[path = "plot/canvas.rs"]
mod canvas;
#[path = "common/mod.rs"]
mod common;
#[path = "plot/font.rs"]
mod font;
#[path = "common/line_chart.rs"]
mod line_chart;
#[path = "stream/tradeoff.rs"]
mod tradeoff;

use crate::common::{peak_rss_mib, status_mib};
use bridson::{Domain, ExactMethod, PoissonDisk, Scheme, Tiled, TiledBuilder, relative_radius};
use clap::{Parser, ValueEnum};
use std::process::ExitCode;
use std::time::Instant;

/// The command line.
#[derive(Debug, Parser)]
#[command(name = "stream", allow_negative_numbers = true)]
struct Args {
    /// Raster size
    #[arg(long = "pixels", value_name = "WxH", default_value = "1024x1024",
          value_parser = common::size)]
    size: (u32, u32),
    /// Minimum distance in pixels [default: from --per-pixel]
    #[arg(long, value_name = "R")]
    radius: Option<f64>,
    /// About N points per pixel (when neither --radius nor --exact is given)
    #[arg(long, value_name = "N", default_value_t = 4.0)]
    per_pixel: f64,
    /// Seed
    #[arg(long, value_name = "S", default_value_t = 1)]
    seed: u64,
    /// Streaming scheme(s) to run
    #[arg(long, value_name = "SCHEME", value_enum, default_value_t = Schemes::Both)]
    scheme: Schemes,
    /// Skip the batch sampler's run on the same area
    #[arg(long)]
    no_batch: bool,
    /// With --exact: skip the plain sweep's run at exact mode's radius
    #[arg(long)]
    no_sweep: bool,
    /// Timed runs of each program, alternating program by program, round
    /// by round (the statistics come from one more, untimed, run; 0: the
    /// statistics only)
    #[arg(long, value_name = "R", default_value_t = 1)]
    rounds: u32,
    /// Exactly N points in every pixel
    #[arg(long, value_name = "N")]
    exact: Option<u32>,
    /// Exact mode: how excess points are dropped (both: each in turn)
    #[arg(long, value_name = "METHOD", value_enum, default_value_t = MethodArg::Eliminate)]
    method: MethodArg,
    /// Exact mode: the sweep's points per pixel over N [default: 1.16]
    #[arg(long, value_name = "S")]
    oversample: Option<f64>,
    /// Exact mode: edge correction BX,BY [default: the calibrated one]
    #[arg(long, value_name = "BX,BY,GY", value_parser = triple)]
    bias: Option<[f64; 3]>,
    /// With --exact: measure both methods, with and without their edge
    /// correction, at oversamplings 1 to 3, and chart the trade-off (PNG)
    #[arg(long, value_name = "FILE", requires = "exact")]
    chart: Option<std::path::PathBuf>,
    /// The streamed runs' attempts k [default: 30; exact mode 10]
    #[arg(long, value_name = "K")]
    attempts: Option<u32>,
    /// How candidates are drawn, in every program run (the radius follows
    /// from the density each kind reaches at k; exact mode's sweep always
    /// draws on the annulus)
    #[arg(long, value_name = "KIND", value_enum, default_value_t = common::CandidatesArg::Annulus)]
    candidates: common::CandidatesArg,
    /// Print progress every ROWS rows (0 counts as 1)
    #[arg(long, value_name = "ROWS")]
    progress: Option<u32>,
    /// Measure the pixel lattice's frequencies (a, b) up to
    /// max(|a|, |b|) = K
    #[arg(long, value_name = "K", default_value_t = 4, value_parser = clap::value_parser!(u32).range(2..=16))]
    lattice_order: u32,
}

/// Three numbers `a,b,c`, for `--bias`.
fn triple(text: &str) -> Result<[f64; 3], String> {
    match common::list::<f64>(text)?.as_slice() {
        &[a, b, c] => Ok([a, b, c]),
        _ => Err(format!("expected three numbers a,b,c, got '{text}'")),
    }
}

/// `--method`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum MethodArg {
    Eliminate,
    Random,
    Both,
}

impl MethodArg {
    fn list(self) -> Vec<ExactMethod> {
        match self {
            Self::Eliminate => vec![ExactMethod::Eliminate],
            Self::Random => vec![ExactMethod::Random],
            Self::Both => vec![ExactMethod::Eliminate, ExactMethod::Random],
        }
    }
}

/// `--scheme`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Schemes {
    Sweep,
    Paper,
    Both,
}

impl Schemes {
    fn list(self) -> Vec<Scheme> {
        match self {
            Self::Sweep => vec![Scheme::Sweep],
            Self::Paper => vec![Scheme::Paper],
            Self::Both => vec![Scheme::Sweep, Scheme::Paper],
        }
    }
}

/// The pixel lattice's frequencies `(a, b)` (cycles per pixel) measured
/// besides `(1, 0)` and `(0, 1)`, one of each pair `±(a, b)`, order by
/// order (the order being `max(|a|, |b|)`): the diagonals `(1, ±1)`
/// first, then `(2, 0)`, `(0, 2)`, `(2, ±1)`, `(1, ±2)`, `(2, ±2)`, and so
/// on up to `order`.
fn lattice(order: usize) -> Vec<(i32, i32)> {
    let mut out = Vec::new();
    for o in 1..=order {
        #[expect(
            clippy::cast_possible_wrap,
            clippy::cast_possible_truncation,
            reason = "order <= 16"
        )]
        let o = o as i32;
        out.extend(if o > 1 { vec![(o, 0), (0, o)] } else { vec![] });
        for m in 1..o {
            out.extend([(o, m), (o, -m), (m, o), (m, -o)]);
        }
        out.extend([(o, o), (o, -o)]);
    }
    out
}

/// How many of [`lattice`]'s frequencies have an order up to `order`.
fn lattice_len(order: usize) -> usize {
    (2 * order + 1) * (2 * order + 1) / 2 - 2
}

/// The highest order `--lattice-order` takes.
const MAX_LATTICE_ORDER: usize = 16;

/// The product of two complex numbers given as `(re, im)`.
fn mul(p: (f64, f64), q: (f64, f64)) -> (f64, f64) {
    (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0)
}

/// `sum += z`, complex.
fn add(sum: &mut (f64, f64), z: (f64, f64)) {
    sum.0 += z.0;
    sum.1 += z.1;
}

/// `z^0` to `z^order`, once a point, for every frequency of [`lattice`]
/// to take its factors from ([`power`]).
fn powers(z: (f64, f64), order: usize) -> [(f64, f64); MAX_LATTICE_ORDER + 1] {
    let mut out = [(1.0, 0.0); MAX_LATTICE_ORDER + 1];
    for k in 1..=order.min(MAX_LATTICE_ORDER) {
        out[k] = mul(out[k - 1], z);
    }
    out
}

/// `z^k` from `z`'s [`powers`], for `|z| = 1` (a negative power is the
/// conjugate's).
fn power(powers: &[(f64, f64)], k: i32) -> (f64, f64) {
    let z = powers
        .get(k.unsigned_abs() as usize)
        .copied()
        .unwrap_or((1.0, 0.0));
    if k < 0 { (z.0, -z.1) } else { z }
}

/// Side frequencies measured beside the pixel frequency: `k` = 1, 2, 4,
/// …, 2¹¹ cycles across the raster, each sign.
const SIDE_STEPS: usize = 12;

/// Per-pixel statistics accumulated over the stream.
#[derive(Default)]
struct Stats {
    points: u64,
    counts: Vec<u64>,
    /// Points in the bands x < 0.1, x >= 0.9, y < 0.1, y >= 0.9 of their
    /// pixel, and in the interior [0.1, 0.9)².
    bands: [u64; 4],
    interior: u64,
    /// Σ exp(-2πi·x) and Σ exp(-2πi·y): the Fourier coefficient of the set
    /// at the pixel frequency along each axis.
    pixel_frequency: [(f64, f64); 2],
    /// Beside it: `Σ exp(-2πi·(x ± k·y/H))` (the first row, [`SIDE_STEPS`]
    /// values of `k`, each sign) and `Σ exp(-2πi·(y ± k·x/W))` (the
    /// second), where a pattern that drifts across the raster would show.
    side: [[[(f64, f64); 2]; SIDE_STEPS]; 2],
    /// The pixel lattice's other frequencies measured ([`lattice`]), up
    /// to `order`, and `Σ exp(-2πi·(a·x + b·y))` at each.
    order: usize,
    frequencies: Vec<(i32, i32)>,
    lattice: Vec<(f64, f64)>,
    /// The raster's size, for the phases across it.
    size: (f64, f64),
    /// Points by tenth of a pixel along x and along y.
    profile: [[u64; 10]; 2],
    /// Smallest squared distance between points in the same or adjacent
    /// pixels (the set's minimum whenever that is below one pixel).
    min_d2: f64,
    previous_row: Vec<Vec<[f64; 2]>>,
    current_row: Vec<Vec<[f64; 2]>>,
}

impl Stats {
    fn new(width: u32, height: u32, order: usize) -> Self {
        let w = width as usize;
        let frequencies = lattice(order);
        Self {
            order,
            lattice: vec![(0.0, 0.0); frequencies.len()],
            frequencies,
            min_d2: f64::INFINITY,
            size: (f64::from(width), f64::from(height)),
            previous_row: vec![Vec::new(); w],
            current_row: vec![Vec::new(); w],
            ..Self::default()
        }
    }

    /// Tracks the minimum distance against this pixel, its left neighbour
    /// and the three pixels above. Each pixel's points are kept sorted by
    /// `x`, so a point is compared only with those whose `x` lies within
    /// the smallest distance found so far: exact, and about `√n` times
    /// fewer comparisons than every pair at `n` points a pixel (the
    /// calibration runs at `n` = 128 to 1024 would spend most of their time
    /// here otherwise).
    fn track_distance(&mut self, x: u32, points: &[[f64; 2]]) {
        let x = x as usize;
        let d2 = |a: &[f64; 2], b: &[f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
        let mut sorted = core::mem::take(&mut self.current_row[x]);
        sorted.clear();
        sorted.extend_from_slice(points);
        sorted.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]));
        for (i, p) in sorted.iter().enumerate() {
            // This pixel's points left of `p`, nearest in `x` first.
            for q in sorted[..i].iter().rev() {
                if (p[0] - q[0]).powi(2) >= self.min_d2 {
                    break;
                }
                self.min_d2 = self.min_d2.min(d2(p, q));
            }
            let left = x.checked_sub(1).map(|l| &self.current_row[l]);
            let above = (x.saturating_sub(1)..=(x + 1).min(self.previous_row.len() - 1))
                .map(|k| &self.previous_row[k]);
            // The same test as above, on both sides of `p` (the cells are
            // sorted by `x`, so the far left is a prefix).
            for cell in left.into_iter().chain(above) {
                let start =
                    cell.partition_point(|q| q[0] < p[0] && (p[0] - q[0]).powi(2) >= self.min_d2);
                for q in &cell[start..] {
                    if q[0] > p[0] && (q[0] - p[0]).powi(2) >= self.min_d2 {
                        break;
                    }
                    self.min_d2 = self.min_d2.min(d2(p, q));
                }
            }
        }
        self.current_row[x] = sorted;
        if x + 1 == self.current_row.len() {
            core::mem::swap(&mut self.previous_row, &mut self.current_row);
        }
    }

    fn add(&mut self, x: u32, y: u32, points: &[[f64; 2]]) {
        self.track_distance(x, points);
        let n = points.len();
        if self.counts.len() <= n {
            self.counts.resize(n + 1, 0);
        }
        self.counts[n] += 1;
        for p in points {
            self.points += 1;
            let fx = p[0] - f64::from(x);
            let fy = p[1] - f64::from(y);
            let (l, r, t, b) = (fx < 0.1, fx >= 0.9, fy < 0.1, fy >= 0.9);
            for (band, inside) in self.bands.iter_mut().zip([l, r, t, b]) {
                *band += u64::from(inside);
            }
            self.interior += u64::from(!(l || r || t || b));
            for (axis, f) in [fx, fy].into_iter().enumerate() {
                #[expect(
                    clippy::cast_possible_truncation,
                    clippy::cast_sign_loss,
                    reason = "a fraction in [0, 1)"
                )]
                let bin = ((f * 10.0) as usize).min(9);
                self.profile[axis][bin] += 1;
            }
            // exp(-2πi·fx) and exp(-2πi·fy), as (re, im).
            let at_pixel = [fx, fy].map(|f| {
                let (s, c) = (core::f64::consts::TAU * f).sin_cos();
                (c, -s)
            });
            for (sum, z) in self.pixel_frequency.iter_mut().zip(at_pixel) {
                add(sum, z);
            }
            let [u, v] = at_pixel.map(|z| powers(z, self.order));
            for (sum, &(a, b)) in self.lattice.iter_mut().zip(&self.frequencies) {
                add(sum, mul(power(&u, a), power(&v, b)));
            }
            // The phase across the raster along the other axis, for
            // k = 1, 2, 4, …: squared from k = 1 step by step.
            for (axis, across) in [p[1] / self.size.1, p[0] / self.size.0]
                .into_iter()
                .enumerate()
            {
                let (s, c) = (core::f64::consts::TAU * across).sin_cos();
                let mut z = (c, -s);
                let h = at_pixel[axis];
                for [plus, minus] in &mut self.side[axis] {
                    add(plus, mul(h, z));
                    add(minus, mul(h, (z.0, -z.1)));
                    z = mul(z, z);
                }
            }
        }
    }

    fn report(&self, pixels: u64) {
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let (n, px) = (self.points as f64, pixels as f64);
        let mean = n / px;
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let var = self
            .counts
            .iter()
            .enumerate()
            .map(|(k, &c)| c as f64 * (k as f64 - mean).powi(2))
            .sum::<f64>()
            / px;
        let min = self.counts.iter().position(|&c| c > 0).unwrap_or(0);
        let max = self.counts.len().saturating_sub(1);
        println!(
            "  per pixel: mean {mean:.3}, sd {:.3}, min {min}, max {max}",
            var.sqrt()
        );
        let [left, right, top, bottom] = self.edge_ratios();
        println!(
            "  edge band / interior density: left {left:.3}, right {right:.3}, top {top:.3}, bottom {bottom:.3}"
        );
        for (axis, name) in ["x", "y"].iter().enumerate() {
            let bins: Vec<String> = self.profile[axis]
                .iter()
                .map(|&c| {
                    #[expect(clippy::cast_precision_loss, reason = "statistics")]
                    let rel = c as f64 * 10.0 / n;
                    format!("{rel:.3}")
                })
                .collect();
            println!(
                "  density by tenth of a pixel along {name}: {}",
                bins.join(" ")
            );
        }
        println!(
            "  first harmonic of the in-pixel density (cos, sin): x {:+.6} {:+.6}, y {:+.6} {:+.6}",
            2.0 * self.pixel_frequency[0].0 / n,
            -2.0 * self.pixel_frequency[0].1 / n,
            2.0 * self.pixel_frequency[1].0 / n,
            -2.0 * self.pixel_frequency[1].1 / n
        );
        let [px, py] = self.power();
        println!("  power at the pixel frequency (1 = no structure): x {px:.2}, y {py:.2}");
        let side = self.side_power();
        println!(
            "  power beside it, k = ±1, ±2, ±4 … up to a quarter of the raster's cycles across it (mean, max): x {:.2} {:.2}, y {:.2} {:.2}",
            side[0].0, side[0].1, side[1].0, side[1].1
        );
        let lattice: Vec<f64> = self.lattice.iter().map(|&z| self.periodogram(z)).collect();
        let largest = |range: core::ops::Range<usize>| {
            lattice
                .iter()
                .zip(&self.frequencies)
                .skip(range.start)
                .take(range.len())
                .fold(
                    (0.0, (0, 0)),
                    |best, (&p, &ab)| if p > best.0 { (p, ab) } else { best },
                )
        };
        let by_order: Vec<String> = (2..=self.order)
            .map(|o| {
                let (p, at) = largest(lattice_len(o - 1).max(2)..lattice_len(o));
                format!("{o}: {p:.2} at {at:?}")
            })
            .collect();
        println!(
            "  power at the lattice's diagonal frequencies (1, 1) and (1, -1): {:.2}, {:.2}; the largest at (a, b) by order max(|a|, |b|): {}",
            lattice.first().copied().unwrap_or(0.0),
            lattice.get(1).copied().unwrap_or(0.0),
            by_order.join("; ")
        );
        let all: Vec<String> = self
            .frequencies
            .iter()
            .take(lattice_len(self.order.min(3)))
            .zip(&lattice)
            .map(|((a, b), p)| format!("({a}, {b}) {p:.2}"))
            .collect();
        println!("  power at each up to order 3: {}", all.join(", "));
        // `(2, 0)` and `(0, 2)` are the third and fourth of [`lattice`].
        let (Some(&x2), Some(&y2)) = (self.lattice.get(2), self.lattice.get(3)) else {
            return;
        };
        println!(
            "  second harmonic of the in-pixel density (cos, sin): x {:+.6} {:+.6}, y {:+.6} {:+.6}",
            2.0 * x2.0 / n,
            -2.0 * x2.1 / n,
            2.0 * y2.0 / n,
            -2.0 * y2.1 / n
        );
    }

    /// Density in the left, right, top and bottom 0.1-pixel bands of the
    /// pixels relative to the interior `[0.1, 0.9)²`.
    fn edge_ratios(&self) -> [f64; 4] {
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let interior = self.interior as f64 / 0.64;
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        self.bands.map(|band| band as f64 / 0.1 / interior)
    }

    /// Periodogram value |Σ e^{-2πi f·x}|² / n at f = (W, 0) and (0, H),
    /// the pixel frequency: ≈ 1 for no structure, ≫ 1 for a pixel pattern.
    fn power(&self) -> [f64; 2] {
        self.pixel_frequency.map(|z| self.periodogram(z))
    }

    /// `|z|² / n` for a sum `z` of `exp(-2πi f·x)` over the `n` points.
    fn periodogram(&self, (c, s): (f64, f64)) -> f64 {
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let n = self.points as f64;
        (c * c + s * s) / n
    }

    /// The periodogram's mean and largest value at the side frequencies
    /// ([`Stats::side`]), per axis.
    fn side_power(&self) -> [(f64, f64); 2] {
        // The other axis's size: `k` up to a quarter of it, short of the
        // lattice's own frequencies `(1, ±1)` at `k` = the size.
        let across = [self.size.1, self.size.0];
        core::array::from_fn(|axis| {
            let values: Vec<f64> = self.side[axis]
                .iter()
                .zip(0..)
                .take_while(|&(_, j)| f64::from(1u32 << j) <= across[axis] / 4.0)
                .flat_map(|(pair, _)| pair)
                .map(|&z| self.periodogram(z))
                .collect();
            #[expect(clippy::cast_precision_loss, reason = "a few values")]
            let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
            (mean, values.iter().copied().fold(0.0, f64::max))
        })
    }

    /// ρ of the smallest distance measured, for the points seen in `area`.
    fn rho_of_minimum(&self, area: f64) -> f64 {
        usize::try_from(self.points)
            .ok()
            .and_then(|n| relative_radius::<2>(self.min_d2.sqrt(), n, area))
            .unwrap_or(f64::NAN)
    }
}

/// The batch sampler's memory budget here, 8 GiB.
const BATCH_BUDGET: u64 = 8 << 30;

/// One program timed by `--rounds`: a stream, or the batch sampler on the
/// same area.
enum Program {
    Stream {
        label: String,
        tiled: Tiled,
        exact: bool,
    },
    Batch {
        sampler: PoissonDisk<2>,
    },
}

impl Program {
    fn label(&self) -> &str {
        match self {
            Self::Stream { label, .. } => label,
            Self::Batch { .. } => "batch",
        }
    }

    /// One timed run: points made, wall seconds, and thread CPU seconds
    /// (the wall clock where the system does not tell).
    fn time(&self, seed: u64) -> (u64, f64, f64) {
        match self {
            Self::Stream { tiled, .. } => timed_pass(tiled, seed),
            Self::Batch { sampler } => {
                let start = Instant::now();
                let cpu = common::thread_cpu_seconds();
                let mut points = sampler.iter_seeded(seed);
                let n = std::hint::black_box(points.by_ref().count());
                // A run cut short (say, by the memory budget) is no
                // yardstick: say so where its figures are printed.
                if let Some(e) = points.error() {
                    eprintln!("stream: the batch run stopped early: {e}");
                }
                let wall = start.elapsed().as_secs_f64();
                let cpu = match (cpu, common::thread_cpu_seconds()) {
                    (Some(a), Some(b)) => b - a,
                    _ => wall,
                };
                (n as u64, wall, cpu)
            }
        }
    }
}

/// Streams `tiled` once as a renderer would take it, doing nothing with
/// the points but counting them: points, wall and thread CPU seconds (the
/// wall clock where the system does not tell). The statistics are
/// gathered in a pass of their own, so their cost (the minimum-distance
/// check grows with the points per pixel) stays out of the rate.
pub(crate) fn timed_pass(tiled: &Tiled, seed: u64) -> (u64, f64, f64) {
    let mut buf = Vec::new();
    let mut points = 0u64;
    let start = Instant::now();
    let cpu = common::thread_cpu_seconds();
    let mut stream = tiled.pixels_seeded(seed);
    while stream.next_into(&mut buf).is_some() {
        points += buf.len() as u64;
        std::hint::black_box(&buf);
    }
    let wall = start.elapsed().as_secs_f64();
    let cpu = match (cpu, common::thread_cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => wall,
    };
    (points, wall, cpu)
}

/// The median of `values` (the mean of the middle two of an even count).
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let half = values.len() / 2;
    match (values.get(half.wrapping_sub(1)), values.get(half)) {
        (Some(a), Some(b)) if values.len().is_multiple_of(2) => f64::midpoint(*a, *b),
        (_, Some(b)) => *b,
        _ => f64::NAN,
    }
}

/// The builder for one streamed configuration of the command line.
fn builder_for(args: &Args, scheme: Scheme, method: Option<ExactMethod>) -> TiledBuilder {
    let (width, height) = args.size;
    let builder = Tiled::builder(width, height)
        .scheme(scheme)
        .candidates(args.candidates.into());
    let builder = match args.attempts {
        Some(k) => builder.attempts(k),
        None => builder,
    };
    match (args.exact, method, args.radius) {
        (Some(n), Some(method), _) => {
            let b = builder.exact(n).exact_method(method);
            let b = match args.oversample {
                Some(s) => b.exact_oversample(s),
                None => b,
            };
            match args.bias {
                Some(beta) => b.exact_edge_bias(beta),
                None => b,
            }
        }
        (_, _, Some(r)) => builder.radius(r),
        (_, _, None) => builder.per_pixel(args.per_pixel),
    }
}

/// The programs the command line asks for, streams first.
fn programs(args: &Args) -> Result<Vec<Program>, String> {
    let (width, height) = args.size;
    let mut list = Vec::new();
    if args.exact.is_some() {
        for method in args.method.list() {
            let tiled = builder_for(args, Scheme::Sweep, Some(method))
                .build()
                .map_err(|e| e.to_string())?;
            let label = format!("exact {}", format!("{method:?}").to_lowercase());
            list.push(Program::Stream {
                label,
                tiled,
                exact: true,
            });
        }
    } else {
        for scheme in args.scheme.list() {
            let tiled = builder_for(args, scheme, None)
                .build()
                .map_err(|e| e.to_string())?;
            let label = format!("{scheme:?}").to_lowercase();
            list.push(Program::Stream {
                label,
                tiled,
                exact: false,
            });
        }
    }
    // The radius, k and candidates the first stream runs with (exact mode
    // draws on the annulus whatever was asked): the other programs use them.
    let (radius, attempts, candidates) = match list.first() {
        Some(Program::Stream { tiled, .. }) => {
            (tiled.radius(), tiled.attempts(), tiled.candidates())
        }
        _ => return Ok(list),
    };
    // Exact mode against the plain sweep that makes its points (same r,
    // same k).
    if args.exact.is_some() && !args.no_sweep {
        let tiled = Tiled::builder(width, height)
            .radius(radius)
            .attempts(attempts)
            .candidates(candidates)
            .build()
            .map_err(|e| e.to_string())?;
        let label = "sweep at the same r".to_owned();
        list.push(Program::Stream {
            label,
            tiled,
            exact: false,
        });
    }
    if !args.no_batch {
        let domain = Domain::from_extent([f64::from(width), f64::from(height)]);
        // At 16 a pixel a megapixel's batch run needs about 1 GB of grid
        // and points: room for the machine's 24 GiB, not the default 1 GiB.
        let sampler = domain
            .and_then(|d| {
                PoissonDisk::builder(d, radius)
                    .candidates(candidates)
                    .max_grid_bytes(BATCH_BUDGET)
                    .build()
            })
            .map_err(|e| format!("batch on the same area: {e}"))?;
        list.push(Program::Batch { sampler });
    }
    Ok(list)
}

/// `--rounds`: every program once per round, in turn, then the medians,
/// and each program's speed against the batch sampler's where it ran
/// (the median over rounds of the round's own ratio).
fn time_rounds(list: &[Program], rounds: u32, seed: u64) {
    let mut figures: Vec<Vec<(u64, f64, f64)>> = vec![Vec::new(); list.len()];
    for round in 1..=rounds {
        let mut line = format!("round {round}:");
        for (program, runs) in list.iter().zip(&mut figures) {
            let (n, wall, cpu) = program.time(seed);
            #[expect(clippy::cast_precision_loss, reason = "statistics")]
            let rate = n as f64 / cpu / 1e6;
            line.push_str(&format!(
                " {} {cpu:.3} s CPU ({rate:.3} M/s), {wall:.3} s wall;",
                program.label()
            ));
            runs.push((n, wall, cpu));
        }
        println!("{line}");
    }
    let batch = list.iter().position(|p| matches!(p, Program::Batch { .. }));
    for (program, runs) in list.iter().zip(&figures) {
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let rate = |pick: fn(&(u64, f64, f64)) -> f64| {
            median(runs.iter().map(|r| r.0 as f64 / pick(r) / 1e6).collect())
        };
        let (cpu, wall) = (rate(|r| r.2), rate(|r| r.1));
        let mut line = format!(
            "median of {rounds}: {}: {} points, {cpu:.3} M/s CPU, {wall:.3} M/s wall",
            program.label(),
            runs.first().map_or(0, |r| r.0)
        );
        if let Some(b) = batch.and_then(|b| figures.get(b))
            && !matches!(program, Program::Batch { .. })
        {
            #[expect(clippy::cast_precision_loss, reason = "statistics")]
            let ratio = |pick: fn(&(u64, f64, f64)) -> f64| {
                let pairs = runs.iter().zip(b);
                median(
                    pairs
                        .map(|(s, t)| (s.0 as f64 / pick(s)) / (t.0 as f64 / pick(t)))
                        .collect(),
                )
            };
            line.push_str(&format!(
                "; {:.0} % of batch's points/s in CPU time, {:.0} % on the wall clock",
                100.0 * ratio(|r| r.2),
                100.0 * ratio(|r| r.1)
            ));
        }
        println!("{line}");
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    let (width, height) = args.size;
    if let (Some(path), Some(n)) = (&args.chart, args.exact) {
        return match tradeoff::chart(args.size, n, args.seed, path) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("stream: {e}");
                ExitCode::from(2)
            }
        };
    }
    let list = match programs(&args) {
        Ok(list) => list,
        Err(e) => {
            eprintln!("stream: {e}");
            return ExitCode::from(2);
        }
    };
    // With --progress the one statistics pass is the timed run (the
    // billion-point run would not afford two).
    if args.progress.is_none() && args.rounds > 0 {
        time_rounds(&list, args.rounds, args.seed);
    }
    let pixels = u64::from(width) * u64::from(height);
    let area = f64::from(width) * f64::from(height);
    for program in &list {
        let Program::Stream {
            label,
            tiled,
            exact,
        } = program
        else {
            continue;
        };
        let mut stats = Stats::new(width, height, args.lattice_order as usize);
        let mut buf = Vec::new();
        let start = Instant::now();
        let cpu_start = common::thread_cpu_seconds();
        let mut stream = tiled.pixels_seeded(args.seed);
        while let Some((x, y)) = stream.next_into(&mut buf) {
            stats.add(x, y, &buf);
            if let Some(every) = args.progress.map(|rows| rows.max(1))
                && x + 1 == width
                && (y + 1) % every == 0
            {
                let s = start.elapsed().as_secs_f64();
                #[expect(clippy::cast_precision_loss, reason = "statistics")]
                let rate = stats.points as f64 / s / 1e6;
                println!(
                    "  rows {}: {} points, {s:.1} s, {rate:.3} M/s, RSS {:.1} MiB",
                    y + 1,
                    stats.points,
                    status_mib("VmRSS:").unwrap_or(f64::NAN)
                );
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let rate = stats.points as f64 / seconds;
        if args.progress.is_some()
            && let (Some(a), Some(b)) = (cpu_start, common::thread_cpu_seconds())
        {
            #[expect(clippy::cast_precision_loss, reason = "statistics")]
            let cpu_rate = stats.points as f64 / (b - a) / 1e6;
            println!(
                "  CPU time {:.3} s ({cpu_rate:.3} M points/s, with the statistics)",
                b - a
            );
        }
        // ρ of the radius r (natural mode: the guaranteed minimum), and of
        // the set's measured minimum distance (what exact mode offers).
        let rho_of = |d: f64| {
            usize::try_from(stats.points)
                .ok()
                .and_then(|n| relative_radius::<2>(d, n, area))
                .unwrap_or(f64::NAN)
        };
        let rho = rho_of(tiled.radius());
        println!(
            "  rho of the measured minimum distance {:.4}",
            rho_of(stats.min_d2.sqrt())
        );
        // Every pair in the same or adjacent pixels was checked (above), so
        // below a radius of one pixel this is the whole union's guarantee.
        let verdict = match (tiled.radius() < 1.0, stats.min_d2 >= tiled.radius().powi(2)) {
            (true, true) => "holds for every pair",
            (true, false) => "VIOLATED",
            (false, true) => "holds for pairs in adjacent pixels (r >= 1: others unchecked)",
            (false, false) => "VIOLATED",
        };
        if !exact {
            println!(
                "  minimum distance {:.6} against r = {:.6}: the guarantee {verdict}",
                stats.min_d2.sqrt(),
                tiled.radius()
            );
        } else {
            println!("  exact mode: {} top-up darts", stream.top_ups());
        }
        let mode = if args.progress.is_some() {
            format!(" in {seconds:.3} s ({:.3} M/s)", rate / 1e6)
        } else {
            String::new()
        };
        println!(
            "{label}: {}x{} pixels, r = {:.5}, {} points{mode}, rho {rho:.4}, window {:.1} MiB",
            width,
            height,
            tiled.radius(),
            stats.points,
            tiled.window_bytes() as f64 / 1048576.0
        );
        stats.report(pixels);
    }
    if let Some(rss) = peak_rss_mib() {
        println!("peak RSS {rss:.1} MiB");
    }
    ExitCode::SUCCESS
}
