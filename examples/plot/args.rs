//! The command line of `plot`: clap parses the flags, [`Args::config`]
//! checks what depends on several of them and resolves the defaults that
//! depend on others (the pictures) into a [`Config`].

use crate::common::{self, CandidatesArg};
use crate::raster::Raster;
use clap::error::ErrorKind;
use clap::{CommandFactory, Parser, ValueEnum};
use std::path::PathBuf;
use std::str::FromStr;

/// A comma-separated list, one value per flag: clap reads a field typed
/// `Vec` as a repeated flag, and this name opts out of that.
type List<T> = Vec<T>;

const ABOUT: &str = "\
Draws Poisson disk point sets (Bridson) as PNG images and writes a JSON
quality report. Set k is drawn with seed S + k; the point plot and the report
use set 0, the spectra and the in-pixel density average over all sets.";

const AFTER: &str = "\
Pictures are written as DIR/NAME-KIND.png. Flags also accept the form
--flag=value.

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
  plot --pixels 8x6 --radius 0.2 --pixel-grid --cell-grid --plots points --out-dir pics";

/// The flags as typed.
#[derive(Debug, Parser)]
#[command(
    name = "plot",
    about = ABOUT,
    after_help = AFTER,
    override_usage = "plot [OPTIONS] (--out-dir DIR | --report FILE | both)",
    allow_negative_numbers = true,
)]
pub(crate) struct Args {
    /// Dimension, 2 to 8
    #[arg(long, value_name = "D", default_value_t = 2, help_heading = "Sampler")]
    dim: usize,
    /// Minimum distance [default: about 4000 points, the radius for rho 0.73]
    #[arg(long, value_name = "R", help_heading = "Sampler")]
    radius: Option<f64>,
    /// Box size, exactly D values [default: all 1]
    #[arg(long, value_name = "A,B,..", value_parser = common::list::<f64>,
          allow_hyphen_values = true, help_heading = "Sampler")]
    extent: Option<List<f64>>,
    /// A raster of W x H pixels of side 1: the box is [0,W) x [0,H) (2-D
    /// only); adds the in-pixel density picture and the raster part of the
    /// report
    #[arg(long, value_name = "WxH", value_parser = common::size,
          conflicts_with = "extent", help_heading = "Sampler")]
    pixels: Option<(u32, u32)>,
    /// With --pixels: stream the sets pixel by pixel with bridson::Tiled
    /// (paper: Ye's per-pixel scheme, which has a border bias); not periodic
    #[arg(
        long,
        value_name = "SCHEME",
        value_enum,
        requires = "pixels",
        conflicts_with = "periodic",
        help_heading = "Sampler"
    )]
    stream: Option<StreamArg>,
    /// With --pixels: stream with exactly N points in every pixel (the
    /// radius is then the oversampled sweep's)
    #[arg(long, value_name = "N", requires = "pixels",
          conflicts_with_all = ["periodic", "stream"], help_heading = "Sampler")]
    exact: Option<u32>,
    /// Make every axis periodic (toroidal)
    #[arg(long, help_heading = "Sampler")]
    periodic: bool,
    /// Candidate attempts per active point [default: 30; 10 with --exact,
    /// the k exact mode is calibrated at]
    #[arg(long, value_name = "K", help_heading = "Sampler")]
    attempts: Option<u32>,
    /// How candidates are drawn
    #[arg(
        long,
        value_name = "KIND",
        value_enum,
        default_value_t,
        help_heading = "Sampler"
    )]
    candidates: CandidatesArg,
    /// Seed of set 0
    #[arg(long, value_name = "S", default_value_t = 0, help_heading = "Sampler")]
    seed: u64,

    /// Directory for the images (created if missing)
    #[arg(long, value_name = "DIR", help_heading = "Pictures")]
    out_dir: Option<PathBuf>,
    /// File name prefix
    #[arg(long, value_name = "NAME", default_value = "plot", value_parser = file_prefix,
          help_heading = "Pictures")]
    name: String,
    /// Points, periodogram, radial, anisotropy, density [default: points;
    /// the three spectra in 2-D; density with --pixels]
    #[arg(long, value_name = "KIND,..", value_parser = common::list::<Plot>,
          help_heading = "Pictures")]
    plots: Option<List<Plot>>,
    /// Longer side of the point plot, 16 to 8192
    #[arg(long, value_name = "PX", default_value_t = 512,
          value_parser = clap::value_parser!(u32).range(16..=8192), help_heading = "Pictures")]
    size: u32,
    /// Show only this rectangle of axes 0 and 1 in the point plot
    /// [default: the whole box]
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = common::list::<f64>,
          allow_hyphen_values = true, help_heading = "Pictures")]
    window: Option<List<f64>>,
    /// Draw pixel borders (lines at whole coordinates)
    #[arg(long, help_heading = "Pictures")]
    pixel_grid: bool,
    /// Draw the background grid, cells of side r/sqrt(D)
    #[arg(long, help_heading = "Pictures")]
    cell_grid: bool,
    /// For D > 2, which points the plot shows
    #[arg(long, value_name = "KIND", value_enum, default_value_t = View::Slice,
          help_heading = "Pictures")]
    view: View,
    /// Independent sets for the spectra and the in-pixel density, 1 to 10000
    #[arg(long, value_name = "M", default_value_t = 8,
          value_parser = clap::value_parser!(u32).range(1..=10_000), help_heading = "Pictures")]
    sets: u32,
    /// Frequencies -F..F on each axis, 1 to 1024
    #[arg(long, value_name = "F", default_value_t = 128,
          value_parser = clap::value_parser!(u32).range(1..=1024), help_heading = "Pictures")]
    freq: u32,
    /// In-pixel density bins per side, 1 to 256
    #[arg(long, value_name = "B", default_value_t = 32,
          value_parser = clap::value_parser!(u16).range(1..=256), help_heading = "Pictures")]
    bins: u16,

    /// Write the JSON quality report of set 0 to FILE ('-' for stdout)
    #[arg(long, value_name = "FILE", help_heading = "Report")]
    report: Option<PathBuf>,
    /// Uniform probe points for the uncovered fraction
    #[arg(
        long,
        value_name = "P",
        default_value_t = 100_000,
        help_heading = "Report"
    )]
    probes: u64,
}

