//! Every invalid input is a precise `Error` from a constructor, never a
//! panic; and some awkward but valid inputs (thin boxes, 1-D, periods
//! shorter than `r`, extreme magnitudes) work and give valid points.

mod common;

use bridson::{
    Candidates, DEFAULT_MAX_GRID_BYTES, Domain, Error, Everywhere, GridLayout, MAX_ATTEMPTS,
    PoissonDisk, PoissonDisk2, Tiled,
};

fn unit_square() -> Domain<2> {
    Domain::from_extent([1.0, 1.0]).expect("the unit square is valid")
}

/// Generates (capped at `cap` points) and checks every point with the oracle.
fn assert_valid<const N: usize>(sampler: &PoissonDisk<N>, seed: u64, cap: usize) -> usize {
    let d = sampler.domain();
    let points: Vec<[f64; N]> = sampler.iter_seeded(seed).take(cap).collect();
    if let Err(report) =
        common::check_points(&points, sampler.radius(), d.lo(), d.hi(), d.periodic())
    {
        panic!(
            "seed {seed}, domain {d:?}, r = {:e}, {:?}: {report}",
            sampler.radius(),
            sampler.candidates()
        );
    }
    points.len()
}

// ---------------------------------------------------------------- domain

#[test]
fn zero_dimension() {
    assert_eq!(
        Domain::<0>::new([], []),
        Err(Error::ZeroDimension),
        "N = 0 via new"
    );
    assert_eq!(
        Domain::<0>::from_extent([]),
        Err(Error::ZeroDimension),
        "N = 0 via from_extent"
    );
}

#[test]
fn nan_bound() {
    assert_eq!(
        Domain::new([0.0, f64::NAN], [1.0, 1.0]),
        Err(Error::NonFiniteBound { axis: 1 }),
        "NaN lo on axis 1"
    );
    assert_eq!(
        Domain::new([0.0, 0.0, 0.0], [1.0, 1.0, f64::NAN]),
        Err(Error::NonFiniteBound { axis: 2 }),
        "NaN hi on axis 2"
    );
}

#[test]
fn positive_infinite_bound() {
    assert_eq!(
        Domain::new([0.0, 0.0, 0.0], [1.0, f64::INFINITY, 1.0]),
        Err(Error::NonFiniteBound { axis: 1 }),
        "+inf hi on axis 1"
    );
    assert_eq!(
        Domain::new([f64::INFINITY], [f64::INFINITY]),
        Err(Error::NonFiniteBound { axis: 0 }),
        "+inf lo and hi on axis 0"
    );
}

#[test]
fn negative_infinite_bound() {
    assert_eq!(
        Domain::new([f64::NEG_INFINITY, 0.0], [1.0, 1.0]),
        Err(Error::NonFiniteBound { axis: 0 }),
        "-inf lo on axis 0"
    );
    assert_eq!(
        Domain::new([0.0, 0.0, f64::NEG_INFINITY], [1.0, 1.0, 1.0]),
        Err(Error::NonFiniteBound { axis: 2 }),
        "-inf lo on axis 2"
    );
}

#[test]
fn the_first_bad_axis_is_reported() {
    assert_eq!(
        Domain::new([0.0, 1.0, f64::NAN], [1.0, 1.0, 1.0]),
        Err(Error::EmptyBox { axis: 1 }),
        "axis 1 (empty) comes before axis 2 (NaN)"
    );
    assert_eq!(
        Domain::new([0.0, f64::NAN, 1.0], [1.0, 1.0, 1.0]),
        Err(Error::NonFiniteBound { axis: 1 }),
        "axis 1 (NaN) comes before axis 2 (empty)"
    );
}

#[test]
fn lo_equal_to_hi() {
    assert_eq!(
        Domain::new([0.0, 0.5], [1.0, 0.5]),
        Err(Error::EmptyBox { axis: 1 }),
        "lo == hi on axis 1"
    );
    assert_eq!(
        Domain::from_extent([0.0]),
        Err(Error::EmptyBox { axis: 0 }),
        "zero extent on axis 0"
    );
    assert_eq!(
        Domain::new([0.0], [-0.0]),
        Err(Error::EmptyBox { axis: 0 }),
        "0.0 .. -0.0 is empty"
    );
}

#[test]
fn lo_above_hi() {
    assert_eq!(
        Domain::new([0.0, 0.0, 2.0], [1.0, 1.0, 1.0]),
        Err(Error::EmptyBox { axis: 2 }),
        "lo > hi on axis 2"
    );
    assert_eq!(
        Domain::from_extent([1.0, -1.0]),
        Err(Error::EmptyBox { axis: 1 }),
        "negative extent on axis 1"
    );
}

#[test]
fn extent_overflow() {
    assert_eq!(
        Domain::new([-1e308], [1e308]),
        Err(Error::ExtentOverflow { axis: 0 }),
        "-1e308 .. 1e308"
    );
    assert_eq!(
        Domain::new([0.0, f64::MIN], [1.0, f64::MAX]),
        Err(Error::ExtentOverflow { axis: 1 }),
        "f64::MIN .. f64::MAX on axis 1"
    );
    assert!(
        Domain::new([-0.8e308], [0.8e308]).is_ok(),
        "an extent of 1.6e308 is still finite"
    );
}

// ---------------------------------------------------------------- radius

fn radius_error(radius: f64) -> Result<PoissonDisk2, Error> {
    PoissonDisk2::new(unit_square(), radius)
}

#[test]
fn radius_nan() {
    assert_eq!(
        radius_error(f64::NAN),
        Err(Error::InvalidRadius),
        "NaN radius"
    );
}

#[test]
fn radius_positive_infinity() {
    assert_eq!(
        radius_error(f64::INFINITY),
        Err(Error::InvalidRadius),
        "+inf radius"
    );
}

