//! Sampling, pictures and the report of `plot`: draws the sets a
//! [`Config`] describes, saves the pictures asked for and writes the JSON
//! quality report.

use crate::args::{Config, Plot, Stream, View};
use crate::common::{Failure, report};
use crate::draw::{self, CellGrid, PointView};
use crate::line_chart::{LineChart, Reference, Series};
use crate::raster::{self, CountHistogram, EdgeRatios, InPixelDensity, Raster};
use crate::spectrum::{self, Periodogram};
use crate::{canvas, quality};
use bridson::{Domain, PoissonDisk, Scheme, Tiled};
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

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

pub(crate) fn dispatch(config: &Config) -> Result<(), Failure> {
    crate::common::by_dimension!(config.dim, run(config), 2, 3, 4, 5, 6, 7, 8)
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
        .attempts(config.attempts.unwrap_or(bridson::DEFAULT_ATTEMPTS))
        .candidates(config.candidates)
        .build()
        .map_err(|e| e.to_string())
}

/// The streaming sampler `--stream` / `--exact` ask for, over the raster.
fn streamer(config: &Config, radius: f64) -> Result<Option<Tiled>, String> {
    let (Some(mode), Some(raster)) = (config.stream, config.pixels) else {
        return Ok(None);
    };
    let mut builder = Tiled::builder(raster.width, raster.height).candidates(config.candidates);
    // Only when asked for: exact mode's own default (10) is the `k` its
    // edge correction is calibrated at.
    if let Some(k) = config.attempts {
        builder = builder.attempts(k);
    }
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
        let attempts = tiled.as_ref().map_or(sampler.attempts(), Tiled::attempts);
        let candidates = tiled
            .as_ref()
            .map_or(sampler.candidates(), Tiled::candidates);
        let json = quality_report(config, domain, (radius, attempts, candidates), &first);
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
/// distance `radius` drawn with `attempts` and `candidates` as `config`
/// says (docs/quality.md describes the fields). Takes the plain list, so a
/// streamed set is measured alike.
fn quality_report<const N: usize>(
    config: &Config,
    domain: Domain<N>,
    (radius, attempts, candidates): (f64, u32, bridson::Candidates),
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
    let candidates = format!("{candidates:?}").to_lowercase();
    let _ = writeln!(j, "{{");
    let _ = writeln!(j, "  \"dim\": {N},");
    let _ = writeln!(j, "  \"radius\": {},", number(radius));
    let _ = writeln!(j, "  \"candidates\": \"{candidates}\",");
    let _ = writeln!(j, "  \"attempts\": {attempts},");
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
    use crate::args::from_line;
    use crate::common::assert_usage_failures;
    use crate::font;

    fn config(line: &str) -> Config {
        from_line(line).unwrap_or_else(|e| panic!("{line}: expected a run, got {e}"))
    }

    /// A fresh, empty directory under the system's temporary directory.
    fn temp_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("bridson-plot-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temporary directory");
        dir
    }

    #[test]
    fn library_errors_are_usage_errors() {
        let lines = [
            "--radius 0 --report r",
            "--radius nan --report r",
            "--extent 1,0 --report r",
            "--attempts 0 --report r",
            "--dim 3 --radius 1e-13 --report r",
        ];
        assert_usage_failures(&lines, |line| dispatch(&config(line)));
    }

    #[test]
    fn exact_mode_keeps_its_own_attempts_unless_asked() {
        let k = |line: &str| {
            let c = config(line);
            streamer(&c, 0.3).unwrap().expect("a stream").attempts()
        };
        assert_eq!(
            k("--pixels 16x8 --exact 4 --report -"),
            bridson::EXACT_ATTEMPTS,
            "exact mode's calibrated k"
        );
        assert_eq!(k("--pixels 16x8 --exact 4 --attempts 30 --report -"), 30);
        // The report gives the candidates the set was drawn with: exact
        // mode's sweep draws on the annulus whatever was asked.
        let kind = |line: &str| {
            let c = config(line);
            streamer(&c, 0.3).unwrap().expect("a stream").candidates()
        };
        assert_eq!(
            kind("--pixels 16x8 --exact 4 --candidates sphere --report -"),
            bridson::Candidates::Annulus
        );
        assert_eq!(
            kind("--pixels 16x8 --stream sweep --candidates sphere --report -"),
            bridson::Candidates::Sphere
        );
        assert_eq!(
            build::<2>(&config("--radius 0.1 --report -"))
                .unwrap()
                .attempts(),
            bridson::DEFAULT_ATTEMPTS,
            "the batch run's default"
        );
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
        let text = quality_report(
            &c,
            *sampler.domain(),
            (sampler.radius(), sampler.attempts(), sampler.candidates()),
            &points,
        );
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
        let settings = (s.radius(), s.attempts(), s.candidates());
        let text = quality_report(&plain, *s.domain(), settings, &[]);
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
