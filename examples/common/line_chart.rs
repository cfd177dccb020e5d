//! A line chart with labelled axes, ticks and dashed reference lines, on
//! the plot example's `Canvas` (`plot/canvas.rs`): used by `plot` and by
//! `stream`'s trade-off chart. An example that uses it includes
//! `plot/canvas.rs` as `canvas`, `plot/font.rs` as `font` and this file as
//! `line_chart`, each with `#[path]`.

use crate::canvas::{BLACK, Canvas, Rect, Rgb, WHITE, f64_of, floor_i64};

const GRID_GREY: Rgb = [225, 225, 225];
/// Text scale of labels: 5×7 glyphs drawn 10×14.
const TEXT: u32 = 2;

/// One curve of a chart.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Series {
    pub(crate) points: Vec<[f64; 2]>,
    pub(crate) colour: Rgb,
}

/// A dashed reference line of a chart, named in the legend.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Reference {
    /// Horizontal (`y = at`) or vertical (`x = at`).
    pub(crate) horizontal: bool,
    pub(crate) at: f64,
    pub(crate) label: String,
    pub(crate) colour: Rgb,
}

/// A line chart with a title, labelled axes with ticks, and reference
/// lines.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct LineChart {
    pub(crate) title: String,
    pub(crate) x_label: String,
    pub(crate) y_label: String,
    pub(crate) x_range: [f64; 2],
    pub(crate) y_range: [f64; 2],
    pub(crate) series: Vec<Series>,
    pub(crate) references: Vec<Reference>,
}

impl LineChart {
    /// Every text the chart draws (for the font-coverage test).
    #[cfg(test)]
    pub(crate) fn texts(&self) -> Vec<String> {
        let mut t = vec![
            self.title.clone(),
            self.x_label.clone(),
            self.y_label.clone(),
        ];
        t.extend(self.references.iter().map(|r| r.label.clone()));
        for range in [self.x_range, self.y_range] {
            let (ticks, decimals) = ticks(range);
            t.extend(ticks.iter().map(|&v| tick_label(v, decimals)));
        }
        t
    }

    pub(crate) fn render(&self, width: u32, height: u32) -> Canvas {
        let mut canvas = Canvas::new(width, height, WHITE);
        let (_, line_height) = Canvas::text_size("0", TEXT);
        let (x_ticks, x_decimals) = ticks(self.x_range);
        let (y_ticks, y_decimals) = ticks(self.y_range);
        let y_tick_width = y_ticks
            .iter()
            .map(|&v| Canvas::text_size(&tick_label(v, y_decimals), TEXT).0)
            .max()
            .unwrap_or(0);
        // A legend row under the title when there are reference lines.
        let legend_row = if self.references.is_empty() {
            0
        } else {
            line_height + 10
        };
        let plot = Rect {
            x0: 12 + line_height + 10 + y_tick_width + 8,
            y0: 12 + line_height + 14 + legend_row,
            x1: i64::from(width) - 24,
            y1: i64::from(height) - (12 + 2 * line_height + 16),
        };
        let map_x = |x: f64| {
            f64_of(plot.x0)
                + (x - self.x_range[0]) / (self.x_range[1] - self.x_range[0])
                    * f64_of(plot.x1 - plot.x0)
        };
        let map_y = |y: f64| {
            f64_of(plot.y1)
                - (y - self.y_range[0]) / (self.y_range[1] - self.y_range[0])
                    * f64_of(plot.y1 - plot.y0)
        };

        // Grid lines and ticks with their labels.
        for &x in &x_ticks {
            let px = floor_i64(map_x(x));
            canvas.vline(px, plot.y0, plot.y1 - 1, GRID_GREY, 1.0, 0);
            canvas.vline(px, plot.y1, plot.y1 + 4, BLACK, 1.0, 0);
            let label = tick_label(x, x_decimals);
            let (w, _) = Canvas::text_size(&label, TEXT);
            canvas.text(px - w / 2, plot.y1 + 8, &label, TEXT, BLACK);
        }
        for &y in &y_ticks {
            let py = floor_i64(map_y(y));
            canvas.hline(py, plot.x0, plot.x1 - 1, GRID_GREY, 1.0, 0);
            canvas.hline(py, plot.x0 - 5, plot.x0 - 1, BLACK, 1.0, 0);
            let label = tick_label(y, y_decimals);
            let (w, h) = Canvas::text_size(&label, TEXT);
            canvas.text(plot.x0 - 8 - w, py - h / 2, &label, TEXT, BLACK);
        }
        // Reference lines, dashed, named in a legend row under the title:
        // a short sample of each line, then its name.
        const SAMPLE: i64 = 24;
        let entries: Vec<i64> = self
            .references
            .iter()
            .map(|r| SAMPLE + 8 + Canvas::text_size(&r.label, TEXT).0)
            .collect();
        let legend_width = entries.iter().sum::<i64>() + 24 * (entries.len() as i64 - 1).max(0);
        let mut x = (plot.x0 + plot.x1 - legend_width) / 2;
        let y = 12 + line_height + 8;
        for (r, width) in self.references.iter().zip(entries) {
            if r.horizontal {
                let py = floor_i64(map_y(r.at));
                canvas.hline(py, plot.x0, plot.x1 - 1, r.colour, 1.0, 6);
                canvas.hline(y + line_height / 2, x, x + SAMPLE - 1, r.colour, 1.0, 6);
            } else {
                let px = floor_i64(map_x(r.at));
                canvas.vline(px, plot.y0, plot.y1 - 1, r.colour, 1.0, 6);
                canvas.vline(x + SAMPLE / 2, y - 2, y + line_height + 1, r.colour, 1.0, 4);
            }
            canvas.text(x + SAMPLE + 8, y, &r.label, TEXT, r.colour);
            x += width + 24;
        }
        // The curves, clipped to the plot area.
        for s in &self.series {
            let points: Vec<[f64; 2]> = s
                .points
                .iter()
                .map(|p| [map_x(p[0]), map_y(p[1])])
                .collect();
            canvas.polyline(&points, 2.0, s.colour, plot);
        }
        // Title, axis labels and outline (outside the plot area, so drawn
        // last without covering anything).
        canvas.chart_frame(plot, [&self.title, &self.x_label, &self.y_label], TEXT);
        canvas
    }
}

