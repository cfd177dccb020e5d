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

use bridson::{
    Candidates, DEFAULT_MAX_GRID_BYTES, Domain, Error, GridLayout, PoissonDisk, Scheme, Tiled,
};
use std::ffi::OsString;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;
use std::str::FromStr;
use std::time::{Duration, Instant};

const USAGE: &str = "\
Usage: points --dim D --radius R [OPTIONS]
       points --pixels WxH (--radius R | --per-pixel N) [--paper] [OPTIONS]

Poisson disk sampling (Bridson) of the box lo <= x < lo + extent: no two
points closer than R. Points go to stdout (or --out) as they are generated;
a one-line summary goes to stderr.

With --pixels, a W x H raster is streamed pixel by pixel (bridson::Tiled):
points in raster coordinates, 0 <= x < W, 0 <= y < H, row 0 first; the
radius is in pixels (--radius), or follows from the samples wanted per
pixel (--per-pixel); the JSON output carries the radius actually used.
--paper uses Ye's per-pixel scheme instead of the default sweep (it shows a
density bias along pixel edges; for comparison). --dim, if given, must be 2;
--extent, --lo, --periodic, --periodic-axes and --max-points do not apply.

Required:
  --dim D                  dimension, 1 to 8
  --radius R               minimum distance between points
Options:
  --extent A,B,..          box size, exactly D values      [default: all 1]
  --lo A,B,..              lower corner, exactly D values  [default: all 0]
  --periodic               make every axis periodic (toroidal)
  --periodic-axes I,J,..   make the listed axes (0-based) periodic
  --attempts K             candidate attempts per active point  [default: 30]
  --candidates KIND        annulus | sphere                [default: annulus]
  --seed S                 seed, an unsigned 64-bit integer     [default: 0]
  --max-points N           stop after N points
  --max-grid-bytes B       memory budget of the run, in bytes [default: 1 GiB];
                             a run that outgrows it stops with exit code 2
  --format FMT             csv | json | none                    [default: csv]
                             csv:  header x0,x1,.. then one point a line
                             json: {\"dim\":..,\"radius\":..,\"lo\":[..],\"hi\":[..],\"points\":[[..],..]}
                             none: write nothing (--out is ignored); the
                                   summary time is then pure generation
  --out FILE               write to FILE instead of stdout
  --pixels WxH             stream a W x H raster pixel by pixel (see above)
  --per-pixel N            with --pixels: about N points per pixel
  --paper                  with --pixels: Ye's per-pixel scheme
  --exact N                with --pixels: exactly N points in every pixel
                             (the JSON radius is then the oversampled
                             sweep's, the minimum distance kept)
  -h, --help               print this help and exit

Flags also accept the form --flag=value. Numbers are printed in the shortest
form that parses back to the identical f64.

Exit status: 0 success, 1 error writing the output, 2 bad arguments or
parameters rejected by the sampler.

Examples:
  points --dim 2 --radius 0.01 --extent 1,1 --seed 7 --out pts.csv
  points --pixels 64x48 --per-pixel 4 --format json --out raster.json
";

/// What to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Csv,
    Json,
    None,
}

/// A fully parsed command line. List lengths and axis numbers are already
/// checked against `dim`; everything else is left to the library.
#[derive(Clone, Debug, PartialEq)]
struct Config {
    dim: usize,
    radius: f64,
    extent: Option<Vec<f64>>,
    lo: Option<Vec<f64>>,
    /// One flag per axis (`dim` of them).
    periodic: Vec<bool>,
    attempts: u32,
    candidates: Candidates,
    seed: u64,
    max_points: Option<u64>,
    /// `--max-grid-bytes`: the run's memory budget.
    max_grid_bytes: Option<u64>,
    format: Format,
    out: Option<PathBuf>,
    /// `--pixels`: stream a raster instead of sampling the box.
    raster: Option<Raster>,
}

/// The raster mode's settings (`--pixels`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Raster {
    width: u32,
    height: u32,
    /// `--per-pixel`; `None` means `--radius` gives the spacing.
    per_pixel: Option<f64>,
    paper: bool,
    /// `--exact N`: exactly N points in every pixel.
    exact: Option<u32>,
}

