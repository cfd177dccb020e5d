//! Property tests of the sampler's guarantees, checked against the naive
//! oracle in `common`, over random boxes, radii, periodic axes, candidate
//! kinds, grid layouts and seeds, in 1-D to 6-D and 8-D.
//!
//! Sizes are kept small enough for the O(n²) oracle and a debug build: up
//! to ~1500 points in 1-D to 3-D, at most a few hundred from 4-D up (the
//! sparse grid is slow there without optimisation). Set `PROPTEST_CASES`
//! for a deeper run than the default 32 / 24 cases per test.

mod common;

use bridson::{Candidates, Domain, GridLayout, PoissonDisk};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use rand::SeedableRng as _;
use rand_xoshiro::Xoshiro256PlusPlus;

/// Grid budget used when forcing the dense layout from 4-D up: keeps the
/// (huge, slow in debug) high-dimensional dense grids out of the tests.
const HIGH_DIM_DENSE_BUDGET: u64 = 32 << 20;

/// `cases` cases, unless `PROPTEST_CASES` is set (for a deeper run).
fn config(cases: u32) -> ProptestConfig {
    let default = ProptestConfig::default();
    let cases = if std::env::var_os("PROPTEST_CASES").is_some() {
        default.cases
    } else {
        cases
    };
    ProptestConfig {
        cases,
        // Failing cases are saved next to this file, in
        // `tests/properties.regressions`, and replayed first on later runs.
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("regressions"))),
        ..default
    }
}

/// One set of sampler inputs.
#[derive(Clone, Debug)]
struct Case<const N: usize> {
    seed: u64,
    lo: [f64; N],
    hi: [f64; N],
    periodic: [bool; N],
    radius: f64,
    candidates: Candidates,
    /// The point cap, as a fraction of the full count (may exceed 1).
    cap_fraction: f64,
    /// The `take(k)` length, as a fraction of the full count.
    take_fraction: f64,
}

fn to_array<T: Copy + core::fmt::Debug, const N: usize>(v: &[T]) -> [T; N] {
    v.try_into()
        .expect("the strategy makes vectors of length N")
}

/// Random inputs in `N` dimensions. The box is `lo + extent` with `lo` in
/// `-10..10` and each extent a factor in `0.2..max_axis` times `r` (so some
/// axes are thinner than `r`), the factors scaled down together so their
/// product stays at most `max_volume` (which bounds the number of points).
/// With `dyadic`, `r` is a power of two, `lo` an integer and every extent
/// a whole number of radii: grid-aligned values where cell faces and
/// distances of exactly `r` are hit exactly.
fn case<const N: usize>(max_volume: f64, max_axis: f64) -> impl Strategy<Value = Case<N>> {
    (
        any::<u64>(),
        prop::collection::vec(-10.0f64..10.0, N),
        prop::collection::vec(0.2f64..max_axis, N),
        prop::collection::vec(any::<bool>(), N),
        -2.0f64..1.0,
        any::<bool>(),
        any::<bool>(),
        0.0f64..1.2,
        0.0f64..1.2,
    )
        .prop_map(
            move |(seed, lo, factors, periodic, log_r, sphere, dyadic, cap, take)| {
                let product: f64 = factors.iter().product();
                let shrink = if product > max_volume {
                    (max_volume / product).powf(1.0 / f64::from(u8::try_from(N).unwrap_or(1)))
                } else {
                    1.0
                };
                let mut radius = 10f64.powf(log_r);
                let mut lo: [f64; N] = to_array(&lo);
                let mut factors: [f64; N] = to_array(&factors).map(|f| f * shrink);
                if dyadic {
                    #[expect(clippy::cast_possible_truncation, reason = "-7..=4")]
                    let exponent = radius.log2().round() as i32;
                    radius = 2f64.powi(exponent);
                    lo = lo.map(f64::round);
                    factors = factors.map(|f| f.floor().max(1.0));
                }
                let hi = core::array::from_fn(|i| lo[i] + factors[i] * radius);
                Case {
                    seed,
                    lo,
                    hi,
                    periodic: to_array(&periodic),
                    radius,
                    candidates: if sphere {
                        Candidates::Sphere
                    } else {
                        Candidates::Annulus
                    },
                    cap_fraction: cap,
                    take_fraction: take,
                }
            },
        )
}

