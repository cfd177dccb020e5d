//! Sampling and output of `points`: builds the sampler a [`Config`]
//! describes, streams its points as CSV or JSON as they come, and prints the
//! one-line summary.

use crate::args::{Config, Format, Raster};
use crate::common::{Failure, report};
use bridson::{DEFAULT_MAX_GRID_BYTES, Domain, Error, GridLayout, PoissonDisk, Scheme, Tiled};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::num::NonZeroUsize;
use std::time::{Duration, Instant};

pub(crate) fn dispatch(config: &Config) -> Result<(), Failure> {
    if let Some(mode) = &config.field {
        return crate::common::by_dimension!(
            config.dim,
            run_field_dim((config, mode)),
            1,
            2,
            3,
            4,
            5
        );
    }
    if let Some(raster) = config.raster {
        return run_raster(config, raster);
    }
    crate::common::by_dimension!(config.dim, run(config), 1, 2, 3, 4, 5, 6, 7, 8)
}

/// Builds the sampler from `config`, streams its points out and prints the
/// summary.
fn run_field_dim<const N: usize>(
    (config, mode): (&Config, &crate::args::FieldMode),
) -> Result<(), Failure> {
    crate::field::run::<N>(config, mode)
}

fn run<const N: usize>(config: &Config) -> Result<(), Failure> {
    if let Some(range) = config.radius_range {
        return run_varying::<N>(config, range);
    }
    let kept = build::<N>(config).map_err(Failure::Usage)?;
    // --f32: sample at the radius padded for f32 rounding; `kept` is the
    // radius the f32 points keep.
    let sampler = if config.f32 {
        kept.for_f32().map_err(|e| Failure::Usage(e.to_string()))?
    } else {
        kept
    };
    let run = (config.seed, config.threads);
    let header = (kept.radius(), config.f32);
    let (count, elapsed, layout, stopped) = match (config.format, &config.out) {
        (Format::None, _) => write_points(io::sink(), Format::None, &sampler, run, header),
        (format, Some(path)) => {
            let file = File::create(path)
                .map_err(|e| Failure::Io(format!("cannot create '{}': {e}", path.display())))?;
            write_points(BufWriter::new(file), format, &sampler, run, header)
        }
        (format, None) => write_points(
            BufWriter::new(io::stdout().lock()),
            format,
            &sampler,
            run,
            header,
        ),
    }
    .map_err(|e| {
        let target = config
            .out
            .as_ref()
            .map_or_else(|| "stdout".to_owned(), |p| format!("'{}'", p.display()));
        Failure::Io(format!("writing to {target}: {e}"))
    })?;
    report(&summary(&kept, &sampler, count, elapsed, layout));
    // The points written are valid, but the set is incomplete: say why.
    stopped.map_or(Ok(()), |e| Err(Failure::Usage(e.to_string())))
}

/// `--radius-range R0,R1`: the radius grows (or falls) linearly along axis
/// 0, from `R0` at `lo` to `R1` at `hi`.
fn run_varying<const N: usize>(config: &Config, (r0, r1): (f64, f64)) -> Result<(), Failure> {
    let config_max = Config {
        radius: r0.max(r1),
        ..config.clone()
    };
    let kept = build::<N>(&config_max).map_err(Failure::Usage)?;
    let (lo, extent) = (kept.domain().lo()[0], kept.domain().extent()[0]);
    // A multiplication per candidate, not a division.
    let slope = (r1 - r0) / extent;
    let field = move |p: &[f64; N]| r0 + slope * (p[0] - lo);
    // --f32: every radius padded for f32 rounding (linear in r, so the
    // two ends checked cover the values between).
    let pad = move |r: f64| {
        if config.f32 {
            kept.f32_radius(r)
        } else {
            Ok(r)
        }
    };
    let usage = |e: Error| Failure::Usage(e.to_string());
    let (p0, p1) = (pad(r0).map_err(usage)?, pad(r1).map_err(usage)?);
    let sampler = build::<N>(&Config {
        radius: p0.max(p1),
        ..config.clone()
    })
    .map_err(Failure::Usage)?;
    let padded = move |p: &[f64; N]| pad(field(p)).unwrap_or(f64::NAN);
    let mut points = sampler
        .iter_varying_seeded(config.seed, p0.min(p1), padded)
        .map_err(usage)?;
    let domain = sampler.domain();
    let header = (kept.radius(), domain.lo(), domain.hi());
    let start = Instant::now();
    let f32 = config.f32;
    let written = match (config.format, &config.out) {
        (Format::None, _) => write_either(io::sink(), Format::None, header, points.by_ref(), f32),
        (format, Some(path)) => {
            let file = File::create(path)
                .map_err(|e| Failure::Io(format!("cannot create '{}': {e}", path.display())))?;
            write_either(BufWriter::new(file), format, header, points.by_ref(), f32)
        }
        (format, None) => write_either(
            BufWriter::new(io::stdout().lock()),
            format,
            header,
            points.by_ref(),
            f32,
        ),
    };
    let count = written.map_err(|e| Failure::Io(format!("writing the points: {e}")))?;
    let seconds = start.elapsed().as_secs_f64();
    let f32_note = if f32 {
        format!(", f32 (sampled at {p0} to {p1})")
    } else {
        String::new()
    };
    report(&format!(
        "points: {count} in {seconds:.3} s, radius {r0} to {r1} along axis 0{f32_note}"
    ));
    points
        .error()
        .map_or(Ok(()), |e| Err(Failure::Usage(e.to_string())))
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
    let builder = match config.count {
        Some(n) => PoissonDisk::<N>::about_points_builder(domain, n),
        None => PoissonDisk::<N>::builder(domain, config.radius),
    };
    builder
        .attempts(config.attempts.unwrap_or(bridson::DEFAULT_ATTEMPTS))
        .max_points(config.max_points.unwrap_or(u64::MAX))
        .max_grid_bytes(config.max_grid_bytes.unwrap_or(DEFAULT_MAX_GRID_BYTES))
        .layout(config.layout)
        .candidates(config.candidates)
        .build()
        .map_err(|e| e.to_string())
}

