//! A log-log line chart on the plot example's [`Canvas`]: one curve per
//! sampler, a legend with each curve's fitted slope, and dashed reference
//! lines of given slopes. `plot`'s `LineChart` has linear axes and no
//! curve legend; this keeps its look (text scale, grey grid, black frame).

use crate::canvas::{BLACK, Canvas, Rect, Rgb, WHITE, f64_of, floor_i64};

/// Text scale: 5×7 glyphs drawn 10×14, as in `plot`.
const TEXT: u32 = 2;
const GRID_GREY: Rgb = [225, 225, 225];
const REFERENCE_GREY: Rgb = [120, 120, 120];

/// Distinct colours for the curves, in order (Okabe–Ito, then black).
pub(crate) const PALETTE: [Rgb; 8] = [
    [0, 114, 178],
    [213, 94, 0],
    [0, 158, 115],
    [204, 121, 167],
    [230, 159, 0],
    [86, 180, 233],
    [0, 0, 0],
    [240, 228, 66],
];

/// One curve: points `(n, mse)`, both positive, and its legend text.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Curve {
    pub(crate) label: String,
    pub(crate) points: Vec<[f64; 2]>,
    pub(crate) colour: Rgb,
}

/// A log-log chart of curves with reference slopes drawn through `anchor`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LogLogChart {
    pub(crate) title: String,
    pub(crate) x_label: String,
    pub(crate) y_label: String,
    pub(crate) curves: Vec<Curve>,
    /// Slopes of the dashed reference lines.
    pub(crate) reference_slopes: Vec<f64>,
    /// The point `(x, y)` the reference lines go through.
    pub(crate) anchor: [f64; 2],
}

/// The whole decades `[floor(log10 lo), ceil(log10 hi)]` around the
/// positive finite values of `values`; `[0, 1]` if there are none.
pub(crate) fn decades(values: impl Iterator<Item = f64>) -> [f64; 2] {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .map(f64::log10)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return [0.0, 1.0];
    }
    let (lo, hi) = (lo.floor(), hi.ceil());
    [lo, if hi > lo { hi } else { lo + 1.0 }]
}

/// The label of the power of ten `10^e`: "1", "10", "100", "1000", else
/// "1e5", "1e-3".
pub(crate) fn power_label(e: f64) -> String {
    match e {
        0.0 => "1".to_owned(),
        1.0 => "10".to_owned(),
        2.0 => "100".to_owned(),
        3.0 => "1000".to_owned(),
        _ => format!("1e{e}"),
    }
}

impl LogLogChart {
    /// The x and y ranges, in decades (log10).
    fn ranges(&self) -> ([f64; 2], [f64; 2]) {
        let all = || self.curves.iter().flat_map(|c| c.points.iter());
        let x = decades(all().map(|p| p[0]));
        let x = [x[0], all().map(|p| p[0].log10()).fold(x[0] + 0.5, f64::max)];
        (x, decades(all().map(|p| p[1])))
    }

    /// Every text the chart draws (for the font-coverage test).
    #[cfg(test)]
    pub(crate) fn texts(&self) -> Vec<String> {
        let (x, y) = self.ranges();
        let mut t = vec![
            self.title.clone(),
            self.x_label.clone(),
            self.y_label.clone(),
        ];
        t.extend(self.curves.iter().map(|c| c.label.clone()));
        t.extend(self.reference_slopes.iter().map(|s| format!("{s}")));
        for range in [x, y] {
            let mut e = range[0];
            while e <= range[1] {
                t.push(power_label(e));
                e += 1.0;
            }
        }
        t
    }

