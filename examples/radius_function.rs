//! A radius that follows a function: dense near a point of interest and
//! sparse far from it. No two points `p`, `q` are closer than
//! `max(r(p), r(q))`.
//!
//! ```sh
//! cargo run --release --example radius_function > points.csv
//! ```

use bridson::{Domain, PoissonDisk2};

fn main() -> Result<(), bridson::Error> {
    let (r_min, r_max) = (0.005, 0.04);
    // The sampler's own radius is the largest the field may ask for.
    let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, r_max)?;

    // Small near (0.3, 0.6), growing with the distance from it.
    let radius = |p: &[f64; 2]| {
        let d = ((p[0] - 0.3).powi(2) + (p[1] - 0.6).powi(2)).sqrt();
        r_min + (r_max - r_min) * d.min(1.0)
    };

    let points: Vec<[f64; 2]> = sampler.iter_varying_seeded(5, r_min, radius)?.collect();

    let near = points.iter().filter(|p| radius(p) < 0.01).count();
    eprintln!("{} points, {near} where r < 0.01", points.len());
    println!("x,y,r");
    for p in &points {
        println!("{},{},{}", p[0], p[1], radius(p));
    }
    Ok(())
}
