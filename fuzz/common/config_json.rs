//! The `config_json` fuzz target's logic, shared with `tests/fuzz_corpus.rs`.
//!
//! Arbitrary bytes are read as a JSON configuration (the `serde` feature)
//! of a 2-D and of a 3-D sampler, and of a streaming `Tiled` sampler.
//! Whatever deserialises must be a sampler that keeps the guarantee: it
//! round-trips, its builder form builds to the same sampler, and its
//! points (capped, with the budget lowered so an execution stays fast; for
//! `Tiled`, small rasters only) pass the naive oracle. The including crate
//! must also declare `mod common;`, `mod bytes;` and `mod batch;` (for
//! `batch::check_generate`).

use crate::batch::check_generate;
use crate::common;
use bridson::{Domain, Error, PoissonDisk, PoissonDiskBuilder, Tiled, TiledBuilder};

/// Most points generated per execution.
const POINT_LIMIT: u64 = 1000;
/// Most attempts `k` used for generation (see `batch::ATTEMPT_LIMIT`).
const ATTEMPT_LIMIT: u32 = 64;
/// Grid budget used for generation.
const BUDGET_LIMIT: u64 = 16 << 20;

/// Checks `data` as a 2-D and as a 3-D configuration; panics (with a
/// readable message) if an accepted configuration breaks the contract.
pub(crate) fn run(data: &[u8]) {
    check::<2>(data);
    check::<3>(data);
    check_tiled(data);
}

/// Reads `data` as a validated sampler `T` and as its unchecked builder
/// form `B`, and checks that they agree (whatever builds deserialises, and
/// to the same sampler) and that `T` round-trips through JSON. `None` if
/// `data` is no `T`.
fn read_checked<T, B>(data: &[u8], ctx: &str, build: fn(B) -> Result<T, Error>) -> Option<T>
where
    T: serde::Serialize + serde::de::DeserializeOwned + PartialEq + core::fmt::Debug,
    B: serde::de::DeserializeOwned + core::fmt::Debug + Copy,
{
    let builder = serde_json::from_slice::<B>(data);
    let Ok(sampler) = serde_json::from_slice::<T>(data) else {
        // The sampler form is the builder form, validated.
        if let Ok(b) = builder {
            assert!(
                build(b).is_err(),
                "{ctx}{b:?} builds, but does not deserialise as a sampler"
            );
        }
        return None;
    };
    let ctx = format!("{ctx}{sampler:?}");
    match builder.map(build) {
        Ok(Ok(built)) => assert_eq!(built, sampler, "{ctx}: the builder form disagrees"),
        other => panic!("{ctx}: the builder form disagrees: {other:?}"),
    }
    let text = match serde_json::to_string(&sampler) {
        Ok(text) => text,
        Err(e) => panic!("{ctx}: does not serialise: {e}"),
    };
    match serde_json::from_str::<T>(&text) {
        Ok(back) => assert_eq!(back, sampler, "{ctx}: round trip through {text}"),
        Err(e) => panic!("{ctx}: {text} does not deserialise: {e}"),
    }
    Some(sampler)
}

/// Most pixels streamed per execution, and the smallest radius streamed
/// (about 7 points per pixel): the O(n²) oracle stays in milliseconds.
const TILED_PIXEL_LIMIT: u64 = 64;
const TILED_MIN_RADIUS: f64 = 0.3;
/// Window budget used for streaming.
const TILED_BUDGET_LIMIT: u64 = 4 << 20;

fn check_tiled(data: &[u8]) {
    let Some(tiled) = read_checked::<Tiled, _>(data, "", TiledBuilder::build) else {
        return;
    };
    let ctx = format!("{tiled:?}");
    let pixels = u64::from(tiled.width()) * u64::from(tiled.height());
    if pixels > TILED_PIXEL_LIMIT || tiled.radius() < TILED_MIN_RADIUS {
        return;
    }
    let small = tiled
        .to_builder()
        .attempts(ATTEMPT_LIMIT.min(tiled_attempts(&tiled)))
        .max_window_bytes(TILED_BUDGET_LIMIT)
        .build();
    let Ok(small) = small else {
        return;
    };
    let mut union = Vec::new();
    let mut top_ups = 0;
    let mut stream = small.pixels_seeded(seed_of(data));
    while let Some(pixel) = stream.next() {
        let (x, y) = (f64::from(pixel.x), f64::from(pixel.y));
        for p in &pixel.points {
            assert!(
                x <= p[0] && p[0] < x + 1.0 && y <= p[1] && p[1] < y + 1.0,
                "{ctx}: pixel ({x}, {y}) holds {p:?}, outside it"
            );
        }
        union.extend_from_slice(&pixel.points);
        top_ups = stream.top_ups();
    }
    let raster = [f64::from(small.width()), f64::from(small.height())];
    // Exact mode keeps the radius only where no top-up dart was placed.
    let close =
        common::min_distance_violations(&union, small.radius(), [0.0; 2], raster, [false; 2]);
    assert!(
        top_ups > 0 || close.is_empty(),
        "{ctx}: pairs closer than r: {close:?}"
    );
}

/// The `attempts` of a `Tiled`, read from its serialised form (the type
/// has no getter for it).
fn tiled_attempts(tiled: &Tiled) -> u32 {
    serde_json::to_value(tiled)
        .ok()
        .and_then(|v| v.get("attempts")?.as_u64())
        .and_then(|k| u32::try_from(k).ok())
        .unwrap_or(u32::MAX)
}

/// FNV-1a of the input: a seed that follows the input.
fn seed_of(data: &[u8]) -> u64 {
    data.iter().fold(0xcbf2_9ce4_8422_2325, |h, &byte| {
        (h ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    })
}

fn check<const N: usize>(data: &[u8]) {
    // A bare domain validates too.
    if let Ok(domain) = serde_json::from_slice::<Domain<N>>(data) {
        let again = Domain::new(domain.lo(), domain.hi());
        assert_eq!(
            again.map(|d| d.with_periodic(domain.periodic())),
            Ok(domain),
            "N = {N}: a deserialised domain that Domain::new rejects"
        );
    }
    let Some(sampler) = read_checked::<PoissonDisk<N>, _>(
        data,
        &format!("N = {N}: "),
        PoissonDiskBuilder::<N>::build,
    ) else {
        return;
    };
    let ctx = format!("N = {N}, {sampler:?}");

    let cap = sampler
        .max_points()
        .map_or(POINT_LIMIT, |c| c.min(POINT_LIMIT));
    let lowered = sampler
        .to_builder()
        .attempts(sampler.attempts().min(ATTEMPT_LIMIT))
        .max_points(cap)
        .build();
    let Ok(lowered) = lowered else {
        panic!("{ctx}: lowering k and the cap made build() fail: {lowered:?}");
    };
    let budget = sampler.max_grid_bytes().min(BUDGET_LIMIT);
    if let Ok(small) = lowered.to_builder().max_grid_bytes(budget).build() {
        check_generate(&ctx, &small, seed_of(data), cap);
    }
}