#[derive(Clone, Debug, PartialEq)]
enum Command {
    Help,
    Run(Config),
}

/// Why a run failed; decides the exit code.
#[derive(Debug)]
enum Failure {
    /// Bad arguments or parameters (exit 2).
    Usage(String),
    /// Writing the output failed (exit 1).
    Io(String),
}

fn main() {
    let code = match parse_args(std::env::args_os().skip(1)) {
        Ok(Command::Help) => print_help(),
        Ok(Command::Run(config)) => match dispatch(&config) {
            Ok(()) => 0,
            Err(Failure::Usage(message)) => usage_error(&message),
            Err(Failure::Io(message)) => {
                report(&format!("points: error: {message}"));
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
            report(&format!("points: error: writing the help to stdout: {e}"));
            1
        }
    }
}

/// Prints a bad-argument message and the hint; returns exit code 2.
fn usage_error(message: &str) -> i32 {
    report(&format!(
        "points: error: {message}\npoints: run with --help for usage"
    ));
    2
}

/// Writes a line to stderr. Unlike `eprintln!`, never panics if stderr is
/// gone: there is nowhere left to report that.
fn report(line: &str) {
    let mut err = io::stderr().lock();
    let _ = writeln!(err, "{line}");
}

// ---------------------------------------------------------------------------
// Argument parsing

/// Parses the arguments after the program name.
fn parse_args<I, S>(args: I) -> Result<Command, String>
where
    I: IntoIterator<Item = S>,
    S: Into<OsString>,
{
    let mut dim: Option<usize> = None;
    let mut radius: Option<f64> = None;
    let mut extent: Option<Vec<f64>> = None;
    let mut lo: Option<Vec<f64>> = None;
    let mut periodic_all = false;
    let mut periodic_axes: Option<Vec<usize>> = None;
    let mut attempts: Option<u32> = None;
    let mut candidates: Option<Candidates> = None;
    let mut seed: Option<u64> = None;
    let mut max_points: Option<u64> = None;
    let mut max_grid_bytes: Option<u64> = None;
    let mut format: Option<Format> = None;
    let mut out: Option<PathBuf> = None;
    let mut pixels: Option<(u32, u32)> = None;
    let mut per_pixel: Option<f64> = None;
    let mut paper = false;
    let mut exact: Option<u32> = None;

    let mut args = args.into_iter().map(Into::into);
    while let Some(raw) = args.next() {
        let Some(arg) = raw.to_str() else {
            return Err(format!(
                "argument '{}' is not valid UTF-8",
                raw.to_string_lossy()
            ));
        };
        // `--flag=value` is the same as `--flag value`.
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
            "--periodic" => {
                no_value(&flag, inline.as_ref())?;
                periodic_all = true;
            }
            "--paper" => {
                no_value(&flag, inline.as_ref())?;
                paper = true;
            }
            "--pixels" => {
                let v = text_value(&flag, inline, &mut args)?;
                let parsed = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)));
                let size = parsed.ok_or_else(|| {
                    format!("{flag} expects WxH with whole numbers, like 64x48, got '{v}'")
                })?;
                set(&mut pixels, size, &flag)?;
            }
            "--exact" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(
                    &mut exact,
                    parse_number(&flag, &v, "a whole number")?,
                    &flag,
                )?;
            }
            "--per-pixel" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut per_pixel, parse_number(&flag, &v, "a number")?, &flag)?;
            }
            "--dim" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(
                    &mut dim,
                    parse_number(&flag, &v, "an integer from 1 to 8")?,
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
            "--lo" => {
                let v = text_value(&flag, inline, &mut args)?;
                set(&mut lo, parse_list(&flag, &v, "a number")?, &flag)?;
            }
            "--periodic-axes" => {
                let v = text_value(&flag, inline, &mut args)?;
                let axes = parse_list(&flag, &v, "an axis number (0-based)")?;
                set(&mut periodic_axes, axes, &flag)?;
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
            "--max-points" => {
                let v = text_value(&flag, inline, &mut args)?;
                let cap = parse_number(&flag, &v, "an unsigned 64-bit integer")?;
                set(&mut max_points, cap, &flag)?;
            }
            "--max-grid-bytes" => {
                let v = text_value(&flag, inline, &mut args)?;
                let bytes = parse_number(&flag, &v, "an unsigned 64-bit integer")?;
                set(&mut max_grid_bytes, bytes, &flag)?;
            }
            "--format" => {
                let v = text_value(&flag, inline, &mut args)?;
                let f = match v.as_str() {
                    "csv" => Format::Csv,
                    "json" => Format::Json,
                    "none" => Format::None,
                    _ => {
                        return Err(format!(
                            "invalid value '{v}' for --format: expected csv, json or none"
                        ));
                    }
                };
                set(&mut format, f, &flag)?;
            }
            "--out" => {
                // A path need not be UTF-8.
                let v = value(&flag, inline, &mut args)?;
                if v.is_empty() {
                    return Err("--out needs a file name".to_owned());
                }
                set(&mut out, PathBuf::from(v), &flag)?;
            }
            other if other.starts_with('-') => return Err(format!("unknown flag '{other}'")),
            other => return Err(format!("unexpected argument '{other}'")),
        }
    }

    if let Some((width, height)) = pixels {
        if dim.is_some_and(|d| d != 2) {
            return Err("--pixels makes a 2-D raster: --dim must be 2 if given".to_owned());
        }
        let not_with_pixels = [
            ("--extent", extent.is_some()),
            ("--lo", lo.is_some()),
            ("--periodic", periodic_all),
            ("--periodic-axes", periodic_axes.is_some()),
            ("--max-points", max_points.is_some()),
            ("--max-grid-bytes", max_grid_bytes.is_some()),
        ];
        if let Some((flag, _)) = not_with_pixels.iter().find(|(_, given)| *given) {
            return Err(format!("{flag} does not apply with --pixels"));
        }
        let radius = match (radius, per_pixel, exact) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) | (_, Some(_), Some(_)) => {
                return Err("give one of --radius, --per-pixel and --exact".to_owned());
            }
            (None, None, None) => {
                return Err("--pixels needs --radius, --per-pixel or --exact".to_owned());
            }
            (r, _, _) => r.unwrap_or(f64::NAN),
        };
        return Ok(Command::Run(Config {
            dim: 2,
            radius,
            extent: None,
            lo: None,
            periodic: vec![false; 2],
            attempts: attempts.unwrap_or(bridson::DEFAULT_ATTEMPTS),
            candidates: candidates.unwrap_or_default(),
            seed: seed.unwrap_or(0),
            max_points: None,
            max_grid_bytes: None,
            format: format.unwrap_or(Format::Csv),
            out,
            raster: Some(Raster {
                width,
                height,
                per_pixel,
                paper,
                exact,
            }),
        }));
    }
    if per_pixel.is_some() {
        return Err("--per-pixel needs --pixels".to_owned());
    }
    if paper {
        return Err("--paper needs --pixels".to_owned());
    }
    if exact.is_some() {
        return Err("--exact needs --pixels".to_owned());
    }
    let dim = dim.ok_or("missing --dim")?;
    if !(1..=8).contains(&dim) {
        return Err(format!("--dim must be from 1 to 8, got {dim}"));
    }
    let radius = radius.ok_or("missing --radius")?;
    for (flag, list) in [("--extent", &extent), ("--lo", &lo)] {
        if let Some(values) = list
            && values.len() != dim
        {
            return Err(format!(
                "{flag} needs exactly {dim} comma-separated values (one per axis), got {}",
                values.len()
            ));
        }
    }
    let mut periodic = vec![periodic_all; dim];
    for &axis in periodic_axes.iter().flatten() {
        match periodic.get_mut(axis) {
            Some(p) => *p = true,
            None => {
                return Err(format!(
                    "--periodic-axes: axis {axis} does not exist with --dim {dim} (axes are 0 to {})",
                    dim - 1
                ));
            }
        }
    }
    Ok(Command::Run(Config {
        dim,
        radius,
        extent,
        lo,
        periodic,
        attempts: attempts.unwrap_or(bridson::DEFAULT_ATTEMPTS),
        candidates: candidates.unwrap_or_default(),
        seed: seed.unwrap_or(0),
        max_points,
        max_grid_bytes,
        format: format.unwrap_or(Format::Csv),
        out,
        raster: None,
    }))
}