/// `--stream sweep | paper`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum StreamArg {
    /// The default sweep of bridson::Tiled
    Sweep,
    /// Ye's per-pixel scheme
    Paper,
}

/// `--name`: a file name prefix, not a path.
fn file_prefix(text: &str) -> Result<String, String> {
    if text.is_empty() || text.contains(['/', '\\']) {
        Err("expected a file name prefix".to_owned())
    } else {
        Ok(text.to_owned())
    }
}

/// One picture.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Plot {
    Points,
    Periodogram,
    Radial,
    Anisotropy,
    Density,
}

impl Plot {
    pub(crate) const ALL: [Self; 5] = [
        Self::Points,
        Self::Periodogram,
        Self::Radial,
        Self::Anisotropy,
        Self::Density,
    ];

    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Points => "points",
            Self::Periodogram => "periodogram",
            Self::Radial => "radial",
            Self::Anisotropy => "anisotropy",
            Self::Density => "density",
        }
    }

    pub(crate) fn is_spectral(self) -> bool {
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
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub(crate) enum View {
    /// The points within `r/2` of the middle of every axis from 2 on.
    Slice,
    /// Every point, by its first two coordinates.
    Projection,
}

/// A fully parsed and checked command line.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Config {
    pub(crate) dim: usize,
    pub(crate) radius: Option<f64>,
    pub(crate) extent: Option<Vec<f64>>,
    pub(crate) pixels: Option<Raster>,
    pub(crate) periodic: bool,
    /// `--attempts`, if given: else the library's default for the run
    /// (30, or 10 in exact mode).
    pub(crate) attempts: Option<u32>,
    pub(crate) candidates: bridson::Candidates,
    pub(crate) seed: u64,
    pub(crate) out_dir: Option<PathBuf>,
    pub(crate) name: String,
    /// The pictures to draw (resolved: never empty when `out_dir` is set).
    pub(crate) plots: Vec<Plot>,
    pub(crate) size: u32,
    /// The rectangle of the point plot: `[x0, y0, x1, y1]`.
    pub(crate) window: Option<[f64; 4]>,
    pub(crate) pixel_grid: bool,
    pub(crate) cell_grid: bool,
    pub(crate) view: View,
    pub(crate) sets: u32,
    pub(crate) freq: u32,
    pub(crate) bins: usize,
    pub(crate) report: Option<PathBuf>,
    pub(crate) probes: u64,
    /// With `--pixels`: take the sets from the streaming mode.
    pub(crate) stream: Option<Stream>,
}

/// Which streamed set (`--stream`, `--exact`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stream {
    Sweep,
    Paper,
    /// Exactly this many points in every pixel.
    Exact(u32),
}

/// A usage error in clap's format (exit code 2).
fn invalid(kind: ErrorKind, message: String) -> clap::Error {
    Args::command().error(kind, message)
}

