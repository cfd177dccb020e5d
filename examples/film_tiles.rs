//! Film points for a tile-parallel renderer, from the field
//! ([`bridson::Field`]): each tile's points asked for on its own, in a
//! shuffled order and on several threads, against one query of the whole
//! image. Checks that the tiles' union is the whole image's set, bit for
//! bit, and prints both rates: medians of `REPEATS` turns, each the whole
//! image then the tiles.
//!
//! ```sh
//! cargo run --release --example film_tiles -- 256 256 16 16 1 5
//! # WIDTH HEIGHT SPP (mean samples a pixel) TILE (pixels) THREADS REPEATS
//! ```

use bridson::{Field, chunk_boxes, field_order};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [width, height, spp, tile, threads, repeats] = args.as_slice() else {
        eprintln!("usage: film_tiles WIDTH HEIGHT SPP TILE THREADS REPEATS");
        std::process::exit(2);
    };
    let [width, height, spp, tile] =
        [width, height, spp, tile].map(|a| a.parse::<f64>().expect("a number"));
    let [threads, repeats] = [threads, repeats].map(|a| a.parse::<usize>().expect("a count"));
    // A maximal set holds about 2ρ²/(√3 r²) points a unit area at ρ 0.777.
    let radius = 0.777 * (2.0 / (3f64.sqrt() * spp)).sqrt();
    let image = ([0.0, 0.0], [width, height]);
    let field = Field::unbounded(radius, 7).expect("a valid radius");

    // Tiles in a shuffled order (a fixed LCG), each asked for alone.
    let mut boxes = chunk_boxes(image.0, image.1, tile).expect("tiles");
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for i in (1..boxes.len()).rev() {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        boxes.swap(i, (state >> 33) as usize % (i + 1));
    }
    let (mut whole_times, mut tile_times) = (Vec::new(), Vec::new());
    let mut whole = Vec::new();
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        whole = field.points_in(image.0, image.1).expect("the image");
        whole_times.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let tiles = field.points_in_boxes(&boxes, threads).expect("the tiles");
        tile_times.push(t.elapsed().as_secs_f64());
        let mut union: Vec<[f64; 2]> = tiles.into_iter().flatten().collect();
        union.sort_by(field_order);
        assert!(union == whole, "the tiles' union differs from the image");
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let ratios: Vec<f64> = whole_times
        .iter()
        .zip(&tile_times)
        .map(|(w, t)| w / t)
        .collect();
    let (whole_secs, tile_secs) = (median(whole_times), median(tile_times));
    #[expect(clippy::cast_precision_loss, reason = "counts below 2^53")]
    let n = whole.len() as f64;
    println!(
        "{width}x{height} px, r {radius:.5} px: {n} points ({:.2} a pixel); whole image {whole_secs:.3} s ({:.0} k/s); {} tiles of {tile} px on {threads} threads {tile_secs:.3} s ({:.0} k/s); tiles/whole rate, median of turns, {:.3}; union identical",
        n / (width * height),
        n / whole_secs / 1e3,
        boxes.len(),
        n / tile_secs / 1e3,
        median(ratios)
    );
}