    pub(crate) fn render(&self, width: u32, height: u32) -> Canvas {
        let mut canvas = Canvas::new(width, height, WHITE);
        let (x_range, y_range) = self.ranges();
        let (_, line_height) = Canvas::text_size("0", TEXT);
        let legend_width = self
            .curves
            .iter()
            .map(|c| 32 + Canvas::text_size(&c.label, TEXT).0)
            .max()
            .unwrap_or(0);
        let y_tick_width = Canvas::text_size(&power_label(y_range[0]), TEXT).0;
        let plot = Rect {
            x0: 12 + line_height + 10 + y_tick_width + 8,
            y0: 12 + line_height + 14,
            x1: i64::from(width) - 24 - legend_width - 16,
            y1: i64::from(height) - (12 + 2 * line_height + 16),
        };
        let map = |p: [f64; 2]| {
            let tx = (p[0].log10() - x_range[0]) / (x_range[1] - x_range[0]);
            let ty = (p[1].log10() - y_range[0]) / (y_range[1] - y_range[0]);
            [
                f64_of(plot.x0) + tx * f64_of(plot.x1 - plot.x0),
                f64_of(plot.y1) - ty * f64_of(plot.y1 - plot.y0),
            ]
        };

        // Decades: grid lines, ticks and labels (every other y decade when
        // there are many).
        let mut e = x_range[0];
        while e <= x_range[1] {
            let px = floor_i64(map([10_f64.powf(e), 1.0])[0]);
            canvas.vline(px, plot.y0, plot.y1 - 1, GRID_GREY, 1.0, 0);
            canvas.vline(px, plot.y1, plot.y1 + 4, BLACK, 1.0, 0);
            let label = power_label(e);
            let (w, _) = Canvas::text_size(&label, TEXT);
            canvas.text(px - w / 2, plot.y1 + 8, &label, TEXT, BLACK);
            e += 1.0;
        }
        let every = if y_range[1] - y_range[0] > 8.0 {
            2.0
        } else {
            1.0
        };
        let mut e = y_range[0];
        while e <= y_range[1] {
            let py = floor_i64(map([1.0, 10_f64.powf(e)])[1]);
            canvas.hline(py, plot.x0, plot.x1 - 1, GRID_GREY, 1.0, 0);
            canvas.hline(py, plot.x0 - 5, plot.x0 - 1, BLACK, 1.0, 0);
            if (e - y_range[0]) % every == 0.0 {
                let label = power_label(e);
                let (w, h) = Canvas::text_size(&label, TEXT);
                canvas.text(plot.x0 - 8 - w, py - h / 2, &label, TEXT, BLACK);
            }
            e += 1.0;
        }

        // Reference lines y = anchor_y (x / anchor_x)^slope, dashed (every
        // other of 40 pieces, even in log x), named where they leave the plot.
        let x_end = 10_f64.powf(x_range[1]);
        let y_floor = 10_f64.powf(y_range[0]);
        for &slope in &self.reference_slopes {
            let [ax, ay] = self.anchor;
            let at = |x: f64| [x, ay * (x / ax).powf(slope)];
            // Where the line meets the bottom of the plot, or its right side.
            let last = (ax * (y_floor / ay).powf(1.0 / slope)).min(x_end);
            let (l0, l1) = (ax.log10(), last.log10());
            for piece in (0..40).step_by(2) {
                let from = 10_f64.powf(l0 + (l1 - l0) * f64::from(piece) / 40.0);
                let to = 10_f64.powf(l0 + (l1 - l0) * f64::from(piece + 1) / 40.0);
                canvas.line(map(at(from)), map(at(to)), 1.0, REFERENCE_GREY, plot);
            }
            let [px, py] = map(at(last));
            let label = format!("{slope}");
            let (w, h) = Canvas::text_size(&label, TEXT);
            let lx = floor_i64(px).min(plot.x1 - w - 2) - w / 2;
            let ly = (floor_i64(py) - h - 4).clamp(plot.y0 + 2, plot.y1 - h - 2);
            canvas.text(lx.max(plot.x0 + 2), ly, &label, TEXT, REFERENCE_GREY);
        }

        for c in &self.curves {
            let points: Vec<[f64; 2]> = c
                .points
                .iter()
                .filter(|p| p[0] > 0.0 && p[1] > 0.0)
                .map(|&p| map(p))
                .collect();
            canvas.polyline(&points, 2.0, c.colour, plot);
        }
        // Title, axis labels and outline (outside the plot area).
        canvas.chart_frame(plot, [&self.title, &self.x_label, &self.y_label], TEXT);

        // The legend, right of the plot: a short line of each colour, then
        // the label.
        let mut y = plot.y0 + 4;
        let x = plot.x1 + 16;
        for c in &self.curves {
            let mid = f64_of(y + line_height / 2);
            let clip = Rect {
                x0: 0,
                y0: 0,
                x1: i64::from(width),
                y1: i64::from(height),
            };
            canvas.line([f64_of(x), mid], [f64_of(x + 22), mid], 3.0, c.colour, clip);
            canvas.text(x + 32, y, &c.label, TEXT, BLACK);
            y += line_height + 10;
        }
        let slopes: Vec<String> = self
            .reference_slopes
            .iter()
            .map(|s| format!("{s}"))
            .collect();
        canvas.text(x, y + 8, "dashed: slopes", TEXT, REFERENCE_GREY);
        canvas.text(
            x,
            y + 8 + line_height + 6,
            &slopes.join(", "),
            TEXT,
            REFERENCE_GREY,
        );
        canvas
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::font;

    #[test]
    fn decades_enclose_the_values() {
        assert_eq!(decades([0.02, 3.0].into_iter()), [-2.0, 1.0], "0.02..3");
        assert_eq!(decades([1.0].into_iter()), [0.0, 1.0], "one value");
        assert_eq!(decades([0.0, f64::NAN].into_iter()), [0.0, 1.0], "none");
        assert_eq!(power_label(-3.0), "1e-3", "small");
        assert_eq!(power_label(2.0), "100", "hundred");
    }

    #[test]
    fn chart_draws_curves_inside_the_frame() {
        let red = [255, 0, 0];
        let chart = LogLogChart {
            title: "disk".into(),
            x_label: "N".into(),
            y_label: "MSE".into(),
            curves: vec![Curve {
                label: "independent -1.00".into(),
                points: (1..=100)
                    .map(|n| [f64::from(n), 0.1 / f64::from(n)])
                    .collect(),
                colour: red,
            }],
            reference_slopes: vec![-1.0, -1.5, -2.0],
            anchor: [1.0, 0.1],
        };
        let c = chart.render(800, 480);
        assert!(
            chart.texts().iter().all(|t| font::covers(t)),
            "{:?}",
            chart.texts()
        );
        let red_pixels = (0..800_i64)
            .flat_map(|x| (0..480_i64).map(move |y| (x, y)))
            .filter(|&(x, y)| c.get(x, y) == Some(red))
            .count();
        assert!(red_pixels > 300, "the curve is drawn: {red_pixels} pixels");
        // Falling curve: red near the top left, and near the bottom right.
        let column_of_red = |x: i64| (0..480).find(|&y| c.get(x, y) == Some(red));
        let (left, right) = (column_of_red(120), column_of_red(500));
        assert!(
            matches!((left, right), (Some(l), Some(r)) if l < r),
            "{left:?} {right:?}"
        );
    }
}
