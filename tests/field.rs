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
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

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
