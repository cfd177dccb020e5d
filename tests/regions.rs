//! Regions and pre-placed points (`PoissonDisk::iter_with`): every new
//! point lies in the region, and the union of the pre-placed and the new
//! points keeps the guarantee, checked by the naive oracle; bad pre-placed
//! points are errors; and the seamless-chunks recipe, run over a
//! 4 × 4 world, keeps the guarantee across chunk borders and leaves no gap
//! along them.

mod common;

use bridson::{Candidates, Domain, Error, GridLayout, PoissonDisk, PoissonDisk2};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use std::collections::HashMap;

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("regressions"))),
        ..ProptestConfig::default()
    }
}

/// The union of `fixed` and `new` passes the oracle, and every new point
/// lies in `region`.
fn check_union<const N: usize>(
    domain: &Domain<N>,
    r: f64,
    fixed: &[[f64; N]],
    new: &[[f64; N]],
    region: impl Fn(&[f64; N]) -> bool,
    ctx: &str,
) {
    for p in new {
        assert!(region(p), "{ctx}: {p:?} outside the region");
    }
    let union: Vec<[f64; N]> = fixed.iter().chain(new).copied().collect();
    if let Err(report) =
        common::check_points(&union, r, domain.lo(), domain.hi(), domain.periodic())
    {
        panic!("{ctx}: {report}");
    }
}

/// A ball mask around `centre` and pre-placed points from an earlier set,
/// every other one: new points fill the ball around them.
fn ball_around_fixed<const N: usize>(
    seed: u64,
    periodic: bool,
    kind: Candidates,
    layout: GridLayout,
) {
    let r = match N {
        1 => 0.01,
        2 => 0.04,
        _ => 0.12,
    };
    let domain = Domain::from_extent([1.0; N])
        .expect("box")
        .with_periodic([periodic; N]);
    let sampler = PoissonDisk::<N>::builder(domain, r)
        .candidates(kind)
        .layout(layout)
        .build()
        .expect("valid");
    let earlier = sampler.generate_seeded(seed ^ 0x5eed).expect("points");
    let fixed: Vec<[f64; N]> = earlier.iter().step_by(2).copied().collect();
    let centre = [0.4; N];
    let ball = move |p: &[f64; N]| {
        let d2: f64 = p.iter().zip(&centre).map(|(a, b)| (a - b) * (a - b)).sum();
        d2 < 0.35 * 0.35
    };
    let new: Vec<[f64; N]> = sampler
        .iter_with_seeded(seed, ball, &fixed)
        .expect("valid fixed points")
        .collect();
    let ctx = format!("{N}-D seed {seed} {kind:?} {layout:?} periodic {periodic}");
    assert!(
        !new.is_empty(),
        "{ctx}: the ball has room between the fixed points"
    );
    check_union(&domain, r, &fixed, &new, ball, &ctx);
    // Every second point was removed: growth from the fixed points fills
    // the ball again, to nearly the same density (on-sphere candidates,
    // which pack a set of their own densest, reach about 88 % around a
    // thinned one).
    let in_ball = earlier.iter().filter(|p| ball(p)).count();
    let now = fixed.iter().filter(|p| ball(p)).count() + new.len();
    assert!(
        now * 10 >= in_ball * 8,
        "{ctx}: {now} points in the ball, {in_ball} before"
    );
}

proptest! {
    #![proptest_config(config(12))]

    #[test]
    fn new_points_stay_in_the_region_and_clear_of_fixed_ones(
        seed: u64,
        periodic: bool,
        sphere: bool,
        sparse: bool,
    ) {
        let kind = if sphere { Candidates::Sphere } else { Candidates::Annulus };
        let layout = if sparse { GridLayout::Sparse } else { GridLayout::Auto };
        ball_around_fixed::<1>(seed, periodic, kind, layout);
        ball_around_fixed::<2>(seed, periodic, kind, layout);
        ball_around_fixed::<3>(seed, periodic, kind, layout);
    }
}

