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
//! The parts live in `examples/plot/`: `spectrum.rs` (periodogram, radial
//! power, anisotropy), `raster.rs` (in-pixel density, per-pixel counts,
//! edge bands — each takes a plain list of points in raster coordinates, so
//! a streamed set is measured like a batch one), `quality.rs` (minimum
//! distance, close pairs, uncovered fraction), `draw.rs` and `canvas.rs`
//! (pictures, PNG), `font.rs` (the 5×7 font).

#[path = "plot/canvas.rs"]
mod canvas;
#[path = "plot/draw.rs"]
mod draw;
#[path = "plot/font.rs"]
mod font;
#[path = "plot/quality.rs"]
mod quality;
#[path = "plot/raster.rs"]
mod raster;
#[path = "plot/spectrum.rs"]
mod spectrum;

use crate::draw::{CellGrid, LineChart, PointView, Reference, Series};
use crate::raster::{CountHistogram, EdgeRatios, InPixelDensity, Raster};
use crate::spectrum::Periodogram;
use bridson::rand::Rng;
use bridson::{Candidates, Domain, PoissonDisk, Scheme, Tiled};
use std::ffi::OsString;
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Instant;

const USAGE: &str = "\
Usage: plot [OPTIONS] (--out-dir DIR | --report FILE | both)

Draws Poisson disk point sets (Bridson) as PNG images and writes a JSON
quality report. Set k is drawn with seed S + k; the point plot and the report
use set 0, the spectra and the in-pixel density average over all sets.

Sampler:
  --dim D                  dimension, 2 to 8                  [default: 2]
  --radius R               minimum distance  [default: about 4000 points,
                           the radius for rho 0.73]
  --extent A,B,..          box size, exactly D values       [default: all 1]
  --pixels WxH             a raster of W x H pixels of side 1: the box is
                           [0,W) x [0,H) (2-D only; not with --extent);
                           adds the in-pixel density picture and the raster
                           part of the report
  --stream SCHEME          with --pixels: stream the sets pixel by pixel
                           with bridson::Tiled, sweep | paper (Ye's per-pixel
                           scheme, which has a border bias); not periodic
  --exact N                with --pixels: stream with exactly N points in
                           every pixel (the radius is then the oversampled
                           sweep's)
  --periodic               make every axis periodic (toroidal)
  --attempts K             candidate attempts per active point [default: 30]
  --candidates KIND        annulus | sphere                [default: annulus]
  --seed S                 seed of set 0                        [default: 0]
Pictures (PNG, written as DIR/NAME-KIND.png):
  --out-dir DIR            directory for the images (created if missing)
  --name NAME              file name prefix                  [default: plot]
  --plots KIND,..          points, periodogram, radial, anisotropy, density
                           [default: points; the three spectra in 2-D;
                           density with --pixels]
  --size PX                longer side of the point plot, 16 to 8192
                                                               [default: 512]
  --window X0,Y0,X1,Y1     show only this rectangle of axes 0 and 1 in the
                           point plot                 [default: the whole box]
  --pixel-grid             draw pixel borders (lines at whole coordinates)
  --cell-grid              draw the background grid, cells of side r/sqrt(D)
  --view KIND              slice | projection: for D > 2, the points within
                           r/2 of the middle of axes 2.. or all of them
                                                             [default: slice]
  --sets M                 independent sets for the spectra and the in-pixel
                           density, 1 to 10000                  [default: 8]
  --freq F                 frequencies -F..F on each axis, 1 to 1024
                                                               [default: 128]
  --bins B                 in-pixel density bins per side, 1 to 256
                                                                [default: 32]
Report:
  --report FILE            write the JSON quality report of set 0 to FILE
                           ('-' for stdout)
  --probes P               uniform probe points for the uncovered fraction
                                                            [default: 100000]
  -h, --help               print this help and exit

Flags also accept the form --flag=value.

The periodogram P(f) = |sum_j exp(-2 pi i f.x_j)|^2 / n is computed exactly
for the points scaled to the unit square, for integer f, and shown in grey
from -20 dB (black) to +10 dB (white); white noise is 0 dB. The radial power
chart marks white noise (1) and, for a square box, the first ring of a
hexagonal lattice of the same density. The anisotropy of M averaged sets of
white noise is -10 log10(M) dB, drawn as a dashed line.

Exit status: 0 success, 1 error writing an output, 2 bad arguments or
parameters rejected by the sampler.

Examples:
  plot --out-dir pics --name annulus --report pics/annulus.json
  plot --pixels 8x6 --radius 0.2 --pixel-grid --cell-grid --plots points --out-dir pics
";

/// The points per set the default radius aims at, with ρ = 0.73.
const DEFAULT_POINTS: usize = 4000;
const DEFAULT_RHO: f64 = 0.73;
/// Width of the edge bands of the raster report, in pixels.
const EDGE_BAND: f64 = 0.1;
/// Mixed into the seed for the uncovered-fraction probes, so that they are
/// not the sampler's own draws.
const PROBE_SALT: u64 = 0x9e37_79b9_7f4a_7c15;
/// Colour of the white-noise reference lines.
const REFERENCE_GREY: canvas::Rgb = [100, 100, 100];
/// Size of the chart images.
const CHART_SIZE: (u32, u32) = (640, 400);

/// One picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Plot {
    Points,
    Periodogram,
    Radial,
    Anisotropy,
    Density,
}

impl Plot {
    const ALL: [Self; 5] = [
        Self::Points,
        Self::Periodogram,
        Self::Radial,
        Self::Anisotropy,
        Self::Density,
    ];

    fn name(self) -> &'static str {
        match self {
            Self::Points => "points",
            Self::Periodogram => "periodogram",
            Self::Radial => "radial",
            Self::Anisotropy => "anisotropy",
            Self::Density => "density",
        }
    }

    fn is_spectral(self) -> bool {
        matches!(self, Self::Periodogram | Self::Radial | Self::Anisotropy)
    }
}

impl FromStr for Plot {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, ()> {
        Self::ALL.into_iter().find(|p| p.name() == s).ok_or(())
    }
}

/// How a point set of more than two dimensions is shown in the plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum View {
    /// The points within `r/2` of the middle of every axis from 2 on.
    Slice,
    /// Every point, by its first two coordinates.
    Projection,
}