#[test]
fn radius_negative_infinity() {
    assert_eq!(
        radius_error(f64::NEG_INFINITY),
        Err(Error::InvalidRadius),
        "-inf radius"
    );
}

#[test]
fn radius_zero() {
    assert_eq!(radius_error(0.0), Err(Error::InvalidRadius), "zero radius");
    assert_eq!(
        radius_error(-0.0),
        Err(Error::InvalidRadius),
        "negative zero radius"
    );
}

#[test]
fn radius_negative() {
    assert_eq!(
        radius_error(-1.0),
        Err(Error::InvalidRadius),
        "negative radius"
    );
}

#[test]
fn radius_subnormal() {
    assert_eq!(
        radius_error(5e-324),
        Err(Error::InvalidRadius),
        "subnormal radius"
    );
}

#[test]
fn radius_too_small_to_square() {
    assert_eq!(
        radius_error(1e-200),
        Err(Error::InvalidRadius),
        "1e-200 squared underflows"
    );
}

#[test]
fn radius_too_large_to_square() {
    assert_eq!(
        radius_error(1e200),
        Err(Error::InvalidRadius),
        "1e200 squared overflows"
    );
    assert_eq!(
        radius_error(f64::MAX),
        Err(Error::InvalidRadius),
        "f64::MAX radius"
    );
}

#[test]
fn radius_at_the_documented_limits_is_accepted() {
    // r = 1e150 in the unit square: room for exactly one point.
    let huge = radius_error(1e150).expect("1e150 is inside 1e-150 ..= 1e150");
    assert_eq!(assert_valid(&huge, 1, usize::MAX), 1, "one point fits");
    // r = 1e-150 in a box of a few radii.
    let tiny = PoissonDisk2::new(
        Domain::from_extent([4e-150, 3e-150]).expect("valid box"),
        1e-150,
    )
    .expect("1e-150 is inside 1e-150 ..= 1e150");
    assert!(
        assert_valid(&tiny, 2, usize::MAX) >= 2,
        "a box of 4r × 3r holds several points"
    );
}

#[test]
fn radius_one_ulp_outside_the_limits() {
    assert_eq!(
        radius_error(1e-150_f64.next_down()),
        Err(Error::InvalidRadius),
        "one ulp below 1e-150"
    );
    assert_eq!(
        radius_error(1e150_f64.next_up()),
        Err(Error::InvalidRadius),
        "one ulp above 1e150"
    );
}

// ---------------------------------------------------------------- attempts

#[test]
fn zero_attempts() {
    let builder = PoissonDisk2::builder(unit_square(), 0.1);
    assert_eq!(
        builder.attempts(0).build(),
        Err(Error::ZeroAttempts),
        "k = 0"
    );
    assert!(builder.attempts(1).build().is_ok(), "k = 1 is fine");
}

/// The streaming builder checks the radius it derives from the samples per
/// pixel before `k`, as its `# Errors` list says, whatever `k` is: a
/// finite, positive but tiny count per pixel gives a radius past `1e150`.
/// Found by the `streaming` fuzz target, whose own model had expected
/// `ZeroAttempts` (`fuzz/corpus/streaming/regression-per-pixel-radius-before-zero-k`).
#[test]
fn a_radius_from_samples_per_pixel_is_checked_before_k() {
    let tiny = Tiled::builder(1, 1 << 20).per_pixel(f64::MIN_POSITIVE);
    for k in [0, 1, 30, MAX_ATTEMPTS + 1] {
        assert_eq!(
            tiny.attempts(k).build().err(),
            Some(Error::InvalidRadius),
            "k = {k}"
        );
    }
    let fine = Tiled::builder(1, 1 << 20).per_pixel(4.0);
    assert_eq!(
        fine.attempts(0).build().err(),
        Some(Error::ZeroAttempts),
        "a valid radius, k = 0"
    );
}

/// Counts the generator calls the sampler makes.
struct CountingRng {
    inner: bridson::DefaultRng,
    draws: u64,
}

impl CountingRng {
    fn new(seed: u64) -> Self {
        Self {
            inner: bridson::seeded_rng(seed),
            draws: 0,
        }
    }
}

impl rand::TryRng for CountingRng {
    type Error = core::convert::Infallible;

    fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
        self.draws += 1;
        self.inner.try_next_u32()
    }

    fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
        self.draws += 1;
        self.inner.try_next_u64()
    }

    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Self::Error> {
        self.draws += 1;
        self.inner.try_fill_bytes(dst)
    }
}

/// `k` is any `u32` in `1..=MAX_ATTEMPTS`, and a point retires after
/// exactly `k` failed candidates, a first point left alone after 64 picks
/// of `k`: in a 1 × 0.001 strip at `r = 0.999`, a first point away from
/// the ends has every candidate land outside (the box is just long enough
/// that the one-point shortcut does not apply). The 2-D annulus makes 2
/// draws for the first point, 1 per candidate (8 at a time, so none left
/// over after `64·k`), and 1 or 2 a pick (the next pick drawn ahead, and
/// this one drawn again if the one drawn ahead is past the list), so the
/// stream ends after `64·k + 2` draws plus 64 to 128.
#[test]
fn large_attempts_cost_exactly_k_candidates_per_retired_point() {
    let strip = Domain::from_extent([1.0, 0.001]).expect("box");
    // At k = MAX_ATTEMPTS, 64 picks are 4 M candidates: one layout only
    // (3 s in a debug build).
    for (k, layouts) in [
        (1, &LAYOUTS[..]),
        (30, &LAYOUTS[..]),
        (MAX_ATTEMPTS, &LAYOUTS[..1]),
    ] {
        for &layout in layouts {
            let s = PoissonDisk2::builder(strip, 0.999)
                .attempts(k)
                .layout(layout)
                .build()
                .expect("any k in 1..=MAX_ATTEMPTS is valid");
            let mut rng = CountingRng::new(4);
            let points: Vec<[f64; 2]> = s.iter(&mut rng).collect();
            assert_eq!(points.len(), 1, "k = {k}, {layout:?}: one point");
            assert!(
                (0.002..0.998).contains(&points[0][0]),
                "seed 4 must put the first point away from the ends: {points:?}"
            );
            let needed = 64 * u64::from(k) + 2;
            assert!(
                (needed + 64..=needed + 128).contains(&rng.draws),
                "k = {k}, {layout:?}: {} draws until the stream ends",
                rng.draws
            );
        }
    }
}

