//! The memory budget, checked against the allocator itself: a counting
//! global allocator records the peak of the heap while a run is built and
//! driven to its end, and that peak never exceeds `max_grid_bytes`, in any
//! dimension, layout or budget; a radius far larger than the box takes a few
//! kilobytes, not gigabytes.
//!
//! The allocator and its per-thread counters are `tests/common/counting.rs`.

use bridson::{Domain, Error, Everywhere, GridLayout, PoissonDisk};

#[path = "common/counting.rs"]
mod counting;

/// Builds the sampler, runs it to its end (at most `limit` points) and
/// returns the points made, why the run stopped early, and the peak heap
/// the run took above what was held before it.
fn run<const N: usize>(
    domain: Domain<N>,
    r: f64,
    layout: GridLayout,
    budget: u64,
    limit: usize,
) -> Result<(usize, Option<Error>, u64), Error> {
    let before = counting::start();
    let sampler = PoissonDisk::builder(domain, r)
        .layout(layout)
        .max_grid_bytes(budget)
        .build()?;
    // In a region (the whole box), so that no run is refused up front and
    // every one grows until the budget; the plain run's refusal is checked
    // by `the_peak_heap_stays_within_the_budget`.
    let mut it = sampler.iter_with_seeded(11, Everywhere, &[])?;
    let n = it.by_ref().take(limit).count();
    let error = it.error();
    drop(it);
    let peak = counting::peak_since(before);
    Ok((n, error, peak as u64))
}

/// The plain run's outcome: its count and error, or its refusal.
fn plain<const N: usize>(
    domain: Domain<N>,
    r: f64,
    layout: GridLayout,
    budget: u64,
) -> (usize, Option<Error>) {
    let sampler = PoissonDisk::builder(domain, r)
        .layout(layout)
        .max_grid_bytes(budget)
        .build()
        .expect("built before");
    let mut it = sampler.iter_seeded(11);
    let n = it.by_ref().count();
    (n, it.error())
}

fn unit<const N: usize>(periodic: bool) -> Domain<N> {
    Domain::from_extent([1.0; N])
        .expect("box")
        .with_periodic([periodic; N])
}

/// Every run's peak heap stays within its budget, whether it completes or
/// stops at the budget; small budgets do stop runs, so the check bites.
#[test]
fn the_peak_heap_stays_within_the_budget() {
    fn check<const N: usize>(r: f64, budgets: &[u64], stops: &mut usize, complete: &mut usize) {
        for &budget in budgets {
            for layout in [
                GridLayout::Auto,
                GridLayout::Dense,
                GridLayout::Paged,
                GridLayout::Sparse,
            ] {
                for periodic in [false, true] {
                    let Ok((n, error, peak)) =
                        run(unit::<N>(periodic), r, layout, budget, usize::MAX)
                    else {
                        continue;
                    };
                    let ctx = format!("{N}-D r = {r}, {layout:?}, periodic {periodic}");
                    assert!(
                        peak <= budget,
                        "{ctx}: peak heap {peak} bytes over the budget of {budget} ({n} points)"
                    );
                    match error {
                        None => *complete += 1,
                        Some(Error::MemoryBudgetExceeded { points, .. }) => {
                            assert_eq!(points, n as u64, "{ctx}: count");
                            *stops += 1;
                        }
                        Some(other) => panic!("{ctx}: {other:?}"),
                    }
                    // The plain run is the same run, or refused at once
                    // where its expected points need over twice the budget
                    // (then this run must not have completed).
                    match plain(unit::<N>(periodic), r, layout, budget) {
                        (
                            0,
                            Some(Error::RunTooLarge {
                                needed, budget: b, ..
                            }),
                        ) => {
                            assert!(needed > 2 * b, "{ctx}: refused at {needed} bytes");
                            assert!(error.is_some(), "{ctx}: refused a run that fits");
                        }
                        same => assert_eq!(same, (n, error), "{ctx}: the plain run"),
                    }
                }
            }
        }
    }
    let (mut stops, mut complete) = (0, 0);
    // From a budget that stops every run to one that lets most complete.
    let budgets = [1 << 12, 1 << 16, 1 << 20];
    check::<1>(1e-4, &budgets, &mut stops, &mut complete);
    check::<2>(0.01, &budgets, &mut stops, &mut complete);
    check::<3>(0.06, &budgets, &mut stops, &mut complete);
    check::<4>(0.15, &budgets, &mut stops, &mut complete);
    check::<5>(0.3, &budgets, &mut stops, &mut complete);
    check::<8>(0.6, &budgets[1..], &mut stops, &mut complete);
    assert!(stops >= 20, "only {stops} runs reached their budget");
    assert!(complete >= 10, "only {complete} runs completed");
}

/// A radius given in the wrong units, far larger than the box, makes one
/// point and ends, in a few kilobytes, in every dimension, bounded or
/// periodic, with the default 1 GiB budget (before the reach was bounded
/// by the box, 3-D r = 200 took 7.9 GiB).
#[test]
fn a_huge_radius_takes_kilobytes() {
    fn check<const N: usize>(lo: f64, r: f64) {
        for periodic in [false, true] {
            let domain = Domain::new([lo; N], [1.0; N])
                .expect("box")
                .with_periodic([periodic; N]);
            let (n, error, peak) = run(
                domain,
                r,
                GridLayout::Auto,
                bridson::DEFAULT_MAX_GRID_BYTES,
                usize::MAX,
            )
            .expect("valid");
            let ctx = format!("{N}-D r = {r}, periodic {periodic}");
            assert_eq!((n, error), (1, None), "{ctx}: one point");
            assert!(peak < 1 << 16, "{ctx}: {peak} bytes");
        }
    }
    for r in [2.0, 49.0, 200.0, 1e6, 1e150] {
        check::<1>(0.1, r);
        check::<2>(0.1, r);
        check::<3>(0.1, r);
        check::<4>(0.1, r);
        check::<5>(0.1, r);
        check::<6>(0.1, r);
        check::<7>(0.1, r);
        check::<8>(0.1, r);
    }
}