/// Rejects `--flag=value` on a flag that takes no value.
fn no_value(flag: &str, inline: Option<&OsString>) -> Result<(), String> {
    match inline {
        Some(_) => Err(format!("{flag} takes no value")),
        None => Ok(()),
    }
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
// Sampling and output

fn dispatch(config: &Config) -> Result<(), Failure> {
    if let Some(raster) = config.raster {
        return run_raster(config, raster);
    }
    match config.dim {
        1 => run::<1>(config),
        2 => run::<2>(config),
        3 => run::<3>(config),
        4 => run::<4>(config),
        5 => run::<5>(config),
        6 => run::<6>(config),
        7 => run::<7>(config),
        8 => run::<8>(config),
        d => Err(Failure::Usage(format!(
            "--dim must be from 1 to 8, got {d}"
        ))),
    }
}

/// Builds the sampler from `config`, streams its points out and prints the
/// summary.
fn run<const N: usize>(config: &Config) -> Result<(), Failure> {
    let sampler = build::<N>(config).map_err(Failure::Usage)?;
    let (count, elapsed, layout, stopped) = match (config.format, &config.out) {
        (Format::None, _) => write_points(io::sink(), Format::None, &sampler, config.seed),
        (format, Some(path)) => {
            let file = File::create(path)
                .map_err(|e| Failure::Io(format!("cannot create '{}': {e}", path.display())))?;
            write_points(BufWriter::new(file), format, &sampler, config.seed)
        }
        (format, None) => write_points(
            BufWriter::new(io::stdout().lock()),
            format,
            &sampler,
            config.seed,
        ),
    }
    .map_err(|e| {
        let target = config
            .out
            .as_ref()
            .map_or_else(|| "stdout".to_owned(), |p| format!("'{}'", p.display()));
        Failure::Io(format!("writing to {target}: {e}"))
    })?;
    report(&summary(&sampler, count, elapsed, layout));
    // The points written are valid, but the set is incomplete: say why.
    stopped.map_or(Ok(()), |e| Err(Failure::Usage(e.to_string())))
}

/// The sampler `config` describes, or the library's reason why not.
fn build<const N: usize>(config: &Config) -> Result<PoissonDisk<N>, String> {
    let extent = match &config.extent {
        Some(v) => array::<N, f64>(v, "--extent")?,
        None => [1.0; N],
    };
    let lo = match &config.lo {
        Some(v) => array::<N, f64>(v, "--lo")?,
        None => [0.0; N],
    };
    let hi: [f64; N] = core::array::from_fn(|i| lo[i] + extent[i]);
    let periodic = array::<N, bool>(&config.periodic, "--periodic")?;
    let domain = Domain::new(lo, hi)
        .map_err(|e| {
            // The library sees only lo and hi; name what the user typed when
            // `lo + extent` itself went wrong.
            let axis = match e {
                Error::EmptyBox { axis } | Error::NonFiniteBound { axis } => axis,
                _ => return e.to_string(),
            };
            match (lo.get(axis), extent.get(axis), hi.get(axis)) {
                (Some(&l), Some(&x), Some(&h))
                    if l.is_finite() && x.is_finite() && x > 0.0 && !(l < h && h.is_finite()) =>
                {
                    format!(
                        "on axis {axis}, lo {l:e} + extent {x:e} gives {h:e}: the extent is lost \
                         to rounding or overflows"
                    )
                }
                _ => e.to_string(),
            }
        })?
        .with_periodic(periodic);
    PoissonDisk::<N>::builder(domain, config.radius)
        .attempts(config.attempts)
        .max_points(config.max_points)
        .max_grid_bytes(config.max_grid_bytes.unwrap_or(DEFAULT_MAX_GRID_BYTES))
        .candidates(config.candidates)
        .build()
        .map_err(|e| e.to_string())
}

fn array<const N: usize, T: Copy>(values: &[T], flag: &str) -> Result<[T; N], String> {
    <[T; N]>::try_from(values)
        .map_err(|_| format!("{flag} needs exactly {N} values, got {}", values.len()))
}

/// Streams the points of `seed` to `out` in `format`, flushing at the end.
/// Returns the count, the time from building the grid to the flush, the
/// layout built, and why the run stopped early if it did (the budget).
fn write_points<const N: usize, W: Write>(
    out: W,
    format: Format,
    sampler: &PoissonDisk<N>,
    seed: u64,
) -> io::Result<(u64, Duration, GridLayout, Option<Error>)> {
    let start = Instant::now();
    let mut points = sampler.iter_seeded(seed);
    let layout = points.layout();
    let domain = sampler.domain();
    let header = (sampler.radius(), domain.lo(), domain.hi());
    let count = write_stream(out, format, header, points.by_ref())?;
    Ok((count, start.elapsed(), layout, points.error()))
}

/// Writes `points` as they come in `format`, with the JSON header values
/// `(radius, lo, hi)`; returns the count.
fn write_stream<const N: usize, W: Write>(
    mut out: W,
    format: Format,
    (radius, lo, hi): (f64, [f64; N], [f64; N]),
    points: impl Iterator<Item = [f64; N]>,
) -> io::Result<u64> {
    let mut count: u64 = 0;
    match format {
        Format::None => {
            for _ in points {
                count += 1;
            }
        }
        Format::Csv => {
            for i in 0..N {
                if i > 0 {
                    out.write_all(b",")?;
                }
                write!(out, "x{i}")?;
            }
            out.write_all(b"\n")?;
            for p in points {
                write_values(&mut out, &p)?;
                out.write_all(b"\n")?;
                count += 1;
            }
        }
        Format::Json => {
            write!(out, "{{\"dim\":{N},\"radius\":{radius},\"lo\":[")?;
            write_values(&mut out, &lo)?;
            out.write_all(b"],\"hi\":[")?;
            write_values(&mut out, &hi)?;
            out.write_all(b"],\"points\":[")?;
            for p in points {
                out.write_all(if count == 0 { b"[" } else { b",[" })?;
                write_values(&mut out, &p)?;
                out.write_all(b"]")?;
                count += 1;
            }
            out.write_all(b"]}\n")?;
        }
    }
    out.flush()?;
    Ok(count)
}

/// `--pixels`: streams the raster pixel by pixel, row 0 first.
fn run_raster(config: &Config, raster: Raster) -> Result<(), Failure> {
    let builder = Tiled::builder(raster.width, raster.height)
        .attempts(config.attempts)
        .candidates(config.candidates)
        .scheme(if raster.paper {
            Scheme::Paper
        } else {
            Scheme::Sweep
        });
    let builder = match (raster.exact, raster.per_pixel) {
        (Some(n), _) => builder.exact(n),
        (None, Some(n)) => builder.per_pixel(n),
        (None, None) => builder.radius(config.radius),
    };
    let tiled = builder.build().map_err(|e| Failure::Usage(e.to_string()))?;
    let (w, h) = (f64::from(raster.width), f64::from(raster.height));
    let header = (tiled.radius(), [0.0, 0.0], [w, h]);
    let start = Instant::now();
    let points = tiled
        .pixels_seeded(config.seed)
        .flat_map(|pixel| pixel.points);
    let written = match (config.format, &config.out) {
        (Format::None, _) => write_stream(io::sink(), Format::None, header, points),
        (format, Some(path)) => {
            let file = File::create(path)
                .map_err(|e| Failure::Io(format!("cannot create '{}': {e}", path.display())))?;
            write_stream(BufWriter::new(file), format, header, points)
        }
        (format, None) => write_stream(BufWriter::new(io::stdout().lock()), format, header, points),
    };
    let count = written.map_err(|e| Failure::Io(format!("writing the points: {e}")))?;
    let seconds = start.elapsed().as_secs_f64();
    let rho = usize::try_from(count)
        .ok()
        .and_then(|n| bridson::relative_radius::<2>(tiled.radius(), n, w * h))
        .map_or_else(|| "n/a".to_owned(), |rho| format!("{rho:.4}"));
    #[expect(clippy::cast_precision_loss, reason = "a rate, for display only")]
    let rate = count as f64 / seconds / 1e6;
    report(&format!(
        "points: {count} in {seconds:.3} s ({rate:.2} M/s), rho {rho}, {}x{} pixels, r = {}, {:?} scheme",
        raster.width,
        raster.height,
        tiled.radius(),
        tiled.scheme()
    ));
    Ok(())
}

/// Comma-separated values with `{}` (shortest round-trip form, never an
/// exponent; every value here is finite, so also valid JSON).
fn write_values<W: Write>(out: &mut W, values: &[f64]) -> io::Result<()> {
    for (i, x) in values.iter().enumerate() {
        if i > 0 {
            out.write_all(b",")?;
        }
        write!(out, "{x}")?;
    }
    Ok(())
}

/// `points: 1234567 in 0.812 s (1.52 M/s), rho 0.7312, grid Dense`.
fn summary<const N: usize>(
    sampler: &PoissonDisk<N>,
    count: u64,
    elapsed: Duration,
    layout: GridLayout,
) -> String {
    let seconds = elapsed.as_secs_f64();
    #[expect(clippy::cast_precision_loss, reason = "a rate, for display only")]
    let per_second = count as f64 / seconds;
    let rate = if seconds > 0.0 && per_second.is_finite() {
        if per_second >= 1e6 {
            format!("{:.2} M/s", per_second / 1e6)
        } else if per_second >= 1e3 {
            format!("{:.2} k/s", per_second / 1e3)
        } else {
            format!("{per_second:.0} /s")
        }
    } else {
        "n/a".to_owned()
    };
    let rho = usize::try_from(count)
        .ok()
        .and_then(|n| bridson::relative_radius::<N>(sampler.radius(), n, sampler.domain().volume()))
        .map_or_else(|| "n/a".to_owned(), |rho| format!("{rho:.4}"));
    format!("points: {count} in {seconds:.3} s ({rate}), rho {rho}, grid {layout:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(line: &str) -> Result<Command, String> {
        parse_args(line.split_whitespace())
    }

    fn config(line: &str) -> Config {
        match parse(line) {
            Ok(Command::Run(c)) => c,
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
    fn parses_the_documented_example() {
        let c = config("--dim 2 --radius 0.01 --extent 1,1 --seed 7 --out pts.csv");
        let expected = Config {
            dim: 2,
            radius: 0.01,
            extent: Some(vec![1.0, 1.0]),
            lo: None,
            periodic: vec![false, false],
            attempts: 30,
            candidates: Candidates::Annulus,
            seed: 7,
            max_points: None,
            max_grid_bytes: None,
            format: Format::Csv,
            out: Some(PathBuf::from("pts.csv")),
            raster: None,
        };
        assert_eq!(c, expected, "example command");
    }

    #[test]
    fn parses_the_raster_flags() {
        let c = config("--pixels 64x48 --per-pixel 4 --paper --seed 3");
        assert_eq!(
            c.raster,
            Some(Raster {
                width: 64,
                height: 48,
                per_pixel: Some(4.0),
                paper: true,
                exact: None,
            }),
            "raster settings"
        );
        assert_eq!((c.dim, c.seed), (2, 3), "dim and seed");
        let r = config("--pixels=5x7 --radius 0.8 --dim 2");
        assert_eq!(r.radius, 0.8, "radius");
        assert_eq!(
            r.raster.map(|x| x.per_pixel),
            Some(None),
            "spacing from --radius"
        );
        for bad in [
            "--pixels 5x7",
            "--pixels 5x7 --radius 1 --per-pixel 2",
            "--pixels 5x7 --radius 1 --dim 3",
            "--pixels 5x7 --radius 1 --extent 1,1",
            "--pixels 5x7 --radius 1 --periodic",
            "--pixels 5x7 --radius 1 --max-points 3",
            "--pixels 5by7 --radius 1",
            "--pixels -5x7 --radius 1",
            "--dim 2 --radius 1 --per-pixel 4",
            "--dim 2 --radius 1 --paper",
            "--dim 2 --radius 1 --exact 4",
            "--pixels 5x7 --exact 4 --per-pixel 4",
            "--pixels 5x7 --exact -1",
        ] {
            assert!(parse(bad).is_err(), "should be rejected: {bad}");
        }
    }

    #[test]
    fn parses_every_flag_in_both_forms() {
        let c = config(
            "--dim=3 --radius=0.5 --extent 2,3,4 --lo=-1,-2,-3 --periodic-axes 0,2 \
             --attempts 12 --candidates=sphere --seed 18446744073709551615 \
             --max-points 100 --format json --out=x.json",
        );
        assert_eq!(c.dim, 3, "dim");
        assert_eq!(c.radius, 0.5, "radius");
        assert_eq!(c.extent, Some(vec![2.0, 3.0, 4.0]), "extent");
        assert_eq!(c.lo, Some(vec![-1.0, -2.0, -3.0]), "lo");
        assert_eq!(c.periodic, vec![true, false, true], "periodic axes");
        assert_eq!(c.attempts, 12, "attempts");
        assert_eq!(c.candidates, Candidates::Sphere, "candidates");
        assert_eq!(c.seed, u64::MAX, "seed");
        assert_eq!(c.max_points, Some(100), "cap");
        assert_eq!(c.format, Format::Json, "format");
        assert_eq!(c.out, Some(PathBuf::from("x.json")), "out");
        let all = config("--periodic --dim 4 --radius 1");
        assert_eq!(
            all.periodic,
            vec![true; 4],
            "--periodic makes every axis periodic"
        );
        assert_eq!(
            config("--dim 1 --radius 1 --format none").format,
            Format::None,
            "none"
        );
    }

    #[test]
    fn help_stops_parsing() {
        assert_eq!(parse("--help"), Ok(Command::Help), "--help");
        assert_eq!(parse("--dim 2 -h"), Ok(Command::Help), "-h");
        assert_eq!(
            parse("--dim 99 --help"),
            Ok(Command::Help),
            "before validation"
        );
    }

    #[test]
    fn rejects_bad_command_lines() {
        let cases = [
            ("--radius 0.1", "missing --dim"),
            ("--dim 2", "missing --radius"),
            ("--dim 0 --radius 1", "--dim must be from 1 to 8, got 0"),
            ("--dim 9 --radius 1", "--dim must be from 1 to 8, got 9"),
            ("--dim -1 --radius 1", "invalid value '-1' for --dim"),
            ("--dim 2 --radius", "missing value for --radius"),
            ("--dim 2 --radius abc", "invalid value 'abc' for --radius"),
            (
                "--dim 2 --radius 1 --extent 1,2,3",
                "--extent needs exactly 2",
            ),
            ("--dim 2 --radius 1 --lo 1", "--lo needs exactly 2"),
            (
                "--dim 2 --radius 1 --extent 1,",
                "invalid item '' in --extent",
            ),
            (
                "--dim 2 --radius 1 --extent 1,x",
                "invalid item 'x' in --extent",
            ),
            (
                "--dim 2 --radius 1 --format xml",
                "expected csv, json or none",
            ),
            (
                "--dim 2 --radius 1 --candidates disk",
                "expected annulus or sphere",
            ),
            (
                "--dim 2 --radius 1 --attempts -3",
                "invalid value '-3' for --attempts",
            ),
            ("--dim 2 --radius 1 --attempts 4294967296", "for --attempts"),
            (
                "--dim 2 --radius 1 --seed 1.5",
                "invalid value '1.5' for --seed",
            ),
            ("--dim 2 --radius 1 --max-points -1", "for --max-points"),
            (
                "--dim 2 --radius 1 --periodic-axes 2",
                "axis 2 does not exist",
            ),
            (
                "--dim 2 --radius 1 --periodic=yes",
                "--periodic takes no value",
            ),
            (
                "--dim 2 --radius 1 --radius 2",
                "--radius given more than once",
            ),
            ("--dim 2 --radius 1 --bogus", "unknown flag '--bogus'"),
            ("--dim 2 --radius 1 stray", "unexpected argument 'stray'"),
            ("--dim 2 --radius 1 --out=", "--out needs a file name"),
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
            "--dim 2 --radius 0",
            "--dim 2 --radius nan",
            "--dim 2 --radius 1 --extent 1,0",
            "--dim 2 --radius 1 --extent 1,inf",
            "--dim 2 --radius 1 --attempts 0",
            "--dim 3 --radius 1e-13",
            "--dim 2 --radius 1 --attempts 65537",
            // Outgrows its budget: the points written are valid, but the
            // run is an error (exit code 2).
            "--dim 3 --radius 1e-9 --max-grid-bytes 100000 --format none",
        ] {
            let c = config(line);
            assert!(
                matches!(dispatch(&c), Err(Failure::Usage(_))),
                "{line}: expected a library error"
            );
        }
    }

    #[test]
    fn a_lost_extent_is_explained() {
        let e = build::<2>(&config("--dim 2 --radius 1 --lo 1e20,0")).unwrap_err();
        assert!(e.contains("lo 1e20 + extent 1e0 gives 1e20"), "{e}");
        let e = build::<1>(&config("--dim 1 --radius 1 --lo 1e308 --extent 1e308")).unwrap_err();
        assert!(e.contains("gives inf"), "{e}");
        let e = build::<1>(&config("--dim 1 --radius 1 --extent -1")).unwrap_err();
        assert!(e.contains("lo must be < hi"), "plain library message: {e}");
    }

    #[test]
    fn display_round_trips_bit_for_bit() {
        let values = [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            2.0f64.sqrt(),
            1e-150,
            1e150,
            1e300,
            123_456_789.123_456_79,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            -f64::MAX,
            f64::EPSILON,
        ];
        for x in values {
            let text = format!("{x}");
            assert!(
                !text.contains(['e', 'E', 'N', 'i']),
                "no exponent or special form: {text}"
            );
            let back: f64 = text.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:?} printed as {text}");
        }
        assert_eq!(format!("{}", 1.0f64), "1", "integers print without a point");
    }

    fn output<const N: usize>(line: &str) -> String {
        let c = config(line);
        let sampler = build::<N>(&c).unwrap();
        let mut bytes = Vec::new();
        write_points(&mut bytes, c.format, &sampler, c.seed).unwrap();
        String::from_utf8(bytes).unwrap()
    }

    #[test]
    fn csv_has_a_header_and_the_seeded_points() {
        let text = output::<2>("--dim 2 --radius 0.2 --lo -1,5 --seed 3");
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("x0,x1"), "header");
        let c = config("--dim 2 --radius 0.2 --lo -1,5 --seed 3");
        let expected = build::<2>(&c).unwrap().generate_seeded(3).unwrap();
        let got: Vec<[f64; 2]> = lines
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                [v[0], v[1]]
            })
            .collect();
        assert!(!got.is_empty(), "some points");
        assert_eq!(got, expected, "CSV round-trips to the generated points");
    }

    #[test]
    fn json_has_the_documented_shape() {
        let text = output::<2>("--dim 2 --radius 0.5 --extent 2,1 --lo 0,-1 --format json");
        assert!(
            text.starts_with(r#"{"dim":2,"radius":0.5,"lo":[0,-1],"hi":[2,0],"points":[["#),
            "prefix: {text}"
        );
        assert!(text.ends_with("]]}\n"), "suffix: {text}");
        let empty = output::<1>("--dim 1 --radius 0.5 --max-points 0 --format json");
        assert_eq!(
            empty, "{\"dim\":1,\"radius\":0.5,\"lo\":[0],\"hi\":[1],\"points\":[]}\n",
            "no points"
        );
        assert_eq!(
            output::<3>("--dim 3 --radius 0.5 --format none"),
            "",
            "none"
        );
    }
}