/// Like [`case`], but far from the origin: `|lo|` up to `1e6` with radii
/// down to `1e-3`, where coordinates carry far fewer bits below `r`.
fn far_case<const N: usize>(max_volume: f64, max_axis: f64) -> impl Strategy<Value = Case<N>> {
    (case::<N>(max_volume, max_axis), 0.0f64..6.0, -3.0f64..0.0).prop_map(
        |(mut c, log_offset, log_r)| {
            let shift = 10f64.powf(log_offset);
            let scale = 10f64.powf(log_r) / c.radius;
            for i in 0..N {
                let extent = (c.hi[i] - c.lo[i]) * scale;
                c.lo[i] = c.lo[i].signum() * shift + c.lo[i];
                c.hi[i] = c.lo[i] + extent;
            }
            c.radius *= scale;
            c
        },
    )
}

/// Like [`case`], with the box shrunk by up to 1000 against `r` on every
/// axis: radii as large as the box or far larger, as a radius given in the
/// wrong units would be. A handful of points, or one.
fn small_box_case<const N: usize>() -> impl Strategy<Value = Case<N>> {
    (case::<N>(50.0, 4.0), 0.0f64..3.0).prop_map(|(mut c, log_shrink)| {
        let shrink = 10f64.powf(-log_shrink);
        for i in 0..N {
            c.hi[i] = c.lo[i] + (c.hi[i] - c.lo[i]) * shrink;
        }
        c
    })
}

fn sampler<const N: usize>(c: &Case<N>, layout: GridLayout) -> Result<PoissonDisk<N>, String> {
    let domain = Domain::new(c.lo, c.hi)
        .map_err(|e| format!("domain rejected: {e}"))?
        .with_periodic(c.periodic);
    let budget = if N <= 3 || layout != GridLayout::Dense {
        bridson::DEFAULT_MAX_GRID_BYTES
    } else {
        HIGH_DIM_DENSE_BUDGET
    };
    PoissonDisk::builder(domain, c.radius)
        .max_grid_bytes(budget)
        .layout(layout)
        .candidates(c.candidates)
        .build()
        .map_err(|e| format!("{layout:?} sampler rejected: {e}"))
}

/// Index `floor(fraction * (n + 2))`, so both 0 and more than `n` occur.
#[expect(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "a small, non-negative index"
)]
fn fraction_of(fraction: f64, n: usize) -> usize {
    (fraction * (n as f64 + 2.0)).floor() as usize
}

