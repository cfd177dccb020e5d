//! The field sampler: a pure function of place. Unions over partitions equal
//! the whole run; chunk size and thread count never matter; no pair closer
//! than `r` across borders (naive oracle); maximal by exhaustive probing;
//! value-stability pins.

use bridson::{Domain, Field, field_order};
use proptest::prelude::*;

fn sorted<const N: usize>(mut v: Vec<[f64; N]>) -> Vec<[f64; N]> {
    v.sort_by(field_order);
    v
}

/// Naive O(n²) check of the minimum distance, periodic axes wrapped.
fn min_distance_ok<const N: usize>(points: &[[f64; N]], r: f64, period: [f64; N]) -> bool {
    for (i, a) in points.iter().enumerate() {
        for b in &points[..i] {
            let mut s = 0.0;
            for k in 0..N {
                let mut d = (a[k] - b[k]).abs();
                if period[k] > 0.0 {
                    d = d.min(period[k] - d);
                }
                s += d * d;
            }
            if s < r * r {
                return false;
            }
        }
    }
    true
}

/// The union of the points of a grid of `cuts` boxes over `[lo, hi)`.
fn union_of_grid<const N: usize>(
    field: &Field<N>,
    lo: [f64; N],
    hi: [f64; N],
    cuts: &[Vec<f64>; N],
) -> Vec<[f64; N]> {
    // cuts[axis]: interior cut positions, increasing.
    let bounds: Vec<Vec<f64>> = (0..N)
        .map(|a| {
            let mut b = vec![lo[a]];
            b.extend(cuts[a].iter().copied().filter(|&c| c > lo[a] && c < hi[a]));
            b.push(hi[a]);
            b.dedup();
            b
        })
        .collect();
    let mut out = Vec::new();
    let mut idx = [0usize; N];
    loop {
        let mut blo = [0.0; N];
        let mut bhi = [0.0; N];
        for a in 0..N {
            blo[a] = bounds[a][idx[a]];
            bhi[a] = bounds[a][idx[a] + 1];
        }
        out.extend(field.points_in(blo, bhi).unwrap());
        let mut a = 0;
        while a < N {
            idx[a] += 1;
            if idx[a] + 1 < bounds[a].len() {
                break;
            }
            idx[a] = 0;
            a += 1;
        }
        if a == N {
            break;
        }
    }
    sorted(out)
}

#[test]
fn halves_equal_the_whole_bounded_2d() {
    let field = Field::<2>::new(Domain::from_extent([10.0, 6.0]).unwrap(), 0.3, 5).unwrap();
    let whole = field.points().unwrap();
    let parts = union_of_grid(
        &field,
        [0.0, 0.0],
        [10.0, 6.0],
        &[vec![3.3, 7.1], vec![2.9]],
    );
    assert_eq!(whole.len(), parts.len(), "counts");
    assert_eq!(whole, parts, "the union of parts is the whole");
    assert!(min_distance_ok(&whole, 0.3, [0.0; 2]), "min distance");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn union_of_random_partition_is_the_whole(
        seed in any::<u64>(),
        r in 0.2f64..0.6,
        cx in proptest::collection::vec(0.0f64..8.0, 0..3),
        cy in proptest::collection::vec(0.0f64..5.0, 0..3),
        px in any::<bool>(),
        py in any::<bool>(),
    ) {
        let domain = Domain::from_extent([8.0, 5.0]).unwrap().with_periodic([px, py]);
        let field = Field::<2>::new(domain, r, seed).unwrap();
        let whole = field.points().unwrap();
        let mut cx = cx; cx.sort_by(f64::total_cmp);
        let mut cy = cy; cy.sort_by(f64::total_cmp);
        let parts = union_of_grid(&field, [0.0, 0.0], [8.0, 5.0], &[cx, cy]);
        prop_assert_eq!(&whole, &parts);
        let period = [if px { 8.0 } else { 0.0 }, if py { 5.0 } else { 0.0 }];
        prop_assert!(min_distance_ok(&whole, r, period));
    }

    #[test]
    #[cfg_attr(debug_assertions, ignore = "slow unoptimised; run with --release")]
    fn unbounded_partitions_agree_3d(
        seed in any::<u64>(),
        ox in -50.0f64..50.0,
        cut in 0.5f64..3.5,
    ) {
        let field = Field::<3>::unbounded(1.0, seed).unwrap();
        let lo = [ox, 0.0, -2.0];
        let hi = [ox + 4.0, 4.0, 2.0];
        let whole = field.points_in(lo, hi).unwrap();
        let parts = union_of_grid(&field, lo, hi, &[vec![ox + cut], vec![cut], vec![]]);
        prop_assert_eq!(&whole, &parts);
        prop_assert!(min_distance_ok(&whole, 1.0, [0.0; 3]));
    }
}