/// From 5-D up most throws around a point near a corner leave the box: in
/// an 8-D unit cube at `r = 0.4`, all 30 around seed 1's first point did,
/// and the run ended at one point. A first point left alone gets more
/// picks; the set it then grows is full and valid.
#[test]
fn a_first_point_near_a_corner_does_not_end_the_run() {
    let cube = Domain::from_extent([1.0; 8]).expect("box");
    let s = PoissonDisk::new(cube, 0.4).expect("valid");
    for seed in [1, 2] {
        let n = assert_valid(&s, seed, usize::MAX);
        assert!(n > 2000, "8-D r = 0.4, seed {seed}: {n} points");
    }
}

/// A box that holds only one point (its diameter, or half-period diagonal,
/// is below `r`) ends after it, without throwing a candidate, whatever `k`.
#[test]
fn a_box_for_one_point_ends_at_once() {
    let cell = Domain::from_extent([0.03, 0.05])
        .expect("box")
        .with_periodic([true, true]);
    for k in [1, MAX_ATTEMPTS] {
        for layout in LAYOUTS {
            let s = PoissonDisk2::builder(cell, 0.1)
                .attempts(k)
                .layout(layout)
                .build()
                .expect("valid");
            let mut rng = CountingRng::new(4);
            assert_eq!(s.iter(&mut rng).count(), 1, "k = {k}, {layout:?}");
            assert_eq!(rng.draws, 2, "k = {k}, {layout:?}: the first point only");
        }
    }
}

/// `k = MAX_ATTEMPTS` is accepted, and the stream is lazy: with annulus
/// candidates the first points come at once. A full run is another matter:
/// every point retires only after `k` failed throws, so a run costs about
/// `n·k` throws whatever the cap. Above `MAX_ATTEMPTS`, `build()` refuses.
#[test]
fn huge_attempts_are_refused_and_the_largest_is_lazy() {
    let roomy = Domain::from_extent([1000.0, 1000.0]).expect("box");
    for k in [MAX_ATTEMPTS + 1, u32::MAX] {
        assert_eq!(
            PoissonDisk2::builder(roomy, 1.0).attempts(k).build(),
            Err(Error::TooManyAttempts { max: MAX_ATTEMPTS }),
            "k = {k}"
        );
    }
    let s = PoissonDisk2::builder(roomy, 1.0)
        .attempts(MAX_ATTEMPTS)
        .build()
        .expect("k = MAX_ATTEMPTS is valid");
    let mut rng = CountingRng::new(5);
    let points: Vec<[f64; 2]> = s.iter(&mut rng).take(4).collect();
    assert_eq!(points.len(), 4, "four points");
    assert!(
        rng.draws < 1000,
        "{} draws for the first four points",
        rng.draws
    );
    let d = s.domain();
    if let Err(report) = common::check_points(&points, 1.0, d.lo(), d.hi(), d.periodic()) {
        panic!("{report}");
    }
}

// ---------------------------------------------------------------- grid size

fn huge_box() -> Domain<2> {
    Domain::from_extent([1e6, 1e6]).expect("valid box")
}

/// Runs `sampler` to its end, checking after every point that the memory
/// it holds is within its budget and that its points are valid; returns
/// the count and why the run ended early, if it did.
fn run_within_budget<const N: usize>(
    sampler: &PoissonDisk<N>,
    seed: u64,
) -> (usize, Option<Error>) {
    let budget = sampler.max_grid_bytes();
    // In a region (the whole box): never refused up front, so the run
    // grows until the budget (`a_plain_run_expected_far_over_is_refused`
    // has the plain run).
    let mut it = sampler
        .iter_with_seeded(seed, Everywhere, &[])
        .expect("no pre-placed points");
    let mut points = Vec::new();
    while let Some(p) = it.next() {
        points.push(p);
        assert!(
            it.heap_bytes() <= budget,
            "{} bytes held after {} points, budget {budget}",
            it.heap_bytes(),
            points.len()
        );
    }
    let d = sampler.domain();
    if let Err(report) =
        common::check_points(&points, sampler.radius(), d.lo(), d.hi(), d.periodic())
    {
        panic!("{report}");
    }
    (points.len(), it.error())
}

/// A plain run whose expected points need over twice the budget is
/// refused at once, with no point and no grid walked; with a cap within the
/// budget it runs.
#[test]
fn a_plain_run_expected_far_over_is_refused() {
    let budget = 1 << 20;
    let s = PoissonDisk2::builder(huge_box(), 1e-3)
        .max_grid_bytes(budget)
        .build()
        .expect("the sparse grid starts empty");
    let mut it = s.iter_seeded(1);
    assert_eq!(it.next(), None, "no point");
    match it.error() {
        Some(Error::RunTooLarge {
            expected_points,
            needed,
            budget: b,
        }) => {
            assert!(
                expected_points > 1 << 50,
                "{expected_points} points expected"
            );
            assert!(needed > 2 * b && b == budget, "{needed} bytes needed");
        }
        other => panic!("expected RunTooLarge, got {other:?}"),
    }
    let capped = s.to_builder().max_points(1000).build().expect("valid");
    assert_eq!(
        capped.generate_seeded(1).map(|p| p.len()),
        Ok(1000),
        "capped"
    );
}

