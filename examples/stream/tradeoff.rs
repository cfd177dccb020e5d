//! `--chart FILE` (with `--exact N`): exact mode's trade-off against the
//! oversampling `s`, for each method with and without its edge
//! correction, drawn as one PNG of four panels: the power at the pixel
//! frequency, ρ of the minimum distance, the edge band farthest from the
//! interior's density, and the speed (kept points/s over the sweep's own
//! points/s at the same radius and `k`, both measured in this run in CPU
//! time, the sweep first at each `s`).

use crate::canvas::{Canvas, Rgb, WHITE};
use crate::line_chart::{LineChart, Reference, Series};
use crate::{Stats, timed_pass};
use bridson::{ExactMethod, Tiled, TiledBuilder};
use std::path::Path;

/// The oversamplings measured.
const OVERSAMPLINGS: [f64; 8] = [1.0, 1.1, 1.16, 1.25, 1.4, 1.6, 2.0, 3.0];

/// One method as charted.
struct Variant {
    label: &'static str,
    method: ExactMethod,
    /// `None`: the calibrated edge correction.
    bias: Option<[f64; 3]>,
    colour: Rgb,
}

const VARIANTS: [Variant; 4] = [
    Variant {
        label: "eliminate",
        method: ExactMethod::Eliminate,
        bias: None,
        colour: [0, 114, 178],
    },
    Variant {
        label: "random",
        method: ExactMethod::Random,
        bias: None,
        colour: [213, 94, 0],
    },
    Variant {
        label: "eliminate uncorrected",
        method: ExactMethod::Eliminate,
        bias: Some([0.0; 3]),
        colour: [86, 180, 233],
    },
    Variant {
        label: "random uncorrected",
        method: ExactMethod::Random,
        bias: Some([0.0; 3]),
        colour: [230, 159, 0],
    },
];

/// Streams `builder`'s pixels twice: timed, doing nothing with the points
/// (`timed_pass`: CPU time of this thread where the system tells it, the
/// machine may be shared, else the wall clock), then for the statistics.
fn run(builder: TiledBuilder, width: u32, seed: u64) -> Result<(Tiled, Stats, f64), String> {
    let tiled = builder.build().map_err(|e| e.to_string())?;
    let (_, _, seconds) = timed_pass(&tiled, seed);
    let mut stats = Stats::new(width, tiled.height(), 2);
    let mut buf = Vec::new();
    let mut stream = tiled.pixels_seeded(seed);
    while let Some((x, y)) = stream.next_into(&mut buf) {
        stats.add(x, y, &buf);
    }
    Ok((tiled, stats, seconds))
}

/// The four figures charted for one run.
#[derive(Clone, Copy, Debug)]
struct Figures {
    power: f64,
    rho: f64,
    edge: f64,
    speed: f64,
}

