//! A field restricted to a region ([`Field::with_region`]): still a pure
//! function of place (unions over partitions equal the whole), every point
//! in the region, no pair closer than `r` (naive oracle), maximal inside the
//! region by exhaustive probing, and a region of zero volume refused by the
//! budget instead of running without end.

use bridson::{Domain, Error, Field, FieldRegion, SignedDistance, field_order};
use proptest::prelude::*;

fn min_distance_ok<const N: usize>(points: &[[f64; N]], r: f64) -> bool {
    points.iter().enumerate().all(|(i, a)| {
        points[..i]
            .iter()
            .all(|b| (0..N).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum::<f64>() >= r * r)
    })
}

/// An annulus around `c`, radii `inner..outer`, as a signed distance.
fn annulus(c: [f64; 2], inner: f64, outer: f64) -> impl Fn(&[f64; 2]) -> f64 + Copy {
    move |p: &[f64; 2]| {
        let d = (p[0] - c[0]).hypot(p[1] - c[1]);
        (d - outer).max(inner - d)
    }
}

/// The points of `field` in `[lo, hi)`, asked for in the boxes that the
/// cuts make, sorted.
fn union_of_cuts<R: FieldRegion<2> + Sync>(
    field: &Field<2, R>,
    lo: [f64; 2],
    hi: [f64; 2],
    cx: &[f64],
    cy: &[f64],
) -> Vec<[f64; 2]> {
    let edges = |a: f64, b: f64, cuts: &[f64]| {
        let mut e = vec![a];
        let mut inner: Vec<f64> = cuts.iter().copied().filter(|&c| a < c && c < b).collect();
        inner.sort_by(f64::total_cmp);
        e.extend(inner);
        e.push(b);
        e.dedup();
        e
    };
    let (xs, ys) = (edges(lo[0], hi[0], cx), edges(lo[1], hi[1], cy));
    let mut out = Vec::new();
    for y in ys.windows(2) {
        for x in xs.windows(2) {
            out.extend(field.points_in([x[0], y[0]], [x[1], y[1]]).unwrap());
        }
    }
    out.sort_by(field_order);
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn a_region_keeps_the_field_a_function_of_place(
        seed in any::<u64>(),
        r in 0.25f64..0.6,
        inner in 0.0f64..2.0,
        width in 0.5f64..3.0,
        cx in proptest::collection::vec(0.0f64..9.0, 0..3),
        cy in proptest::collection::vec(0.0f64..7.0, 0..3),
        unbounded in any::<bool>(),
    ) {
        let sd = annulus([4.5, 3.5], inner, inner + width);
        let base = if unbounded {
            Field::<2>::unbounded(r, seed).unwrap()
        } else {
            Field::new(Domain::from_extent([9.0, 7.0]).unwrap(), r, seed).unwrap()
        };
        let field = base.with_region(SignedDistance(sd));
        let whole = field.points_in([0.0, 0.0], [9.0, 7.0]).unwrap();
        prop_assert_eq!(&whole, &union_of_cuts(&field, [0.0, 0.0], [9.0, 7.0], &cx, &cy));
        prop_assert!(whole.iter().all(|p| sd(p) <= 0.0), "a point outside the region");
        prop_assert!(min_distance_ok(&whole, r));
        let threads = field.points_in_parallel([0.0, 0.0], [9.0, 7.0], 2.5, 3).unwrap();
        prop_assert_eq!(&whole, &threads);
    }
}

#[test]
fn maximal_inside_the_region_by_probing() {
    let r = 0.2;
    let sd = annulus([2.0, 1.5], 0.4, 1.3);
    let field = Field::new(Domain::from_extent([4.0, 3.0]).unwrap(), r, 4)
        .unwrap()
        .with_region(SignedDistance(sd));
    let points = field.points().unwrap();
    assert!(points.len() > 50, "{} points", points.len());
    let n = 400;
    let mut probed = 0;
    for i in 0..n {
        for j in 0..n {
            let p = [
                4.0 * (i as f64 + 0.5) / n as f64,
                3.0 * (j as f64 + 0.5) / n as f64,
            ];
            if sd(&p) > 0.0 {
                continue;
            }
            probed += 1;
            let covered = points
                .iter()
                .any(|q| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) <= r * r);
            assert!(
                covered,
                "probe {p:?} of the region is farther than r from every point"
            );
        }
    }
    assert!(probed > 40_000, "{probed} probes in the region");
}

#[test]
fn a_region_holding_everything_changes_no_point() {
    let domain = Domain::from_extent([6.0, 5.0]).unwrap();
    let plain = Field::new(domain, 0.3, 11).unwrap();
    let all = plain.with_region(SignedDistance(|_: &[f64; 2]| -1.0));
    assert_eq!(plain.points().unwrap(), all.points().unwrap());
}

#[test]
fn a_region_in_3d_keeps_its_points_inside_and_apart() {
    let ball = |p: &[f64; 3]| (p[0] - 1.0).hypot(p[1] - 1.0).hypot(p[2] - 1.0) - 0.8;
    let field = Field::new(Domain::from_extent([2.0, 2.0, 2.0]).unwrap(), 0.3, 2)
        .unwrap()
        .with_region(SignedDistance(ball));
    let whole = field.points().unwrap();
    assert!(whole.iter().all(|p| ball(p) <= 0.0));
    assert!(min_distance_ok(&whole, 0.3));
    let parts = field
        .points_in_parallel([0.0; 3], [2.0; 3], 0.7, 2)
        .unwrap();
    assert_eq!(whole, parts);
}

#[test]
fn a_window_over_the_budget_is_refused_and_chunks_get_round_it() {
    let field = Field::new(Domain::from_extent([1.0, 1.0]).unwrap(), 0.01, 5)
        .unwrap()
        .with_max_window_bytes(1 << 20);
    match field.points() {
        Err(Error::GridTooLarge { needed, budget }) => {
            assert_eq!(budget, 1 << 20);
            assert!(needed > budget);
        }
        other => panic!("expected GridTooLarge, got {other:?}"),
    }
    let chunked = field
        .points_in_parallel([0.0; 2], [1.0; 2], 0.1, 2)
        .unwrap();
    let plain = Field::new(Domain::from_extent([1.0, 1.0]).unwrap(), 0.01, 5).unwrap();
    assert_eq!(chunked, plain.points().unwrap());
}

#[test]
fn a_region_of_zero_volume_is_refused_not_run_forever() {
    // A line: every box across it meets the region, no dart ever lands on
    // it, so its cells split without end until the budget stops them.
    let line = SignedDistance(|p: &[f64; 2]| (p[0] - 2.5).abs());
    let field = Field::new(Domain::from_extent([5.0, 5.0]).unwrap(), 0.5, 1)
        .unwrap()
        .with_max_window_bytes(1 << 20)
        .with_region(line);
    match field.points() {
        Err(Error::GridTooLarge { needed, budget }) => {
            assert_eq!(budget, 1 << 20);
            assert!(needed > budget);
        }
        other => panic!("expected GridTooLarge, got {other:?}"),
    }
}
