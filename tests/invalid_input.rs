//! Every invalid input is a precise `Error` from a constructor, never a
//! panic; and some awkward but valid inputs (thin boxes, 1-D, periods
//! shorter than `r`, extreme magnitudes) work and give valid points.

mod common;

use bridson::{
    Candidates, DEFAULT_MAX_GRID_BYTES, Domain, Error, GridLayout, PoissonDisk, PoissonDisk2,
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

// ---------------------------------------------------------------- grid size

fn huge_box() -> Domain<2> {
    Domain::from_extent([1e6, 1e6]).expect("valid box")
}

#[test]
fn tiny_radius_in_a_huge_box_is_grid_too_large() {
    match PoissonDisk2::new(huge_box(), 1e-3) {
        Err(Error::GridTooLarge { needed, budget }) => {
            assert_eq!(budget, DEFAULT_MAX_GRID_BYTES, "the default budget");
            assert!(needed > budget, "needed {needed} <= budget {budget}");
        }
        other => panic!("expected GridTooLarge, got {other:?}"),
    }
}

#[test]
fn a_point_cap_makes_the_huge_box_feasible() {
    let capped = PoissonDisk2::builder(huge_box(), 1e-3)
        .max_points(Some(1000))
        .build()
        .expect("a cap of 1000 points fits the default budget");
    assert_eq!(
        capped.resolved_layout(),
        GridLayout::Sparse,
        "only the sparse grid can fit"
    );
    assert!(
        capped.grid_bytes() <= DEFAULT_MAX_GRID_BYTES,
        "planned {} bytes",
        capped.grid_bytes()
    );
    let n = assert_valid(&capped, 3, usize::MAX);
    assert!((1..=1000).contains(&n), "{n} points, cap 1000");
    assert_eq!(n, 1000, "the box holds far more than 1000 points");
    // Lifting the cap again is too large.
    assert!(
        matches!(
            capped.to_builder().max_points(None).build(),
            Err(Error::GridTooLarge { .. })
        ),
        "no cap: too large"
    );
}

/// The same through a deserialised configuration.
#[cfg(feature = "serde")]
#[test]
fn a_point_cap_makes_the_huge_box_feasible_from_json() {
    let json = r#"{
        "domain": {"lo": [0.0, 0.0], "hi": [1e6, 1e6], "periodic": [false, false]},
        "radius": 1e-3,
        "max_points": 1000
    }"#;
    let capped: PoissonDisk2 = serde_json::from_str(json).expect("capped sampler fits");
    let n = assert_valid(&capped, 3, usize::MAX);
    assert!((1..=1000).contains(&n), "{n} points, cap 1000");
    let uncapped = json.replace("\"max_points\": 1000", "\"max_points\": null");
    let err = serde_json::from_str::<PoissonDisk2>(&uncapped).expect_err("no cap: too large");
    assert!(
        err.to_string().contains("budget"),
        "the message names the budget: {err}"
    );
}

/// A box whose dense grid fits the default budget but not a small one; a
/// point cap then lets the sparse grid fit.
#[test]
fn a_point_cap_makes_a_small_budget_feasible() {
    let domain = Domain::from_extent([10.0, 10.0]).expect("valid box");
    assert!(
        PoissonDisk2::new(domain, 0.01).is_ok(),
        "fits the default 1 GiB"
    );
    let budget = 1 << 20;
    let small = PoissonDisk2::builder(domain, 0.01).max_grid_bytes(budget);
    match small.build() {
        Err(Error::GridTooLarge {
            needed,
            budget: reported,
        }) => {
            assert_eq!(reported, budget, "the budget in force is reported");
            assert!(needed > budget, "needed {needed} <= budget {budget}");
        }
        other => panic!("expected GridTooLarge without a cap, got {other:?}"),
    }
    let capped = small
        .max_points(Some(1000))
        .build()
        .expect("a cap of 1000 points fits 1 MiB");
    assert_eq!(
        capped.resolved_layout(),
        GridLayout::Sparse,
        "sparse under the cap"
    );
    assert!(capped.grid_bytes() <= budget, "planned within budget");
    let n = assert_valid(&capped, 4, usize::MAX);
    assert_eq!(
        n, 1000,
        "a 10 × 10 box at r = 0.01 holds far more than 1000"
    );
}

#[test]
fn forced_dense_over_budget_is_grid_too_large() {
    let budget = 1 << 20;
    // Capped, so the sparse grid fits the small budget and Auto is fine...
    let small = PoissonDisk2::builder(unit_square(), 0.001)
        .max_points(Some(100))
        .max_grid_bytes(budget);
    let auto = small.build().expect("sparse fits under the cap");
    assert_eq!(
        auto.resolved_layout(),
        GridLayout::Sparse,
        "Auto falls back to sparse"
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
    let huge = PoissonDisk2::new(huge_box(), 1e-3).expect_err("too large");
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

/// Validity with the default `k`, and at least `min_filled` points with
/// [`MANY_ATTEMPTS`].
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
    let n = assert_valid(&many, seed, usize::MAX);
    assert!(
        (min_filled..=max_filled).contains(&n),
        "{domain:?} {layout:?} {candidates:?} k = {MANY_ATTEMPTS}: {n} points, \
         expected {min_filled}..={max_filled}"
    );
}

const LAYOUTS: [GridLayout; 3] = [GridLayout::Auto, GridLayout::Dense, GridLayout::Sparse];
const CANDIDATES: [Candidates; 2] = [Candidates::Annulus, Candidates::Sphere];

#[test]
fn box_thinner_than_r_on_an_axis() {
    for candidates in CANDIDATES {
        for layout in LAYOUTS {
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
        .max_points(Some(0))
        .build()
        .expect("valid");
    assert_eq!(s.generate_seeded(1).len(), 0, "cap 0");
    assert_eq!(s.iter_seeded(1).size_hint(), (0, Some(0)), "size_hint");
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
        .max_points(Some(10))
        .max_grid_bytes(u64::MAX)
        .build();
    let err = result.expect_err("1e13 radii wide must be refused");
    assert_eq!(err, Error::BoxTooWide { axis: 1 }, "variant and axis");
    assert!(err.to_string().contains("2^40"), "message: {err}");
    // 1e12 radii (< 2^40) with a cap is fine.
    let ok = PoissonDisk2::builder(domain, 1e-6)
        .max_points(Some(10))
        .build();
    assert!(ok.is_ok(), "{ok:?}");
}
