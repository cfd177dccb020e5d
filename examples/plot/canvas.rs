//! An RGB raster to draw on — discs, lines, rectangles and bitmap text,
//! with anti-aliased edges where it matters — and its PNG encoding.

use crate::font;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// An sRGB colour.
pub(crate) type Rgb = [u8; 3];

pub(crate) const WHITE: Rgb = [255, 255, 255];
pub(crate) const BLACK: Rgb = [0, 0, 0];

/// A rectangle of pixels: `x0 <= x < x1`, `y0 <= y < y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Rect {
    pub(crate) x0: i64,
    pub(crate) y0: i64,
    pub(crate) x1: i64,
    pub(crate) y1: i64,
}

/// An image, row-major from the top-left corner, in 8-bit RGB.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Canvas {
    width: u32,
    height: u32,
    pixels: Vec<Rgb>,
}

impl Canvas {
    /// A `width × height` canvas filled with `background`.
    pub(crate) fn new(width: u32, height: u32, background: Rgb) -> Self {
        let len = usize::try_from(u64::from(width) * u64::from(height))
            .expect("image size fits in memory");
        Self {
            width,
            height,
            pixels: vec![background; len],
        }
    }

    #[cfg(test)]
    pub(crate) fn width(&self) -> u32 {
        self.width
    }

    #[cfg(test)]
    pub(crate) fn height(&self) -> u32 {
        self.height
    }

    /// The whole canvas as a rectangle.
    #[cfg(test)]
    pub(crate) fn bounds(&self) -> Rect {
        Rect {
            x0: 0,
            y0: 0,
            x1: i64::from(self.width),
            y1: i64::from(self.height),
        }
    }

    fn index(&self, x: i64, y: i64) -> Option<usize> {
        let x = u32::try_from(x).ok().filter(|&x| x < self.width)?;
        let y = u32::try_from(y).ok().filter(|&y| y < self.height)?;
        usize::try_from(u64::from(y) * u64::from(self.width) + u64::from(x)).ok()
    }

    /// The colour at `(x, y)`, `None` outside.
    pub(crate) fn get(&self, x: i64, y: i64) -> Option<Rgb> {
        self.index(x, y).map(|i| self.pixels[i])
    }

    /// Paints one pixel; ignored outside the canvas.
    pub(crate) fn set(&mut self, x: i64, y: i64, colour: Rgb) {
        if let Some(i) = self.index(x, y) {
            self.pixels[i] = colour;
        }
    }

    /// Mixes `colour` into one pixel with weight `alpha` (0 to 1).
    pub(crate) fn blend(&mut self, x: i64, y: i64, colour: Rgb, alpha: f64) {
        if alpha.is_nan() || alpha <= 0.0 {
            return;
        }
        let alpha = alpha.min(1.0);
        if let Some(i) = self.index(x, y) {
            let old = self.pixels[i];
            self.pixels[i] = core::array::from_fn(|c| {
                let mixed = f64::from(old[c]) + alpha * (f64::from(colour[c]) - f64::from(old[c]));
                channel(mixed)
            });
        }
    }

    /// Fills `rect` (clipped to the canvas).
    pub(crate) fn fill(&mut self, rect: Rect, colour: Rgb) {
        for y in rect.y0.max(0)..rect.y1.min(i64::from(self.height)) {
            for x in rect.x0.max(0)..rect.x1.min(i64::from(self.width)) {
                self.set(x, y, colour);
            }
        }
    }

    /// A disc centred at `(cx, cy)` (pixel centres sit at half-integers)
    /// with an anti-aliased rim.
    pub(crate) fn disc(&mut self, cx: f64, cy: f64, radius: f64, colour: Rgb) {
        let reach = radius + 1.0;
        let (x0, x1) = (floor_i64(cx - reach), floor_i64(cx + reach));
        let (y0, y1) = (floor_i64(cy - reach), floor_i64(cy + reach));
        for y in y0..=y1 {
            for x in x0..=x1 {
                let dx = f64_of(x) + 0.5 - cx;
                let dy = f64_of(y) + 0.5 - cy;
                let d = (dx * dx + dy * dy).sqrt();
                self.blend(x, y, colour, radius + 0.5 - d);
            }
        }
    }

