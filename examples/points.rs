//! Poisson disk points on the command line: samples the box
//! `lo <= x < lo + extent` in 1 to 8 dimensions with `bridson::PoissonDisk`,
//! or a `W × H` raster pixel by pixel with `bridson::Tiled` (`--pixels`), and
//! streams the points, as they are generated, as CSV or JSON to a file or
//! stdout, then prints a one-line summary (count, time, points/s, relative
//! radius ρ, grid layout) to stderr. Run it as
//! `cargo run --release --example points -- --dim 2 --radius 0.01 --extent 1,1 --seed 7 --out pts.csv`
//! or `cargo run --release --example points -- --pixels 64x48 --per-pixel 4 --format json`;
//! `--help` lists every flag. Exit status: 0 on success, 1 if writing the
//! output fails (for example a broken pipe), 2 for bad arguments or
//! parameters the sampler rejects.
//!
//! The parts live in `examples/points/`: `args.rs` (the command line),
//! `output.rs` (sampling, CSV and JSON, the summary) and `camera.rs`
//! (`--camera`: a renderer's camera samples).

#[path = "points/args.rs"]
mod args;
#[path = "points/camera.rs"]
mod camera;
#[path = "common/mod.rs"]
mod common;
#[path = "points/field.rs"]
mod field;
#[path = "points/output.rs"]
mod output;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Bad flags print clap's message and exit 2; --help exits 0.
    let config = args::Args::parse().config().unwrap_or_else(|e| e.exit());
    common::finish("points", output::dispatch(&config))
}
