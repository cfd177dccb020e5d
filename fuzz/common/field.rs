//! The `field` fuzz target's logic: the field sampler (`bridson::Field`).
//!
//! Every byte string decodes to a box (bounded or periodic per axis, or an
//! unbounded field), a radius, a seed, a query box and a cut through it,
//! raw `f64` bit patterns now and then, and a region (none, a ball, or a
//! slab that may have no width) given as a signed distance. For every
//! input: construction and queries return a result, never panic; every
//! point is in the query box and in the region; when they succeed on a set
//! small enough for the O(n²) oracle, the two halves of the query box
//! together equal the whole box's points and no pair is closer than `r`.

use crate::bytes::{Bytes, log_uniform};
use bridson::{Domain, Field, FieldRegion, SignedDistance};

/// The window budget for one query: a few MB, so executions stay fast.
const WINDOW_BYTES: u64 = 8 << 20;

/// The most points the oracle checks.
const POINT_LIMIT: usize = 1500;

fn value(b: &mut Bytes<'_>, usual: f64) -> f64 {
    match b.u8() % 8 {
        0 => b.f64_bits(),
        1 => -usual,
        _ => usual * f64::from(b.u16()) / 65535.0,
    }
}

fn run_dim<const N: usize>(b: &mut Bytes<'_>) {
    let unbounded = b.u8().is_multiple_of(4);
    let mut lo = [0.0; N];
    let mut hi = [0.0; N];
    let mut periodic = [false; N];
    for axis in 0..N {
        lo[axis] = value(b, 10.0);
        hi[axis] = lo[axis] + value(b, 10.0).abs() + 1e-3;
        periodic[axis] = b.u8() % 2 == 1;
    }
    let radius = if b.u8().is_multiple_of(8) {
        b.f64_bits()
    } else {
        log_uniform(b, 0.05, 20.0)
    };
    let seed = b.u64();
    let field = if unbounded {
        Field::<N>::unbounded(radius, seed)
    } else {
        match Domain::new(lo, hi) {
            Ok(d) => Field::new(d.with_periodic(periodic), radius, seed),
            Err(_) => return,
        }
    };
    let Ok(field) = field else { return };
    let field = field.with_max_window_bytes(WINDOW_BYTES);
    let shape = Shape {
        kind: b.u8() % 3,
        centre: core::array::from_fn(|_| value(b, 10.0)),
        size: value(b, 5.0),
        axis: usize::from(b.u8()) % N,
    };
    let sd = move |p: &[f64; N]| shape.distance(p);
    match shape.kind {
        0 => check(&field, b, &lo, &hi, unbounded, &periodic, |_| true),
        _ => check(
            &field.with_region(SignedDistance(sd)),
            b,
            &lo,
            &hi,
            unbounded,
            &periodic,
            |p| sd(p) <= 0.0,
        ),
    }
}

/// A region decoded from the input: a ball (kind 1) or a slab across one
/// axis (kind 2), of half-width `size` (which may be negative or zero).
#[derive(Clone, Copy)]
struct Shape<const N: usize> {
    kind: u8,
    centre: [f64; N],
    size: f64,
    axis: usize,
}

impl<const N: usize> Shape<N> {
    fn distance(&self, p: &[f64; N]) -> f64 {
        if self.kind == 1 {
            let d2: f64 = (0..N).map(|a| (p[a] - self.centre[a]).powi(2)).sum();
            d2.sqrt() - self.size
        } else {
            (p[self.axis] - self.centre[self.axis]).abs() - self.size
        }
    }
}

/// The checks on one field, its region's test beside it.
fn check<const N: usize, R: FieldRegion<N> + Sync>(
    field: &Field<N, R>,
    b: &mut Bytes<'_>,
    lo: &[f64; N],
    hi: &[f64; N],
    unbounded: bool,
    periodic: &[bool; N],
    admits: impl Fn(&[f64; N]) -> bool,
) {
    let radius = field.radius();
    // The query box: the domain's, or one decoded from the input.
    let (qlo, qhi) = if b.u8().is_multiple_of(2) && !unbounded {
        (*lo, *hi)
    } else {
        let mut a = [0.0; N];
        let mut c = [0.0; N];
        for axis in 0..N {
            a[axis] = value(b, 10.0);
            c[axis] = a[axis] + value(b, 10.0).abs() + 1e-3;
        }
        (a, c)
    };
    let Ok(whole) = field.points_in(qlo, qhi) else {
        return;
    };
    assert!(
        whole
            .iter()
            .all(|p| (0..N).all(|a| qlo[a] <= p[a] && p[a] < qhi[a])),
        "a point outside the query box"
    );
    assert!(whole.iter().all(admits), "a point outside the region");
    if whole.len() > POINT_LIMIT {
        return;
    }
    // Two halves, cut on one axis.
    let axis = usize::from(b.u8()) % N;
    let t = f64::from(b.u16()) / 65535.0;
    let cut = qlo[axis] + t * (qhi[axis] - qlo[axis]);
    if cut > qlo[axis] && cut < qhi[axis] {
        let mut mid_hi = qhi;
        mid_hi[axis] = cut;
        let mut mid_lo = qlo;
        mid_lo[axis] = cut;
        if let (Ok(mut a), Ok(c)) = (field.points_in(qlo, mid_hi), field.points_in(mid_lo, qhi)) {
            a.extend(c);
            a.sort_by(bridson::field_order);
            assert_eq!(a, whole, "the halves' union differs from the whole");
        }
    }
    let (dlo, dhi) = field.domain().unwrap_or(([0.0; N], [0.0; N]));
    let r2 = radius * radius;
    for (i, p) in whole.iter().enumerate() {
        for q in &whole[..i] {
            let mut s = 0.0;
            for a in 0..N {
                let mut d = (p[a] - q[a]).abs();
                if !unbounded && periodic[a] {
                    d = d.min((dhi[a] - dlo[a]) - d);
                }
                s += d * d;
            }
            assert!(s >= r2, "two points closer than r: {p:?} {q:?}");
        }
    }
}

/// Decodes one input and checks it.
pub(crate) fn run(data: &[u8]) {
    let mut b = Bytes::new(data);
    match b.u8() % 3 {
        0 => run_dim::<1>(&mut b),
        1 => run_dim::<2>(&mut b),
        _ => run_dim::<3>(&mut b),
    }
}
