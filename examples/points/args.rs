//! The command line of `points`: clap parses the flags, [`Args::config`]
//! checks what depends on several of them (list lengths against `--dim`,
//! axis numbers, the raster mode's rules) and gives a [`Config`].

use crate::common::{self, CandidatesArg};
use clap::error::ErrorKind;
use clap::{CommandFactory, Parser, ValueEnum};
use std::num::NonZeroUsize;
use std::path::PathBuf;

/// A comma-separated list, one value per flag: clap reads a field typed
/// `Vec` as a repeated flag, and this name opts out of that.
type List<T> = Vec<T>;

const ABOUT: &str = "\
Poisson disk sampling (Bridson) of the box lo <= x < lo + extent: no two
points closer than R, or (--count N) about N points, the radius following
from the box. Points go to stdout (or --out) as they are generated; a
one-line summary goes to stderr.

With --pixels, a W x H raster is streamed pixel by pixel (bridson::Tiled):
points in raster coordinates, 0 <= x < W, 0 <= y < H, row 0 first; the
radius is in pixels (--radius), or follows from the samples wanted per
pixel (--per-pixel); the JSON output carries the radius actually used.
--paper uses Ye's per-pixel scheme instead of the default sweep (it shows a
density bias along pixel edges; for comparison). --dim, if given, must be 2;
--extent, --lo, --periodic, --periodic-axes, --max-points and
--max-grid-bytes do not apply.";