/// A tiny radius in a huge box: the paged grid is not refused up front
/// (it allocates one page for its first point); the run
/// stops cleanly when the next point would take it past the budget, and
/// says so. A dense grid of 1e18 cells is refused by `build()`.
#[test]
fn tiny_radius_in_a_huge_box_stops_at_the_budget() {
    let budget = 1 << 20;
    let s = PoissonDisk2::builder(huge_box(), 1e-3)
        .max_grid_bytes(budget)
        .build()
        .expect("the paged grid starts with a page");
    assert_eq!(s.resolved_layout(), GridLayout::Paged, "paged");
    let (n, error) = run_within_budget(&s, 1);
    assert!(n > 1000, "{n} points in 1 MiB");
    assert_eq!(
        error,
        Some(Error::MemoryBudgetExceeded {
            points: n as u64,
            budget
        }),
        "the reason"
    );
    // `generate` on a box it does not refuse (about 45 000 points, under
    // twice the budget at 16 bytes each): the same stop, the points kept.
    let moderate = PoissonDisk2::builder(unit_square(), 0.0037)
        .max_grid_bytes(budget)
        .build()
        .expect("valid");
    let (n, _) = run_within_budget(&moderate, 1);
    let stopped = moderate.generate_seeded(1).expect_err("over budget");
    assert_eq!(
        stopped.error(),
        Error::MemoryBudgetExceeded {
            points: n as u64,
            budget
        },
        "generate reports it too"
    );
    assert_eq!(stopped.points().len(), n, "and keeps the points made");
    assert_eq!(
        PoissonDisk2::builder(huge_box(), 1e-3)
            .layout(GridLayout::Dense)
            .build(),
        Err(Error::GridTooLarge {
            needed: u64::MAX,
            budget: DEFAULT_MAX_GRID_BYTES
        }),
        "a dense grid of 1e18 cells"
    );
}

#[test]
fn a_point_cap_makes_the_huge_box_complete() {
    let capped = PoissonDisk2::builder(huge_box(), 1e-3)
        .max_points(1000)
        .build()
        .expect("the paged grid starts with a page");
    assert_eq!(
        capped.resolved_layout(),
        GridLayout::Paged,
        "the dense grid cannot fit: pages"
    );
    assert!(
        capped.grid_bytes() <= DEFAULT_MAX_GRID_BYTES,
        "planned {} bytes",
        capped.grid_bytes()
    );
    let (n, error) = run_within_budget(&capped, 3);
    assert_eq!(n, 1000, "the box holds far more than 1000 points");
    assert_eq!(error, None, "a cap is no error");
}

/// The budget `build()` checks is what a grid allocates before its first
/// point: a budget of 0 refuses every layout, an astronomical dense grid
/// is refused with `needed` saturated at `u64::MAX`, and an accepted
/// sampler's up-front bytes never exceed its budget. The rest is counted as
/// the points come.
#[test]
fn the_budget_is_checked_by_build() {
    for layout in LAYOUTS {
        match PoissonDisk2::builder(unit_square(), 0.1)
            .layout(layout)
            .max_grid_bytes(0)
            .build()
        {
            Err(Error::GridTooLarge { needed, budget }) => {
                assert_eq!(budget, 0, "{layout:?}: the budget in force");
                assert!(needed > 0, "{layout:?}: needed {needed}");
            }
            other => panic!("{layout:?}: expected GridTooLarge, got {other:?}"),
        }
    }
    for budget in [1 << 12, 1 << 16, 1 << 20, 1 << 24, DEFAULT_MAX_GRID_BYTES] {
        for layout in LAYOUTS {
            for cap in [u64::MAX, 100] {
                let built = PoissonDisk2::builder(unit_square(), 0.002)
                    .layout(layout)
                    .max_grid_bytes(budget)
                    .max_points(cap)
                    .build();
                if let Ok(s) = built {
                    assert!(
                        s.grid_bytes() <= budget,
                        "{layout:?}, cap {cap:?}: planned {} > budget {budget}",
                        s.grid_bytes()
                    );
                    if budget <= 1 << 20 {
                        let (n, error) = run_within_budget(&s, 2);
                        let complete = if cap == u64::MAX {
                            error.is_none()
                        } else {
                            n as u64 == cap
                        };
                        assert!(
                            complete || matches!(error, Some(Error::MemoryBudgetExceeded { .. })),
                            "{layout:?}, cap {cap:?}, budget {budget}: {n} points, {error:?}"
                        );
                    }
                }
            }
        }
    }
}

/// `Some(u64::MAX)` is the same as no cap, and `size_hint` reports a cap.
#[test]
fn a_cap_of_u64_max_is_no_cap() {
    let builder = PoissonDisk2::builder(unit_square(), 0.05);
    let uncapped = builder.build().expect("valid");
    let capped = builder.max_points(u64::MAX).build().expect("valid");
    assert_eq!(
        capped.generate_seeded(8).unwrap(),
        uncapped.generate_seeded(8).unwrap(),
        "same points"
    );
    let seven = builder.max_points(7).build().expect("valid");
    assert_eq!(seven.iter_seeded(8).size_hint(), (0, Some(7)), "size_hint");
    assert_eq!(
        seven.generate_seeded(8).unwrap(),
        uncapped.generate_seeded(8).unwrap()[..7],
        "a cap is a prefix of the uncapped stream"
    );
}