/// A triangle mask, no pre-placed points: the first point is drawn in the
/// region; a region no point of the box can satisfy gives an empty stream.
#[test]
fn a_polygon_mask_with_no_fixed_points() {
    let domain = Domain::from_extent([2.0, 1.0]).expect("box");
    let sampler = PoissonDisk2::new(domain, 0.03).expect("valid");
    let triangle = |p: &[f64; 2]| p[1] < p[0] && p[1] < 2.0 - p[0];
    for seed in 0..4 {
        let new: Vec<[f64; 2]> = sampler
            .iter_with_seeded(seed, triangle, &[])
            .expect("valid")
            .collect();
        // Area 1, about 0.6 / r² points.
        assert!(new.len() > 500, "seed {seed}: {} points", new.len());
        check_union(&domain, 0.03, &[], &new, triangle, &format!("seed {seed}"));
    }
    // A region no try hits is an error, not an empty stream: an empty
    // mask, and a disc of radius 1 in a 1000 x 1000 box.
    let nowhere = |_: &[f64; 2]| false;
    assert_eq!(
        sampler.iter_with_seeded(1, nowhere, &[]).err(),
        Some(Error::RegionMissed { tries: 64 * 30 }),
        "an empty region"
    );
    let wide =
        PoissonDisk2::new(Domain::from_extent([1000.0, 1000.0]).expect("box"), 0.5).expect("valid");
    let speck = |p: &[f64; 2]| (p[0] - 500.0).powi(2) + (p[1] - 500.0).powi(2) < 1.0;
    assert!(
        matches!(
            wide.iter_with_seeded(1, speck, &[]).err(),
            Some(Error::RegionMissed { .. })
        ),
        "a region too small to hit"
    );
    // Pre-placed in it, the same region grows.
    let grown = wide
        .iter_with_seeded(1, speck, &[[500.0, 500.0]])
        .expect("valid")
        .count();
    assert!(grown > 0, "grown from a pre-placed point");
    // The plain run is the `Everywhere` region.
    let everywhere: Vec<[f64; 2]> = sampler
        .iter_with_seeded(9, bridson::Everywhere, &[])
        .expect("valid")
        .collect();
    assert_eq!(
        everywhere,
        sampler.generate_seeded(9).expect("points"),
        "same stream"
    );
}

#[test]
fn bad_fixed_points_are_errors() {
    let domain = Domain::from_extent([1.0, 1.0]).expect("box");
    let sampler = PoissonDisk2::new(domain, 0.1).expect("valid");
    let any = |_: &[f64; 2]| true;
    for (fixed, index, what) in [
        (vec![[0.5, 0.5], [1.0, 0.5]], 1, "on hi"),
        (vec![[-0.1, 0.5]], 0, "below lo"),
        (vec![[0.2, 0.2], [f64::NAN, 0.5]], 1, "NaN"),
        (
            vec![[0.2, 0.2], [0.5, 0.5], [0.55, 0.5]],
            2,
            "closer than r",
        ),
    ] {
        assert_eq!(
            sampler.iter_with_seeded(1, any, &fixed).err(),
            Some(Error::InvalidFixedPoint { index }),
            "{what}"
        );
    }
    // Exactly r apart is allowed, as between sampled points.
    let ok = [[0.2, 0.2], [0.2, 0.30000000000000004]];
    assert!(sampler.iter_with_seeded(1, any, &ok).is_ok(), "r apart");
    let tight = PoissonDisk2::builder(domain, 0.001)
        .max_grid_bytes(1 << 12)
        .layout(GridLayout::Sparse)
        .build()
        .expect("valid");
    let many: Vec<[f64; 2]> = (0..400).map(|i| [f64::from(i) / 400.0, 0.5]).collect();
    let over = tight.iter_with_seeded(1, any, &many).err();
    assert!(
        matches!(over, Some(Error::MemoryBudgetExceeded { points: 0, .. })),
        "fixed points over the budget: {over:?}"
    );
}

// ---------------------------------------------------------------- chunks