const AFTER: &str = "\
Output formats:
  csv:  header x0,x1,.. then one point a line
  json: {\"dim\":..,\"radius\":..,\"lo\":[..],\"hi\":[..],\"points\":[[..],..]}
  none: write nothing (--out is ignored); the summary time is then pure
        generation
With --f32 the points are f32 (binary: 4 bytes a value); the JSON radius is
the one they keep.

Flags also accept the form --flag=value. Numbers are printed in the shortest
form that parses back to the identical f64.

Exit status: 0 success, 1 error writing the output, 2 bad arguments or
parameters rejected by the sampler.

Examples:
  points --dim 2 --radius 0.01 --extent 1,1 --seed 7 --out pts.csv
  points --pixels 64x48 --per-pixel 4 --format json --out raster.json";

/// The flags as typed.
#[derive(Debug, Parser)]
#[command(
    name = "points",
    about = ABOUT,
    after_help = AFTER,
    override_usage = "points --dim D (--radius R | --count N | --radius-range R0,R1) [OPTIONS]\n       \
                      points --pixels WxH (--radius R | --per-pixel N | --exact N) [--paper] [OPTIONS]\n       \
                      points --pixels WxH --camera --spp N [--dims D] [--stream | --sampler KIND] [OPTIONS]",
    allow_negative_numbers = true,
    group = clap::ArgGroup::new("spacing").args(["radius", "per_pixel", "exact"]),
)]
pub(crate) struct Args {
    /// Dimension, 1 to 8
    #[arg(long, value_name = "D", required_unless_present = "pixels")]
    dim: Option<usize>,
    /// Minimum distance between points
    #[arg(long, value_name = "R", required_unless_present_any = ["pixels", "count", "radius_range"])]
    radius: Option<f64>,
    /// A radius varying linearly along axis 0, from R0 at lo to R1 at hi:
    /// no two points p, q closer than max(r(p), r(q))
    #[arg(long, value_name = "R0,R1", value_parser = common::list::<f64>,
          conflicts_with_all = ["radius", "count", "pixels"])]
    radius_range: Option<List<f64>>,
    /// About N points instead of a radius: the radius follows from the box
    /// (count mode; within 2 % from 1000 points in 2-D and 3-D)
    #[arg(long, value_name = "N", conflicts_with_all = ["radius", "pixels"])]
    count: Option<u64>,
    /// Box size, exactly D values [default: all 1]
    #[arg(long, value_name = "A,B,..", value_parser = common::list::<f64>, allow_hyphen_values = true)]
    extent: Option<List<f64>>,
    /// Lower corner, exactly D values [default: all 0]
    #[arg(long, value_name = "A,B,..", value_parser = common::list::<f64>, allow_hyphen_values = true)]
    lo: Option<List<f64>>,
    /// Make every axis periodic (toroidal)
    #[arg(long)]
    periodic: bool,
    /// Make the listed axes (0-based) periodic
    #[arg(long, value_name = "I,J,..", value_parser = common::list::<usize>)]
    periodic_axes: Option<List<usize>>,
    /// Candidate attempts per active point [default: 30; 10 with --exact,
    /// the k exact mode is calibrated at]
    #[arg(long, value_name = "K")]
    attempts: Option<u32>,
    /// How candidates are drawn
    #[arg(long, value_name = "KIND", value_enum, default_value_t)]
    candidates: CandidatesArg,
    /// Seed, an unsigned 64-bit integer
    #[arg(long, value_name = "S", default_value_t = 0)]
    seed: u64,
    /// Stop after N points
    #[arg(long, value_name = "N")]
    max_points: Option<u64>,
    /// Memory budget of the run, in bytes [default: 1 GiB]; with --field,
    /// of one chunk's window; a run that outgrows it stops with exit code 2
    #[arg(long, value_name = "B")]
    max_grid_bytes: Option<u64>,
    /// The background grid (GridLayout) [default: auto]
    #[arg(long, value_name = "KIND", value_enum, default_value_t)]
    layout: LayoutArg,
    /// Generate on T threads (PoissonDisk::generate_parallel): slabs along
    /// the widest axis, a different set from the serial run's (same
    /// statistics), the same for every T; written once complete
    #[arg(long, value_name = "T", conflicts_with_all = ["pixels", "radius_range"])]
    threads: Option<NonZeroUsize>,
    /// The field sampler (bridson::Field): a maximal set that is a pure
    /// function of place, written chunk by chunk in the canonical order
    /// (last axis slowest); --threads and --chunk never change the output
    #[arg(long, conflicts_with_all = ["pixels", "count", "radius_range", "max_points", "attempts"])]
    field: bool,
    /// With --field: write only the points in the half-open sub-box
    /// [A, B), two comma lists (e.g. 0.2,0:0.7,0.5)
    #[arg(
        long,
        value_name = "A:B",
        requires = "field",
        allow_hyphen_values = true
    )]
    region: Option<String>,
    /// With --field: the chunk side in the box's units [default: 64 R]
    #[arg(long, value_name = "S", requires = "field")]
    chunk: Option<f64>,
    /// Write f32 points that keep the radius in f32 arithmetic: the run
    /// samples at a radius padded for f32 rounding
    /// (PoissonDisk::for_f32; fewer points), and a radius within a few
    /// f32 ulps of the box's largest coordinate is refused (exit 2); every
    /// batch run (plain, --count, --threads, --radius-range), not
    /// --pixels or --field; binary output is then 4-byte floats
    #[arg(long, conflicts_with_all = ["pixels", "field"])]
    f32: bool,
    /// What to write (see "Output formats" below)
    #[arg(long, value_name = "FMT", value_enum, default_value_t = Format::Csv)]
    format: Format,
    /// Write to FILE instead of stdout
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Stream a W x H raster pixel by pixel (see above)
    #[arg(long, value_name = "WxH", value_parser = common::size,
          conflicts_with_all = ["extent", "lo", "periodic", "periodic_axes", "max_points", "max_grid_bytes"])]
    pixels: Option<(u32, u32)>,
    /// With --pixels: about N points per pixel
    #[arg(long, value_name = "N", requires = "pixels")]
    per_pixel: Option<f64>,
    /// With --pixels: Ye's per-pixel scheme
    #[arg(long, requires = "pixels")]
    paper: bool,
    /// With --pixels: exactly N points in every pixel (the JSON radius is
    /// then the oversampled sweep's, the minimum distance kept)
    #[arg(long, value_name = "N", requires = "pixels")]
    exact: Option<u32>,
    /// With --pixels: write camera samples (CSV: px,py,index,film_x,film_y,
    /// lens_u,lens_v,time,d5,..), exactly --spp in every pixel; film in
    /// raster coordinates, the rest in [0, 1)
    #[arg(long, requires_all = ["pixels", "spp"],
          conflicts_with_all = ["per_pixel", "paper", "exact", "radius"])]
    camera: bool,
    /// With --camera: samples per pixel
    #[arg(long, value_name = "N", requires = "camera")]
    spp: Option<u32>,
    /// With --camera: values per sample after px,py,index (at least 5: film
    /// 2, lens 2, time 1; the rest are further dimensions)
    #[arg(long, value_name = "D", default_value_t = 5, requires = "camera")]
    dims: u32,
    /// With --camera: film points from the streaming sampler (exact scheme,
    /// across pixel borders) instead of the random-access pixel sampler
    #[arg(long, requires = "camera")]
    stream: bool,
    /// With --camera: the random-access pixel sampler (poisson:
    /// PoissonPixelSampler; net: NetPixelSampler, (0,m,2)-nets kept well
    /// spaced, at most 256 per pixel) [default: poisson]; not with --stream
    #[arg(long, value_name = "KIND", value_enum, requires = "camera")]
    sampler: Option<SamplerArg>,
}

