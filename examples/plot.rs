//! Pictures of Poisson disk point sets, to judge a sampler by eye, and a
//! JSON quality report. Writes PNG images: the point set (2-D, or a slice of
//! the first two axes in higher dimensions) as dots, optionally over the
//! pixel borders and the background grid of side `r/√N` (the look of Figure
//! 1 of Ye's report on Bridson's sampler in pbrt); the periodogram, averaged over several
//! independent sets (exact transform on an integer frequency grid, log grey
//! scale, DC suppressed); its radially averaged power and its anisotropy in
//! dB as line charts, labelled with a built-in bitmap font (Lagae & Dutré
//! 2008; the PSA tool of Schlömer & Heck); and, over a pixel raster, the
//! density of points as a function of the position inside a pixel, where
//! border bias shows. The report gives n, the minimum distance, the pairs
//! closer than `r`, ρ, the uncovered fraction of the domain and, over a
//! raster, the per-pixel count histogram and the edge-band/interior density
//! ratios. Run it as
//! `cargo run --release --example plot -- --out-dir pics --report pics/report.json`
//! (about 4000 points a set, 8 sets, frequencies up to ±128: a few seconds);
//! `--help` lists every flag. Exit status: 0 on success, 1 if writing fails,
//! 2 for bad arguments or parameters the sampler rejects.
//!
//! The parts live in `examples/plot/`: `args.rs` (the command line),
//! `run.rs` (sampling, pictures and the report), `spectrum.rs` (periodogram, radial
//! power, anisotropy), `raster.rs` (in-pixel density, per-pixel counts,
//! edge bands — each takes a plain list of points in raster coordinates, so
//! a streamed set is measured like a batch one), `quality.rs` (minimum
//! distance, close pairs, uncovered fraction), `draw.rs`, `canvas.rs` and
//! `common/line_chart.rs` (pictures, PNG), `font.rs` (the 5×7 font).

#[path = "plot/args.rs"]
mod args;
#[path = "plot/canvas.rs"]
mod canvas;
#[path = "common/mod.rs"]
mod common;
#[path = "plot/draw.rs"]
mod draw;
#[path = "plot/font.rs"]
mod font;
#[path = "common/line_chart.rs"]
mod line_chart;
// The integration tests' naive oracle: the one independent distance check.
#[path = "../tests/common/mod.rs"]
mod oracle;
#[path = "plot/quality.rs"]
mod quality;
#[path = "plot/raster.rs"]
mod raster;
#[path = "plot/run.rs"]
mod run;
#[path = "plot/spectrum.rs"]
mod spectrum;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Bad flags print clap's message and exit 2; --help exits 0.
    let config = args::Args::parse().config().unwrap_or_else(|e| e.exit());
    common::finish("plot", run::dispatch(&config))
}
