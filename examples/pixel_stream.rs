//! A pixel stream: a 2-D Poisson disk set over a raster, handed out pixel
//! by pixel in scan order while memory stays at about one row of pixels.
//! The spacing holds across pixel borders.
//!
//! ```sh
//! cargo run --release --example pixel_stream
//! ```

use bridson::Tiled;

fn main() -> Result<(), bridson::Error> {
    let (width, height) = (256, 144);
    // About 4 points a pixel; `.exact(4)` would give exactly 4 in each.
    let tiled = Tiled::builder(width, height).per_pixel(4.0).build()?;

    let mut total = 0_usize;
    let mut busiest = (0, [0, 0]);
    for pixel in tiled.pixels_seeded(3) {
        // Raster coordinates: each point lies inside its pixel's square.
        let (x, y) = (f64::from(pixel.x), f64::from(pixel.y));
        assert!(
            pixel
                .points
                .iter()
                .all(|p| (p[0] - x) < 1.0 && (p[1] - y) < 1.0),
            "a point outside its pixel"
        );
        total += pixel.points.len();
        if pixel.points.len() > busiest.0 {
            busiest = (pixel.points.len(), [pixel.x, pixel.y]);
        }
    }
    let mean = total as f64 / f64::from(width * height);
    println!("{total} points over {width}x{height} pixels, {mean:.3} a pixel");
    println!("the busiest pixel, {:?}, holds {}", busiest.1, busiest.0);
    println!("window memory: {} bytes", tiled.window_bytes());
    Ok(())
}
