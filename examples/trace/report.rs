//! What the study shows: the markdown tables, the JSON, a PNG per render
//! and a montage per scene laid out like the paper's figures.

use crate::canvas::{BLACK, Canvas, Rect, Rgb, WHITE, channel, floor_i64};
use crate::common::Failure;
use crate::render::Image;
use crate::study::{Reference, Row};
use std::fmt::Write as _;
use std::path::Path;

/// The markdown table of the results, with the RMSE at equal time: the
/// RMSE a sampler would reach in the time `independent` takes at the same
/// count, assuming its MSE falls as 1/time from where it was measured;
/// the RMSE after a Gaussian blur of σ = 1 and 2 pixels (σ2's spread over
/// seeds beside it); and the error's low-frequency power over white
/// noise's ("low f": 1 for white noise, below 1 for blue; its spread
/// over seeds beside it).
pub(crate) fn table(rows: &[Row]) -> String {
    let mut out = String::from(
        "| scene | sampler | spp | RMSE | ± sd | bias² | variance | blur σ1 | blur σ2 | ± sd | low f | ± sd | samples/pixel | sample s | render s | RMSE at equal time |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for row in rows {
        let independent = rows
            .iter()
            .find(|r| r.scene == row.scene && r.spp == row.spp && r.sampler == "independent");
        let e = row.errors;
        let num = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.3e}"));
        let equal_time = e
            .zip(independent)
            .map(|(e, ind)| e.rmse * (row.render_seconds / ind.render_seconds).sqrt());
        let [lo, hi] = row.samples_per_pixel;
        let counts = if lo == hi {
            format!("{lo}")
        } else {
            format!("{lo}–{hi}")
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {counts} | {:.3} | {:.3} | {} |",
            row.scene,
            row.sampler,
            row.spp,
            num(e.map(|e| e.rmse)),
            num(e.map(|e| e.rmse_sd)),
            num(e.map(|e| e.bias2)),
            num(e.map(|e| e.variance)),
            num(e.map(|e| e.blurred[0].0)),
            num(e.map(|e| e.blurred[1].0)),
            num(e.map(|e| e.blurred[1].1)),
            e.and_then(|e| e.low_frequency)
                .map_or_else(|| "-".to_owned(), |v| format!("{v:.3}")),
            e.and_then(|e| e.low_frequency_sd)
                .map_or_else(|| "-".to_owned(), |v| format!("{v:.3}")),
            row.sample_seconds,
            row.render_seconds,
            num(equal_time),
        );
    }
    out
}

/// The references' table: their own RMSE, and how it compares with the
/// smallest RMSE it judges.
pub(crate) fn reference_table(references: &[(String, Reference)], rows: &[Row]) -> String {
    let mut out = String::from(
        "| scene | reference spp | reference RMSE | smallest RMSE judged | ratio | seconds |\n|---|---:|---:|---:|---:|---:|\n",
    );
    for (scene, reference) in references {
        let smallest = rows
            .iter()
            .filter(|r| &r.scene == scene)
            .filter_map(|r| r.errors.map(|e| e.rmse))
            .fold(f64::INFINITY, f64::min);
        let _ = writeln!(
            out,
            "| {scene} | {} | {:.3e} | {smallest:.3e} | {:.3} | {:.1} |",
            reference.spp,
            reference.rmse(),
            reference.rmse() / smallest,
            reference.seconds
        );
    }
    out
}

/// The results as JSON values, in the schema (one per row; errors
/// `null` without a reference).
pub(crate) fn json(rows: &[Row]) -> Vec<serde_json::Value> {
    rows.iter()
        .map(|row| {
            let e = row.errors;
            serde_json::json!({
                "scene": row.scene,
                "sampler": row.sampler,
                "spp": row.spp,
                "rmse": e.map(|e| e.rmse),
                "rmse_sd": e.map(|e| e.rmse_sd),
                "bias2": e.map(|e| e.bias2),
                "variance": e.map(|e| e.variance),
                "rmse_blur1": e.map(|e| e.blurred[0].0),
                "rmse_blur1_sd": e.map(|e| e.blurred[0].1),
                "rmse_blur2": e.map(|e| e.blurred[1].0),
                "rmse_blur2_sd": e.map(|e| e.blurred[1].1),
                "low_frequency_power": e.and_then(|e| e.low_frequency),
                "low_frequency_power_sd": e.and_then(|e| e.low_frequency_sd),
                "samples_per_pixel_min": row.samples_per_pixel[0],
                "samples_per_pixel_max": row.samples_per_pixel[1],
                "sample_seconds": row.sample_seconds,
                "render_seconds": row.render_seconds,
                "seeds": row.seeds,
            })
        })
        .collect()
}

/// Radiance to an 8-bit grey level: clamped to `[0, 1]`, with the sRGB
/// transfer curve's usual 1/2.2 power.
fn tone(v: f64) -> u8 {
    channel(255.0 * v.clamp(0.0, 1.0).powf(1.0 / 2.2))
}

