//! A deliberately naive oracle for the integration tests.
//!
//! Nothing here calls into the crate: points are plain `[f64; N]` arrays and
//! the box is plain `lo` / `hi` / `periodic` arrays, so a bug in the crate's
//! own distance or containment code cannot hide itself. The pair check
//! visits every pair whose gap along one non-periodic axis is under `r`, in
//! that axis's order, and every pair when all axes are periodic (see
//! [`min_distance_violations`]); [`all_pairs_violations`] is the plain
//! O(n²) check, and a test in `tests/properties.rs` holds the two equal.
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

/// Every pair `(i, j, squared distance)` with `i < j` closer than `r`,
/// ordered by `j`, then `i`.
///
/// The answer of [`all_pairs_violations`], found faster: pairs are visited
/// in the order of the first non-periodic axis, and only while their gap
/// along it, squared, is under `r²`. A pair whose squared gap on one axis
/// reaches `r²` cannot be closer than `r`: the squared distance adds
/// non-negative terms to that gap's square, and rounding is monotone, so
/// the sum never falls below it. With every axis periodic, every pair is
/// visited.
pub(crate) fn min_distance_violations<const N: usize>(
    points: &[[f64; N]],
    r: f64,
    lo: [f64; N],
    hi: [f64; N],
    periodic: [bool; N],
) -> Vec<(usize, usize, f64)> {
    let Some(axis) = (0..N).find(|&a| !periodic[a]) else {
        return all_pairs_violations(points, r, lo, hi, periodic);
    };
    let r2 = r * r;
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a][axis].total_cmp(&points[b][axis]));
    let mut bad = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            // Sorted, so the gap only grows along the scan (NaN never
            // stops it).
            let gap = (points[b][axis] - points[a][axis]).abs();
            if gap * gap >= r2 {
                break;
            }
            let (i, j) = (a.min(b), a.max(b));
            let d2 = distance_squared(&points[i], &points[j], &lo, &hi, &periodic);
            if d2 < r2 {
                bad.push((i, j, d2));
            }
        }
    }
    bad.sort_unstable_by_key(|&(i, j, _)| (j, i));
    bad
}

/// Every pair `(i, j, squared distance)` with `i < j` closer than `r`,
/// ordered by `j`, then `i`: every pair checked, O(n²).
pub(crate) fn all_pairs_violations<const N: usize>(
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