/// The background grid behind `--layout`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub(crate) enum LayoutArg {
    /// Dense where it fits the budget, else paged (bounded 2-D and 3-D
    /// boxes) or sparse
    #[default]
    Auto,
    /// Bridson's dense grid
    Dense,
    /// Dense cells allocated in pages where the points land
    Paged,
    /// The sparse hash grid
    Sparse,
}

impl From<LayoutArg> for bridson::GridLayout {
    fn from(layout: LayoutArg) -> Self {
        match layout {
            LayoutArg::Auto => Self::Auto,
            LayoutArg::Dense => Self::Dense,
            LayoutArg::Paged => Self::Paged,
            LayoutArg::Sparse => Self::Sparse,
        }
    }
}

/// The pixel sampler behind `--camera`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub(crate) enum SamplerArg {
    /// `PoissonPixelSampler`: Poisson disk sets in every dimension
    #[default]
    Poisson,
    /// `NetPixelSampler`: Poisson disk nets
    Net,
}

/// What to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum Format {
    /// Header x0,x1,.. then one point a line
    Csv,
    /// One object with the header values and the points
    Json,
    /// Nothing: the summary time is pure generation (with --field, the
    /// count and an order-independent digest on stdout)
    None,
    /// Raw little-endian f64, D values a point, no header
    Binary,
}

/// A fully parsed command line. List lengths and axis numbers are already
/// checked against `dim`; everything else is left to the library.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Config {
    pub(crate) dim: usize,
    pub(crate) radius: f64,
    /// `--count`: about this many points, instead of `radius`.
    pub(crate) count: Option<u64>,
    /// `--radius-range R0,R1`: the radius along axis 0, from `lo` to `hi`.
    pub(crate) radius_range: Option<(f64, f64)>,
    pub(crate) extent: Option<Vec<f64>>,
    pub(crate) lo: Option<Vec<f64>>,
    /// One flag per axis (`dim` of them).
    pub(crate) periodic: Vec<bool>,
    /// `--attempts`, if given: else the library's default for the run
    /// (30, or 10 in exact mode).
    pub(crate) attempts: Option<u32>,
    pub(crate) candidates: bridson::Candidates,
    pub(crate) seed: u64,
    pub(crate) max_points: Option<u64>,
    /// `--max-grid-bytes`: the run's memory budget.
    pub(crate) max_grid_bytes: Option<u64>,
    /// `--layout`: the background grid.
    pub(crate) layout: bridson::GridLayout,
    /// `--threads`: the parallel generator on this many threads.
    pub(crate) threads: Option<NonZeroUsize>,
    pub(crate) format: Format,
    pub(crate) out: Option<PathBuf>,
    /// `--pixels`: stream a raster instead of sampling the box.
    pub(crate) raster: Option<Raster>,
    /// `--field`: the field sampler.
    pub(crate) field: Option<FieldMode>,
    /// `--f32`: f32 points that keep the radius in f32.
    pub(crate) f32: bool,
}