/// The same through a deserialised configuration.
#[cfg(feature = "serde")]
#[test]
fn a_point_cap_makes_the_huge_box_complete_from_json() {
    let json = r#"{
        "domain": {"lo": [0.0, 0.0], "hi": [1e6, 1e6], "periodic": [false, false]},
        "radius": 1e-3,
        "max_points": 1000
    }"#;
    let capped: PoissonDisk2 = serde_json::from_str(json).expect("capped sampler fits");
    let n = assert_valid(&capped, 3, usize::MAX);
    assert_eq!(n, 1000, "{n} points, cap 1000");
    let dense = json.replace("\"max_points\": 1000", "\"layout\": \"dense\"");
    let err = serde_json::from_str::<PoissonDisk2>(&dense).expect_err("dense: too large");
    assert!(
        err.to_string().contains("budget"),
        "the message names the budget: {err}"
    );
}

/// A box whose dense grid fits the default budget but not a small one:
/// under the small budget the paged grid runs until the budget, and a
/// point cap within it completes.
#[test]
fn a_small_budget_stops_the_run_and_a_cap_completes_it() {
    let domain = Domain::from_extent([10.0, 10.0]).expect("valid box");
    assert_eq!(
        PoissonDisk2::new(domain, 0.01).map(|s| s.resolved_layout()),
        Ok(GridLayout::Dense),
        "dense fits the default 1 GiB"
    );
    let budget = 1 << 20;
    let small = PoissonDisk2::builder(domain, 0.01).max_grid_bytes(budget);
    let uncapped = small.build().expect("the paged grid starts with a page");
    assert_eq!(uncapped.resolved_layout(), GridLayout::Paged, "paged");
    let (n, error) = run_within_budget(&uncapped, 4);
    assert!(
        matches!(error, Some(Error::MemoryBudgetExceeded { points, budget: b })
            if points == n as u64 && b == budget),
        "{n} points, {error:?}"
    );
    let capped = small
        .max_points(1000)
        .build()
        .expect("a cap of 1000 points fits 1 MiB");
    assert!(capped.grid_bytes() <= budget, "planned within budget");
    let (n, error) = run_within_budget(&capped, 4);
    assert_eq!(
        (n, error),
        (1000, None),
        "a 10 × 10 box at r = 0.01 holds far more"
    );
}

#[test]
fn forced_dense_over_budget_is_grid_too_large() {
    let budget = 1 << 20;
    // Capped, so pages fit the small budget and Auto is fine...
    let small = PoissonDisk2::builder(unit_square(), 0.001)
        .max_points(100)
        .max_grid_bytes(budget);
    let auto = small.build().expect("pages fit under the cap");
    assert_eq!(
        auto.resolved_layout(),
        GridLayout::Paged,
        "Auto falls back to pages"
    );
    // ...but the dense grid of ~1400² cells does not.
    let dense_bytes = PoissonDisk2::builder(unit_square(), 0.001)
        .layout(GridLayout::Dense)
        .build()
        .expect("dense fits the default budget")
        .grid_bytes();
    assert!(dense_bytes > budget, "{dense_bytes} bytes");
    assert_eq!(
        small.layout(GridLayout::Dense).build(),
        Err(Error::GridTooLarge {
            needed: dense_bytes,
            budget
        }),
        "forced Dense over budget"
    );
}

/// Found by the `batch` fuzz target: a forced dense grid that could hold
/// 2³² points or more (its `u32` indices run out) was refused with the
/// grid's byte count as `needed`, which could be within the budget
/// ("needs 36241146383744 bytes, over the budget of 9007199254740992").
/// No budget makes such a grid possible, so `needed` is `u64::MAX`.
#[test]
fn a_dense_grid_past_u32_indices_is_refused_whatever_the_budget() {
    // About 1.3e10 points fit in the unit square at r = 1e-5.
    let dense = PoissonDisk2::builder(unit_square(), 1e-5).layout(GridLayout::Dense);
    for budget in [1 << 40, 1 << 53, u64::MAX] {
        assert_eq!(
            dense.max_grid_bytes(budget).build(),
            Err(Error::GridTooLarge {
                needed: u64::MAX,
                budget
            }),
            "budget {budget}"
        );
    }
    // The same in 8-D, as the fuzzer found it.
    let mut lo = [469.828_125; 8];
    let mut hi = [475.358_209_135_837_06; 8];
    lo[0] = 117.0;
    hi[0] = 127.999_916_076_660_16;
    let domain = Domain::new(lo, hi)
        .expect("valid box")
        .with_periodic([true, false, true, false, true, true, true, false]);
    let budget = 1 << 53;
    let err = PoissonDisk::builder(domain, f64::from_bits(0x3fdf_fff0_0000_0000))
        .layout(GridLayout::Dense)
        .max_grid_bytes(budget)
        .build()
        .expect_err("too many points for u32 indices");
    assert_eq!(
        err,
        Error::GridTooLarge {
            needed: u64::MAX,
            budget
        },
        "8-D"
    );
    // Auto falls back to the sparse grid, which has no such limit (pages
    // index their points with `u32` too).
    let auto = PoissonDisk2::builder(unit_square(), 1e-5)
        .max_grid_bytes(u64::MAX)
        .build()
        .expect("sparse fits an unlimited budget");
    assert_eq!(auto.resolved_layout(), GridLayout::Sparse, "Auto");
}

// ---------------------------------------------------------------- messages