/// Measures every variant at every oversampling for `n` per pixel on a
/// `width × height` raster, prints a line per run and writes the chart.
pub(crate) fn chart(
    (width, height): (u32, u32),
    n: u32,
    seed: u64,
    path: &Path,
) -> Result<(), String> {
    let area = f64::from(width) * f64::from(height);
    let mut figures: Vec<Vec<[f64; 2]>> = vec![Vec::new(); 4 * VARIANTS.len()];
    for s in OVERSAMPLINGS {
        let exact = Tiled::builder(width, height)
            .exact(n)
            .exact_oversample(s)
            .build()
            .map_err(|e| e.to_string())?;
        let (radius, k) = (exact.radius(), exact.attempts());
        let sweep_at = Tiled::builder(width, height).radius(radius).attempts(k);
        let (_, sweep, sweep_seconds) = run(sweep_at, width, seed)?;
        #[expect(clippy::cast_precision_loss, reason = "statistics")]
        let sweep_rate = sweep.points as f64 / sweep_seconds;
        println!(
            "s = {s}: sweep at r = {radius:.5}, k = {k}: {:.3} M points/s",
            sweep_rate / 1e6
        );
        for (k, v) in VARIANTS.iter().enumerate() {
            let builder = Tiled::builder(width, height)
                .exact(n)
                .exact_method(v.method)
                .exact_oversample(s);
            let builder = match v.bias {
                Some(b) => builder.exact_edge_bias(b),
                None => builder,
            };
            let (_, stats, seconds) = run(builder, width, seed)?;
            #[expect(clippy::cast_precision_loss, reason = "statistics")]
            let rate = stats.points as f64 / seconds;
            let [px, py] = stats.power();
            let f = Figures {
                power: px.max(py),
                rho: stats.rho_of_minimum(area),
                edge: stats.edge_ratios().into_iter().fold(1.0, |w, e| {
                    if (e - 1.0).abs() > (w - 1.0).abs() {
                        e
                    } else {
                        w
                    }
                }),
                speed: rate / sweep_rate,
            };
            println!(
                "  {:<22} {:.3} M kept/s ({:.2} of the sweep), power {:.2}, rho {:.4}, worst edge band {:.3}",
                v.label,
                rate / 1e6,
                f.speed,
                f.power,
                f.rho,
                f.edge
            );
            for (panel, value) in [f.power, f.rho, f.edge, f.speed].into_iter().enumerate() {
                if let Some(list) = figures.get_mut(panel * VARIANTS.len() + k) {
                    list.push([s, value]);
                }
            }
        }
    }
    draw(&figures, n, (width, height))
        .save(path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The four panels side by side, two by two, under a legend row.
fn draw(figures: &[Vec<[f64; 2]>], n: u32, (width, height): (u32, u32)) -> Canvas {
    let grey = [90, 90, 90];
    let x_range = [1.0, 3.0];
    let series = |panel: usize| -> Vec<Series> {
        VARIANTS
            .iter()
            .enumerate()
            .map(|(k, v)| Series {
                points: figures
                    .get(panel * VARIANTS.len() + k)
                    .cloned()
                    .unwrap_or_default(),
                colour: v.colour,
            })
            .collect()
    };
    let top = |panel: usize, floor: f64| {
        figures
            .iter()
            .skip(panel * VARIANTS.len())
            .take(VARIANTS.len())
            .flatten()
            .map(|p| p[1])
            .fold(floor, f64::max)
    };
    let reference = |at: f64, label: &str| Reference {
        horizontal: true,
        at,
        label: label.to_owned(),
        colour: grey,
    };
    let x_label = "oversampling s".to_owned();
    let panels = [
        LineChart {
            title: "power at the pixel frequency".into(),
            x_label: x_label.clone(),
            y_label: "max of x and y - clipped at 40".into(),
            x_range,
            y_range: [0.0, top(0, 4.0).min(40.0)],
            series: series(0),
            references: vec![reference(3.0, "goal 3")],
        },
        LineChart {
            title: "ρ of the minimum distance".into(),
            x_label: x_label.clone(),
            y_label: "ρ".into(),
            x_range,
            y_range: [0.35, 0.75],
            series: series(1),
            references: vec![reference(0.65, "goal 0.65")],
        },
        LineChart {
            title: "edge band farthest from interior".into(),
            x_label: x_label.clone(),
            y_label: "band / interior density".into(),
            x_range,
            y_range: [0.85, 1.15],
            series: series(2),
            references: vec![reference(0.95, "goal 0.95"), reference(1.05, "1.05")],
        },
        LineChart {
            title: "speed".into(),
            x_label,
            y_label: "kept/s over sweep points/s - CPU".into(),
            x_range,
            y_range: [0.0, top(3, 1.0) * 1.05],
            series: series(3),
            references: vec![reference(1.0, "sweep")],
        },
    ];
    let (pw, ph) = (640_u32, 440_u32);
    let legend = 40_i64;
    let mut canvas = Canvas::new(2 * pw, 2 * ph + 40, WHITE);
    for (k, panel) in panels.iter().enumerate() {
        let image = panel.render(pw, ph);
        let (ox, oy) = (
            i64::from(pw) * (k as i64 % 2),
            legend + i64::from(ph) * (k as i64 / 2),
        );
        for y in 0..i64::from(ph) {
            for x in 0..i64::from(pw) {
                if let Some(c) = image.get(x, y) {
                    canvas.set(ox + x, oy + y, c);
                }
            }
        }
    }
    let mut x = 16;
    let title = format!("exact {n} per pixel on {width}x{height}:");
    canvas.text(x, 12, &title, 2, [0, 0, 0]);
    x += Canvas::text_size(&title, 2).0 + 16;
    for v in &VARIANTS {
        canvas.hline(19, x, x + 23, v.colour, 1.0, 0);
        canvas.hline(20, x, x + 23, v.colour, 1.0, 0);
        canvas.text(x + 30, 12, v.label, 2, v.colour);
        x += 30 + Canvas::text_size(v.label, 2).0 + 24;
    }
    canvas
}
