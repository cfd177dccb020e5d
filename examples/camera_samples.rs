//! Camera samples in a render loop: a pbrt-style pixel sampler gives each
//! pixel exactly `spp` samples in every dimension, as a pure function of
//! (seed, pixel, sample index, dimension), so pixels and threads can go in
//! any order. Here it estimates a soft disk's coverage of each pixel.
//!
//! ```sh
//! cargo run --release --example camera_samples
//! ```

use bridson::{PixelSampler, PoissonPixelSampler};

/// The scene: how much light reaches a film point through a lens point.
fn radiance(film: [f64; 2], lens: [f64; 2]) -> f64 {
    let (dx, dy) = (film[0] - 32.0 + 2.0 * lens[0], film[1] - 24.0);
    f64::from(u8::from(dx * dx + dy * dy < 15.0 * 15.0))
}

fn main() -> Result<(), bridson::Error> {
    let (width, height, spp) = (64_u32, 48_u32, 16_u32);
    let mut sampler = PoissonPixelSampler::new(spp, 7)?;
    let mut image = vec![0.0; (width * height) as usize];

    for y in 0..height {
        for x in 0..width {
            let mut sum = 0.0;
            for index in 0..spp {
                sampler.start_pixel_sample([x, y], index, 0)?;
                let camera = sampler.camera_sample(); // film, time, lens
                let film = [f64::from(x) + camera.film[0], f64::from(y) + camera.film[1]];
                sum += radiance(film, camera.lens);
            }
            image[(y * width + x) as usize] = sum / f64::from(spp);
        }
    }
    let covered: f64 = image.iter().sum();
    println!("{width}x{height} at {spp} spp: the disk covers {covered:.1} pixels");
    for row in image.chunks(width as usize).step_by(4) {
        let line: String = row
            .iter()
            .step_by(2)
            .map(|v| if *v > 0.5 { '#' } else { '.' })
            .collect();
        println!("{line}");
    }
    Ok(())
}