/// Every property for one case: the oracle on the sparse and (where it
/// fits) dense layouts, determinism, `iter_seeded` vs `iter`, prefixes of
/// `take(k)` and of a point cap, and that the layout never changes output.
fn check_case<const N: usize>(c: &Case<N>) -> Result<(), TestCaseError> {
    let ctx = format!("N = {N}, seed = {}, inputs = {c:?}", c.seed);
    let sparse =
        sampler(c, GridLayout::Sparse).map_err(|e| TestCaseError::fail(format!("{ctx}: {e}")))?;
    prop_assert_eq!(sparse.resolved_layout(), GridLayout::Sparse, "{}", ctx);

    // The guarantees, checked by the oracle.
    let points = sparse
        .generate_seeded(c.seed)
        .map_err(|e| TestCaseError::fail(format!("{ctx}: {e}")))?;
    let n = points.len();
    prop_assert!(n >= 1, "{}: no point at all", ctx);
    if let Err(report) = common::check_points(&points, c.radius, c.lo, c.hi, c.periodic) {
        prop_assert!(false, "{}, Sparse layout: {}", ctx, report);
    }

    // Same seed, same points (a freshly built sampler, a fresh run).
    let again = sampler(c, GridLayout::Sparse)
        .map_err(|e| TestCaseError::fail(format!("{ctx}: {e}")))?
        .generate_seeded(c.seed)
        .map_err(|e| TestCaseError::fail(format!("{ctx}: {e}")))?;
    prop_assert!(
        again == points,
        "{}: a second run with the same seed differs",
        ctx
    );

    // iter_seeded(seed) is iter(Xoshiro256PlusPlus::seed_from_u64(seed)),
    // and the stream stays ended.
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(c.seed);
    let mut it = sparse.iter(&mut rng);
    prop_assert_eq!(it.layout(), GridLayout::Sparse, "{}: built layout", ctx);
    let from_rng: Vec<[f64; N]> = it.by_ref().collect();
    prop_assert!(
        from_rng == points,
        "{}: iter(seed_from_u64(seed)) differs from generate_seeded(seed)",
        ctx
    );
    prop_assert!(it.next().is_none(), "{}: iterator not fused", ctx);

    // take(k) of the stream is a prefix of the whole.
    let k = fraction_of(c.take_fraction, n);
    let taken: Vec<[f64; N]> = sparse.iter_seeded(c.seed).take(k).collect();
    prop_assert!(
        taken[..] == points[..k.min(n)],
        "{}: take({}) is not a prefix of the {} points",
        ctx,
        k,
        n
    );

    // A point cap yields min(cap, n) points, a prefix of the uncapped run.
    let cap = fraction_of(c.cap_fraction, n);
    let capped = sparse
        .to_builder()
        .max_points(u64::try_from(cap).expect("small"))
        .build()
        .map_err(|e| TestCaseError::fail(format!("{ctx}: cap {cap} rejected: {e}")))?
        .generate_seeded(c.seed)
        .map_err(|e| TestCaseError::fail(format!("{ctx}: cap {cap}: {e}")))?;
    prop_assert!(
        capped[..] == points[..cap.min(n)],
        "{}: max_points({}) gave {} points, not the first {} of {}",
        ctx,
        cap,
        capped.len(),
        cap.min(n),
        n
    );

    // The dense layout, where it fits: valid, and the very same points.
    match sampler(c, GridLayout::Dense) {
        Ok(dense) => {
            prop_assert_eq!(dense.resolved_layout(), GridLayout::Dense, "{}", ctx);
            let dense_iter = dense.iter_seeded(c.seed);
            prop_assert_eq!(
                dense_iter.layout(),
                GridLayout::Dense,
                "{}: built layout",
                ctx
            );
            let dense_points: Vec<[f64; N]> = dense_iter.collect();
            if let Err(report) =
                common::check_points(&dense_points, c.radius, c.lo, c.hi, c.periodic)
            {
                prop_assert!(false, "{}, Dense layout: {}", ctx, report);
            }
            if let Some(i) =
                (0..n.max(dense_points.len())).find(|&i| points.get(i) != dense_points.get(i))
            {
                prop_assert!(
                    false,
                    "{}: Dense and Sparse differ first at point #{} (dense {} points {:?}, sparse {} points {:?})",
                    ctx,
                    i,
                    dense_points.len(),
                    dense_points.get(i),
                    n,
                    points.get(i)
                );
            }
        }
        Err(e) => {
            // 1-D to 3-D boxes here are small: the dense grid always fits.
            prop_assert!(N > 3, "{}: {}", ctx, e);
        }
    }

    // Pages, where they apply (bounded boxes, 1-D to 3-D): the same points.
    match sampler(c, GridLayout::Paged) {
        Ok(paged) => {
            let paged_points: Vec<[f64; N]> = paged.iter_seeded(c.seed).collect();
            prop_assert!(
                paged_points == points,
                "{}: Paged and Sparse differ ({} and {} points)",
                ctx,
                paged_points.len(),
                n
            );
        }
        Err(e) => {
            prop_assert!(N > 3 || c.periodic.iter().any(|&p| p), "{}: {}", ctx, e);
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(32))]

    #[test]
    fn properties_1d(c in case::<1>(1500.0, 2000.0)) {
        check_case(&c)?;
    }

    #[test]
    fn properties_2d(c in case::<2>(1500.0, 80.0)) {
        check_case(&c)?;
    }

    #[test]
    fn properties_3d(c in case::<3>(1000.0, 20.0)) {
        check_case(&c)?;
    }

    #[test]
    fn far_from_origin_2d(c in far_case::<2>(600.0, 50.0)) {
        check_case(&c)?;
    }

    #[test]
    fn far_from_origin_3d(c in far_case::<3>(400.0, 15.0)) {
        check_case(&c)?;
    }
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn properties_4d(c in case::<4>(300.0, 8.0)) {
        check_case(&c)?;
    }

    #[test]
    fn properties_5d(c in case::<5>(250.0, 5.0)) {
        check_case(&c)?;
    }

    #[test]
    fn properties_6d(c in case::<6>(200.0, 4.0)) {
        check_case(&c)?;
    }

    #[test]
    fn properties_8d(c in case::<8>(120.0, 3.0)) {
        check_case(&c)?;
    }
}