/// The field mode's settings (`--field`).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FieldMode {
    /// `--region A:B`: only the points in `[A, B)`.
    pub(crate) region: Option<(Vec<f64>, Vec<f64>)>,
    /// `--chunk S`: the chunk side.
    pub(crate) chunk: Option<f64>,
}

/// The raster mode's settings (`--pixels`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Raster {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// `--per-pixel`; `None` means `--radius` gives the spacing.
    pub(crate) per_pixel: Option<f64>,
    pub(crate) paper: bool,
    /// `--exact N`: exactly N points in every pixel.
    pub(crate) exact: Option<u32>,
    /// `--camera`: camera samples instead of points.
    pub(crate) camera: Option<Camera>,
}

/// The camera-sample mode's settings (`--camera`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Camera {
    /// `--spp`: samples in every pixel.
    pub(crate) spp: u32,
    /// `--dims`: values per sample after `px,py,index`, at least 5.
    pub(crate) dims: u32,
    /// `--stream`: film points from `CameraPixels` (exact scheme).
    pub(crate) stream: bool,
    /// `--sampler`: the random-access pixel sampler.
    pub(crate) sampler: SamplerArg,
}

/// A usage error in clap's format (exit code 2).
fn invalid(message: String) -> clap::Error {
    Args::command().error(ErrorKind::ValueValidation, message)
}