/// The seamless-chunks recipe (chunks made in order, each around its
/// neighbours' points): chunk (i, j) is the unit square at (i, j), sampled
/// in the square grown by 2r, its new points kept in the chunk, around the
/// points of the neighbours already made.
fn chunk(
    i: i32,
    j: i32,
    r: f64,
    made: &HashMap<(i32, i32), Vec<[f64; 2]>>,
) -> Result<Vec<[f64; 2]>, Error> {
    let (x, y) = (f64::from(i), f64::from(j));
    let grown = Domain::new(
        [x - 2.0 * r, y - 2.0 * r],
        [x + 1.0 + 2.0 * r, y + 1.0 + 2.0 * r],
    )?;
    let fixed: Vec<[f64; 2]> = (-1..=1)
        .flat_map(|di| (-1..=1).map(move |dj| (i + di, j + dj)))
        .filter_map(|key| made.get(&key))
        .flatten()
        .copied()
        .filter(|p| grown.contains(p))
        .collect();
    let inside = move |p: &[f64; 2]| x <= p[0] && p[0] < x + 1.0 && y <= p[1] && p[1] < y + 1.0;
    let seed = (u64::from(i.cast_unsigned()) << 32) | u64::from(j.cast_unsigned());
    Ok(PoissonDisk2::new(grown, r)?
        .iter_with_seeded(seed, inside, &fixed)?
        .collect())
}

/// The chunks of a world, made in `order`.
fn world(r: f64, order: &[(i32, i32)]) -> HashMap<(i32, i32), Vec<[f64; 2]>> {
    let mut made = HashMap::new();
    for &key in order {
        let points = chunk(key.0, key.1, r, &made).expect("valid chunk");
        let (x, y) = (f64::from(key.0), f64::from(key.1));
        assert!(
            points
                .iter()
                .all(|p| x <= p[0] && p[0] < x + 1.0 && y <= p[1] && p[1] < y + 1.0),
            "chunk {key:?} has a point outside it"
        );
        made.insert(key, points);
    }
    assert_eq!(made.len(), order.len(), "every chunk made");
    made
}

#[test]
fn seamless_chunks_keep_the_guarantee_across_borders() {
    const SIDE: i32 = 4;
    let r = 0.05;
    let row_major: Vec<(i32, i32)> = (0..SIDE)
        .flat_map(|j| (0..SIDE).map(move |i| (i, j)))
        .collect();
    let made = world(r, &row_major);
    let all: Vec<[f64; 2]> = row_major.iter().flat_map(|k| made[k].clone()).collect();
    let extent = f64::from(SIDE);
    if let Err(report) = common::check_points(&all, r, [0.0; 2], [extent; 2], [false; 2]) {
        panic!("the union of the chunks: {report}");
    }
    // No gap along the borders: probes within 0.1 of an inner chunk border
    // (away from the world's edge) are almost all within r of a point, as
    // in a chunk's interior.
    let mut rng_state = 0x1234_5678_9abc_def0_u64;
    let mut next = || {
        rng_state ^= rng_state << 13;
        rng_state ^= rng_state >> 7;
        rng_state ^= rng_state << 17;
        (rng_state >> 11) as f64 / (1u64 << 53) as f64
    };
    // [probes, uncovered] inside chunks, and near a border.
    let mut tally = [[0u32; 2]; 2];
    for _ in 0..20_000 {
        let p = [0.5 + next() * (extent - 1.0), 0.5 + next() * (extent - 1.0)];
        let near_border = p.iter().any(|c| (c - c.round()).abs() < 0.1);
        let covered = all
            .iter()
            .any(|q| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) < r * r);
        let t = &mut tally[usize::from(near_border)];
        t[0] += 1;
        t[1] += u32::from(!covered);
    }
    let [[inner, inner_uncovered], [border, border_uncovered]] = tally;
    println!(
        "uncovered probes: {border_uncovered} of {border} near a chunk border, \
         {inner_uncovered} of {inner} inside chunks"
    );
    assert!(border > 1000, "{border} probes near a border");
    assert!(
        border_uncovered * 100 <= border,
        "{border_uncovered} of {border} probes near a chunk border are farther than r from every point"
    );
    // Deterministic: the same order gives the same world.
    assert_eq!(world(r, &row_major), made, "same order, same chunks");
}