/// A fully parsed and checked command line.
#[derive(Clone, Debug, PartialEq)]
struct Config {
    dim: usize,
    radius: Option<f64>,
    extent: Option<Vec<f64>>,
    pixels: Option<Raster>,
    periodic: bool,
    attempts: u32,
    candidates: Candidates,
    seed: u64,
    out_dir: Option<PathBuf>,
    name: String,
    /// The pictures to draw (resolved: never empty when `out_dir` is set).
    plots: Vec<Plot>,
    size: u32,
    /// The rectangle of the point plot: `[x0, y0, x1, y1]`.
    window: Option<[f64; 4]>,
    pixel_grid: bool,
    cell_grid: bool,
    view: View,
    sets: u32,
    freq: u32,
    bins: usize,
    report: Option<PathBuf>,
    probes: u64,
    /// With `--pixels`: take the sets from the streaming mode.
    stream: Option<Stream>,
}

/// Which streamed set (`--stream`, `--exact`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stream {
    Sweep,
    Paper,
    /// Exactly this many points in every pixel.
    Exact(u32),
}

#[derive(Clone, Debug, PartialEq)]
enum Command {
    Help,
    Run(Box<Config>),
}

/// Why a run failed; decides the exit code.
#[derive(Debug)]
enum Failure {
    /// Bad arguments or parameters (exit 2).
    Usage(String),
    /// Writing an output failed (exit 1).
    Io(String),
}

fn main() {
    let code = match parse_args(std::env::args_os().skip(1)) {
        Ok(Command::Help) => print_help(),
        Ok(Command::Run(config)) => match dispatch(&config) {
            Ok(()) => 0,
            Err(Failure::Usage(message)) => usage_error(&message),
            Err(Failure::Io(message)) => {
                report(&format!("plot: error: {message}"));
                1
            }
        },
        Err(message) => usage_error(&message),
    };
    std::process::exit(code);
}

fn print_help() -> i32 {
    let mut out = io::stdout().lock();
    match out.write_all(USAGE.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => 0,
        Err(e) => {
            report(&format!("plot: error: writing the help to stdout: {e}"));
            1
        }
    }
}

/// Prints a bad-argument message and the hint; returns exit code 2.
fn usage_error(message: &str) -> i32 {
    report(&format!(
        "plot: error: {message}\nplot: run with --help for usage"
    ));
    2
}

/// Writes a line to stderr, never panicking if stderr is gone.
fn report(line: &str) {
    let mut err = io::stderr().lock();
    let _ = writeln!(err, "{line}");
}

/// A uniform `f64` in `[0, 1)` from the top 53 bits of one draw.
fn uniform01<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
}

// ---------------------------------------------------------------------------
// Argument parsing (the helpers follow examples/points.rs)