impl Args {
    /// The checked configuration, or a usage error.
    pub(crate) fn config(self) -> Result<Config, clap::Error> {
        let raster = match self.pixels {
            Some((width, height)) => {
                if self.dim.is_some_and(|d| d != 2) {
                    return Err(invalid(
                        "--pixels makes a 2-D raster: --dim must be 2 if given".to_owned(),
                    ));
                }
                let camera = match self.spp.filter(|_| self.camera) {
                    Some(_) if self.stream && self.sampler.is_some() => {
                        return Err(invalid(
                            "--sampler picks the random-access pixel sampler; --stream has its own"
                                .to_owned(),
                        ));
                    }
                    Some(spp) if self.dims >= 5 => Some(Camera {
                        spp,
                        dims: self.dims,
                        stream: self.stream,
                        sampler: self.sampler.unwrap_or_default(),
                    }),
                    Some(_) => {
                        return Err(invalid(format!(
                            "--dims counts film, lens and time, so it is at least 5, got {}",
                            self.dims
                        )));
                    }
                    None => None,
                };
                if camera.is_some() && matches!(self.format, Format::Json | Format::Binary) {
                    return Err(invalid("--camera writes CSV (or none)".to_owned()));
                }
                if camera.is_none()
                    && self.radius.is_none()
                    && self.per_pixel.is_none()
                    && self.exact.is_none()
                {
                    return Err(Args::command().error(
                        ErrorKind::MissingRequiredArgument,
                        "--pixels needs --radius, --per-pixel or --exact",
                    ));
                }
                Some(Raster {
                    width,
                    height,
                    per_pixel: self.per_pixel,
                    paper: self.paper,
                    exact: self.exact,
                    camera,
                })
            }
            None => None,
        };
        let dim = if raster.is_some() {
            2
        } else {
            self.dim.unwrap_or_default()
        };
        if !(1..=8).contains(&dim) {
            return Err(invalid(format!("--dim must be from 1 to 8, got {dim}")));
        }
        let (mut extent, mut lo) = (self.extent, self.lo);
        if self.field {
            // --field takes one value for every axis, as in `--extent 1`.
            for list in [&mut extent, &mut lo].into_iter().flatten() {
                if list.len() == 1 {
                    *list = vec![list[0]; dim];
                }
            }
        }
        let field = if self.field {
            let region = match self.region.as_deref() {
                None => None,
                Some(text) => {
                    let parse = |part: &str| -> Result<Vec<f64>, clap::Error> {
                        let values = common::list::<f64>(part)
                            .map_err(|e| invalid(format!("--region: {e}")))?;
                        if values.len() == dim {
                            Ok(values)
                        } else {
                            Err(invalid(format!(
                                "--region needs {dim} values on each side of ':', got {}",
                                values.len()
                            )))
                        }
                    };
                    let Some((a, b)) = text.split_once(':') else {
                        return Err(invalid("--region is A:B, two comma lists".to_owned()));
                    };
                    Some((parse(a)?, parse(b)?))
                }
            };
            Some(FieldMode {
                region,
                chunk: self.chunk,
            })
        } else {
            None
        };
        for (flag, list) in [("--extent", &extent), ("--lo", &lo)] {
            if let Some(values) = list
                && values.len() != dim
            {
                return Err(invalid(format!(
                    "{flag} needs exactly {dim} comma-separated values (one per axis), got {}",
                    values.len()
                )));
            }
        }
        let radius_range = match self.radius_range.as_deref() {
            None => None,
            Some(&[r0, r1]) => Some((r0, r1)),
            Some(other) => {
                return Err(invalid(format!(
                    "--radius-range needs two values, R0,R1, got {}",
                    other.len()
                )));
            }
        };
        let mut periodic = vec![self.periodic; dim];
        for &axis in self.periodic_axes.iter().flatten() {
            let Some(p) = periodic.get_mut(axis) else {
                return Err(invalid(format!(
                    "--periodic-axes: axis {axis} does not exist with --dim {dim} (axes are 0 to {})",
                    dim - 1
                )));
            };
            *p = true;
        }
        Ok(Config {
            dim,
            radius: self.radius.unwrap_or(f64::NAN),
            count: self.count,
            radius_range,
            extent,
            lo,
            periodic,
            attempts: self.attempts,
            candidates: self.candidates.into(),
            seed: self.seed,
            max_points: self.max_points,
            max_grid_bytes: self.max_grid_bytes,
            layout: self.layout.into(),
            threads: self.threads,
            format: self.format,
            out: self.out,
            raster,
            field,
            f32: self.f32,
        })
    }
}

