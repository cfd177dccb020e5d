//! An independent check of a point set: every point inside the half-open
//! box, and no two points closer than `r` (toroidal distance where the box
//! is periodic), in exact `f64` arithmetic summed in axis order, as the
//! library's guarantee states it.
//!
//! Pairs are found with a grid of cells of side at least `r·(1 + 10⁻⁹)`, so
//! two points closer than `r` lie in the same or adjacent cells even when a
//! cell index is rounded across a face; each point is compared with the
//! points of its `3^N` neighbour cells (wrapped on a torus, clamped in a
//! box). Points sorted by cell, neighbour cells found by binary search:
//! O(n · 3^N · log n), never O(n²).

/// What the check found on a set that passed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Passed {
    /// The smallest pairwise distance (toroidal where periodic), or
    /// infinity for fewer than two points.
    pub(crate) min_distance: f64,
}

/// Checks `points` against the box `[0, extent)` and the radius `r`.
///
/// # Errors
/// Says how the set is wrong: points outside the box (or not finite), or
/// pairs closer than `r`, with counts and an example.
pub(crate) fn check<const N: usize>(
    points: &[[f64; N]],
    extent: [f64; N],
    periodic: bool,
    r: f64,
) -> Result<Passed, String> {
    let outside = points
        .iter()
        .filter(|p| (0..N).any(|a| !(p[a] >= 0.0 && p[a] < extent[a])))
        .count();
    if outside > 0 {
        let example = points
            .iter()
            .find(|p| (0..N).any(|a| !(p[a] >= 0.0 && p[a] < extent[a])));
        return Err(format!(
            "{outside} of {} points outside the box, e.g. {example:?}",
            points.len()
        ));
    }
    let cells = Cells::new(extent, r)?;
    let keyed = cells.sorted(points);
    let r_squared = r * r;
    let (mut closer, mut min_squared, mut example) = (0usize, f64::INFINITY, None);
    let mut neighbours = Vec::new();
    for (key, i) in &keyed {
        let p = &points[*i];
        cells.neighbours(*key, periodic, &mut neighbours);
        for &cell in &neighbours {
            let start = keyed.partition_point(|(k, _)| *k < cell);
            for (k, j) in &keyed[start..] {
                if *k != cell {
                    break;
                }
                if j <= i {
                    continue;
                }
                let d_squared = distance_squared(p, &points[*j], extent, periodic);
                if d_squared < min_squared {
                    min_squared = d_squared;
                }
                if d_squared < r_squared {
                    closer += 1;
                    example.get_or_insert((*i, *j));
                }
            }
        }
    }
    if closer > 0 {
        return Err(format!(
            "{closer} pairs closer than r = {r} (min distance {}, e.g. points {example:?})",
            min_squared.sqrt()
        ));
    }
    Ok(Passed {
        min_distance: min_squared.sqrt(),
    })
}

/// `Σ Δ²` in axis order, `Δ = min(|a − b|, L − |a − b|)` when periodic.
fn distance_squared<const N: usize>(
    a: &[f64; N],
    b: &[f64; N],
    extent: [f64; N],
    periodic: bool,
) -> f64 {
    let mut sum = 0.0;
    for axis in 0..N {
        let mut d = (a[axis] - b[axis]).abs();
        if periodic {
            d = d.min(extent[axis] - d);
        }
        sum += d * d;
    }
    sum
}

/// The checker's grid: `counts[a]` cells of side `extent[a] / counts[a] >= r`.
struct Cells<const N: usize> {
    counts: [u64; N],
    scale: [f64; N],
}

impl<const N: usize> Cells<N> {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a count clamped to 1..=2^20"
    )]
    fn new(extent: [f64; N], r: f64) -> Result<Self, String> {
        let side = r * (1.0 + 1e-9);
        let counts = extent.map(|e| (e / side).floor().clamp(1.0, f64::from(1u32 << 20)) as u64);
        counts
            .iter()
            .try_fold(1u64, |total, &c| total.checked_mul(c))
            .ok_or("the checker's grid has over 2^64 cells")?;
        #[expect(clippy::cast_precision_loss, reason = "at most 2^20")]
        let scale = core::array::from_fn(|a| counts[a] as f64 / extent[a]);
        Ok(Self { counts, scale })
    }

    /// Each point's cell key, with the point's index, sorted by key.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "coordinates are checked inside the box first"
    )]
    fn sorted(&self, points: &[[f64; N]]) -> Vec<(u64, usize)> {
        let mut keyed: Vec<(u64, usize)> = points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let cell: [u64; N] = core::array::from_fn(|a| {
                    ((p[a] * self.scale[a]) as u64).min(self.counts[a] - 1)
                });
                (self.key(&cell), i)
            })
            .collect();
        keyed.sort_unstable();
        keyed
    }

    fn key(&self, cell: &[u64; N]) -> u64 {
        cell.iter()
            .zip(&self.counts)
            .rev()
            .fold(0, |key, (c, n)| key * n + c)
    }

    /// The distinct cells adjacent to (and including) the cell `key`.
    fn neighbours(&self, key: u64, periodic: bool, out: &mut Vec<u64>) {
        let mut cell = [0u64; N];
        let mut rest = key;
        for (c, n) in cell.iter_mut().zip(&self.counts) {
            *c = rest % n;
            rest /= n;
        }
        out.clear();
        let block = 3usize.pow(u32::try_from(N).unwrap_or(u32::MAX));
        'codes: for code in 0..block {
            let mut rest = code;
            let mut other = [0u64; N];
            for axis in 0..N {
                let step = rest % 3;
                rest /= 3;
                let n = self.counts[axis];
                let c = cell[axis];
                other[axis] = match step {
                    0 => c,
                    1 if c + 1 < n => c + 1,
                    1 if periodic => 0,
                    2 if c > 0 => c - 1,
                    2 if periodic => n - 1,
                    _ => continue 'codes,
                };
            }
            out.push(self.key(&other));
        }
        out.sort_unstable();
        out.dedup();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_close_pair_across_the_periodic_seam() {
        let points = [[0.01, 0.5], [0.99, 0.5], [0.5, 0.5]];
        assert!(
            check(&points, [1.0, 1.0], false, 0.1).is_ok(),
            "box: 0.98 apart"
        );
        let found = check(&points, [1.0, 1.0], true, 0.1);
        assert!(found.is_err(), "torus: 0.02 apart, got {found:?}");
    }

    #[test]
    fn finds_points_outside_and_matches_brute_force() {
        assert!(
            check(&[[1.0, 0.5]], [1.0, 1.0], false, 0.1).is_err(),
            "x = hi"
        );
        // A lattice of spacing 0.1 passes at r = 0.1 and fails just above.
        let points: Vec<[f64; 3]> = (0..1000)
            .map(|i| {
                [
                    0.1 * f64::from(i % 10),
                    0.1 * f64::from(i / 10 % 10),
                    0.1 * f64::from(i / 100),
                ]
            })
            .collect();
        let ok = check(&points, [1.0; 3], true, 0.099).expect("spacing 0.1");
        assert!((ok.min_distance - 0.1).abs() < 1e-12, "{}", ok.min_distance);
        let err = check(&points, [1.0; 3], true, 0.1001).expect_err("spacing 0.1 < r");
        // Each point has 3 neighbours in + directions on the torus.
        assert!(err.starts_with("3000 pairs"), "{err}");
    }
}