/// Parses the arguments after the program name.
fn parse_args<I, S>(args: I) -> Result<Command, String>
where
    I: IntoIterator<Item = S>,
    S: Into<OsString>,
{
    let mut dim: Option<usize> = None;
    let mut radius: Option<f64> = None;
    let mut extent: Option<Vec<f64>> = None;
    let mut pixels: Option<Raster> = None;
    let mut stream: Option<Stream> = None;
    let mut periodic = false;
    let mut attempts: Option<u32> = None;
    let mut candidates: Option<Candidates> = None;
    let mut seed: Option<u64> = None;
    let mut out_dir: Option<PathBuf> = None;
    let mut name: Option<String> = None;
    let mut plots: Option<Vec<Plot>> = None;
    let mut size: Option<u32> = None;
    let mut window: Option<Vec<f64>> = None;
    let mut pixel_grid = false;
    let mut cell_grid = false;
    let mut view: Option<View> = None;
    let mut sets: Option<u32> = None;
    let mut freq: Option<u32> = None;
    let mut bins: Option<usize> = None;
    let mut report_to: Option<PathBuf> = None;
    let mut probes: Option<u64> = None;

    let mut args = args.into_iter().map(Into::into);
    while let Some(raw) = args.next() {
        let Some(arg) = raw.to_str() else {
            return Err(format!(
                "argument '{}' is not valid UTF-8",
                raw.to_string_lossy()
            ));
        };
        let (flag, inline) = match arg.split_once('=') {
            Some((flag, value)) if flag.starts_with("--") => (flag, Some(value)),
            _ => (arg, None),
        };
        let flag = flag.to_owned();
        let inline: Option<OsString> = inline.map(OsString::from);
        match flag.as_str() {
            "-h" | "--help" => {
                no_value(&flag, inline.as_ref())?;
                return Ok(Command::Help);
            }
            "--periodic" => switch(&flag, inline.as_ref(), &mut periodic)?,
            "--pixel-grid" => switch(&flag, inline.as_ref(), &mut pixel_grid)?,
            "--cell-grid" => switch(&flag, inline.as_ref(), &mut cell_grid)?,
            "--dim" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(
                    &mut dim,
                    parse_number(&flag, &v, "an integer from 2 to 8")?,
                    &flag,
                )?;
            }
            "--radius" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut radius, parse_number(&flag, &v, "a number")?, &flag)?;
            }
            "--extent" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut extent, parse_list(&flag, &v, "a number")?, &flag)?;
            }
            "--stream" => {
                let v = text_value(&flag, inline, &mut args)?;
                let mode = match v.as_str() {
                    "sweep" => Stream::Sweep,
                    "paper" => Stream::Paper,
                    other => {
                        return Err(format!("--stream expects sweep or paper, got '{other}'"));
                    }
                };
                set(&mut stream, mode, &flag)?;
            }
            "--exact" => {
                let v = text_value(&flag, inline, &mut args)?;
                let n: u32 = parse_number(&flag, &v, "a whole number")?;
                set(&mut stream, Stream::Exact(n), &flag)?;
            }
            "--pixels" => {
                let v = text_value(&flag, inline, &mut args)?;
                let size = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)))
                    .filter(|&(w, h)| w > 0 && h > 0)
                    .map(|(width, height)| Raster { width, height })
                    .ok_or_else(|| {
                        format!(
                            "invalid value '{v}' for --pixels: expected WxH, two positive \
                             whole numbers (e.g. 64x48)"
                        )
                    })?;
                set(&mut pixels, size, &flag)?;
            }
            "--attempts" => {
                let v = text_value(&flag, inline, &mut args)?;
                let k = parse_number(&flag, &v, "a positive integer below 2^32")?;
                set(&mut attempts, k, &flag)?;
            }
            "--candidates" => {
                let v = text_value(&flag, inline, &mut args)?;
                let kind = match v.as_str() {
                    "annulus" => Candidates::Annulus,
                    "sphere" => Candidates::Sphere,
                    _ => {
                        return Err(format!(
                            "invalid value '{v}' for --candidates: expected annulus or sphere"
                        ));
                    }
                };
                set(&mut candidates, kind, &flag)?;
            }
            "--seed" => {
                let v = text_value(&flag, inline, &mut args)?;
                let s = parse_number(&flag, &v, "an unsigned 64-bit integer")?;
                set(&mut seed, s, &flag)?;
            }
            "--out-dir" => {
                let v = value(&flag, inline, &mut args)?;
                if v.is_empty() {
                    return Err("--out-dir needs a directory name".to_owned());
                }
                set(&mut out_dir, PathBuf::from(v), &flag)?;
            }
            "--name" => {
                let v = text_value(&flag, inline, &mut args)?;
                if v.is_empty() || v.contains(['/', '\\']) {
                    return Err(format!(
                        "invalid value '{v}' for --name: expected a file name prefix"
                    ));
                }
                set(&mut name, v, &flag)?;
            }
            "--plots" => {
                let v = text_value(&flag, inline, &mut args)?;
                let list = parse_list(
                    &flag,
                    &v,
                    "points, periodogram, radial, anisotropy or density",
                )?;
                set(&mut plots, list, &flag)?;
            }
            "--size" => {
                let v = text_value(&flag, inline, &mut args)?;
                let s = parse_number(&flag, &v, "a whole number of pixels")?;
                set(&mut size, s, &flag)?;
            }
            "--window" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut window, parse_list(&flag, &v, "a number")?, &flag)?;
            }
            "--view" => {
                let v = text_value(&flag, inline, &mut args)?;
                let kind = match v.as_str() {
                    "slice" => View::Slice,
                    "projection" => View::Projection,
                    _ => {
                        return Err(format!(
                            "invalid value '{v}' for --view: expected slice or projection"
                        ));
                    }
                };
                set(&mut view, kind, &flag)?;
            }
            "--sets" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut sets, parse_number(&flag, &v, "an integer")?, &flag)?;
            }
            "--freq" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut freq, parse_number(&flag, &v, "an integer")?, &flag)?;
            }
            "--bins" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut bins, parse_number(&flag, &v, "an integer")?, &flag)?;
            }
            "--report" => {
                let v = value(&flag, inline, &mut args)?;
                if v.is_empty() {
                    return Err("--report needs a file name (or '-')".to_owned());
                }
                set(&mut report_to, PathBuf::from(v), &flag)?;
            }
            "--probes" => {
                let v = text_value(&flag, inline, &mut args)?;
                let p = parse_number(&flag, &v, "an unsigned integer")?;
                set(&mut probes, p, &flag)?;
            }
            other if other.starts_with('-') => return Err(format!("unknown flag '{other}'")),
            other => return Err(format!("unexpected argument '{other}'")),
        }
    }

    let dim = dim.unwrap_or(2);
    if !(2..=8).contains(&dim) {
        return Err(format!("--dim must be from 2 to 8, got {dim}"));
    }
    if let Some(values) = &extent
        && values.len() != dim
    {
        return Err(format!(
            "--extent needs exactly {dim} comma-separated values (one per axis), got {}",
            values.len()
        ));
    }
    if pixels.is_some() && extent.is_some() {
        return Err("--pixels and --extent both set the box: give one".to_owned());
    }
    if pixels.is_some() && dim != 2 {
        return Err(format!("--pixels needs --dim 2, got --dim {dim}"));
    }
    if stream.is_some() && pixels.is_none() {
        return Err("--stream and --exact need --pixels WxH".to_owned());
    }
    if stream.is_some() && periodic {
        return Err("the streaming mode is not periodic: drop --periodic".to_owned());
    }
    let plots = match plots {
        Some(list) => {
            for p in &list {
                if p.is_spectral() && dim != 2 {
                    return Err(format!(
                        "--plots {}: the spectra are 2-D only, got --dim {dim}",
                        p.name()
                    ));
                }
                if *p == Plot::Density && pixels.is_none() {
                    return Err("--plots density needs --pixels WxH".to_owned());
                }
            }
            list
        }
        None => Plot::ALL
            .into_iter()
            .filter(|p| match p {
                Plot::Points => true,
                Plot::Periodogram | Plot::Radial | Plot::Anisotropy => dim == 2,
                Plot::Density => pixels.is_some(),
            })
            .collect(),
    };
    if out_dir.is_none() && report_to.is_none() {
        return Err("nothing to do: give --out-dir DIR, --report FILE or both".to_owned());
    }
    let window = match window.as_deref() {
        None => None,
        Some(&[x0, y0, x1, y1])
            if x0 < x1 && y0 < y1 && x1 - x0 < f64::INFINITY && y1 - y0 < f64::INFINITY =>
        {
            Some([x0, y0, x1, y1])
        }
        Some(_) => {
            return Err(
                "--window needs four finite numbers X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1"
                    .to_owned(),
            );
        }
    };
    let size = in_range("--size", size.unwrap_or(512), 16, 8192)?;
    let sets = in_range("--sets", sets.unwrap_or(8), 1, 10_000)?;
    let freq = in_range("--freq", freq.unwrap_or(128), 1, 1024)?;
    let bins = in_range("--bins", bins.unwrap_or(32), 1, 256)?;
    Ok(Command::Run(Box::new(Config {
        dim,
        radius,
        extent,
        pixels,
        periodic,
        attempts: attempts.unwrap_or(bridson::DEFAULT_ATTEMPTS),
        candidates: candidates.unwrap_or_default(),
        seed: seed.unwrap_or(0),
        out_dir,
        name: name.unwrap_or_else(|| "plot".to_owned()),
        plots,
        size,
        window,
        pixel_grid,
        cell_grid,
        view: view.unwrap_or(View::Slice),
        sets,
        freq,
        bins,
        report: report_to,
        probes: probes.unwrap_or(100_000),
        stream,
    })))
}

fn in_range<T: PartialOrd + std::fmt::Display>(
    flag: &str,
    value: T,
    lo: T,
    hi: T,
) -> Result<T, String> {
    if lo <= value && value <= hi {
        Ok(value)
    } else {
        Err(format!("{flag} must be from {lo} to {hi}, got {value}"))
    }
}

