//! The pictures: a point plot with its overlays, the periodogram as a grey
//! image, and a heat map with a colour bar (line charts are in
//! `common/line_chart.rs`, shared with `stream`).

use crate::canvas::{BLACK, Canvas, Rect, Rgb, WHITE, channel, f64_of, floor_i64};
use crate::line_chart::tick_label;
use crate::spectrum;

const PIXEL_RED: Rgb = [210, 40, 40];
const CELL_BLUE: Rgb = [90, 140, 220];
/// Text scale of labels: 5×7 glyphs drawn 10×14.
const TEXT: u32 = 2;

/// What the point plot shows and overlays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PointView {
    /// The rectangle of the plane shown: `lo` to `hi` on axes 0 and 1.
    pub(crate) lo: [f64; 2],
    pub(crate) hi: [f64; 2],
    /// Longer side of the image in pixels.
    pub(crate) size: u32,
    /// The sampler's radius, for the dot size.
    pub(crate) radius: f64,
    /// Lines at whole coordinates: the pixel borders of a raster.
    pub(crate) pixel_grid: bool,
    /// Lines every `side` from `origin` (the domain's lower corner): the
    /// background grid (side `r/√N`).
    pub(crate) cell_grid: Option<CellGrid>,
}

/// The background grid's lines: every `side` from `origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CellGrid {
    pub(crate) side: f64,
    pub(crate) origin: [f64; 2],
}

/// The points (first two coordinates) inside the view as small discs, y
/// growing downwards as in raster coordinates, with the optional grids
/// beneath them.
pub(crate) fn point_plot(points: &[[f64; 2]], view: &PointView) -> Canvas {
    const MARGIN: f64 = 8.0;
    let extent = [view.hi[0] - view.lo[0], view.hi[1] - view.lo[1]];
    let inner = f64::from(view.size) - 2.0 * MARGIN;
    let scale = inner / extent[0].max(extent[1]);
    let pixels = |e: f64| {
        let p = (e * scale + 2.0 * MARGIN).ceil().clamp(1.0, 65_536.0);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a whole number in 1..=65536"
        )]
        let p = p as u32;
        p
    };
    let mut canvas = Canvas::new(pixels(extent[0]), pixels(extent[1]), WHITE);
    let to_image = |p: [f64; 2]| {
        [
            MARGIN + (p[0] - view.lo[0]) * scale,
            MARGIN + (p[1] - view.lo[1]) * scale,
        ]
    };
    let [x0, y0] = to_image(view.lo).map(floor_i64);
    let [x1, y1] = to_image(view.hi).map(floor_i64);
    // Lines at origin + k·step inside the view, on both axes.
    let mut grid = |step: f64, origin: [f64; 2], colour: Rgb, alpha: f64| {
        for axis in 0..2 {
            let first = ((view.lo[axis] - origin[axis]) / step).ceil();
            let last = ((view.hi[axis] - origin[axis]) / step).floor();
            let count = last - first;
            if count.is_nan() || count > 100_000.0 {
                continue;
            }
            let mut k = first;
            while k <= last {
                let mut p = view.lo;
                p[axis] = origin[axis] + k * step;
                let line = floor_i64(to_image(p)[axis]);
                if axis == 0 {
                    canvas.vline(line, y0, y1, colour, alpha, 0);
                } else {
                    canvas.hline(line, x0, x1, colour, alpha, 0);
                }
                k += 1.0;
            }
        }
    };
    if let Some(cells) = view.cell_grid.filter(|c| c.side > 0.0) {
        grid(cells.side, cells.origin, CELL_BLUE, 0.45);
    }
    if view.pixel_grid {
        grid(1.0, [0.0, 0.0], PIXEL_RED, 0.9);
    }
    canvas.outline(
        Rect {
            x0,
            y0,
            x1: x1 + 1,
            y1: y1 + 1,
        },
        [150, 150, 150],
    );
    let dot = (0.16 * view.radius * scale).clamp(1.0, 4.0);
    let inside = |p: &[f64; 2]| (0..2).all(|i| view.lo[i] <= p[i] && p[i] <= view.hi[i]);
    for p in points.iter().filter(|p| inside(p)) {
        let [x, y] = to_image(*p);
        canvas.disc(x, y, dot, BLACK);
    }
    canvas
}