#[test]
fn display_messages_name_the_failed_condition() {
    let dense_over = PoissonDisk2::builder(unit_square(), 0.001)
        .layout(GridLayout::Dense)
        .max_grid_bytes(1000)
        .build()
        .expect_err("over budget");
    let Error::GridTooLarge { needed, budget } = dense_over else {
        panic!("expected GridTooLarge, got {dense_over:?}");
    };
    let huge = PoissonDisk2::builder(huge_box(), 1e-3)
        .layout(GridLayout::Dense)
        .build()
        .expect_err("too large");
    // A run expected to need less than twice the budget starts, and stops
    // at the budget; one expected far over it is refused at once.
    let stopped = PoissonDisk2::builder(unit_square(), 0.02)
        .max_grid_bytes(1 << 16)
        .build()
        .expect("sparse")
        .generate_seeded(1)
        .expect_err("over budget")
        .error();
    let refused = PoissonDisk2::builder(huge_box(), 1e-3)
        .max_grid_bytes(1 << 16)
        .build()
        .expect("sparse")
        .generate_seeded(1)
        .expect_err("refused");
    assert!(refused.points().is_empty(), "a refused run makes no point");
    let Error::RunTooLarge {
        expected_points, ..
    } = refused.error()
    else {
        panic!("expected RunTooLarge, got {refused:?}");
    };
    let Error::MemoryBudgetExceeded { points, .. } = stopped else {
        panic!("expected MemoryBudgetExceeded, got {stopped:?}");
    };
    let cases: Vec<(Error, Vec<String>)> = vec![
        (
            Domain::<0>::new([], []).expect_err("N = 0"),
            vec!["dimension".into()],
        ),
        (
            radius_error(-1.0).expect_err("bad radius"),
            vec!["radius".into()],
        ),
        (
            Domain::new([0.0, 0.0], [1.0, f64::NAN]).expect_err("NaN"),
            vec!["axis 1".into(), "finite".into()],
        ),
        (
            Domain::new([0.0, 0.0, 1.0], [1.0, 1.0, 1.0]).expect_err("empty"),
            vec!["axis 2".into(), "empty".into(), "lo must be < hi".into()],
        ),
        (
            Domain::new([-1e308], [1e308]).expect_err("overflow"),
            vec!["axis 0".into(), "overflow".into()],
        ),
        (
            PoissonDisk2::builder(unit_square(), 0.1)
                .attempts(0)
                .build()
                .expect_err("k = 0"),
            vec!["attempts".into()],
        ),
        (
            dense_over,
            vec![
                format!("{needed} bytes"),
                format!("budget of {budget} bytes"),
            ],
        ),
        (
            huge,
            vec!["budget".into(), format!("{DEFAULT_MAX_GRID_BYTES} bytes")],
        ),
        (
            stopped,
            vec![
                format!("after {points} points"),
                "budget of 65536 bytes".into(),
                "valid".into(),
            ],
        ),
        (
            refused.error(),
            vec![
                format!("about {expected_points} points"),
                "budget of 65536 bytes".into(),
                "larger radius".into(),
            ],
        ),
        (
            PoissonDisk2::builder(unit_square(), 0.1)
                .attempts(u32::MAX)
                .build()
                .expect_err("k too large"),
            vec!["attempts".into(), format!("at most {MAX_ATTEMPTS}")],
        ),
    ];
    for (error, words) in cases {
        let message = error.to_string();
        assert!(!message.is_empty(), "{error:?} has an empty message");
        for word in words {
            assert!(
                message.contains(&word),
                "{error:?}: message {message:?} does not mention {word:?}"
            );
        }
        let as_std: &dyn std::error::Error = &error;
        assert!(as_std.source().is_none(), "{error:?}: no source error");
    }
}

// ---------------------------------------------------------------- awkward but valid

/// Many attempts, so that a thin domain, where few candidates land inside,
/// still fills up: with `k = 30` a strip or rod often stays at one point
/// (each candidate has a small chance to land in it), which is valid but
/// says little.
const MANY_ATTEMPTS: u32 = 2000;

/// Seeds the thin-domain runs with [`MANY_ATTEMPTS`] take, from the given
/// one on.
const THIN_SEEDS: u64 = 9;

/// Validity with the default `k`; and with [`MANY_ATTEMPTS`], over
/// [`THIN_SEEDS`] seeds, valid sets of at most `max_filled` points (the
/// packing bound) whose median count is at least `min_filled`.
///
/// The median, not every seed: even with 2 000 attempts a chain of points
/// along a thin rod can stop early, when one end point's throws all miss
/// the rod on its open side (in the 2 × 0.01 × 0.05 rod below, about 3.4
/// throws of 2 000 land there, so a pick misses with probability about
/// `e^-3.4`, and a run meets some ten such ends). The same rod at the
/// origin (`points --dim 3 --radius 0.1 --extent 2,0.01,0.05 --attempts
/// 2000`) gave 4 to 15 points on seeds 1–40, 5 of them under 10, before
/// the batch sampler's offsets went 32 at a time, and 5 to 15 on seeds
/// 1–30, 7 under 10, after.
fn assert_thin_domain<const N: usize>(
    domain: Domain<N>,
    r: f64,
    layout: GridLayout,
    candidates: Candidates,
    seed: u64,
    min_filled: usize,
    max_filled: usize,
) {
    let builder = PoissonDisk::builder(domain, r)
        .layout(layout)
        .candidates(candidates);
    let sampler = builder.build().expect("valid");
    let n = assert_valid(&sampler, seed, usize::MAX);
    assert!(n >= 1, "{domain:?} {layout:?} {candidates:?}: no point");
    let many = builder
        .attempts(MANY_ATTEMPTS)
        .build()
        .expect("k = 2000 is valid");
    let mut counts: Vec<usize> = (seed..seed + THIN_SEEDS)
        .map(|s| assert_valid(&many, s, usize::MAX))
        .collect();
    counts.sort_unstable();
    let median = counts[counts.len() / 2];
    assert!(
        counts.iter().all(|&n| (1..=max_filled).contains(&n)) && median >= min_filled,
        "{domain:?} {layout:?} {candidates:?} k = {MANY_ATTEMPTS}: counts {counts:?}, \
         expected at most {max_filled} and a median of at least {min_filled}"
    );
}

