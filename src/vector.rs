//! Small `[f64; N]` helpers, written once for every dimension.

/// Squared Euclidean distance, summed in axis order.
///
/// The order is part of the contract: the minimum-distance check and any
/// independent checker that sums `(a[i] - b[i])²` from axis 0 upwards get
/// bit-identical results.
#[inline(always)]
pub(crate) fn distance_squared<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    let mut acc = 0.0;
    for (x, y) in a.iter().zip(b) {
        let d = x - y;
        acc += d * d;
    }
    acc
}

/// Squared toroidal distance: on axis `i` with `period[i] > 0` the
/// difference is `min(|Δ|, period - |Δ|)`, the nearest image for points
/// inside one period; other axes (period `0.0`) use the plain difference.
#[inline(always)]
pub(crate) fn periodic_distance_squared<const N: usize>(
    a: &[f64; N],
    b: &[f64; N],
    period: &[f64; N],
) -> f64 {
    let mut acc = 0.0;
    for ((x, y), &l) in a.iter().zip(b).zip(period) {
        let mut d = (x - y).abs();
        if l > 0.0 {
            d = d.min(l - d);
        }
        acc += d * d;
    }
    acc
}

/// Whether every component is finite.
pub(crate) fn all_finite<const N: usize>(a: &[f64; N]) -> bool {
    a.iter().all(|x| x.is_finite())
}

/// Component-wise `a + b`.
#[inline(always)]
pub(crate) fn add<const N: usize>(a: &[f64; N], b: &[f64; N]) -> [f64; N] {
    zip_map(a, b, |x, y| x + y)
}

/// `[f(a[0], b[0]), f(a[1], b[1]), …]`: the one place where per-axis
/// arrays are indexed, so that callers need not.
#[inline(always)]
pub(crate) fn zip_map<A: Copy, B: Copy, T, const N: usize>(
    a: &[A; N],
    b: &[B; N],
    mut f: impl FnMut(A, B) -> T,
) -> [T; N] {
    #[expect(
        clippy::indexing_slicing,
        reason = "from_fn calls the closure with i < N only, and both arrays have length N"
    )]
    let out = core::array::from_fn(|i| f(a[i], b[i]));
    out
}

/// `‖a‖²`.
#[inline(always)]
pub(crate) fn norm_squared<const N: usize>(a: &[f64; N]) -> f64 {
    a.iter().map(|x| x * x).sum()
}

/// Component-wise `a * s`.
#[inline(always)]
pub(crate) fn scale<const N: usize>(a: &[f64; N], s: f64) -> [f64; N] {
    a.map(|x| x * s)
}

/// Volume of the unit ball in `n` dimensions.
pub(crate) fn unit_ball_volume(n: usize) -> f64 {
    let (mut v, start) = if n.is_multiple_of(2) {
        (1.0, 2)
    } else {
        (2.0, 3)
    };
    let mut k = start;
    while k <= n {
        #[expect(clippy::cast_precision_loss, reason = "N is small")]
        let kf = k as f64;
        v *= core::f64::consts::TAU / kf;
        k += 2;
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_ball_volumes() {
        let expected = [
            1.0,
            2.0,
            core::f64::consts::PI,
            4.0 / 3.0 * core::f64::consts::PI,
        ];
        for (n, v) in expected.iter().enumerate() {
            assert!((unit_ball_volume(n) - v).abs() < 1e-12, "V_{n}");
        }
        let v8 = core::f64::consts::PI.powi(4) / 24.0;
        assert!((unit_ball_volume(8) - v8).abs() < 1e-12, "V_8");
    }

    #[test]
    fn periodic_distance_takes_the_nearest_image() {
        let period = [1.0, 0.0];
        let a = [0.05, 0.5];
        let b = [0.95, 0.5];
        let d2 = periodic_distance_squared(&a, &b, &period);
        assert!((d2 - 0.01).abs() < 1e-15, "wrapped distance², got {d2}");
        assert!(
            (distance_squared(&a, &b) - 0.81).abs() < 1e-15,
            "plain distance²"
        );
    }

    #[test]
    fn infinite_sentinel_is_never_close() {
        let empty = [f64::INFINITY; 3];
        let p = [0.1, 0.2, 0.3];
        assert!(distance_squared(&p, &empty) == f64::INFINITY, "plain");
        let d2 = periodic_distance_squared(&p, &empty, &[1.0, 1.0, 1.0]);
        assert!(d2 == f64::INFINITY, "periodic: {d2}");
    }
}
