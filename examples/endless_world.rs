//! An endless world in chunks, visited in any order: the field sampler
//! (`bridson::Field`) makes each chunk's points a pure function of place,
//! so a world explored in one random order is, chunk for chunk and bit for
//! bit, the world explored in another.
//!
//! ```sh
//! cargo run --release --example endless_world
//! ```

use bridson::{Field, field_order};

/// A small generator for the visiting orders (the points need none).
fn shuffle<T>(items: &mut [T], mut state: u64) {
    for i in (1..items.len()).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let j = usize::try_from((state >> 33) % (i as u64 + 1)).expect("small");
        items.swap(i, j);
    }
}

fn main() -> Result<(), bridson::Error> {
    // Trees at least 3 m apart, in chunks of 64 m, around the origin.
    let world = Field::<2>::unbounded(3.0, 2026)?;
    let chunk = 64.0;
    let mut chunks: Vec<(i32, i32)> = (-3..3)
        .flat_map(|cx| (-3..3).map(move |cy| (cx, cy)))
        .collect();
    let mut visit = |order_seed: u64| -> Result<Vec<[f64; 2]>, bridson::Error> {
        shuffle(&mut chunks, order_seed);
        let mut trees = Vec::new();
        for &(cx, cy) in &chunks {
            let lo = [f64::from(cx) * chunk, f64::from(cy) * chunk];
            let hi = [lo[0] + chunk, lo[1] + chunk];
            trees.extend(world.points_in(lo, hi)?);
        }
        trees.sort_by(field_order);
        Ok(trees)
    };
    let first = visit(1)?;
    let second = visit(2)?;
    assert_eq!(first, second, "two visiting orders, one world");
    // The same world asked for in one piece.
    let whole = world.points_in([-3.0 * chunk; 2], [3.0 * chunk; 2])?;
    assert_eq!(first, whole, "the chunks' union is the whole");
    println!(
        "{} trees in 36 chunks of {chunk} m, the same in two random orders and in one piece",
        first.len()
    );
    Ok(())
}