const LAYOUTS: [GridLayout; 3] = [GridLayout::Auto, GridLayout::Dense, GridLayout::Sparse];
const CANDIDATES: [Candidates; 2] = [Candidates::Annulus, Candidates::Sphere];

#[test]
fn box_thinner_than_r_on_an_axis() {
    for candidates in CANDIDATES {
        // Pages too: these boxes are bounded.
        for layout in LAYOUTS.into_iter().chain([GridLayout::Paged]) {
            // A 1 × 0.01 strip at r = 0.1: between 1 / 0.2 and 1 / 0.1 + 1.
            let strip = Domain::from_extent([1.0, 0.01]).expect("box");
            assert_thin_domain(strip, 0.1, layout, candidates, 5, 5, 11);
            // A 2 × 0.01 × 0.05 rod at r = 0.1.
            let rod = Domain::new([-1.0, 2.0, 0.0], [1.0, 2.01, 0.05]).expect("box");
            assert_thin_domain(rod, 0.1, layout, candidates, 6, 10, 21);
        }
    }
}

#[test]
fn one_dimension_works() {
    for candidates in CANDIDATES {
        for layout in LAYOUTS {
            for periodic in [false, true] {
                let domain = Domain::new([-3.0], [7.0])
                    .expect("box")
                    .with_periodic([periodic]);
                let s = PoissonDisk::<1>::builder(domain, 0.1)
                    .layout(layout)
                    .candidates(candidates)
                    .build()
                    .expect("valid");
                let n = assert_valid(&s, 7, usize::MAX);
                // A maximal set leaves no gap of 2r: at least L / 2r points.
                // Allow slack for the finite number of attempts.
                assert!(
                    n >= 40,
                    "{candidates:?} {layout:?} periodic={periodic}: only {n} points in 10 / 0.1"
                );
                assert!(n <= 100, "{n} points cannot be 0.1 apart in a length of 10");
            }
        }
    }
}

#[test]
fn periodic_axis_shorter_than_r() {
    for candidates in CANDIDATES {
        for layout in LAYOUTS {
            // Period 0.05 < r = 0.1 on x: points are spaced along y only.
            let strip = Domain::from_extent([0.05, 1.0])
                .expect("box")
                .with_periodic([true, false]);
            assert_thin_domain(strip, 0.1, layout, candidates, 8, 5, 11);
            // 3-D, two short periodic axes of different lengths.
            let rod = Domain::new([0.0, -1.0, 5.0], [0.07, 1.0, 5.03])
                .expect("box")
                .with_periodic([true, false, true]);
            assert_thin_domain(rod, 0.1, layout, candidates, 10, 10, 21);
            // Every axis periodic and shorter than r: exactly one point fits.
            let cell = Domain::from_extent([0.03, 0.05])
                .expect("box")
                .with_periodic([true, true]);
            assert_thin_domain(cell, 0.1, layout, candidates, 9, 1, 1);
        }
    }
}

#[test]
fn a_zero_cap_yields_nothing() {
    let s = PoissonDisk2::builder(unit_square(), 0.1)
        .max_points(0)
        .build()
        .expect("valid");
    assert_eq!(s.generate_seeded(1).unwrap().len(), 0, "cap 0");
    assert_eq!(s.iter_seeded(1).size_hint(), (0, Some(0)), "size_hint");
}

/// A cap is a `u64` (a negative one does not compile: the doctest on
/// `max_points` holds that); a later cap replaces an earlier one, and
/// `u64::MAX` means no cap.
#[test]
fn a_cap_is_unsigned_and_max_means_none() {
    let builder = PoissonDisk2::builder(unit_square(), 0.1);
    let s = builder.max_points(12).build().expect("valid");
    assert_eq!(s.max_points(), Some(12), "cap 12");
    assert_eq!(s.generate_seeded(2).unwrap().len(), 12, "cap 12 points");
    assert_eq!(
        builder
            .max_points(3)
            .max_points(u64::MAX)
            .build()
            .map(|s| s.max_points()),
        Ok(None),
        "u64::MAX clears a cap"
    );
}