    /// A straight segment `width` pixels wide with anti-aliased edges, drawn
    /// only inside `clip`.
    pub(crate) fn line(
        &mut self,
        from: [f64; 2],
        to: [f64; 2],
        width: f64,
        colour: Rgb,
        clip: Rect,
    ) {
        let half = width / 2.0;
        let reach = half + 1.0;
        let x0 = floor_i64(from[0].min(to[0]) - reach).max(clip.x0);
        let x1 = floor_i64(from[0].max(to[0]) + reach).min(clip.x1 - 1);
        let y0 = floor_i64(from[1].min(to[1]) - reach).max(clip.y0);
        let y1 = floor_i64(from[1].max(to[1]) + reach).min(clip.y1 - 1);
        let (dx, dy) = (to[0] - from[0], to[1] - from[1]);
        let length_squared = dx * dx + dy * dy;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (f64_of(x) + 0.5 - from[0], f64_of(y) + 0.5 - from[1]);
                let t = if length_squared > 0.0 {
                    ((px * dx + py * dy) / length_squared).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (ex, ey) = (px - t * dx, py - t * dy);
                let d = (ex * ex + ey * ey).sqrt();
                self.blend(x, y, colour, half + 0.5 - d);
            }
        }
    }

    /// A polyline through `points` (see [`Canvas::line`]); non-finite
    /// points break it.
    pub(crate) fn polyline(&mut self, points: &[[f64; 2]], width: f64, colour: Rgb, clip: Rect) {
        for pair in points.windows(2) {
            if pair.iter().flatten().all(|v| v.is_finite()) {
                self.line(pair[0], pair[1], width, colour, clip);
            }
        }
    }

    /// A one-pixel horizontal line in row `y` from `x0` to `x1` (inclusive),
    /// blended with `alpha`; `dash` > 0 draws `dash` pixels on, `dash` off.
    pub(crate) fn hline(&mut self, y: i64, x0: i64, x1: i64, colour: Rgb, alpha: f64, dash: i64) {
        for x in x0..=x1 {
            if dash <= 0 || (x - x0).rem_euclid(2 * dash) < dash {
                self.blend(x, y, colour, alpha);
            }
        }
    }

    /// A one-pixel vertical line in column `x` (see [`Canvas::hline`]).
    pub(crate) fn vline(&mut self, x: i64, y0: i64, y1: i64, colour: Rgb, alpha: f64, dash: i64) {
        for y in y0..=y1 {
            if dash <= 0 || (y - y0).rem_euclid(2 * dash) < dash {
                self.blend(x, y, colour, alpha);
            }
        }
    }

    /// The outline of `rect`, one pixel wide, on its inside.
    pub(crate) fn outline(&mut self, rect: Rect, colour: Rgb) {
        self.hline(rect.y0, rect.x0, rect.x1 - 1, colour, 1.0, 0);
        self.hline(rect.y1 - 1, rect.x0, rect.x1 - 1, colour, 1.0, 0);
        self.vline(rect.x0, rect.y0, rect.y1 - 1, colour, 1.0, 0);
        self.vline(rect.x1 - 1, rect.y0, rect.y1 - 1, colour, 1.0, 0);
    }

    /// A chart's frame around its plot area `plot`, in black: `title`
    /// centred 12 pixels from the top, `x_label` centred under the x tick
    /// labels (which sit 8 pixels below `plot`), `y_label` upright 12
    /// pixels from the left, and a one-pixel outline just outside `plot`.
    /// Shared by `LineChart` and the convergence study's log-log chart.
    pub(crate) fn chart_frame(
        &mut self,
        plot: Rect,
        [title, x_label, y_label]: [&str; 3],
        scale: u32,
    ) {
        let (title_width, line_height) = Self::text_size(title, scale);
        let width = i64::from(self.width);
        self.text((width - title_width) / 2, 12, title, scale, BLACK);
        let (w, _) = Self::text_size(x_label, scale);
        let y = plot.y1 + 8 + line_height + 8;
        self.text((plot.x0 + plot.x1 - w) / 2, y, x_label, scale, BLACK);
        let (w, _) = Self::text_size(y_label, scale);
        self.text_up(12, (plot.y0 + plot.y1 - w) / 2, y_label, scale, BLACK);
        self.outline(
            Rect {
                x0: plot.x0 - 1,
                y0: plot.y0 - 1,
                x1: plot.x1 + 1,
                y1: plot.y1 + 1,
            },
            BLACK,
        );
    }

    /// `text` with its top-left corner at `(x, y)`, each font pixel a
    /// `scale × scale` square.
    pub(crate) fn text(&mut self, x: i64, y: i64, text: &str, scale: u32, colour: Rgb) {
        let s = i64::from(scale);
        for (u, v) in ink(text) {
            self.fill(
                Rect {
                    x0: x + u * s,
                    y0: y + v * s,
                    x1: x + (u + 1) * s,
                    y1: y + (v + 1) * s,
                },
                colour,
            );
        }
    }

    /// `text` turned a quarter turn anticlockwise (reading bottom to top),
    /// its bounding box's top-left corner at `(x, y)`.
    pub(crate) fn text_up(&mut self, x: i64, y: i64, text: &str, scale: u32, colour: Rgb) {
        let s = i64::from(scale);
        let length = i64::from(font::text_width(text));
        // The font pixel (u, v) of the upright text lands at (v, length − 1 − u).
        for (u, v) in ink(text) {
            let (px, py) = (x + v * s, y + (length - 1 - u) * s);
            self.fill(
                Rect {
                    x0: px,
                    y0: py,
                    x1: px + s,
                    y1: py + s,
                },
                colour,
            );
        }
    }

    /// `width × height` of `text` at `scale`, in pixels.
    pub(crate) fn text_size(text: &str, scale: u32) -> (i64, i64) {
        (
            i64::from(font::text_width(text)) * i64::from(scale),
            i64::from(font::GLYPH_HEIGHT) * i64::from(scale),
        )
    }

    /// This canvas scaled up `factor` times, each pixel a block.
    pub(crate) fn enlarged(&self, factor: u32) -> Self {
        let mut out = Self::new(self.width * factor, self.height * factor, BLACK);
        let f = i64::from(factor);
        for y in 0..i64::from(self.height) {
            for x in 0..i64::from(self.width) {
                if let Some(c) = self.get(x, y) {
                    out.fill(
                        Rect {
                            x0: x * f,
                            y0: y * f,
                            x1: (x + 1) * f,
                            y1: (y + 1) * f,
                        },
                        c,
                    );
                }
            }
        }
        out
    }

    /// The PNG encoding: 8-bit RGB, or 8-bit grey when every pixel is grey
    /// (smaller files for the periodogram).
    pub(crate) fn encode_png<W: Write>(&self, out: W) -> Result<(), png::EncodingError> {
        let grey = self.pixels.iter().all(|p| p[0] == p[1] && p[1] == p[2]);
        let mut encoder = png::Encoder::new(out, self.width, self.height);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::High);
        let data: Vec<u8> = if grey {
            encoder.set_color(png::ColorType::Grayscale);
            self.pixels.iter().map(|p| p[0]).collect()
        } else {
            encoder.set_color(png::ColorType::Rgb);
            self.pixels.iter().flatten().copied().collect()
        };
        let mut writer = encoder.write_header()?;
        writer.write_image_data(&data)?;
        writer.finish()
    }

    /// Writes the PNG encoding to `path`.
    pub(crate) fn save(&self, path: &Path) -> io::Result<()> {
        let mut out = BufWriter::new(File::create(path)?);
        self.encode_png(&mut out).map_err(io::Error::other)?;
        out.flush()
    }
}

