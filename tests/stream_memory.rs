//! The stream's memory, checked against the allocator itself: a counting
//! global allocator records the peak of the heap while a `Tiled` stream is
//! built and driven to its end. The peak stays flat as the raster grows
//! taller (a stream keeps a window of rows, never the image), in every
//! scheme and in exact mode; and it stays near the multiple of
//! `window_bytes()` that `TiledBuilder::max_window_bytes` documents for the
//! stream's working memory on top of the window.
//!
//! The allocator and its per-thread counters are `tests/common/counting.rs`.

use bridson::{ExactMethod, Scheme, Tiled, TiledBuilder};

#[path = "common/counting.rs"]
mod counting;

/// Builds the stream `builder` makes for `height` rows, drives it to its
/// end and returns its window's bytes and the peak heap the stream took
/// above what was held before it.
fn peak(builder: impl Fn(u32) -> TiledBuilder, height: u32) -> (u64, usize) {
    let before = counting::start();
    let tiled = builder(height).build().expect("a valid stream");
    let mut pixels = tiled.pixels_seeded(3);
    let mut points = Vec::new();
    let mut count = 0usize;
    while pixels.next_into(&mut points).is_some() {
        count += points.len();
    }
    assert!(count > 0, "the stream made no point");
    drop(pixels);
    (tiled.window_bytes(), counting::peak_since(before))
}

#[test]
fn the_peak_heap_is_flat_in_the_height() {
    type Case = (&'static str, fn(u32) -> TiledBuilder);
    let cases: [Case; 6] = [
        ("sweep, 4 a pixel", |h| Tiled::builder(96, h).per_pixel(4.0)),
        ("sweep, 24 a pixel", |h| {
            Tiled::builder(32, h).per_pixel(24.0)
        }),
        ("Ye's scheme", |h| {
            Tiled::builder(96, h).per_pixel(4.0).scheme(Scheme::Paper)
        }),
        ("exact 4, elimination", |h| Tiled::builder(96, h).exact(4)),
        ("exact 4, random dropping", |h| {
            Tiled::builder(96, h)
                .exact(4)
                .exact_method(ExactMethod::Random)
        }),
        ("exact 24, elimination", |h| Tiled::builder(32, h).exact(24)),
    ];
    for (name, builder) in cases {
        let (window, short) = peak(builder, 16);
        let (tall_window, tall) = peak(builder, 128);
        assert_eq!(window, tall_window, "{name}: the window's bytes");
        // Eight times the rows: the same peak, give or take a doubling of
        // the vectors that grow to the largest band or row met so far (a
        // taller raster meets a fuller one). A stream that held on to a
        // part of each row (a quarter of a row's points, say) would be
        // past this by the last row.
        assert!(
            tall <= short + short / 2,
            "{name}: {short} bytes at 16 rows, {tall} at 128"
        );
        // `max_window_bytes` documents the working memory on top of the
        // window as measured: the whole peak 1.15–1.32 times the window for
        // the sweep, up to about 3 times in exact mode at 24–64 a pixel.
        // Four times is the line past which those figures are wrong.
        #[expect(clippy::cast_possible_truncation, reason = "test sizes")]
        let window = window as usize;
        assert!(
            tall <= 4 * window,
            "{name}: peak {tall} bytes against a window of {window}"
        );
    }
}
