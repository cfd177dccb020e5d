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
//! correction is calibrated on) and ρ of the measured minimum distance.
//! `--chart FILE` charts the trade-off against the oversampling instead:
//!
//! ```text
//! cargo run --release --example stream -- --pixels 160x160 --exact 4 --scheme sweep --no-batch
//! cargo run --release --example stream -- --pixels 160x160 --exact 4 --chart docs/images/exact-tradeoff.png
//! ```
//!
//! `--progress ROWS` prints, every ROWS rows, the points so far, the rate and
//! the current RSS, so a long run shows its memory staying flat.
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
use bridson::{Domain, ExactMethod, PoissonDisk, Scheme, Tiled, relative_radius};
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
    /// Exactly N points in every pixel
    #[arg(long, value_name = "N")]
    exact: Option<u32>,
    /// Exact mode: how excess points are dropped
    #[arg(long, value_name = "METHOD", value_enum, default_value_t = MethodArg::Eliminate)]
    method: MethodArg,
    /// Exact mode: the sweep's points per pixel over N
    #[arg(long, value_name = "S", default_value_t = 1.25)]
    oversample: f64,
    /// Exact mode: edge correction BX,BY [default: the calibrated one]
    #[arg(long, value_name = "BX,BY,GY", value_parser = triple)]
    bias: Option<[f64; 3]>,
    /// With --exact: measure both methods, with and without their edge
    /// correction, at oversamplings 1 to 3, and chart the trade-off (PNG)
    #[arg(long, value_name = "FILE", requires = "exact")]
    chart: Option<std::path::PathBuf>,
    /// Print progress every ROWS rows (0 counts as 1)
    #[arg(long, value_name = "ROWS")]
    progress: Option<u32>,
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
}

impl From<MethodArg> for ExactMethod {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Eliminate => Self::Eliminate,
            MethodArg::Random => Self::Random,
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
    /// Points by tenth of a pixel along x and along y.
    profile: [[u64; 10]; 2],
    /// Smallest squared distance between points in the same or adjacent
    /// pixels (the set's minimum whenever that is below one pixel).
    min_d2: f64,
    previous_row: Vec<Vec<[f64; 2]>>,
    current_row: Vec<Vec<[f64; 2]>>,
}

impl Stats {
    fn new(width: u32) -> Self {
        let w = width as usize;
        Self {
            min_d2: f64::INFINITY,
            previous_row: vec![Vec::new(); w],
            current_row: vec![Vec::new(); w],
            ..Self::default()
        }
    }

    /// Tracks the minimum distance against this pixel, its left neighbour
    /// and the three pixels above.
    fn track_distance(&mut self, x: u32, points: &[[f64; 2]]) {
        let x = x as usize;
        let d2 = |a: &[f64; 2], b: &[f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
        for (i, p) in points.iter().enumerate() {
            for q in &points[..i] {
                self.min_d2 = self.min_d2.min(d2(p, q));
            }
            let left = x.checked_sub(1).map(|l| &self.current_row[l]);
            let above = (x.saturating_sub(1)..=(x + 1).min(self.previous_row.len() - 1))
                .map(|k| &self.previous_row[k]);
            for cell in left.into_iter().chain(above) {
                for q in cell {
                    self.min_d2 = self.min_d2.min(d2(p, q));
                }
            }
        }
        self.current_row[x].clear();
        self.current_row[x].extend_from_slice(points);
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
            for (axis, f) in [fx, fy].into_iter().enumerate() {
                let (s, c) = (core::f64::consts::TAU * f).sin_cos();
                self.pixel_frequency[axis].0 += c;
                self.pixel_frequency[axis].1 -= s;
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
            "  first harmonic of the in-pixel density (cos, sin): x {:+.4} {:+.4}, y {:+.4} {:+.4}",
            2.0 * self.pixel_frequency[0].0 / n,
            -2.0 * self.pixel_frequency[0].1 / n,
            2.0 * self.pixel_frequency[1].0 / n,
            -2.0 * self.pixel_frequency[1].1 / n
        );
        let [px, py] = self.power();
        println!("  power at the pixel frequency (1 = no structure): x {px:.2}, y {py:.2}");
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
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let n = self.points as f64;
        self.pixel_frequency.map(|(c, s)| (c * c + s * s) / n)
    }

    /// ρ of the smallest distance measured, for the points seen in `area`.
    fn rho_of_minimum(&self, area: f64) -> f64 {
        usize::try_from(self.points)
            .ok()
            .and_then(|n| relative_radius::<2>(self.min_d2.sqrt(), n, area))
            .unwrap_or(f64::NAN)
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
    let pixels = u64::from(width) * u64::from(height);
    let area = f64::from(width) * f64::from(height);
    let mut stream_rate = None;
    for scheme in args.scheme.list() {
        let builder = Tiled::builder(width, height).scheme(scheme);
        let builder = match (args.exact, args.radius) {
            (Some(n), _) => {
                let b = builder
                    .exact(n)
                    .exact_method(args.method.into())
                    .exact_oversample(args.oversample);
                match args.bias {
                    Some(beta) => b.exact_edge_bias(beta),
                    None => b,
                }
            }
            (None, Some(r)) => builder.radius(r),
            (None, None) => builder.per_pixel(args.per_pixel),
        };
        let tiled = match builder.build() {
            Ok(t) => t,
            Err(e) => {
                eprintln!("stream: {e}");
                return ExitCode::from(2);
            }
        };
        let mut stats = Stats::new(width);
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
        // On a shared machine the thread's CPU time is the steadier cost.
        if let (Some(a), Some(b)) = (cpu_start, common::thread_cpu_seconds()) {
            #[expect(clippy::cast_precision_loss, reason = "statistics")]
            let cpu_rate = stats.points as f64 / (b - a) / 1e6;
            println!("  CPU time {:.3} s ({cpu_rate:.3} M points/s)", b - a);
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
        if args.exact.is_none() {
            println!(
                "  minimum distance {:.6} against r = {:.6}: the guarantee {verdict}",
                stats.min_d2.sqrt(),
                tiled.radius()
            );
        }
        if args.exact.is_some() {
            println!("  exact mode: {} top-up darts", stream.top_ups());
        }
        println!(
            "{scheme:?}: {}x{} pixels, r = {:.5}, {} points in {seconds:.3} s ({:.3} M/s), rho {rho:.4}, window {:.1} MiB",
            width,
            height,
            tiled.radius(),
            stats.points,
            rate / 1e6,
            tiled.window_bytes() as f64 / 1048576.0
        );
        stats.report(pixels);
        if scheme == Scheme::Sweep {
            stream_rate = Some((tiled.radius(), rate));
        }
    }
    if !args.no_batch
        && let Some((radius, rate)) = stream_rate
    {
        let domain = Domain::from_extent([f64::from(width), f64::from(height)]);
        let sampler = domain.and_then(|d| PoissonDisk::new(d, radius));
        match sampler {
            Ok(s) => {
                let start = Instant::now();
                let n = s.iter_seeded(args.seed).count();
                let seconds = start.elapsed().as_secs_f64();
                #[expect(clippy::cast_precision_loss, reason = "statistics")]
                let batch = n as f64 / seconds;
                println!(
                    "batch on the same area: {n} points in {seconds:.3} s ({:.3} M/s); sweep streaming at {:.0} % of batch",
                    batch / 1e6,
                    100.0 * rate / batch
                );
            }
            Err(e) => println!("batch on the same area: {e}"),
        }
    }
    if let Some(rss) = peak_rss_mib() {
        println!("peak RSS {rss:.1} MiB");
    }
    ExitCode::SUCCESS
}