/// Rejects `--flag=value` on a flag that takes no value.
fn no_value(flag: &str, inline: Option<&OsString>) -> Result<(), String> {
    match inline {
        Some(_) => Err(format!("{flag} takes no value")),
        None => Ok(()),
    }
}

/// Sets a flag that takes no value, refusing a second occurrence.
fn switch(flag: &str, inline: Option<&OsString>, slot: &mut bool) -> Result<(), String> {
    no_value(flag, inline)?;
    if *slot {
        return Err(format!("{flag} given more than once"));
    }
    *slot = true;
    Ok(())
}

/// The flag's value: the `=value` part, else the next argument.
fn value(
    flag: &str,
    inline: Option<OsString>,
    rest: &mut impl Iterator<Item = OsString>,
) -> Result<OsString, String> {
    inline
        .or_else(|| rest.next())
        .ok_or_else(|| format!("missing value for {flag}"))
}

/// The flag's value as text.
fn text_value(
    flag: &str,
    inline: Option<OsString>,
    rest: &mut impl Iterator<Item = OsString>,
) -> Result<String, String> {
    value(flag, inline, rest)?.into_string().map_err(|raw| {
        format!(
            "invalid value '{}' for {flag}: not valid UTF-8",
            raw.to_string_lossy()
        )
    })
}

/// Stores a flag's value, refusing a second occurrence.
fn set<T>(slot: &mut Option<T>, value: T, flag: &str) -> Result<(), String> {
    if slot.is_some() {
        return Err(format!("{flag} given more than once"));
    }
    *slot = Some(value);
    Ok(())
}

fn parse_number<T: FromStr>(flag: &str, text: &str, expected: &str) -> Result<T, String> {
    text.trim()
        .parse()
        .map_err(|_| format!("invalid value '{text}' for {flag}: expected {expected}"))
}

/// A comma-separated list; every item must parse (no empty items).
fn parse_list<T: FromStr>(flag: &str, text: &str, expected: &str) -> Result<Vec<T>, String> {
    text.split(',')
        .map(|item| {
            item.trim().parse().map_err(|_| {
                format!("invalid item '{item}' in {flag} '{text}': expected {expected}")
            })
        })
        .collect()
}

// ---------------------------------------------------------------------------
// Sampling, pictures and the report

fn dispatch(config: &Config) -> Result<(), Failure> {
    match config.dim {
        2 => run::<2>(config),
        3 => run::<3>(config),
        4 => run::<4>(config),
        5 => run::<5>(config),
        6 => run::<6>(config),
        7 => run::<7>(config),
        8 => run::<8>(config),
        d => Err(Failure::Usage(format!(
            "--dim must be from 2 to 8, got {d}"
        ))),
    }
}

/// The sampler `config` describes, or the library's reason why not.
fn build<const N: usize>(config: &Config) -> Result<PoissonDisk<N>, String> {
    let extent: [f64; N] = match (&config.extent, config.pixels) {
        (Some(v), _) => <[f64; N]>::try_from(v.as_slice())
            .map_err(|_| format!("--extent needs exactly {N} values, got {}", v.len()))?,
        (None, Some(r)) => core::array::from_fn(|i| match i {
            0 => f64::from(r.width),
            _ => f64::from(r.height),
        }),
        (None, None) => [1.0; N],
    };
    let domain = Domain::from_extent(extent)
        .map_err(|e| e.to_string())?
        .with_periodic([config.periodic; N]);
    let radius = match config.radius {
        Some(r) => r,
        None => default_radius::<N>(domain.volume())
            .ok_or("no default radius for this box: give --radius")?,
    };
    PoissonDisk::<N>::builder(domain, radius)
        .attempts(config.attempts)
        .candidates(config.candidates)
        .build()
        .map_err(|e| e.to_string())
}

/// The streaming sampler `--stream` / `--exact` ask for, over the raster.
fn streamer(config: &Config, radius: f64) -> Result<Option<Tiled>, String> {
    let (Some(mode), Some(raster)) = (config.stream, config.pixels) else {
        return Ok(None);
    };
    let builder = Tiled::builder(raster.width, raster.height)
        .attempts(config.attempts)
        .candidates(config.candidates);
    let builder = match mode {
        Stream::Sweep => builder.radius(radius),
        Stream::Paper => builder.radius(radius).scheme(Scheme::Paper),
        Stream::Exact(n) => builder.exact(n),
    };
    builder.build().map(Some).map_err(|e| e.to_string())
}

/// The radius that gives about [`DEFAULT_POINTS`] points in `volume` at
/// ρ = [`DEFAULT_RHO`] (the annulus candidates' ρ in 2-D).
fn default_radius<const N: usize>(volume: f64) -> Option<f64> {
    // ρ is proportional to the radius: ρ(1) = 1 / r_max.
    let per_unit = bridson::relative_radius::<N>(1.0, DEFAULT_POINTS, volume)?;
    let r = DEFAULT_RHO / per_unit;
    r.is_finite().then_some(r)
}

/// The points scaled from the domain's first two axes to the unit square.
fn to_unit_square<const N: usize>(points: &[[f64; N]], domain: &Domain<N>) -> Vec<[f64; 2]> {
    let (lo, extent) = (domain.lo(), domain.extent());
    points
        .iter()
        .map(|p| [(p[0] - lo[0]) / extent[0], (p[1] - lo[1]) / extent[1]])
        .collect()
}

/// The first two coordinates of the points the plot shows: all of them in
/// 2-D or with [`View::Projection`], else those within `r/2` of the middle
/// of every further axis.
fn visible<const N: usize>(
    points: &[[f64; N]],
    domain: &Domain<N>,
    radius: f64,
    view: View,
) -> Vec<[f64; 2]> {
    let (lo, hi) = (domain.lo(), domain.hi());
    points
        .iter()
        .filter(|p| {
            view == View::Projection
                || (2..N).all(|i| (p[i] - 0.5 * (lo[i] + hi[i])).abs() <= 0.5 * radius)
        })
        .map(|p| [p[0], p[1]])
        .collect()
}