/// The image as a grey canvas.
pub(crate) fn canvas(image: &Image) -> Canvas {
    let mut c = Canvas::new(image.width, image.height, BLACK);
    for (i, &v) in image.values.iter().enumerate() {
        let (x, y) = (i % image.width as usize, i / image.width as usize);
        let g = tone(v);
        c.set(x as i64, y as i64, [g, g, g]);
    }
    c
}

/// A false-colour scale from black (no error) through blue, red and yellow
/// to white (`scale` and above).
fn false_colour(error: f64, scale: f64) -> Rgb {
    const STOPS: [[f64; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [0.1, 0.1, 0.8],
        [0.85, 0.1, 0.15],
        [1.0, 0.85, 0.0],
        [1.0, 1.0, 1.0],
    ];
    let t = (error / scale).clamp(0.0, 1.0) * 4.0;
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "0..=3"
    )]
    let k = (t.floor() as usize).min(3);
    let f = t - k as f64;
    core::array::from_fn(|c| channel(255.0 * (STOPS[k][c] + f * (STOPS[k + 1][c] - STOPS[k][c]))))
}

/// The absolute error of `image` against `truth`, in false colour.
fn error_map(image: &Image, truth: &Image, scale: f64) -> Canvas {
    let mut c = Canvas::new(image.width, image.height, BLACK);
    for (i, (v, t)) in image.values.iter().zip(&truth.values).enumerate() {
        let (x, y) = (i % image.width as usize, i / image.width as usize);
        c.set(x as i64, y as i64, false_colour((v - t).abs(), scale));
    }
    c
}

/// The crop magnified in the montages: a quarter of the image's width and
/// height around `centre` (fractions of the image), scaled up four times.
fn crop(c: &Canvas, image: &Image, centre: [f64; 2]) -> Canvas {
    let (cw, ch) = ((image.width / 4).max(1), (image.height / 4).max(1));
    let x0 = (floor_i64(centre[0] * f64::from(image.width)) - i64::from(cw / 2))
        .clamp(0, i64::from(image.width - cw));
    let y0 = (floor_i64(centre[1] * f64::from(image.height)) - i64::from(ch / 2))
        .clamp(0, i64::from(image.height - ch));
    let mut out = Canvas::new(cw, ch, BLACK);
    for y in 0..i64::from(ch) {
        for x in 0..i64::from(cw) {
            out.set(x, y, c.get(x0 + x, y0 + y).unwrap_or(BLACK));
        }
    }
    out.enlarged(4)
}

/// Where each scene's crop sits: an edge, a penumbra, a defocused border,
/// the checkerboard's horizon, the moving sphere.
fn crop_centre(scene: &str) -> [f64; 2] {
    match scene {
        "figure" => [0.58, 0.72],
        "dof" => [0.3, 0.62],
        "checker" => [0.6, 0.42],
        "motion" => [0.45, 0.5],
        _ => [0.5, 0.5],
    }
}

/// One column of a montage.
pub(crate) struct Panel<'a> {
    pub(crate) label: String,
    pub(crate) caption: String,
    pub(crate) image: &'a Image,
}

