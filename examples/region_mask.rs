//! A region mask and pre-placed points: trees around a lake. New points
//! fall only where the mask is true, and keep their distance from points
//! placed beforehand (here, a row of houses along the shore).
//!
//! ```sh
//! cargo run --release --example region_mask
//! ```

use bridson::{Domain, PoissonDisk2};

fn main() -> Result<(), bridson::Error> {
    let r = 2.0;
    let sampler = PoissonDisk2::new(Domain::from_extent([100.0, 60.0])?, r)?;

    // The lake: an ellipse. A tree may grow anywhere else.
    let in_lake =
        |p: &[f64; 2]| ((p[0] - 50.0) / 30.0).powi(2) + ((p[1] - 30.0) / 15.0).powi(2) < 1.0;
    // Annotate the argument (`&[f64; 2]`): Rust cannot infer it from the call.
    let land = |p: &[f64; 2]| !in_lake(p);

    // Houses on the south shore, fixed before the trees grow.
    let houses: Vec<[f64; 2]> = (0..8).map(|i| [30.0 + 5.0 * f64::from(i), 12.0]).collect();

    let trees: Vec<[f64; 2]> = sampler.iter_with_seeded(11, land, &houses)?.collect();

    assert!(trees.iter().all(|t| !in_lake(t)), "no tree in the lake");
    for t in &trees {
        for h in &houses {
            let d2 = (t[0] - h[0]).powi(2) + (t[1] - h[1]).powi(2);
            assert!(d2 >= r * r, "a tree {t:?} too close to a house {h:?}");
        }
    }
    println!(
        "{} trees around the lake, {} houses",
        trees.len(),
        houses.len()
    );
    Ok(())
}