/// The inked font pixels `(u, v)` of `text` set upright at scale 1: `u`
/// from the left of the first glyph, `v` from the top.
fn ink(text: &str) -> impl Iterator<Item = (i64, i64)> + '_ {
    let advance = i64::from(font::ADVANCE);
    (0_i64..).zip(text.chars()).flat_map(move |(k, c)| {
        (0_i64..)
            .zip(font::glyph_or_box(c))
            .flat_map(move |(v, bits)| {
                (0..i64::from(font::GLYPH_WIDTH))
                    .filter(move |col| bits & (0b10000 >> col) != 0)
                    .map(move |col| (k * advance + col, v))
            })
    })
}

/// A colour channel from a value nominally in `0..=255`.
pub(crate) fn channel(value: f64) -> u8 {
    let v = value.round().clamp(0.0, 255.0);
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "rounded and clamped to 0..=255 first (NaN casts to 0)"
    )]
    let c = v as u8;
    c
}

/// `floor(v)` as an integer pixel coordinate, saturating far off-canvas.
pub(crate) fn floor_i64(v: f64) -> i64 {
    #[expect(
        clippy::cast_possible_truncation,
        reason = "float-to-int `as` saturates; values this far off-canvas are clipped anyway"
    )]
    let i = v.floor().clamp(-1e15, 1e15) as i64;
    i
}