/// Maximal: no probe of the box is farther than r from every point.
fn assert_maximal<const N: usize>(
    field: &Field<N>,
    lo: [f64; N],
    hi: [f64; N],
    period: [f64; N],
    probes_per_axis: usize,
) {
    let points = field.points_in(lo, hi).unwrap();
    let r = field.radius();
    let mut idx = [0usize; N];
    loop {
        let mut p = [0.0; N];
        for a in 0..N {
            p[a] = lo[a] + (hi[a] - lo[a]) * (idx[a] as f64 + 0.5) / probes_per_axis as f64;
        }
        let covered = points.iter().any(|q| {
            let mut s = 0.0;
            for a in 0..N {
                let mut d = (p[a] - q[a]).abs();
                if period[a] > 0.0 {
                    d = d.min(period[a] - d);
                }
                s += d * d;
            }
            s <= r * r
        });
        assert!(covered, "probe {p:?} is farther than r from every point");
        let mut a = 0;
        while a < N {
            idx[a] += 1;
            if idx[a] < probes_per_axis {
                break;
            }
            idx[a] = 0;
            a += 1;
        }
        if a == N {
            break;
        }
    }
}

#[test]
fn maximal_by_probing_2d_bounded_and_periodic() {
    let f = Field::<2>::new(Domain::from_extent([3.0, 2.0]).unwrap(), 0.25, 1).unwrap();
    assert_maximal(&f, [0.0, 0.0], [3.0, 2.0], [0.0; 2], 300);
    let d = Domain::from_extent([3.0, 2.0])
        .unwrap()
        .with_periodic([true, true]);
    let f = Field::<2>::new(d, 0.25, 2).unwrap();
    assert_maximal(&f, [0.0, 0.0], [3.0, 2.0], [3.0, 2.0], 300);
}

#[test]
fn maximal_by_probing_3d() {
    let f = Field::<3>::new(Domain::from_extent([1.5, 1.5, 1.5]).unwrap(), 0.3, 3).unwrap();
    assert_maximal(&f, [0.0; 3], [1.5; 3], [0.0; 3], 40);
}

#[test]
fn chunk_side_and_threads_never_change_the_points() {
    let field = Field::<2>::unbounded(1.0, 9).unwrap();
    let (lo, hi) = ([-20.0, 3.5], [45.0, 40.0]);
    let one = field.points_in(lo, hi).unwrap();
    for (chunk, threads) in [(64.0, 1), (7.5, 2), (13.0, 3), (5.0, 4)] {
        let other = field.points_in_parallel(lo, hi, chunk, threads).unwrap();
        assert_eq!(one, other, "chunk {chunk}, threads {threads}");
    }
    // The naive oracle on the union across chunk borders.
    assert!(
        min_distance_ok(&one, 1.0, [0.0; 2]),
        "min distance across borders"
    );
}

#[test]
fn visiting_order_never_changes_a_chunk() {
    let field = Field::<2>::unbounded(3.0, 1).unwrap();
    let boxes = bridson::chunk_boxes([0.0, 0.0], [256.0, 256.0], 64.0).unwrap();
    let forward: Vec<_> = boxes
        .iter()
        .map(|(a, b)| field.points_in(*a, *b).unwrap())
        .collect();
    let backward: Vec<_> = boxes
        .iter()
        .rev()
        .map(|(a, b)| field.points_in(*a, *b).unwrap())
        .collect();
    let backward: Vec<_> = backward.into_iter().rev().collect();
    assert_eq!(forward, backward, "every chunk the same in either order");
}

#[test]
fn a_wider_world_holds_the_same_points() {
    // Unbounded: the lattice depends only on r, so a box sees the same
    // points whatever else is asked.
    let field = Field::<2>::unbounded(0.5, 4).unwrap();
    let small = field.points_in([1.0, 1.0], [6.0, 4.0]).unwrap();
    let mut big = field.points_in([-10.0, -10.0], [30.0, 30.0]).unwrap();
    big.retain(|p| (1.0..6.0).contains(&p[0]) && (1.0..4.0).contains(&p[1]));
    assert_eq!(small, big, "same points in the small box");
}

#[test]
fn maximal_with_relative_radius_over_0_76() {
    let r = 0.01;
    let field = Field::<2>::new(Domain::from_extent([1.0, 1.0]).unwrap(), r, 2).unwrap();
    let n = field.points().unwrap().len();
    let rho = bridson::relative_radius::<2>(r, n, 1.0).unwrap();
    assert!(rho >= 0.76, "rho {rho} with {n} points");
}

#[test]
fn value_stability_pins() {
    // Changing these is a value-breaking change: flag it in the CHANGELOG.
    let field = Field::<2>::unbounded(1.0, 42).unwrap();
    let p = field.points_in([0.0, 0.0], [4.0, 4.0]).unwrap();
    let bits: Vec<[u64; 2]> = p.iter().take(3).map(|q| q.map(f64::to_bits)).collect();
    assert_eq!(p.len(), PIN_COUNT, "count");
    assert_eq!(bits, PIN_BITS.to_vec(), "first points {p:?}");
}

// Changed deliberately when each round became greedy in priority order
// (sequential adsorption) instead of one Luby step: 12 points before.
const PIN_COUNT: usize = 13;
const PIN_BITS: [[u64; 2]; 3] = [
    [4615375762897648064, 4598989264115772609],
    [4609100074228431292, 4599076810316951081],
    [4612662781044659894, 4599319026160518061],
];