proptest! {
    #![proptest_config(config(16))]

    #[test]
    fn radius_large_against_the_box_1d(c in small_box_case::<1>()) {
        check_case(&c)?;
    }

    #[test]
    fn radius_large_against_the_box_2d(c in small_box_case::<2>()) {
        check_case(&c)?;
    }

    #[test]
    fn radius_large_against_the_box_3d(c in small_box_case::<3>()) {
        check_case(&c)?;
    }

    #[test]
    fn radius_large_against_the_box_4d(c in small_box_case::<4>()) {
        check_case(&c)?;
    }

    #[test]
    fn radius_large_against_the_box_5d(c in small_box_case::<5>()) {
        check_case(&c)?;
    }

    #[test]
    fn radius_large_against_the_box_6d(c in small_box_case::<6>()) {
        check_case(&c)?;
    }

    #[test]
    fn radius_large_against_the_box_7d(c in small_box_case::<7>()) {
        check_case(&c)?;
    }

    #[test]
    fn radius_large_against_the_box_8d(c in small_box_case::<8>()) {
        check_case(&c)?;
    }
}

/// The oracle's sweep along one axis finds exactly the pairs the plain
/// all-pairs check finds, in the same order: random points with clusters
/// and repeats (so that there are pairs closer than `r`, at distance 0 too),
/// on boxes with any axes periodic, some of them all.
fn sweep_matches_all_pairs<const N: usize>(
    seed: u64,
    periodic: [bool; N],
    r: f64,
) -> Result<(), TestCaseError> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let (lo, hi) = ([-1.0; N], [2.0; N]);
    let mut points: Vec<[f64; N]> = Vec::new();
    for _ in 0..300 {
        let p = match rng.random_range(0..4) {
            // Near an earlier point (within about r), or a repeat of one.
            0 | 1 if !points.is_empty() => {
                let q = points[rng.random_range(0..points.len())];
                let step = if rng.random_bool(0.2) { 0.0 } else { r };
                core::array::from_fn(|a| {
                    (q[a] + step * rng.random_range(-1.0..1.0)).clamp(-1.0, 1.9)
                })
            }
            // Near the box's faces, for the periodic axes' wrap.
            2 => core::array::from_fn(|_| {
                if rng.random_bool(0.5) {
                    rng.random_range(-1.0..-0.9)
                } else {
                    rng.random_range(1.9..2.0)
                }
            }),
            _ => core::array::from_fn(|_| rng.random_range(-1.0..2.0)),
        };
        points.push(p);
    }
    let sweep = common::min_distance_violations(&points, r, lo, hi, periodic);
    let all = common::all_pairs_violations(&points, r, lo, hi, periodic);
    prop_assert!(!all.is_empty(), "the case has pairs closer than r");
    let bits = |v: &[(usize, usize, f64)]| {
        v.iter()
            .map(|&(i, j, d)| (i, j, d.to_bits()))
            .collect::<Vec<_>>()
    };
    prop_assert_eq!(bits(&sweep), bits(&all));
    Ok(())
}

proptest! {
    #![proptest_config(config(16))]

    #[test]
    fn the_oracles_sweep_matches_all_pairs(
        seed: u64,
        p2 in proptest::array::uniform2(any::<bool>()),
        p3 in proptest::array::uniform3(any::<bool>()),
        r in 0.01..0.5f64,
    ) {
        sweep_matches_all_pairs::<1>(seed, [p2[0]], r)?;
        sweep_matches_all_pairs::<2>(seed, p2, r)?;
        sweep_matches_all_pairs::<3>(seed, p3, r)?;
    }
}