/// A pixel coordinate as `f64` (exact: coordinates stay far below 2^53).
pub(crate) fn f64_of(v: i64) -> f64 {
    #[expect(
        clippy::cast_precision_loss,
        reason = "pixel coordinates are far below 2^53"
    )]
    let f = v as f64;
    f
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(bytes: &[u8]) -> (png::OutputInfo, Vec<u8>) {
        let mut reader = png::Decoder::new(io::Cursor::new(bytes))
            .read_info()
            .expect("valid PNG");
        let mut buf = vec![0; reader.output_buffer_size().expect("size")];
        let info = reader.next_frame(&mut buf).expect("one frame");
        buf.truncate(info.buffer_size());
        (info, buf)
    }

    #[test]
    fn png_round_trips_rgb_and_grey() {
        let mut c = Canvas::new(3, 2, WHITE);
        c.set(1, 0, [10, 20, 30]);
        let mut bytes = Vec::new();
        c.encode_png(&mut bytes).expect("encodes");
        let (info, data) = decode(&bytes);
        assert_eq!((info.width, info.height), (3, 2), "size");
        assert_eq!(info.color_type, png::ColorType::Rgb, "colour");
        assert_eq!(&data[3..6], &[10, 20, 30], "pixel (1, 0)");
        assert_eq!(data.len(), 18, "3 bytes a pixel");

        let mut g = Canvas::new(2, 2, BLACK);
        g.set(1, 1, [7, 7, 7]);
        let mut bytes = Vec::new();
        g.encode_png(&mut bytes).expect("encodes");
        let (info, data) = decode(&bytes);
        assert_eq!(info.color_type, png::ColorType::Grayscale, "grey");
        assert_eq!(data, vec![0, 0, 0, 7], "grey pixels");
    }

    #[test]
    fn text_renders_the_glyph_bits() {
        let mut c = Canvas::new(12, 7, WHITE);
        c.text(0, 0, "1-", 1, BLACK);
        // The "1" glyph: its stem is column 2 in every row but the last,
        // whose base spans columns 1..=3.
        let one = font::glyph('1').expect("glyph");
        for (y, bits) in (0_i64..).zip(one) {
            for x in 0..5 {
                let ink = bits & (0b10000 >> x) != 0;
                assert_eq!(c.get(x, y) == Some(BLACK), ink, "'1' at ({x}, {y})");
            }
        }
        // The "-" starts one advance (6 pixels) later, in row 3.
        for x in 6..11 {
            assert_eq!(c.get(x, 3), Some(BLACK), "dash at ({x}, 3)");
            assert_eq!(c.get(x, 2), Some(WHITE), "above the dash at ({x}, 2)");
        }
        assert_eq!(Canvas::text_size("1-", 2), (22, 14), "size at scale 2");
    }

    #[test]
    fn rotated_text_reads_upwards() {
        let mut c = Canvas::new(7, 5, WHITE);
        c.text_up(0, 0, "-", 1, BLACK);
        // The dash (row 3 of the glyph) becomes column 3, all five rows.
        for y in 0..5 {
            assert_eq!(c.get(3, y), Some(BLACK), "column 3, row {y}");
            assert_eq!(c.get(2, y), Some(WHITE), "column 2, row {y}");
        }
        let mut l = Canvas::new(7, 5, WHITE);
        l.text_up(0, 0, "L", 1, BLACK);
        // "L": the stem (glyph column 0) is the bottom row once turned; the
        // foot (glyph row 6) is the right column.
        for x in 0..7 {
            assert_eq!(l.get(x, 4), Some(BLACK), "stem at ({x}, 4)");
        }
        for y in 0..5 {
            assert_eq!(l.get(6, y), Some(BLACK), "foot at (6, {y})");
        }
    }

    #[test]
    fn discs_and_lines_cover_what_they_should() {
        let mut c = Canvas::new(20, 20, WHITE);
        c.disc(10.0, 10.0, 3.0, BLACK);
        assert_eq!(c.get(10, 10), Some(BLACK), "centre");
        assert_eq!(c.get(10, 15), Some(WHITE), "outside");
        let clip = c.bounds();
        c.line([0.0, 2.5], [20.0, 2.5], 1.0, BLACK, clip);
        assert_eq!(c.get(7, 2), Some(BLACK), "on the line");
        assert_eq!(c.get(7, 0), Some(WHITE), "off the line");
        c.line(
            [0.0, 18.5],
            [20.0, 18.5],
            1.0,
            BLACK,
            Rect { x1: 5, ..clip },
        );
        assert_eq!(c.get(3, 18), Some(BLACK), "inside the clip");
        assert_eq!(c.get(6, 18), Some(WHITE), "clipped");
    }

    #[test]
    fn helpers_clamp() {
        assert_eq!(channel(-3.0), 0, "below");
        assert_eq!(channel(300.0), 255, "above");
        assert_eq!(channel(f64::NAN), 0, "NaN");
        assert_eq!(floor_i64(-0.5), -1, "floor");
        assert_eq!(floor_i64(f64::INFINITY), 1_000_000_000_000_000, "saturates");
        let big = Canvas::new(2, 1, WHITE).enlarged(3);
        assert_eq!((big.width(), big.height()), (6, 3), "enlarged");
    }
}