/// Black at or below this power (in dB, 10·log10 P) in the periodogram
/// image, white at or above [`PERIODOGRAM_TOP_DB`]; white noise is 0 dB.
pub(crate) const PERIODOGRAM_BOTTOM_DB: f64 = -20.0;
pub(crate) const PERIODOGRAM_TOP_DB: f64 = 10.0;

/// The periodogram as a grey image, log-scaled (see
/// [`PERIODOGRAM_BOTTOM_DB`]), DC term suppressed (black), the origin in
/// the centre, `fx` to the right and `fy` down; enlarged to at least 256
/// pixels.
pub(crate) fn periodogram_image(mean: &[f64], max_freq: u32) -> Canvas {
    let side = spectrum::side(max_freq);
    let side_u32 = u32::try_from(side).expect("grid side fits u32");
    let mut canvas = Canvas::new(side_u32, side_u32, BLACK);
    for (row, values) in (0_i64..).zip(mean.chunks_exact(side)) {
        for (col, &p) in (0_i64..).zip(values) {
            let db = 10.0 * p.log10();
            let t = (db - PERIODOGRAM_BOTTOM_DB) / (PERIODOGRAM_TOP_DB - PERIODOGRAM_BOTTOM_DB);
            let g = channel(255.0 * t.clamp(0.0, 1.0));
            canvas.set(col, row, [g; 3]);
        }
    }
    let centre = i64::from(max_freq);
    canvas.set(centre, centre, BLACK);
    let factor = 256_u32.div_ceil(side_u32).max(1);
    canvas.enlarged(factor)
}

/// Blue below 1, white at 1, red above, saturating at `1 ± spread`.
fn diverging(v: f64, spread: f64) -> Rgb {
    const BLUE: Rgb = [33, 102, 172];
    const RED: Rgb = [178, 24, 43];
    let t = ((v - 1.0) / spread).clamp(-1.0, 1.0);
    if t.is_nan() {
        return [128, 128, 128];
    }
    let (end, w) = if t < 0.0 { (BLUE, -t) } else { (RED, t) };
    core::array::from_fn(|c| channel(255.0 + w * (f64::from(end[c]) - 255.0)))
}