fn array<const N: usize, T: Copy>(values: &[T], flag: &str) -> Result<[T; N], String> {
    <[T; N]>::try_from(values)
        .map_err(|_| format!("{flag} needs exactly {N} values, got {}", values.len()))
}

/// Streams the points of `seed` to `out` in `format`, flushing at the end;
/// with `threads`, generates them all in parallel first
/// (`generate_parallel`), then writes them. Returns the count, the time from
/// building the grid to the flush, the layout built (planned, in parallel),
/// and why the run stopped early if it did (the budget).
///
/// `(radius, f32)`: the radius the JSON header states (with `--f32`, the
/// one the points keep, not the padded one sampled at), and whether to
/// write the points as `f32`.
fn write_points<const N: usize, W: Write>(
    out: W,
    format: Format,
    sampler: &PoissonDisk<N>,
    (seed, threads): (u64, Option<NonZeroUsize>),
    (radius, f32): (f64, bool),
) -> io::Result<(u64, Duration, GridLayout, Option<Error>)> {
    let start = Instant::now();
    let domain = sampler.domain();
    let header = (radius, domain.lo(), domain.hi());
    if let Some(threads) = threads {
        let layout = sampler.resolved_layout();
        return match sampler.generate_parallel_seeded(seed, threads) {
            Ok(points) => {
                let count = write_either(out, format, header, points.into_iter(), f32)?;
                Ok((count, start.elapsed(), layout, None))
            }
            Err(e) => Ok((0, start.elapsed(), layout, Some(e.error()))),
        };
    }
    let mut points = sampler.iter_seeded(seed);
    let layout = points.layout();
    let count = write_either(out, format, header, points.by_ref(), f32)?;
    Ok((count, start.elapsed(), layout, points.error()))
}

/// [`write_stream`] of the points, or of the points rounded to `f32`
/// (`as f32`: to nearest) if `f32`.
fn write_either<const N: usize, W: Write>(
    out: W,
    format: Format,
    header: (f64, [f64; N], [f64; N]),
    points: impl Iterator<Item = [f64; N]>,
    f32: bool,
) -> io::Result<u64> {
    if f32 {
        #[expect(
            clippy::cast_possible_truncation,
            reason = "--f32: rounding is the point"
        )]
        let single = points.map(|p| p.map(|x| x as f32));
        write_stream(out, format, header, single)
    } else {
        write_stream(out, format, header, points)
    }
}

/// A coordinate as written: `f64`, or `f32` with `--f32`. Both print in
/// the shortest form that parses back to the same value (`{}`).
pub(crate) trait Coord: Copy + std::fmt::Display {
    /// The raw little-endian bytes (`--format binary`).
    fn write_le<W: Write + ?Sized>(self, out: &mut W) -> io::Result<()>;
}

impl Coord for f64 {
    fn write_le<W: Write + ?Sized>(self, out: &mut W) -> io::Result<()> {
        out.write_all(&self.to_le_bytes())
    }
}

impl Coord for f32 {
    fn write_le<W: Write + ?Sized>(self, out: &mut W) -> io::Result<()> {
        out.write_all(&self.to_le_bytes())
    }
}