impl Args {
    /// The checked configuration, or a usage error.
    pub(crate) fn config(self) -> Result<Config, clap::Error> {
        use ErrorKind::{ArgumentConflict, MissingRequiredArgument, ValueValidation};
        let dim = self.dim;
        if !(2..=8).contains(&dim) {
            return Err(invalid(
                ValueValidation,
                format!("--dim must be from 2 to 8, got {dim}"),
            ));
        }
        if let Some(values) = &self.extent
            && values.len() != dim
        {
            return Err(invalid(
                ValueValidation,
                format!(
                    "--extent needs exactly {dim} comma-separated values (one per axis), got {}",
                    values.len()
                ),
            ));
        }
        let pixels = self.pixels.map(|(width, height)| Raster { width, height });
        if pixels.is_some() && dim != 2 {
            return Err(invalid(
                ArgumentConflict,
                format!("--pixels needs --dim 2, got --dim {dim}"),
            ));
        }
        let plots = match self.plots {
            Some(list) => {
                for p in &list {
                    if p.is_spectral() && dim != 2 {
                        return Err(invalid(
                            ArgumentConflict,
                            format!(
                                "--plots {}: the spectra are 2-D only, got --dim {dim}",
                                p.name()
                            ),
                        ));
                    }
                    if *p == Plot::Density && pixels.is_none() {
                        return Err(invalid(
                            MissingRequiredArgument,
                            "--plots density needs --pixels WxH".to_owned(),
                        ));
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
        if self.out_dir.is_none() && self.report.is_none() {
            return Err(invalid(
                MissingRequiredArgument,
                "nothing to do: give --out-dir DIR, --report FILE or both".to_owned(),
            ));
        }
        let window = match self.window.as_deref() {
            None => None,
            Some(&[x0, y0, x1, y1])
                if x0 < x1 && y0 < y1 && x1 - x0 < f64::INFINITY && y1 - y0 < f64::INFINITY =>
            {
                Some([x0, y0, x1, y1])
            }
            Some(_) => {
                return Err(invalid(
                    ValueValidation,
                    "--window needs four finite numbers X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1"
                        .to_owned(),
                ));
            }
        };
        let stream = match (self.stream, self.exact) {
            (_, Some(n)) => Some(Stream::Exact(n)),
            (Some(StreamArg::Sweep), None) => Some(Stream::Sweep),
            (Some(StreamArg::Paper), None) => Some(Stream::Paper),
            (None, None) => None,
        };
        Ok(Config {
            dim,
            radius: self.radius,
            extent: self.extent,
            pixels,
            periodic: self.periodic,
            attempts: self.attempts,
            candidates: self.candidates.into(),
            seed: self.seed,
            out_dir: self.out_dir,
            name: self.name,
            plots,
            size: self.size,
            window,
            pixel_grid: self.pixel_grid,
            cell_grid: self.cell_grid,
            view: self.view,
            sets: self.sets,
            freq: self.freq,
            bins: usize::from(self.bins),
            report: self.report,
            probes: self.probes,
            stream,
        })
    }
}

/// The configuration of a command line given as one string (for tests).
#[cfg(test)]
pub(crate) fn from_line(line: &str) -> Result<Config, clap::Error> {
    common::parse_line::<Args>("plot", line)?.config()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bridson::Candidates;

    fn config(line: &str) -> Config {
        from_line(line).unwrap_or_else(|e| panic!("{line}: expected a run, got {e}"))
    }

    fn error(line: &str) -> String {
        match from_line(line) {
            Err(e) => {
                assert_eq!(e.exit_code(), 2, "{line}: exit code");
                e.to_string()
            }
            Ok(c) => panic!("{line}: expected an error, got {c:?}"),
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
        assert_eq!(c.attempts, Some(12), "attempts");
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
        let help = from_line("--help").expect_err("help is not a run");
        assert_eq!(help.kind(), ErrorKind::DisplayHelp, "help");
        assert_eq!(help.exit_code(), 0, "help exits 0");
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
                "invalid value '4' for '--pixels <WxH>': expected WxH",
            ),
            ("--pixels 4x0 --report r", "expected WxH"),
            ("--pixels 4x-1 --report r", "expected WxH"),
            ("--pixels 4,4 --report r", "expected WxH"),
            (
                "--pixels 4x4 --extent 1,1 --report r",
                "'--pixels <WxH>' cannot be used with '--extent <A,B,..>'",
            ),
            ("--dim 3 --pixels 4x4 --report r", "--pixels needs --dim 2"),
            ("--dim 3 --plots radial --out-dir o", "2-D only"),
            ("--plots density --out-dir o", "needs --pixels"),
            (
                "--plots dots --out-dir o",
                "invalid value 'dots' for '--plots <KIND,..>'",
            ),
            (
                "--size 8 --out-dir o",
                "'--size <PX>': 8 is not in 16..=8192",
            ),
            (
                "--sets 0 --out-dir o",
                "'--sets <M>': 0 is not in 1..=10000",
            ),
            (
                "--freq 2000 --out-dir o",
                "'--freq <F>': 2000 is not in 1..=1024",
            ),
            ("--bins 0 --out-dir o", "'--bins <B>': 0 is not in 1..=256"),
            (
                "--view side --out-dir o",
                "[possible values: slice, projection]",
            ),
            ("--window 0,0,1 --out-dir o", "--window needs four finite"),
            ("--window 1,0,0,1 --out-dir o", "X0 < X1"),
            (
                "--window 0,0,1,inf --out-dir o",
                "--window needs four finite",
            ),
            (
                "--candidates disk --out-dir o",
                "[possible values: annulus, sphere]",
            ),
            ("--name a/b --out-dir o", "expected a file name prefix"),
            ("--out-dir= --report r", "'--out-dir <DIR>'"),
            ("--report= --out-dir o", "'--report <FILE>'"),
            (
                "--pixel-grid --pixel-grid --out-dir o",
                "'--pixel-grid' cannot be used multiple times",
            ),
            ("--periodic=yes --out-dir o", "'--periodic'"),
            ("--seed x --out-dir o", "invalid value 'x' for '--seed <S>'"),
            ("--bogus --out-dir o", "unexpected argument '--bogus'"),
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
}