/// Generates the sets, draws the pictures, writes the report.
fn run<const N: usize>(config: &Config) -> Result<(), Failure> {
    let sampler = build::<N>(config).map_err(Failure::Usage)?;
    let domain = *sampler.domain();
    let tiled = streamer(config, sampler.radius()).map_err(Failure::Usage)?;
    let radius = tiled.as_ref().map_or(sampler.radius(), Tiled::radius);
    let wants = |p: Plot| config.out_dir.is_some() && config.plots.contains(&p);
    let spectra = Plot::ALL.into_iter().any(|p| p.is_spectral() && wants(p));
    let density = wants(Plot::Density);
    let sets = if spectra || density { config.sets } else { 1 };
    if let Some(dir) = &config.out_dir {
        std::fs::create_dir_all(dir)
            .map_err(|e| Failure::Io(format!("cannot create '{}': {e}", dir.display())))?;
    }

    let clock = Instant::now();
    let mut periodogram = spectra.then(|| Periodogram::new(config.freq));
    let mut in_pixel = density.then(|| InPixelDensity::new(config.bins));
    let mut first: Vec<[f64; N]> = Vec::new();
    let mut total = 0;
    let mut spectrum_time = 0.0;
    for k in 0..sets {
        // A streamed set is every pixel's points (raster coordinates) in
        // one list; all that follows takes a plain list of points.
        let seed = config.seed.wrapping_add(u64::from(k));
        let points: Vec<[f64; N]> = match &tiled {
            Some(t) => t
                .pixels_seeded(seed)
                .flat_map(|pixel| pixel.points)
                .map(|p| core::array::from_fn(|i| p.get(i).copied().unwrap_or(0.0)))
                .collect(),
            None => sampler
                .generate_seeded(seed)
                .map_err(|e| Failure::Usage(e.to_string()))?,
        };
        total += points.len();
        if let Some(pg) = &mut periodogram {
            let start = Instant::now();
            pg.add_set(&to_unit_square(&points, &domain));
            spectrum_time += start.elapsed().as_secs_f64();
        }
        if let (Some(d), Some(raster)) = (&mut in_pixel, config.pixels) {
            let plane: Vec<[f64; 2]> = points.iter().map(|p| [p[0], p[1]]).collect();
            d.add(&plane, raster);
        }
        if k == 0 {
            first = points;
        }
    }
    report(&format!(
        "plot: {sets} set(s), {total} points, set 0: {} points, rho {}, radius {radius} \
         ({:.2} s, of which periodogram {spectrum_time:.2} s)",
        first.len(),
        bridson::relative_radius::<N>(radius, first.len(), domain.volume())
            .map_or_else(|| "n/a".to_owned(), |rho| format!("{rho:.4}")),
        clock.elapsed().as_secs_f64(),
    ));

    if let Some(dir) = &config.out_dir {
        let path = |p: Plot| dir.join(format!("{}-{}.png", config.name, p.name()));
        if wants(Plot::Points) {
            let (lo, hi) = (domain.lo(), domain.hi());
            let [x0, y0, x1, y1] = config.window.unwrap_or([lo[0], lo[1], hi[0], hi[1]]);
            let view = PointView {
                lo: [x0, y0],
                hi: [x1, y1],
                size: config.size,
                radius,
                pixel_grid: config.pixel_grid,
                cell_grid: config.cell_grid.then(|| CellGrid {
                    side: radius / (N as f64).sqrt(),
                    origin: [lo[0], lo[1]],
                }),
            };
            let shown = visible(&first, &domain, radius, config.view);
            save(&draw::point_plot(&shown, &view), &path(Plot::Points))?;
        }
        if let Some(pg) = &periodogram {
            let mean_n = total as f64 / f64::from(sets);
            // Scaling to the unit square keeps angles only for a square box.
            let square = domain.extent()[0] == domain.extent()[1];
            spectrum_pictures(pg, mean_n, square, config, &path)?;
        }
        if let Some(d) = &in_pixel {
            if d.outside() > 0 {
                report(&format!(
                    "plot: warning: {} points outside the raster",
                    d.outside()
                ));
            }
            let title = "density in pixel (mean 1)";
            let (canvas, spread) = draw::heat_map(&d.relative(), d.bins(), title);
            report(&format!(
                "plot: in-pixel density from {} points, colours span 1 +- {spread}",
                d.inside()
            ));
            save(&canvas, &path(Plot::Density))?;
        }
    }

    if let Some(target) = &config.report {
        let start = Instant::now();
        let json = quality_report(config, domain, radius, &first);
        write_report(target, &json)?;
        report(&format!(
            "plot: report in {:.2} s",
            start.elapsed().as_secs_f64()
        ));
    }
    Ok(())
}