/// Writes `points` as they come in `format`, with the JSON header values
/// `(radius, lo, hi)`; returns the count.
fn write_stream<const N: usize, W: Write, T: Coord>(
    mut out: W,
    format: Format,
    (radius, lo, hi): (f64, [f64; N], [f64; N]),
    points: impl Iterator<Item = [T; N]>,
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
        Format::Binary => {
            for p in points {
                for x in p {
                    x.write_le(&mut out)?;
                }
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

/// The stream `--pixels` asks for (the camera's aside).
fn raster_stream(config: &Config, raster: &Raster) -> Result<Tiled, Failure> {
    let mut builder = Tiled::builder(raster.width, raster.height)
        .candidates(config.candidates)
        .scheme(if raster.paper {
            Scheme::Paper
        } else {
            Scheme::Sweep
        });
    // Only when asked for: exact mode's own default (10) is the `k` its
    // edge correction is calibrated at.
    if let Some(k) = config.attempts {
        builder = builder.attempts(k);
    }
    let builder = match (raster.exact, raster.per_pixel) {
        (Some(n), _) => builder.exact(n),
        (None, Some(n)) => builder.per_pixel(n),
        (None, None) => builder.radius(config.radius),
    };
    builder.build().map_err(|e| Failure::Usage(e.to_string()))
}

/// `--pixels`: streams the raster pixel by pixel, row 0 first.
fn run_raster(config: &Config, raster: Raster) -> Result<(), Failure> {
    if let Some(camera) = raster.camera {
        return crate::camera::run(config, raster, camera);
    }
    let tiled = raster_stream(config, &raster)?;
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
pub(crate) fn write_values<W: Write + ?Sized, T: Coord>(
    out: &mut W,
    values: &[T],
) -> io::Result<()> {
    for (i, x) in values.iter().enumerate() {
        if i > 0 {
            out.write_all(b",")?;
        }
        write!(out, "{x}")?;
    }
    Ok(())
}

/// `points: 1234567 in 0.812 s (1.52 M/s), rho 0.7312, grid Dense`.
///
/// ρ is at `kept`'s radius: with `--f32` the one the points keep, whose
/// padded copy `sampler` ran (the summary then names its radius).
fn summary<const N: usize>(
    kept: &PoissonDisk<N>,
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
        .and_then(|n| bridson::relative_radius::<N>(kept.radius(), n, kept.domain().volume()))
        .map_or_else(|| "n/a".to_owned(), |rho| format!("{rho:.4}"));
    // Count mode: the radius was derived, so say which.
    let derived = kept
        .requested_count()
        .map_or_else(String::new, |_| format!(", radius {}", kept.radius()));
    let f32_note = if sampler.radius() == kept.radius() {
        String::new()
    } else {
        format!(", f32 (sampled at radius {})", sampler.radius())
    };
    format!(
        "points: {count} in {seconds:.3} s ({rate}), rho {rho}, grid {layout:?}{derived}{f32_note}"
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::from_line;
    use crate::common::assert_usage_failures;

    fn config(line: &str) -> Config {
        from_line(line).unwrap_or_else(|e| panic!("{line}: expected a run, got {e}"))
    }

    #[test]
    fn library_errors_are_usage_errors() {
        let lines = [
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
            // f32 cannot hold a radius of 4 ulps at 10⁷ (exit code 2).
            "--dim 2 --radius 4 --lo 1e7,0 --extent 400,400 --f32 --format none",
            "--dim 2 --radius-range 4,8 --lo 1e7,0 --extent 400,400 --f32 --format none",
        ];
        assert_usage_failures(&lines, |line| dispatch(&config(line)));
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
        let sampler = if c.f32 {
            sampler.for_f32().unwrap()
        } else {
            sampler
        };
        let header = (build::<N>(&c).unwrap().radius(), c.f32);
        write_points(&mut bytes, c.format, &sampler, (c.seed, c.threads), header).unwrap();
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
    fn threads_write_the_parallel_set() {
        let line = "--dim 2 --radius 0.01 --extent 1,0.2 --seed 3 --threads 2";
        let c = config(line);
        let sampler = build::<2>(&c).unwrap();
        let expected = sampler
            .generate_parallel_seeded(3, NonZeroUsize::MIN)
            .unwrap();
        assert_ne!(
            expected,
            sampler.generate_seeded(3).unwrap(),
            "a set of its own"
        );
        let got: Vec<[f64; 2]> = output::<2>(line)
            .lines()
            .skip(1)
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
                [v[0], v[1]]
            })
            .collect();
        assert_eq!(got, expected, "{line}: the parallel set, as on one thread");
    }

    /// The count of f32 points in a CSV, or the first pair the naive
    /// oracle in f32 (squared distance against `r·r`, and its root against
    /// `r`) finds too close.
    fn f32_points_keep<const N: usize>(
        text: &str,
        r: impl Fn(&[f32; N]) -> f64,
    ) -> Result<usize, String> {
        let points: Vec<[f32; N]> = text
            .lines()
            .skip(1)
            .map(|l| {
                let v: Vec<f32> = l.split(',').map(|x| x.parse().unwrap()).collect();
                core::array::from_fn(|i| v[i])
            })
            .collect();
        for (i, a) in points.iter().enumerate() {
            for b in &points[..i] {
                #[expect(clippy::cast_possible_truncation, reason = "the f32 radius")]
                let r = r(a).max(r(b)) as f32;
                let d2 = (0..N).fold(0.0f32, |s, k| s + (a[k] - b[k]) * (a[k] - b[k]));
                if d2 < r * r || d2.sqrt() < r {
                    return Err(format!("{a:?} {b:?}: {} < {r}", d2.sqrt()));
                }
            }
        }
        Ok(points.len())
    }

    #[test]
    fn f32_writes_points_that_keep_r_in_f32() {
        // r = 12 f32 ulps at 10⁶: rounding to f32 costs up to 1/6 of r.
        let base = "--dim 2 --radius 0.75 --lo 1e6,1e6 --extent 30,30 --seed 2";
        let plain = output::<2>(base);
        assert!(
            f32_points_keep::<2>(&plain, |_| 0.75).is_err(),
            "the f64 points, read as f32, come closer than r"
        );
        let text = output::<2>(&format!("{base} --f32"));
        let count = f32_points_keep::<2>(&text, |_| 0.75).unwrap();
        assert!(count > 500, "{count} points");
        assert!(count < plain.lines().count() - 1, "padded: fewer points");
        let threads = output::<2>(&format!("{base} --f32 --threads 2"));
        let count = f32_points_keep::<2>(&threads, |_| 0.75).unwrap();
        assert!(count > 500, "threads: {count} points");
        let counted = "--dim 3 --count 2000 --lo 1e6,0,0 --extent 10,10,10 --f32 --seed 1";
        let r = build::<3>(&config(counted)).unwrap().radius();
        assert!(f32_points_keep::<3>(&output::<3>(counted), |_| r).unwrap() > 1000);
        let json = output::<2>(&format!("{base} --f32 --format json"));
        assert!(
            json.contains("\"radius\":0.75,"),
            "the radius kept: {json:.80}"
        );
        let mut binary = Vec::new();
        let c = config(&format!("{base} --f32 --format binary --max-points 3"));
        let sampler = build::<2>(&c).unwrap().for_f32().unwrap();
        write_points(
            &mut binary,
            c.format,
            &sampler,
            (c.seed, None),
            (0.75, true),
        )
        .unwrap();
        assert_eq!(binary.len(), 3 * 2 * 4, "4 bytes a value");
    }

    #[test]
    fn f32_with_a_radius_range_keeps_max_r_in_f32() {
        let path = std::env::temp_dir().join(format!("points-f32-{}.csv", std::process::id()));
        let line = format!(
            "--dim 2 --radius-range 0.5,1.5 --lo 1e6,0 --extent 40,40 --f32 --seed 3 --out {}",
            path.display()
        );
        dispatch(&config(&line)).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        // The guarantee is at the field's value at the f64 point, which
        // lies within half an ulp (1/32 at 10⁶) of the f32 one: the field
        // (slope 1/40) there is at least its value here minus 1/1280.
        let count = f32_points_keep::<2>(&text, |p| {
            0.5 + (f64::from(p[0]) - 1e6) / 40.0 - 1.0 / 1280.0
        })
        .unwrap();
        assert!(count > 500, "{count} points");
    }

    #[test]
    fn exact_mode_keeps_its_own_attempts_unless_asked() {
        let stream = |line: &str| {
            let c = config(line);
            let raster = c.raster.expect("a raster");
            raster_stream(&c, &raster).unwrap().attempts()
        };
        assert_eq!(
            stream("--pixels 16x8 --exact 4"),
            bridson::EXACT_ATTEMPTS,
            "exact mode's calibrated k"
        );
        assert_eq!(stream("--pixels 16x8 --exact 4 --attempts 30"), 30);
        assert_eq!(
            stream("--pixels 16x8 --per-pixel 4"),
            bridson::DEFAULT_ATTEMPTS
        );
        assert_eq!(
            config("--dim 2 --radius 0.1").attempts,
            None,
            "the batch run's default is the library's"
        );
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