/// The montage of one scene at one count, laid out like the paper's
/// figures: a column per sampler (the reference first), with the render,
/// a magnified crop and the false-colour error map (the reference's own
/// error, from its halves, under the reference), at most six columns a
/// row.
pub(crate) fn montage(
    scene: &str,
    spp: u32,
    reference: &Reference,
    panels: &[Panel<'_>],
) -> Canvas {
    const PER_ROW: usize = 6;
    const GAP: u32 = 8;
    const TEXT: u32 = 12;
    let (w, h) = (reference.image.width, reference.image.height);
    let cell_w = (w / 4).max(1) * 4;
    let cell_h = (h / 4).max(1) * 4;
    let column_h = TEXT + h + GAP + cell_h + GAP + h + TEXT + GAP;
    let total = panels.len() + 1;
    let rows = total.div_ceil(PER_ROW);
    let columns = total.min(PER_ROW);
    let width = GAP + u32::try_from(columns).unwrap_or(1) * (w.max(cell_w) + GAP);
    let height = 3 * TEXT + u32::try_from(rows).unwrap_or(1) * column_h;
    let mut out = Canvas::new(width, height, WHITE);
    out.text(
        i64::from(GAP),
        4,
        &format!("{scene}, {spp} samples per pixel. Crop magnified 4x. |error| from 0 (black) to 3x the median RMSE (white)"),
        1,
        BLACK,
    );
    // One error scale for the whole montage.
    let mut rmses: Vec<f64> = panels
        .iter()
        .map(|p| rms_difference(p.image, &reference.image))
        .collect();
    rmses.sort_by(f64::total_cmp);
    let scale = 3.0 * rmses.get(rmses.len() / 2).copied().unwrap_or(1.0).max(1e-6);
    let own = Image {
        values: reference
            .own_squared_error
            .iter()
            .map(|e| e.sqrt())
            .collect(),
        ..reference.image.clone()
    };
    let zero = Image {
        values: vec![0.0; own.values.len()],
        ..own.clone()
    };
    let reference_panel = Panel {
        label: format!("reference {}", reference.spp),
        caption: format!("own rmse {:.1e}", reference.rmse()),
        image: &reference.image,
    };
    let centre = crop_centre(scene);
    for (k, panel) in std::iter::once(&reference_panel).chain(panels).enumerate() {
        let col = i64::try_from(k % PER_ROW).unwrap_or(0);
        let row = i64::try_from(k / PER_ROW).unwrap_or(0);
        let x = i64::from(GAP) + col * i64::from(w.max(cell_w) + GAP);
        let mut y = i64::from(3 * TEXT) + row * i64::from(column_h);
        out.text(x, y, &panel.label, 1, BLACK);
        y += i64::from(TEXT);
        let picture = canvas(panel.image);
        paste(&mut out, &picture, [w, h], x, y);
        y += i64::from(h + GAP);
        let magnified = crop(&picture, panel.image, centre);
        paste(&mut out, &magnified, [cell_w, cell_h], x, y);
        y += i64::from(cell_h + GAP);
        let errors = if k == 0 {
            error_map(&own, &zero, scale)
        } else {
            error_map(panel.image, &reference.image, scale)
        };
        paste(&mut out, &errors, [w, h], x, y);
        y += i64::from(h) + 2;
        out.text(x, y, &panel.caption, 1, BLACK);
    }
    out
}

/// The root mean squared difference of two images.
fn rms_difference(a: &Image, b: &Image) -> f64 {
    let squared: Vec<f64> = a
        .values
        .iter()
        .zip(&b.values)
        .map(|(x, y)| (x - y).powi(2))
        .collect();
    crate::study::mean(&squared).sqrt()
}

/// Copies `picture` (`size` pixels) onto `out` with its top-left corner at
/// `(x, y)`, framed in grey.
fn paste(out: &mut Canvas, picture: &Canvas, size: [u32; 2], x: i64, y: i64) {
    let [w, h] = size.map(i64::from);
    for v in 0..h {
        for u in 0..w {
            out.set(x + u, y + v, picture.get(u, v).unwrap_or(BLACK));
        }
    }
    let frame = Rect {
        x0: x - 1,
        y0: y - 1,
        x1: x + w + 1,
        y1: y + h + 1,
    };
    out.outline(frame, [160, 160, 160]);
}

/// Writes `canvas` to `path`.
///
/// # Errors
/// [`Failure::Io`] if writing fails.
pub(crate) fn save(canvas: &Canvas, path: &Path) -> Result<(), Failure> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| Failure::Io(format!("creating {}: {e}", parent.display())))?;
    }
    canvas
        .save(path)
        .map_err(|e| Failure::Io(format!("writing {}: {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::Errors;

    /// The table's rows have as many cells as its header, and the JSON
    /// carries the blurred RMSE and the low-frequency power.
    #[test]
    fn table_and_json_carry_the_new_metrics() {
        let row = Row {
            scene: "checker".to_owned(),
            sampler: "zsobol".to_owned(),
            spp: 16,
            errors: Some(Errors {
                rmse: 0.03,
                rmse_sd: 0.001,
                bias2: 0.0,
                variance: 0.0009,
                blurred: [(0.009, 0.0005), (0.004, 0.0003)],
                low_frequency: Some(0.8),
                low_frequency_sd: Some(0.1),
            }),
            samples_per_pixel: [16, 16],
            sample_seconds: 0.1,
            render_seconds: 0.2,
            seeds: 4,
        };
        let text = table(std::slice::from_ref(&row));
        let cells: Vec<usize> = text.lines().map(|l| l.matches('|').count()).collect();
        assert!(cells.iter().all(|&c| c == cells[0]), "{text}");
        assert!(
            text.contains("| 9.000e-3 | 4.000e-3 | 3.000e-4 | 0.800 |"),
            "{text}"
        );
        let value = &json(&[row])[0];
        assert_eq!(value["rmse_blur1"], 0.009, "{value}");
        assert_eq!(value["rmse_blur2_sd"], 0.0003, "{value}");
        assert_eq!(value["low_frequency_power"], 0.8, "{value}");
    }

    #[test]
    fn false_colour_runs_from_black_to_white() {
        assert_eq!(false_colour(0.0, 1.0), [0, 0, 0], "no error");
        assert_eq!(false_colour(5.0, 1.0), [255, 255, 255], "saturated");
        let mid = false_colour(0.5, 1.0);
        assert!(mid[0] > 150 && mid[2] < 100, "red in the middle: {mid:?}");
        assert_eq!(tone(0.0), 0, "black");
        assert_eq!(tone(1.0), 255, "white");
        assert_eq!(tone(2.0), 255, "clamped");
    }
}
