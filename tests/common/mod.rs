//! A deliberately naive oracle for the integration tests.
//!
//! Nothing here calls into the crate: points are plain `[f64; N]` arrays and
//! the box is plain `lo` / `hi` / `periodic` arrays, so a bug in the crate's
//! own distance or containment code cannot hide itself. The pair check is
//! O(n²) on purpose.
//!
//! The squared distance is evaluated exactly as the crate documents its
//! guarantee: axes in order `0..N`, `d = |a[i] - b[i]|`, on a periodic axis
//! `d = min(d, L - d)` with `L = hi[i] - lo[i]`, `acc += d * d`, and a pair
//! violates the guarantee iff `acc < r * r`. Same operations in the same
//! order give bit-identical results, so the check is exact, not approximate.
#![allow(
    dead_code,
    reason = "each test binary compiles this module and uses only part of it"
)]

use std::fmt::Write as _;

/// Squared distance between `a` and `b`, summed in axis order, wrapping on
/// periodic axes.
pub(crate) fn distance_squared<const N: usize>(
    a: &[f64; N],
    b: &[f64; N],
    lo: &[f64; N],
    hi: &[f64; N],
    periodic: &[bool; N],
) -> f64 {
    let mut acc = 0.0;
    for i in 0..N {
        let mut d = (a[i] - b[i]).abs();
        if periodic[i] {
            let l = hi[i] - lo[i];
            d = d.min(l - d);
        }
        acc += d * d;
    }
    acc
}

/// Every pair `(i, j, squared distance)` with `i < j` closer than `r`.
pub(crate) fn min_distance_violations<const N: usize>(
    points: &[[f64; N]],
    r: f64,
    lo: [f64; N],
    hi: [f64; N],
    periodic: [bool; N],
) -> Vec<(usize, usize, f64)> {
    let r2 = r * r;
    let mut bad = Vec::new();
    for (j, b) in points.iter().enumerate() {
        for (i, a) in points.iter().enumerate().take(j) {
            let d2 = distance_squared(a, b, &lo, &hi, &periodic);
            if d2 < r2 {
                bad.push((i, j, d2));
            }
        }
    }
    bad
}

/// Every point `(index, point)` with some coordinate outside `lo <= x < hi`
/// (NaN counts as outside).
pub(crate) fn out_of_bounds<const N: usize>(
    points: &[[f64; N]],
    lo: [f64; N],
    hi: [f64; N],
) -> Vec<(usize, [f64; N])> {
    points
        .iter()
        .enumerate()
        .filter(|(_, p)| !(0..N).all(|i| lo[i] <= p[i] && p[i] < hi[i]))
        .map(|(k, p)| (k, *p))
        .collect()
}

/// Both checks at once: `Err` with a readable report of the first few
/// violations (points and distances printed with full precision).
pub(crate) fn check_points<const N: usize>(
    points: &[[f64; N]],
    r: f64,
    lo: [f64; N],
    hi: [f64; N],
    periodic: [bool; N],
) -> Result<(), String> {
    let outside = out_of_bounds(points, lo, hi);
    let close = min_distance_violations(points, r, lo, hi, periodic);
    if outside.is_empty() && close.is_empty() {
        return Ok(());
    }
    let mut report = format!(
        "{} of {} points outside the box, {} pairs closer than r = {r:e} (r² = {:e})",
        outside.len(),
        points.len(),
        close.len(),
        r * r
    );
    for (k, p) in outside.iter().take(5) {
        let _ = write!(report, "\n  outside: #{k} {p:?}");
    }
    for &(i, j, d2) in close.iter().take(5) {
        let _ = write!(
            report,
            "\n  too close: #{i} {:?} and #{j} {:?}, d² = {d2:e}",
            points[i], points[j]
        );
    }
    Err(report)
}
