//! An endless forest with a river through it: a field kept to a region
//! (`Field::with_region`) given by a signed distance. The trees stay out of
//! the river and fill the land up to its banks (maximal there), and the
//! world is still a pure function of place: chunks asked for backwards give
//! the same trees as one query of the whole.
//!
//! ```sh
//! cargo run --release --example field_region
//! ```

use bridson::{Field, SignedDistance, field_order};

fn main() -> Result<(), bridson::Error> {
    // Land is where the distance to the line y = x / 2 exceeds 3 m: the
    // signed distance is negative there, positive in the river.
    let river = |p: &[f64; 2]| 3.0 - (p[1] - 0.5 * p[0]).abs() / 1.25f64.sqrt();
    let forest = Field::<2>::unbounded(2.0, 7)?.with_region(SignedDistance(river));
    let chunk = 32.0;
    let mut trees = Vec::new();
    for cy in (-2..2).rev() {
        for cx in (-2..2).rev() {
            let lo = [f64::from(cx) * chunk, f64::from(cy) * chunk];
            trees.extend(forest.points_in(lo, [lo[0] + chunk, lo[1] + chunk])?);
        }
    }
    trees.sort_by(field_order);
    let whole = forest.points_in([-2.0 * chunk; 2], [2.0 * chunk; 2])?;
    assert_eq!(trees, whole, "the chunks' union is the whole");
    assert!(trees.iter().all(|p| river(p) <= 0.0), "a tree in the river");
    // Every point of the land is within 2 m of a tree: probe a grid of it.
    let mut probes = 0;
    for i in 0..256 {
        for j in 0..256 {
            let p = [
                -64.0 + f64::from(i) * 0.5 + 0.25,
                -64.0 + f64::from(j) * 0.5 + 0.25,
            ];
            if river(&p) > 0.0 {
                continue;
            }
            probes += 1;
            let near = |q: &&[f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) <= 2.0;
            // Near the box's edge the covering tree may lie outside it.
            let inner = p.iter().all(|x| x.abs() < 62.0);
            assert!(!inner || trees.iter().any(|q| near(&q)), "a gap at {p:?}");
        }
    }
    println!(
        "{} trees in 16 chunks of {chunk} m, none in the river, the land covered at {probes} probes",
        trees.len()
    );
    Ok(())
}