/// Round tick values inside `range` (4 to 9 of them) and the decimals
/// their labels need.
pub(crate) fn ticks(range: [f64; 2]) -> (Vec<f64>, usize) {
    let span = range[1] - range[0];
    if !(span > 0.0 && span.is_finite()) {
        return (Vec::new(), 0);
    }
    let raw = span / 8.0;
    let magnitude = 10_f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * magnitude)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * magnitude);
    let decimals = (-step.log10().floor()).max(0.0);
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a small whole number, at least 0"
    )]
    let decimals = decimals.min(12.0) as usize;
    let mut ticks = Vec::new();
    let mut k = (range[0] / step).ceil();
    while k * step <= range[1] + 1e-9 * span && ticks.len() < 100 {
        ticks.push(k * step);
        k += 1.0;
    }
    (ticks, decimals)
}

/// A tick value with `decimals` decimals, never "-0".
pub(crate) fn tick_label(v: f64, decimals: usize) -> String {
    let text = format!("{v:.decimals$}");
    if text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        text.trim_start_matches('-').to_owned()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::font;

    #[test]
    fn ticks_are_round() {
        assert_eq!(
            ticks([0.0, 128.0]),
            (vec![0.0, 20.0, 40.0, 60.0, 80.0, 100.0, 120.0], 0),
            "0..128"
        );
        let (t, d) = ticks([-20.0, 10.0]);
        assert_eq!(t, vec![-20.0, -15.0, -10.0, -5.0, 0.0, 5.0, 10.0], "dB");
        assert_eq!(d, 0, "whole dB");
        let (t, d) = ticks([0.0, 1.0]);
        assert_eq!((t.len(), d), (6, 1), "0, 0.2, .., 1.0");
        assert_eq!(ticks([1.0, 1.0]), (Vec::new(), 0), "empty range");
        assert_eq!(tick_label(-0.0, 1), "0.0", "no negative zero");
        assert_eq!(tick_label(-1e-17, 0), "0", "rounds to zero");
        assert_eq!(tick_label(-2.5, 1), "-2.5", "negative");
    }

    #[test]
    fn chart_draws_its_curve_inside_the_axes() {
        let chart = LineChart {
            title: "Test".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            x_range: [0.0, 10.0],
            y_range: [0.0, 1.0],
            series: vec![Series {
                points: vec![[0.0, 0.5], [10.0, 0.5]],
                colour: [255, 0, 0],
            }],
            references: vec![Reference {
                horizontal: true,
                at: 0.25,
                label: "ref".into(),
                colour: [90, 90, 90],
            }],
        };
        let c = chart.render(400, 300);
        assert_eq!((c.width(), c.height()), (400, 300), "size");
        let red_rows: Vec<i64> = (0..300)
            .filter(|&y| c.get(200, y) == Some([255, 0, 0]))
            .collect();
        assert!(!red_rows.is_empty(), "the curve crosses the middle column");
        let mid = red_rows[red_rows.len() / 2];
        assert!((100..200).contains(&mid), "y = 0.5 near the middle: {mid}");
        assert!(
            chart.texts().iter().all(|t| font::covers(t)),
            "{:?}",
            chart.texts()
        );
    }
}