/// Name, `lo`, `hi`, periodic axes and radius.
type ExtremeCase = (&'static str, [f64; 2], [f64; 2], [bool; 2], f64);

/// Extreme but accepted inputs: whatever the constructor says, nothing
/// panics, and any points made are valid.
#[test]
fn extreme_inputs_never_panic() {
    let cases: Vec<ExtremeCase> = vec![
        (
            "subnormal extent",
            [0.0, 0.0],
            [5e-324, 1.0],
            [false, false],
            0.1,
        ),
        (
            "subnormal periodic extent",
            [0.0, 0.0],
            [5e-324, 1.0],
            [true, false],
            0.1,
        ),
        (
            "1e-300 periodic extent",
            [0.0, 0.0],
            [1e-300, 1.0],
            [true, true],
            0.1,
        ),
        (
            "far from the origin",
            [1e15, -1e15],
            [1e15 + 100.0, -1e15 + 100.0],
            [false, true],
            1.0,
        ),
        (
            "one ulp wide",
            [1.0, 0.0],
            [1.0 + f64::EPSILON, 1.0],
            [false, false],
            0.05,
        ),
        (
            "one ulp wide, periodic",
            [1.0, 0.0],
            [1.0 + f64::EPSILON, 1.0],
            [true, false],
            0.05,
        ),
        (
            "radius 1e150 in a box of 1e151",
            [-5e150, 0.0],
            [5e150, 1e151],
            [false, true],
            1e150,
        ),
        (
            "radius 1e-150 in a box of 1e-149",
            [0.0, 2e-149],
            [1e-149, 3e-149],
            [true, false],
            1e-150,
        ),
        (
            "huge box, radius 1e150",
            [-0.8e308, -0.8e308],
            [0.8e308, 0.8e308],
            [false, false],
            1e150,
        ),
        (
            "huge periodic box",
            [-0.8e308, 0.0],
            [0.8e308, 1.0],
            [true, false],
            0.1,
        ),
    ];
    for (name, lo, hi, periodic, r) in cases {
        let domain = Domain::new(lo, hi)
            .expect("valid box")
            .with_periodic(periodic);
        for candidates in CANDIDATES {
            for layout in LAYOUTS {
                let sampler = PoissonDisk2::builder(domain, r)
                    .layout(layout)
                    .candidates(candidates)
                    .build();
                match sampler {
                    Ok(s) => {
                        let n = assert_valid(&s, 11, 3000);
                        eprintln!("{name}, {candidates:?}, {layout:?}: {n} points");
                    }
                    Err(e) => {
                        assert!(
                            matches!(e, Error::GridTooLarge { .. } | Error::BoxTooWide { .. }),
                            "{name}, {layout:?}: unexpected {e:?}"
                        );
                        eprintln!("{name}, {candidates:?}, {layout:?}: {e}");
                    }
                }
            }
        }
    }
}

#[test]
fn box_wider_than_2_pow_40_radii_is_box_too_wide_even_with_a_cap() {
    let domain = Domain::from_extent([1.0, 1e6]).expect("valid box");
    let result = PoissonDisk2::builder(domain, 1e-7)
        .max_points(10)
        .max_grid_bytes(u64::MAX)
        .build();
    let err = result.expect_err("1e13 radii wide must be refused");
    assert_eq!(err, Error::BoxTooWide { axis: 1 }, "variant and axis");
    assert!(err.to_string().contains("2^40"), "message: {err}");
    // 1e12 radii (< 2^40) with a cap is fine.
    let ok = PoissonDisk2::builder(domain, 1e-6).max_points(10).build();
    assert!(ok.is_ok(), "{ok:?}");
}

/// `BoxTooWide` starts one ulp past 2⁴⁰ radii; at exactly 2⁴⁰ radii a
/// capped sampler works.
#[test]
fn box_too_wide_starts_just_past_2_pow_40_radii() {
    let limit = 2f64.powi(40);
    let at = Domain::from_extent([limit, 1.0]).expect("valid box");
    let s = PoissonDisk2::builder(at, 1.0)
        .max_points(20)
        .build()
        .expect("exactly 2^40 radii is accepted");
    assert_eq!(s.resolved_layout(), GridLayout::Sparse, "sparse");
    assert_eq!(assert_valid(&s, 12, usize::MAX), 20, "the cap is reached");
    let past = Domain::from_extent([1.0, limit.next_up()]).expect("valid box");
    assert_eq!(
        PoissonDisk2::builder(past, 1.0).max_points(20).build(),
        Err(Error::BoxTooWide { axis: 1 }),
        "one ulp past 2^40 radii"
    );
}

/// Negative, subnormal and far-from-zero coordinates are ordinary values.
#[test]
fn negative_and_subnormal_bounds_are_ordinary_values() {
    let negative = Domain::new([-3.0, -1e6 - 1.0], [-1.0, -1e6]).expect("valid box");
    let s = PoissonDisk2::new(negative, 0.1).expect("valid");
    assert!(assert_valid(&s, 13, usize::MAX) > 100, "fills the box");
    // A box between two subnormals is 2 ulps wide: one point fits.
    let subnormal = Domain::new([5e-324], [1.5e-323]).expect("a 2-ulp box");
    let s = PoissonDisk::<1>::new(subnormal, 1e-150).expect("valid");
    assert_eq!(assert_valid(&s, 14, usize::MAX), 1, "one point");
}

/// Coordinates are never `hi`, even where rounding can reach it: wrapped
/// periodic candidates, few-ulp boxes, and boxes far from the origin
/// whose coordinates are whole numbers.
#[test]
fn no_point_ever_equals_hi() {
    let far = 2f64.powi(52);
    let cases: Vec<(Domain<2>, f64)> = vec![
        (
            Domain::new([1.0, 0.0], [1.0 + 4.0 * f64::EPSILON, 1.0]).expect("box"),
            0.05,
        ),
        (
            Domain::new([far, -far], [far + 8.0, -far + 6.0]).expect("box"),
            1.0,
        ),
        (Domain::new([0.0, 0.0], [1e-300, 1.0]).expect("box"), 0.1),
        (Domain::from_extent([1.0, 1.0]).expect("box"), 0.1),
    ];
    for (domain, r) in cases {
        for periodic in [[false, false], [true, false], [true, true]] {
            let d = domain.with_periodic(periodic);
            let hi = d.hi();
            for candidates in CANDIDATES {
                for layout in LAYOUTS {
                    let built = PoissonDisk2::builder(d, r)
                        .layout(layout)
                        .candidates(candidates)
                        .build();
                    // A forced dense grid cannot reach r across a 1e-300
                    // axis; Auto then takes the sparse one.
                    let Ok(s) = built else {
                        assert_ne!(layout, GridLayout::Auto, "{d:?}: {built:?}");
                        continue;
                    };
                    for seed in 0..20 {
                        for p in s.iter_seeded(seed) {
                            assert!(
                                p[0] < hi[0] && p[1] < hi[1],
                                "{d:?} {candidates:?} {layout:?} seed {seed}: {p:?} reaches hi"
                            );
                        }
                        assert_valid(&s, seed, usize::MAX);
                    }
                }
            }
        }
    }
}
