//! `points --pixels WxH --camera --spp N`: a renderer's camera samples,
//! pixel by pixel in scan order, as CSV: `px,py,index,film_x,film_y,
//! lens_u,lens_v,time,d5,..`. Film positions are in raster coordinates,
//! every other value in `[0, 1)`; each pixel has exactly `N` samples.
//! Without `--stream` they come from the random-access
//! `PoissonPixelSampler` (or, with `--sampler net`, `NetPixelSampler`);
//! with it, from `CameraPixels`, whose film points
//! are a `Tiled` stream in the exact scheme (one set across pixel borders).

use crate::args::{Camera, Config, Format, Raster, SamplerArg};
use crate::common::{Failure, report};
use bridson::{
    CameraPixels, CameraSample, NetPixelSampler, PixelSampler, PoissonPixelSampler, Tiled,
};
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::time::Instant;

/// Writes the camera samples `config` asks for and prints a summary.
pub(crate) fn run(config: &Config, raster: Raster, camera: Camera) -> Result<(), Failure> {
    let start = Instant::now();
    let written = match (config.format, &config.out) {
        (Format::None, _) => write(io::sink(), false, raster, camera, config.seed),
        (_, Some(path)) => {
            let file = File::create(path)
                .map_err(|e| Failure::Io(format!("cannot create '{}': {e}", path.display())))?;
            write(BufWriter::new(file), true, raster, camera, config.seed)
        }
        (_, None) => write(
            BufWriter::new(io::stdout().lock()),
            true,
            raster,
            camera,
            config.seed,
        ),
    }?;
    let seconds = start.elapsed().as_secs_f64();
    report(&format!(
        "points: {written} camera samples of {} values in {seconds:.3} s, {}x{} pixels, {} per pixel{}",
        camera.dims,
        raster.width,
        raster.height,
        camera.spp,
        match (camera.stream, camera.sampler) {
            (true, _) => ", streamed",
            (false, SamplerArg::Poisson) => "",
            (false, SamplerArg::Net) => ", nets",
        }
    ));
    Ok(())
}

/// Writes the samples to `out` (the header and lines only if `csv`);
/// returns how many.
fn write<W: Write>(
    mut out: W,
    csv: bool,
    raster: Raster,
    camera: Camera,
    seed: u64,
) -> Result<u64, Failure> {
    let io = |e: io::Error| Failure::Io(format!("writing the samples: {e}"));
    let usage = |e: bridson::Error| Failure::Usage(e.to_string());
    let extra = camera.dims.saturating_sub(5);
    if csv {
        write!(out, "px,py,index,film_x,film_y,lens_u,lens_v,time").map_err(io)?;
        for d in 0..extra {
            write!(out, ",d{}", d + 5).map_err(io)?;
        }
        writeln!(out).map_err(io)?;
    }
    let mut count = 0u64;
    let mut line = |out: &mut W, px: u32, py: u32, index: u32, s: &CameraSample, more: &[f64]| {
        count += 1;
        if !csv {
            return Ok(());
        }
        let film = [f64::from(px) + s.film[0], f64::from(py) + s.film[1]];
        write!(out, "{px},{py},{index}")?;
        for v in film.iter().chain(&s.lens).chain([&s.time]).chain(more) {
            write!(out, ",{v}")?;
        }
        writeln!(out)
    };
    let (width, height) = (raster.width, raster.height);
    if camera.stream {
        let tiled = Tiled::builder(width, height)
            .exact(camera.spp)
            .build()
            .map_err(usage)?;
        for pixel in CameraPixels::new(&tiled, seed, extra).map_err(usage)? {
            let per_sample = usize::try_from(extra).unwrap_or(usize::MAX);
            for (index, s) in (0u32..).zip(&pixel.samples) {
                let at = usize::try_from(index)
                    .unwrap_or(usize::MAX)
                    .saturating_mul(per_sample);
                let more = pixel.extra.get(at..at + per_sample).unwrap_or(&[]);
                line(&mut out, pixel.x, pixel.y, index, s, more).map_err(io)?;
            }
        }
    } else {
        let mut sampler: Box<dyn PixelSampler> = match camera.sampler {
            SamplerArg::Poisson => Box::new(
                PoissonPixelSampler::new(camera.spp, seed)
                    .map_err(usage)?
                    .with_resolution([width, height]),
            ),
            SamplerArg::Net => Box::new(
                NetPixelSampler::new(camera.spp, seed)
                    .map_err(usage)?
                    .with_resolution([width, height]),
            ),
        };
        let mut more = Vec::new();
        for py in 0..height {
            for px in 0..width {
                for index in 0..camera.spp {
                    sampler
                        .start_pixel_sample([px, py], index, 0)
                        .map_err(usage)?;
                    let s = sampler.camera_sample();
                    more.clear();
                    more.extend((0..extra).map(|_| sampler.get_1d()));
                    line(&mut out, px, py, index, &s, &more).map_err(io)?;
                }
            }
        }
    }
    out.flush().map_err(io)?;
    Ok(count)
}