/// The periodogram, radial power and anisotropy pictures that are asked
/// for; `mean_n` is the mean number of points a set, `square` whether the
/// hexagonal-lattice frequency applies.
fn spectrum_pictures(
    pg: &Periodogram,
    mean_n: f64,
    square: bool,
    config: &Config,
    path: &dyn Fn(Plot) -> PathBuf,
) -> Result<(), Failure> {
    let wants = |p: Plot| config.plots.contains(&p);
    let mean = pg.mean();
    let max_freq = pg.max_freq();
    if wants(Plot::Periodogram) {
        save(
            &draw::periodogram_image(&mean, max_freq),
            &path(Plot::Periodogram),
        )?;
    }
    let rings = spectrum::radial(&mean, max_freq);
    let x_range = [0.0, f64::from(max_freq)];
    let line = |value: &dyn Fn(&spectrum::Ring) -> Option<f64>| {
        rings
            .iter()
            .map(|r| [f64::from(r.frequency), value(r).unwrap_or(f64::NAN)])
            .collect::<Vec<_>>()
    };
    if wants(Plot::Radial) {
        let top = rings
            .iter()
            .map(|r| r.power)
            .filter(|p| p.is_finite())
            .fold(0.0, f64::max);
        let mut references = vec![Reference {
            horizontal: true,
            at: 1.0,
            label: "white noise".to_owned(),
            colour: REFERENCE_GREY,
        }];
        if square {
            // The first ring of a hexagonal lattice of the same density:
            // spacing d = sqrt(2 / (√3 n)), frequency 2 / (√3 d).
            references.push(Reference {
                horizontal: false,
                at: (2.0 * mean_n / 3_f64.sqrt()).sqrt(),
                label: "hexagonal lattice".to_owned(),
                colour: [40, 150, 60],
            });
        }
        let chart = LineChart {
            title: format!(
                "radial power, {} sets of about {mean_n:.0} points",
                pg.sets()
            ),
            x_label: "frequency |f|".to_owned(),
            y_label: "power".to_owned(),
            x_range,
            // At least 0..2, with headroom above the peak, in steps of 0.5.
            y_range: [0.0, ((top * 1.1).max(2.0) * 2.0).ceil() / 2.0],
            series: vec![Series {
                points: line(&|r| Some(r.power)),
                colour: [30, 80, 200],
            }],
            references,
        };
        save(
            &chart.render(CHART_SIZE.0, CHART_SIZE.1),
            &path(Plot::Radial),
        )?;
    }
    if wants(Plot::Anisotropy) {
        let reference = -10.0 * f64::from(pg.sets()).log10();
        let (low, high) = rings
            .iter()
            .filter_map(|r| r.anisotropy_db)
            .fold((-20.0_f64, 10.0_f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
        let chart = LineChart {
            title: format!("anisotropy, {} sets", pg.sets()),
            x_label: "frequency |f|".to_owned(),
            y_label: "anisotropy (dB)".to_owned(),
            x_range,
            y_range: [
                (low / 5.0).floor().max(-8.0) * 5.0,
                (high / 5.0).ceil().min(8.0) * 5.0,
            ],
            series: vec![Series {
                points: line(&|r| r.anisotropy_db),
                colour: [200, 40, 40],
            }],
            references: vec![Reference {
                horizontal: true,
                at: reference,
                label: format!("white noise {reference:.1} dB"),
                colour: REFERENCE_GREY,
            }],
        };
        save(
            &chart.render(CHART_SIZE.0, CHART_SIZE.1),
            &path(Plot::Anisotropy),
        )?;
    }
    Ok(())
}

fn save(canvas: &canvas::Canvas, path: &Path) -> Result<(), Failure> {
    canvas
        .save(path)
        .map_err(|e| Failure::Io(format!("writing '{}': {e}", path.display())))?;
    report(&format!("plot: wrote {}", path.display()));
    Ok(())
}

fn write_report(target: &Path, json: &str) -> Result<(), Failure> {
    let result = if target == Path::new("-") {
        let mut out = io::stdout().lock();
        out.write_all(json.as_bytes()).and_then(|()| out.flush())
    } else {
        std::fs::write(target, json)
    };
    result.map_err(|e| Failure::Io(format!("writing '{}': {e}", target.display())))
}

/// The raster part of the report.
struct RasterReport {
    raster: Raster,
    counts: CountHistogram,
    edges: EdgeRatios,
}

/// The JSON quality report of `points`, a set of `domain` with minimum
/// distance `radius` drawn as `config` says (see the README for the
/// fields). Takes the plain list, so a streamed set is measured alike.
fn quality_report<const N: usize>(
    config: &Config,
    domain: Domain<N>,
    radius: f64,
    points: &[[f64; N]],
) -> String {
    let pairs = quality::pair_stats(points, domain, radius);
    let uncovered = quality::uncovered_fraction(
        points,
        domain,
        radius,
        config.probes,
        config.seed ^ PROBE_SALT,
    );
    let raster = config.pixels.map(|raster| {
        let plane: Vec<[f64; 2]> = points.iter().map(|p| [p[0], p[1]]).collect();
        RasterReport {
            raster,
            counts: raster::pixel_count_histogram(&plane, raster),
            edges: raster::edge_ratios(&plane, raster, EDGE_BAND),
        }
    });
    let rho = bridson::relative_radius::<N>(radius, points.len(), domain.volume());
    let mut j = String::new();
    let candidates = format!("{:?}", config.candidates).to_lowercase();
    let _ = writeln!(j, "{{");
    let _ = writeln!(j, "  \"dim\": {N},");
    let _ = writeln!(j, "  \"radius\": {},", number(radius));
    let _ = writeln!(j, "  \"candidates\": \"{candidates}\",");
    let _ = writeln!(j, "  \"attempts\": {},", config.attempts);
    let _ = writeln!(j, "  \"seed\": {},", config.seed);
    let _ = writeln!(j, "  \"lo\": [{}],", numbers(&domain.lo()));
    let _ = writeln!(j, "  \"hi\": [{}],", numbers(&domain.hi()));
    let periodic: Vec<String> = domain.periodic().iter().map(bool::to_string).collect();
    let _ = writeln!(j, "  \"periodic\": [{}],", periodic.join(", "));
    let _ = writeln!(j, "  \"n\": {},", points.len());
    let _ = writeln!(
        j,
        "  \"min_distance\": {},",
        pairs.min_distance.map_or_else(|| "null".to_owned(), number)
    );
    let _ = writeln!(
        j,
        "  \"pairs_closer_than_radius\": {},",
        pairs.closer_than_radius
    );
    let _ = writeln!(
        j,
        "  \"rho\": {},",
        rho.map_or_else(|| "null".to_owned(), number)
    );
    let _ = writeln!(j, "  \"uncovered_fraction\": {},", number(uncovered));
    let _ = writeln!(j, "  \"probes\": {},", config.probes);
    match raster {
        None => {
            let _ = writeln!(j, "  \"raster\": null");
        }
        Some(r) => {
            let _ = writeln!(j, "  \"raster\": {{");
            let _ = writeln!(j, "    \"width\": {},", r.raster.width);
            let _ = writeln!(j, "    \"height\": {},", r.raster.height);
            let _ = writeln!(j, "    \"points_outside\": {},", r.counts.outside);
            let hist: Vec<String> = r.counts.pixels_with.iter().map(u64::to_string).collect();
            let _ = writeln!(j, "    \"pixel_count_histogram\": [{}],", hist.join(", "));
            let e = r.edges;
            let _ = writeln!(j, "    \"edge_band\": {},", number(e.band));
            let _ = writeln!(
                j,
                "    \"edge_to_interior_density\": {{\"left\": {}, \"right\": {}, \
                 \"top\": {}, \"bottom\": {}}}",
                number(e.left),
                number(e.right),
                number(e.top),
                number(e.bottom)
            );
            let _ = writeln!(j, "  }}");
        }
    }
    let _ = writeln!(j, "}}");
    j
}

/// A JSON number: the shortest text that parses back to `v`, or `null`
/// for NaN and infinities.
fn number(v: f64) -> String {
    if v.is_finite() {
        format!("{v}")
    } else {
        "null".to_owned()
    }
}

fn numbers(values: &[f64]) -> String {
    values
        .iter()
        .map(|&v| number(v))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(line: &str) -> Result<Command, String> {
        parse_args(line.split_whitespace())
    }

    fn config(line: &str) -> Config {
        match parse(line) {
            Ok(Command::Run(c)) => *c,
            other => panic!("{line}: expected a run, got {other:?}"),
        }
    }

    fn error(line: &str) -> String {
        match parse(line) {
            Err(e) => e,
            other => panic!("{line}: expected an error, got {other:?}"),
        }
    }

    #[test]
    fn parses_the_streaming_flags() {
        let c = config("--pixels 4x4 --radius 0.3 --stream paper --report -");
        assert_eq!(c.stream, Some(Stream::Paper), "paper");
        let c = config("--pixels 4x4 --exact 3 --report -");
        assert_eq!(c.stream, Some(Stream::Exact(3)), "exact");
        assert!(
            error("--radius 0.3 --stream sweep --report -").contains("--pixels"),
            "no raster"
        );
        assert!(
            error("--pixels 4x4 --radius 0.3 --stream sweep --periodic --report -")
                .contains("periodic"),
            "periodic"
        );
        assert!(
            error("--pixels 4x4 --stream zigzag --report -").contains("sweep"),
            "scheme"
        );
    }

    /// A fresh, empty directory under the system's temporary directory.
    fn temp_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("bridson-plot-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temporary directory");
        dir
    }

    #[test]
    fn defaults() {
        let c = config("--out-dir pics");
        assert_eq!(c.dim, 2, "dim");
        assert_eq!(c.radius, None, "radius from the point target");
        assert_eq!(
            c.plots,
            vec![
                Plot::Points,
                Plot::Periodogram,
                Plot::Radial,
                Plot::Anisotropy
            ],
            "2-D default pictures"
        );
        assert_eq!(
            (c.sets, c.freq, c.bins, c.size, c.probes),
            (8, 128, 32, 512, 100_000),
            "numbers"
        );
        assert_eq!(c.name, "plot", "name");
        let c = config("--dim 3 --report r.json");
        assert_eq!(c.plots, vec![Plot::Points], "no spectra in 3-D");
        let c = config("--pixels 4x3 --out-dir d");
        assert_eq!(c.plots.last(), Some(&Plot::Density), "density with pixels");
        assert_eq!(
            c.pixels,
            Some(Raster {
                width: 4,
                height: 3
            }),
            "raster"
        );
    }

    #[test]
    fn parses_every_flag() {
        let c = config(
            "--dim=2 --radius 0.2 --pixels 8x6 --periodic --attempts 12 \
             --candidates=sphere --seed 9 --out-dir=o --name x --plots points,density \
             --size 300 --window 0,0.5,2,3 --pixel-grid --cell-grid --view projection --sets 3 --freq 16 \
             --bins 8 --report - --probes 500",
        );
        assert_eq!(c.radius, Some(0.2), "radius");
        assert!(c.periodic && c.pixel_grid && c.cell_grid, "switches");
        assert_eq!(c.attempts, 12, "attempts");
        assert_eq!(c.candidates, Candidates::Sphere, "candidates");
        assert_eq!(c.seed, 9, "seed");
        assert_eq!(c.out_dir, Some(PathBuf::from("o")), "out dir");
        assert_eq!(c.name, "x", "name");
        assert_eq!(c.plots, vec![Plot::Points, Plot::Density], "plots");
        assert_eq!((c.size, c.sets, c.freq, c.bins), (300, 3, 16, 8), "sizes");
        assert_eq!(c.view, View::Projection, "view");
        assert_eq!(c.window, Some([0.0, 0.5, 2.0, 3.0]), "window");
        assert_eq!(c.report, Some(PathBuf::from("-")), "report");
        assert_eq!(c.probes, 500, "probes");
        let e = config("--dim 3 --extent 1,2,3 --report r");
        assert_eq!(e.extent, Some(vec![1.0, 2.0, 3.0]), "extent");
        assert_eq!(parse("--help"), Ok(Command::Help), "help");
    }

    #[test]
    fn rejects_bad_command_lines() {
        let cases = [
            ("", "nothing to do"),
            ("--dim 1 --report r", "--dim must be from 2 to 8, got 1"),
            ("--dim 9 --report r", "--dim must be from 2 to 8, got 9"),
            ("--extent 1 --report r", "--extent needs exactly 2"),
            (
                "--pixels 4 --report r",
                "invalid value '4' for --pixels: expected WxH",
            ),
            ("--pixels 4x0 --report r", "expected WxH"),
            ("--pixels 4x-1 --report r", "expected WxH"),
            ("--pixels 4,4 --report r", "expected WxH"),
            ("--pixels 4x4 --extent 1,1 --report r", "give one"),
            ("--dim 3 --pixels 4x4 --report r", "--pixels needs --dim 2"),
            ("--dim 3 --plots radial --out-dir o", "2-D only"),
            ("--plots density --out-dir o", "needs --pixels"),
            ("--plots dots --out-dir o", "invalid item 'dots' in --plots"),
            ("--size 8 --out-dir o", "--size must be from 16 to 8192"),
            ("--sets 0 --out-dir o", "--sets must be from 1 to 10000"),
            ("--freq 2000 --out-dir o", "--freq must be from 1 to 1024"),
            ("--bins 0 --out-dir o", "--bins must be from 1 to 256"),
            ("--view side --out-dir o", "expected slice or projection"),
            ("--window 0,0,1 --out-dir o", "--window needs four finite"),
            ("--window 1,0,0,1 --out-dir o", "X0 < X1"),
            (
                "--window 0,0,1,inf --out-dir o",
                "--window needs four finite",
            ),
            (
                "--candidates disk --out-dir o",
                "expected annulus or sphere",
            ),
            ("--name a/b --out-dir o", "expected a file name prefix"),
            ("--out-dir= --report r", "--out-dir needs a directory"),
            ("--report= --out-dir o", "--report needs a file name"),
            (
                "--pixel-grid --pixel-grid --out-dir o",
                "given more than once",
            ),
            ("--periodic=yes --out-dir o", "--periodic takes no value"),
            ("--seed x --out-dir o", "invalid value 'x' for --seed"),
            ("--bogus --out-dir o", "unknown flag '--bogus'"),
            ("stray --out-dir o", "unexpected argument 'stray'"),
        ];
        for (line, expected) in cases {
            let e = error(line);
            assert!(
                e.contains(expected),
                "{line}: got '{e}', expected '{expected}'"
            );
        }
    }

    #[test]
    fn library_errors_are_usage_errors() {
        for line in [
            "--radius 0 --report r",
            "--radius nan --report r",
            "--extent 1,0 --report r",
            "--attempts 0 --report r",
            "--dim 3 --radius 1e-13 --report r",
        ] {
            let c = config(line);
            assert!(
                matches!(dispatch(&c), Err(Failure::Usage(_))),
                "{line}: expected a library error"
            );
        }
    }

    #[test]
    fn the_default_radius_gives_about_4000_points() {
        let r = default_radius::<2>(1.0).expect("radius");
        assert!((r - 0.0124).abs() < 1e-4, "r {r}");
        let sampler = build::<2>(&config("--report r")).expect("sampler");
        let n = sampler.generate_seeded(0).unwrap().len();
        assert!((3700..4300).contains(&n), "{n} points");
    }

    #[test]
    fn slices_keep_the_middle_layer() {
        let d = Domain::from_extent([1.0, 1.0, 1.0]).expect("box");
        let pts = [[0.1, 0.2, 0.5], [0.3, 0.4, 0.9]];
        assert_eq!(
            visible(&pts, &d, 0.1, View::Slice),
            vec![[0.1, 0.2]],
            "slice"
        );
        assert_eq!(
            visible(&pts, &d, 0.1, View::Projection).len(),
            2,
            "projection"
        );
        let wide = Domain::from_extent([2.0, 4.0]).expect("box");
        assert_eq!(
            to_unit_square(&[[1.0, 1.0]], &wide),
            vec![[0.5, 0.25]],
            "scaled"
        );
    }

    #[test]
    fn the_report_is_valid_json_with_every_field() {
        let c = config("--pixels 6x4 --radius 0.3 --probes 2000 --report -");
        let sampler = build::<2>(&c).expect("sampler");
        let points = sampler.generate_seeded(0).unwrap();
        let text = quality_report(&c, *sampler.domain(), sampler.radius(), &points);
        let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(v["n"].as_u64(), Some(points.len() as u64), "n");
        assert_eq!(v["pairs_closer_than_radius"].as_u64(), Some(0), "no pair");
        let min = v["min_distance"].as_f64().expect("min distance");
        assert!(min >= 0.3, "min distance {min}");
        let rho = v["rho"].as_f64().expect("rho");
        assert!((0.6..0.8).contains(&rho), "rho {rho}");
        let u = v["uncovered_fraction"].as_f64().expect("uncovered");
        assert!((0.0..0.05).contains(&u), "uncovered {u}");
        assert_eq!(v["candidates"], "annulus", "candidates");
        assert_eq!(v["periodic"], serde_json::json!([false, false]), "periodic");
        let r = &v["raster"];
        assert_eq!(
            (r["width"].as_u64(), r["height"].as_u64()),
            (Some(6), Some(4)),
            "size"
        );
        let hist: Vec<u64> = r["pixel_count_histogram"]
            .as_array()
            .expect("histogram")
            .iter()
            .map(|x| x.as_u64().expect("count"))
            .collect();
        assert_eq!(hist.iter().sum::<u64>(), 24, "24 pixels");
        for edge in ["left", "right", "top", "bottom"] {
            let ratio = r["edge_to_interior_density"][edge].as_f64().expect("ratio");
            assert!(ratio > 0.0, "{edge} = {ratio}");
        }
        let plain = config("--radius 0.3 --probes 0 --report -");
        let s = build::<2>(&plain).expect("sampler");
        let text = quality_report(&plain, *s.domain(), s.radius(), &[]);
        let v: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert!(v["min_distance"].is_null(), "no pair: null");
        assert!(v["rho"].is_null(), "no points: null");
        assert!(v["uncovered_fraction"].is_null(), "no probes: null");
        assert!(v["raster"].is_null(), "no raster");
    }

    #[test]
    fn numbers_round_trip_and_non_finite_is_null() {
        for x in [0.0, 0.1, 1.0 / 3.0, 1e-300, 12_345.678] {
            assert_eq!(number(x).parse::<f64>().ok(), Some(x), "{x}");
        }
        assert_eq!(number(f64::NAN), "null", "NaN");
        assert_eq!(number(f64::NEG_INFINITY), "null", "infinity");
    }

    fn decode_size(path: &Path) -> (u32, u32) {
        let file = std::fs::File::open(path).expect("written");
        let reader = png::Decoder::new(io::BufReader::new(file))
            .read_info()
            .expect("a PNG");
        (reader.info().width, reader.info().height)
    }

    #[test]
    fn a_tiny_run_writes_every_picture_and_the_report() {
        let dir = temp_dir("run");
        let line = format!(
            "--pixels 4x4 --radius 0.3 --sets 2 --freq 8 --bins 4 --size 64 --pixel-grid \
             --cell-grid --probes 500 --name t --out-dir {} --report {}",
            dir.display(),
            dir.join("r.json").display()
        );
        dispatch(&config(&line)).expect("runs");
        for kind in Plot::ALL {
            let (w, h) = decode_size(&dir.join(format!("t-{}.png", kind.name())));
            assert!(w >= 16 && h >= 16, "{kind:?}: {w}x{h}");
        }
        let json = std::fs::read_to_string(dir.join("r.json")).expect("report");
        let v: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
        assert_eq!(
            v["pairs_closer_than_radius"].as_u64(),
            Some(0),
            "the guarantee"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn three_dimensional_runs_plot_a_slice() {
        let dir = temp_dir("3d");
        let line = format!(
            "--dim 3 --radius 0.15 --periodic --candidates sphere --probes 500 --out-dir {}",
            dir.display()
        );
        dispatch(&config(&line)).expect("runs");
        assert_eq!(
            decode_size(&dir.join("plot-points.png")),
            (512, 512),
            "size"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn chart_labels_are_in_the_font() {
        for text in [
            "radial power, 8 sets of about 4012 points",
            "frequency |f|",
            "power",
            "white noise",
            "anisotropy, 8 sets",
            "anisotropy (dB)",
            "white noise -9.0 dB",
            "density in pixel (mean 1)",
        ] {
            assert!(font::covers(text), "{text}");
        }
    }
}
