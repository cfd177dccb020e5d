//! The `config_json` fuzz target's logic, shared with `tests/fuzz_corpus.rs`.
//!
//! Arbitrary bytes are read as a JSON configuration (the `serde` feature)
//! of a 2-D and of a 3-D sampler. Whatever deserialises must be a sampler
//! that keeps the guarantee: it round-trips, its `Builder` form builds to
//! the same sampler, and its points (capped, with the grid budget lowered
//! so an execution stays fast) pass the naive oracle. The including crate
//! must also declare `mod common;`, `mod bytes;` and `mod batch;` (for
//! `batch::check_generate`).

use crate::batch::check_generate;
use bridson::{Builder, Domain, PoissonDisk};

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
    let builder = serde_json::from_slice::<Builder<N>>(data);
    let Ok(sampler) = serde_json::from_slice::<PoissonDisk<N>>(data) else {
        // The sampler form is the builder form, validated.
        if let Ok(b) = builder {
            assert!(
                b.build().is_err(),
                "N = {N}: {b:?} builds, but does not deserialise as a sampler"
            );
        }
        return;
    };
    let ctx = format!("N = {N}, {sampler:?}");
    assert_eq!(
        builder.map(Builder::build).ok(),
        Some(Ok(sampler)),
        "{ctx}: the builder form disagrees"
    );
    let text = match serde_json::to_string(&sampler) {
        Ok(text) => text,
        Err(e) => panic!("{ctx}: does not serialise: {e}"),
    };
    match serde_json::from_str::<PoissonDisk<N>>(&text) {
        Ok(back) => assert_eq!(back, sampler, "{ctx}: round trip through {text}"),
        Err(e) => panic!("{ctx}: {text} does not deserialise: {e}"),
    }

    let cap = sampler
        .max_points()
        .map_or(POINT_LIMIT, |c| c.min(POINT_LIMIT));
    let lowered = sampler
        .to_builder()
        .attempts(sampler.attempts().min(ATTEMPT_LIMIT))
        .max_points(Some(cap))
        .build();
    let Ok(lowered) = lowered else {
        panic!("{ctx}: lowering k and the cap made build() fail: {lowered:?}");
    };
    let budget = sampler.max_grid_bytes().min(BUDGET_LIMIT);
    if let Ok(small) = lowered.to_builder().max_grid_bytes(budget).build() {
        check_generate(&ctx, &small, seed_of(data), cap);
    }
}