/// The configuration of a command line given as one string (for tests).
#[cfg(test)]
pub(crate) fn from_line(line: &str) -> Result<Config, clap::Error> {
    common::parse_line::<Args>("points", line)?.config()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bridson::Candidates;

    fn parse(line: &str) -> Result<Config, clap::Error> {
        from_line(line)
    }

    fn config(line: &str) -> Config {
        parse(line).unwrap_or_else(|e| panic!("{line}: expected a run, got {e}"))
    }

    fn error(line: &str) -> clap::Error {
        match parse(line) {
            Err(e) => e,
            Ok(c) => panic!("{line}: expected an error, got {c:?}"),
        }
    }

    #[test]
    fn parses_the_documented_example() {
        let c = config("--dim 2 --radius 0.01 --extent 1,1 --seed 7 --out pts.csv");
        let expected = Config {
            dim: 2,
            radius: 0.01,
            count: None,
            radius_range: None,
            extent: Some(vec![1.0, 1.0]),
            lo: None,
            periodic: vec![false, false],
            attempts: None,
            candidates: Candidates::Annulus,
            seed: 7,
            max_points: None,
            max_grid_bytes: None,
            layout: bridson::GridLayout::Auto,
            threads: None,
            format: Format::Csv,
            out: Some(PathBuf::from("pts.csv")),
            raster: None,
            field: None,
            f32: false,
        };
        assert_eq!(c, expected, "example command");
    }

    #[test]
    fn parses_the_field_flags() {
        let c =
            config("--dim 2 --radius 0.05 --extent 1 --field --region 0.2,0:0.7,0.5 --chunk 0.1");
        assert_eq!(c.extent, Some(vec![1.0, 1.0]), "one extent for every axis");
        assert_eq!(
            c.field,
            Some(FieldMode {
                region: Some((vec![0.2, 0.0], vec![0.7, 0.5])),
                chunk: Some(0.1),
            }),
            "field mode"
        );
        for bad in [
            "--dim 2 --radius 0.05 --field --region 0.2,0",
            "--dim 2 --radius 0.05 --field --region 0.2:0.7",
            "--dim 2 --radius 0.05 --region 0,0:1,1",
        ] {
            let _ = error(bad);
        }
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
                camera: None,
            }),
            "raster settings"
        );
        let camera = config("--pixels 4x3 --camera --spp 16 --dims 7 --stream --seed 2");
        assert_eq!(
            camera.raster.and_then(|r| r.camera),
            Some(Camera {
                spp: 16,
                dims: 7,
                stream: true,
                sampler: SamplerArg::Poisson,
            }),
            "camera settings"
        );
        let net = config("--pixels 4x3 --camera --spp 16 --sampler net");
        assert_eq!(
            net.raster.and_then(|r| r.camera).map(|c| c.sampler),
            Some(SamplerArg::Net),
            "--sampler net"
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
            "--pixels 5x7 --camera --spp 4 --stream --sampler net",
            "--pixels 5x7 --camera --spp 4 --stream --sampler poisson",
            "--pixels 5x7 --camera --spp 4 --sampler sobol",
        ] {
            let e = error(bad);
            assert_eq!(e.exit_code(), 2, "{bad}: exit code");
        }
    }

    #[test]
    fn parses_every_flag_in_both_forms() {
        let c = config(
            "--dim=3 --radius=0.5 --extent 2,3,4 --lo=-1,-2,-3 --periodic-axes 0,2 \
             --attempts 12 --candidates=sphere --seed 18446744073709551615 \
             --max-points 100 --threads 3 --format json --out=x.json",
        );
        assert_eq!(c.threads, NonZeroUsize::new(3), "threads");
        assert_eq!(c.dim, 3, "dim");
        assert_eq!(c.radius, 0.5, "radius");
        assert_eq!(c.extent, Some(vec![2.0, 3.0, 4.0]), "extent");
        assert_eq!(c.lo, Some(vec![-1.0, -2.0, -3.0]), "lo");
        assert_eq!(c.periodic, vec![true, false, true], "periodic axes");
        assert_eq!(c.attempts, Some(12), "attempts");
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
        let negative = config("--dim 2 --radius 1 --lo -1,-2");
        assert_eq!(negative.lo, Some(vec![-1.0, -2.0]), "negative list");
    }

    #[test]
    fn parses_a_count_instead_of_a_radius() {
        let c = config("--dim 3 --count 5000 --extent 2,1,1 --periodic");
        assert_eq!(c.count, Some(5000), "count");
        assert!(c.radius.is_nan(), "no radius given");
        for bad in [
            "--dim 2 --count 100 --radius 0.1",
            "--pixels 4x4 --count 100",
            "--dim 2 --count -1",
            "--dim 2 --count 1.5",
        ] {
            assert_eq!(error(bad).exit_code(), 2, "{bad}: exit code");
        }
    }

    #[test]
    fn parses_a_radius_range() {
        let c = config("--dim 2 --radius-range 0.01,0.04");
        assert_eq!(c.radius_range, Some((0.01, 0.04)), "range");
        for bad in [
            "--dim 2 --radius-range 0.01",
            "--dim 2 --radius-range 0.01,0.02,0.03",
            "--dim 2 --radius-range 0.01,0.02 --radius 0.1",
            "--dim 2 --radius-range 0.01,0.02 --count 100",
        ] {
            assert_eq!(error(bad).exit_code(), 2, "{bad}: exit code");
        }
    }

    #[test]
    fn f32_goes_with_every_batch_run_only() {
        for line in [
            "--dim 2 --radius 0.1 --f32",
            "--dim 3 --count 100 --f32",
            "--dim 2 --radius 0.1 --threads 2 --f32",
            "--dim 2 --radius-range 0.01,0.04 --f32",
        ] {
            assert!(config(line).f32, "{line}");
        }
        for bad in [
            "--pixels 4x4 --radius 1 --f32",
            "--dim 2 --radius 0.1 --field --f32",
        ] {
            assert_eq!(error(bad).exit_code(), 2, "{bad}: exit code");
        }
    }

    #[test]
    fn help_stops_parsing() {
        for line in ["--help", "--dim 2 -h", "--dim 99 --help"] {
            let e = error(line);
            assert_eq!(e.kind(), ErrorKind::DisplayHelp, "{line}");
            assert_eq!(e.exit_code(), 0, "{line}: help exits 0");
        }
    }

    #[test]
    fn rejects_bad_command_lines() {
        let cases = [
            ("--radius 0.1", "--dim"),
            ("--dim 2", "--radius"),
            ("--dim 0 --radius 1", "--dim must be from 1 to 8, got 0"),
            ("--dim 9 --radius 1", "--dim must be from 1 to 8, got 9"),
            ("--dim -1 --radius 1", "invalid value '-1' for '--dim <D>'"),
            ("--dim 2 --radius", "'--radius <R>'"),
            (
                "--dim 2 --radius abc",
                "invalid value 'abc' for '--radius <R>'",
            ),
            (
                "--dim 2 --radius 1 --extent 1,2,3",
                "--extent needs exactly 2",
            ),
            ("--dim 2 --radius 1 --lo 1", "--lo needs exactly 2"),
            ("--dim 2 --radius 1 --extent 1,", "invalid item '' in '1,'"),
            (
                "--dim 2 --radius 1 --extent 1,x",
                "invalid item 'x' in '1,x'",
            ),
            (
                "--dim 2 --radius 1 --format xml",
                "[possible values: csv, json, none, binary]",
            ),
            (
                "--dim 2 --radius 1 --candidates disk",
                "[possible values: annulus, sphere]",
            ),
            (
                "--dim 2 --radius 1 --attempts -3",
                "invalid value '-3' for '--attempts <K>'",
            ),
            (
                "--dim 2 --radius 1 --attempts 4294967296",
                "'--attempts <K>'",
            ),
            (
                "--dim 2 --radius 1 --seed 1.5",
                "invalid value '1.5' for '--seed <S>'",
            ),
            ("--dim 2 --radius 1 --max-points -1", "'--max-points <N>'"),
            (
                "--dim 2 --radius 1 --periodic-axes 2",
                "axis 2 does not exist",
            ),
            ("--dim 2 --radius 1 --periodic=yes", "'--periodic'"),
            (
                "--dim 2 --radius 1 --radius 2",
                "'--radius <R>' cannot be used multiple times",
            ),
            (
                "--dim 2 --radius 1 --bogus",
                "unexpected argument '--bogus'",
            ),
            ("--dim 2 --radius 1 stray", "unexpected argument 'stray'"),
            ("--dim 2 --radius 1 --out=", "'--out <FILE>'"),
        ];
        for (line, expected) in cases {
            let e = error(line);
            let text = e.to_string();
            assert_eq!(e.exit_code(), 2, "{line}: exit code");
            assert!(
                text.contains(expected),
                "{line}: got '{text}', expected '{expected}'"
            );
        }
    }
}