/// The smallest of a ladder of round spreads that holds `deviation` (with
/// a little slack, so 1.1 − 1 still fits 0.1).
pub(crate) fn nice_spread(deviation: f64) -> f64 {
    [0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .find(|&s| deviation <= s * (1.0 + 1e-9))
        .unwrap_or(10.0)
}

/// A `bins × bins` map of relative densities (row-major, first row = top
/// of the pixel) in a diverging colour map centred on 1, with a titled
/// colour bar. Returns the image and the spread used (`1 ± spread`).
pub(crate) fn heat_map(relative: &[f64], bins: usize, title: &str) -> (Canvas, f64) {
    let deviation = relative
        .iter()
        .filter(|v| v.is_finite())
        .map(|v| (v - 1.0).abs())
        .fold(0.0, f64::max);
    let spread = nice_spread(deviation);
    let bins_i64 = i64::try_from(bins).expect("bins fit i64");
    let cell = (256 / bins_i64).max(1);
    let map_side = cell * bins_i64;
    let (title_width, line_height) = Canvas::text_size(title, TEXT);
    let labels = [1.0 + spread, 1.0, 1.0 - spread].map(|v| tick_label(v, 2));
    let label_width = labels
        .iter()
        .map(|l| Canvas::text_size(l, TEXT).0)
        .max()
        .unwrap_or(0);
    let map = Rect {
        x0: 12,
        y0: 12 + line_height + 12,
        x1: 12 + map_side,
        y1: 12 + line_height + 12 + map_side,
    };
    let bar = Rect {
        x0: map.x1 + 16,
        y0: map.y0,
        x1: map.x1 + 32,
        y1: map.y1,
    };
    let width = (bar.x1 + 8 + label_width + 12).max(title_width + 24);
    let height = map.y1 + 12;
    let mut canvas = Canvas::new(
        u32::try_from(width).expect("small image"),
        u32::try_from(height).expect("small image"),
        WHITE,
    );
    canvas.text(12, 12, title, TEXT, BLACK);
    for (k, &v) in (0_i64..).zip(relative) {
        let (row, col) = (k / bins_i64, k % bins_i64);
        let x0 = map.x0 + col * cell;
        let y0 = map.y0 + row * cell;
        canvas.fill(
            Rect {
                x0,
                y0,
                x1: x0 + cell,
                y1: y0 + cell,
            },
            diverging(v, spread),
        );
    }
    let bar_height = bar.y1 - bar.y0;
    for y in bar.y0..bar.y1 {
        // Top: 1 + spread; bottom: 1 - spread.
        let t = 1.0 - 2.0 * (f64_of(y - bar.y0) + 0.5) / f64_of(bar_height);
        let colour = diverging(1.0 + t * spread, spread);
        canvas.hline(y, bar.x0, bar.x1 - 1, colour, 1.0, 0);
    }
    canvas.outline(bar, BLACK);
    for (label, y) in labels.iter().zip([
        bar.y0,
        (bar.y0 + bar.y1) / 2 - line_height / 2,
        bar.y1 - line_height,
    ]) {
        canvas.text(bar.x1 + 8, y, label, TEXT, BLACK);
    }
    (canvas, spread)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::font;

    #[test]
    fn periodogram_image_maps_decibels_to_grey() {
        let max_freq = 1;
        // 3×3 grid: P = 0.01 (-20 dB, black), 1 (0 dB), 10 (+10 dB, white).
        let mean = [0.01, 1.0, 10.0, 1.0, 100.0, 1.0, 10.0, 1.0, 0.01];
        let c = periodogram_image(&mean, max_freq);
        let factor = 86; // ceil(256 / 3)
        assert_eq!(i64::from(c.width()), 3 * factor, "enlarged");
        assert_eq!(c.get(0, 0), Some(BLACK), "-20 dB is black");
        assert_eq!(c.get(2 * factor, 0), Some(WHITE), "+10 dB is white");
        assert_eq!(c.get(factor, 0), Some([170; 3]), "0 dB is 2/3 grey");
        assert_eq!(c.get(factor, factor), Some(BLACK), "DC suppressed");
    }

    #[test]
    fn heat_map_colours_around_one() {
        let (c, spread) = heat_map(&[1.0, 1.1, 0.9, 1.0], 2, "density");
        assert!((spread - 0.1).abs() < 1e-12, "spread {spread}");
        assert!(font::covers("density 1.10 0.90"), "labels");
        // Top-left bin (value 1) is white; the top-right (1.1) full red.
        let (x, y) = (12 + 10, 12 + 14 + 12 + 10);
        assert_eq!(c.get(x, y), Some(WHITE), "1.0 is white");
        assert_eq!(c.get(x + 128, y), Some([178, 24, 43]), "1.1 is red");
        assert_eq!(c.get(x, y + 128), Some([33, 102, 172]), "0.9 is blue");
    }

    #[test]
    fn point_plot_places_points_and_grids() {
        let view = PointView {
            lo: [0.0, 0.0],
            hi: [2.0, 1.0],
            size: 216,
            radius: 0.1,
            pixel_grid: true,
            cell_grid: None,
        };
        let c = point_plot(&[[0.5, 0.5]], &view);
        // 200 usable pixels for 2 units: 100 pixels a unit, 8 of margin.
        assert_eq!((c.width(), c.height()), (216, 116), "aspect kept");
        assert_eq!(c.get(58, 58), Some(BLACK), "the point at (0.5, 0.5)");
        let border = c.get(108, 30).expect("inside");
        assert!(border[0] > border[1], "pixel border at x = 1 is red");

        // A window on [1, 2] × [0, 1] with the cell grid from the origin:
        // the point at x = 0.97 is outside it (though its dot would land in
        // the margin), cell lines at x = 1.25, 1.5, ..
        let window = PointView {
            lo: [1.0, 0.0],
            hi: [2.0, 1.0],
            size: 116,
            pixel_grid: false,
            cell_grid: Some(CellGrid {
                side: 0.25,
                origin: [0.0, 0.0],
            }),
            ..view
        };
        let c = point_plot(&[[0.97, 0.5], [1.5, 0.2]], &window);
        assert_eq!((c.width(), c.height()), (116, 116), "square window");
        assert_eq!(c.get(58, 28), Some(BLACK), "the point at (1.5, 0.2)");
        assert_eq!(c.get(5, 58), Some(WHITE), "nothing at (0.97, 0.5)");
        let line = c.get(8 + 25, 90).expect("inside");
        assert!(line[2] > line[0], "cell line at x = 1.25 is blue: {line:?}");
    }
}
