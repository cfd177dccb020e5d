//! Draws a set whose radius varies (`PoissonDisk::iter_varying`) as a PNG:
//! black dots on white, all of one size (0.4·r_min), so that the density
//! shows as darkness. docs/quality.md's
//! pictures, from the repository root:
//!
//! ```text
//! cargo run --release --example varying -- gradient --out docs/images/varying-gradient.png
//! cargo run --release --example varying -- source --out docs/images/varying-source.png
//! cargo run --release --example varying -- image --image docs/images/varying-source.png \
//!     --out docs/images/varying-image.png
//! ```
//!
//! `source` draws the small grey picture `image` reads (made here, so its
//! licence is the crate's): the word "bridson" on a radial gradient.

#[allow(dead_code, reason = "shared with `plot`, which uses all of it")]
#[path = "plot/canvas.rs"]
mod canvas;
#[path = "common/mod.rs"]
mod common;
#[path = "plot/font.rs"]
mod font;

use bridson::{Domain, PoissonDisk2};
use canvas::{BLACK, Canvas, WHITE, channel};
use clap::{Parser, ValueEnum};
use common::{Failure, report};
use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The command line.
#[derive(Debug, Parser)]
#[command(
    name = "varying",
    about = "Draws a varying-radius Poisson disk set as a PNG: a linear \
             gradient of radius, or a radius following an image's brightness \
             (dark is dense)"
)]
struct Args {
    /// What to draw
    #[arg(value_enum)]
    what: What,
    /// The PNG to write
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// With `image`: the picture (8-bit grey or RGB PNG) whose brightness
    /// sets the radius
    #[arg(long, value_name = "FILE", required_if_eq("what", "image"))]
    image: Option<PathBuf>,
    /// Smallest radius, in units of the box's height
    #[arg(long, value_name = "R", default_value_t = 0.008)]
    r_min: f64,
    /// Largest radius, in units of the box's height
    #[arg(long, value_name = "R", default_value_t = 0.032)]
    r_max: f64,
    /// Height of the picture in pixels
    #[arg(long, value_name = "PX", default_value_t = 300)]
    height: u32,
    /// Seed
    #[arg(long, value_name = "S", default_value_t = 1)]
    seed: u64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum What {
    /// The radius grows linearly from left to right, r_min to r_max
    Gradient,
    /// The radius follows --image's brightness, r_min where black
    Image,
    /// The source picture for `image`
    Source,
}

/// A radius field over the plane.
type Field = dyn Fn(&[f64; 2]) -> f64;

fn main() -> ExitCode {
    let args = Args::parse();
    common::finish("varying", run(&args))
}

fn run(args: &Args) -> Result<(), Failure> {
    if args.what == What::Source {
        return save(&source(), &args.out);
    }
    let (width, field): (f64, Box<Field>) = match &args.image {
        Some(path) if args.what == What::Image => {
            let image = Grey::read(path)?;
            let width = f64::from(image.width) / f64::from(image.height);
            let (r_min, r_max) = (args.r_min, args.r_max);
            (
                width,
                Box::new(move |p| r_min + (r_max - r_min) * image.at(p[0] / width, p[1])),
            )
        }
        _ => {
            let (r_min, r_max, width) = (args.r_min, args.r_max, 2.0);
            (
                width,
                Box::new(move |p| r_min + (r_max - r_min) * p[0] / width),
            )
        }
    };
    let domain = Domain::from_extent([width, 1.0]).map_err(|e| Failure::Usage(e.to_string()))?;
    let sampler =
        PoissonDisk2::new(domain, args.r_max).map_err(|e| Failure::Usage(e.to_string()))?;
    let points: Vec<[f64; 2]> = sampler
        .iter_varying_seeded(args.seed, args.r_min, &field)
        .map_err(|e| Failure::Usage(e.to_string()))?
        .collect();
    let scale = f64::from(args.height);
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a picture a few thousand pixels wide"
    )]
    let mut canvas = Canvas::new((width * scale).round() as u32, args.height, WHITE);
    // One dot size: the density shows as darkness.
    let dot = 0.4 * args.r_min * scale;
    for p in &points {
        canvas.disc(p[0] * scale, p[1] * scale, dot, BLACK);
    }
    save(&canvas, &args.out)?;
    report(&format!(
        "varying: {} points, radius {} to {}, written to {}",
        points.len(),
        args.r_min,
        args.r_max,
        args.out.display()
    ));
    Ok(())
}

fn save(canvas: &Canvas, path: &Path) -> Result<(), Failure> {
    canvas
        .save(path)
        .map_err(|e| Failure::Io(format!("cannot write '{}': {e}", path.display())))
}

/// The source picture: the word "bridson" in black on a grey radial
/// gradient, light at the corners, 200 × 100 pixels.
fn source() -> Canvas {
    let (w, h) = (200_i64, 100_i64);
    let mut canvas = Canvas::new(200, 100, WHITE);
    for y in 0..h {
        for x in 0..w {
            let dx = (x as f64 + 0.5) / w as f64 - 0.5;
            let dy = (y as f64 + 0.5) / h as f64 - 0.5;
            let t = (4.0 * (dx * dx + dy * dy)).sqrt().min(1.0);
            let v = channel(255.0 * (0.35 + 0.65 * t));
            canvas.set(x, y, [v; 3]);
        }
    }
    let text = "bridson";
    let scale = 4;
    let (tw, th) = Canvas::text_size(text, scale);
    canvas.text((w - tw) / 2, (h - th) / 2, text, scale, BLACK);
    canvas
}

/// An 8-bit picture's brightness, `0.0` black to `1.0` white.
struct Grey {
    width: u32,
    height: u32,
    values: Vec<f64>,
}

impl Grey {
    /// Reads an 8-bit grey or RGB PNG (alpha ignored).
    fn read(path: &Path) -> Result<Self, Failure> {
        let fail = |e: &dyn std::fmt::Display| {
            Failure::Io(format!("cannot read '{}': {e}", path.display()))
        };
        let file = File::open(path).map_err(|e| fail(&e))?;
        let mut decoder = png::Decoder::new(BufReader::new(file));
        decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = decoder.read_info().map_err(|e| fail(&e))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| fail(&"picture too large"))?;
        let mut buffer = vec![0; size];
        let info = reader.next_frame(&mut buffer).map_err(|e| fail(&e))?;
        let channels = info.color_type.samples();
        let values = buffer
            .get(..info.buffer_size())
            .unwrap_or_default()
            .chunks(channels)
            .map(|px| {
                // Grey (and alpha), or RGB (and alpha): the colour channels'
                // mean.
                let colour = if channels >= 3 { &px[..3] } else { &px[..1] };
                colour.iter().map(|&c| f64::from(c)).sum::<f64>() / (255.0 * colour.len() as f64)
            })
            .collect();
        Ok(Self {
            width: info.width,
            height: info.height,
            values,
        })
    }

    /// The brightness at `(u, v)` in `[0, 1)²` of the picture (v down),
    /// the nearest pixel's.
    fn at(&self, u: f64, v: f64) -> f64 {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to the picture"
        )]
        let (x, y) = (
            ((u * f64::from(self.width)) as u32).min(self.width - 1),
            ((v * f64::from(self.height)) as u32).min(self.height - 1),
        );
        let i = y as usize * self.width as usize + x as usize;
        self.values.get(i).copied().unwrap_or(1.0)
    }
}
