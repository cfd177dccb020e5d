//! A straightforward textbook Bridson, kept as the speed baseline: a flat
//! `u32` grid of point indices (cell side `r/√N`), candidates by rejection
//! from the cube around the active point, a random active point per round
//! and swap-remove retirement, neighbours searched over the `±ceil(√N)`
//! block clamped to the grid, early exit on the first conflict.
//!
//! It uses the same generator and the same `k` as the library, so a ratio of
//! points/s at equal ρ compares the implementations, not the parameters.

use rand::{Rng, RngExt};

const EMPTY: u32 = u32::MAX;

#[expect(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "coordinates are inside the box, cell indices small"
)]
fn cell(x: f64, inv: f64, n: usize) -> usize {
    ((x * inv) as usize).min(n - 1)
}

/// Textbook Bridson in the box `[0, w) × [0, h)`.
pub(crate) fn textbook_2d<R: Rng>(w: f64, h: f64, r: f64, k: u32, rng: &mut R) -> Vec<[f64; 2]> {
    let side = r / 2f64.sqrt();
    let inv = 1.0 / side;
    let (nx, ny) = (cell_count(w, side), cell_count(h, side));
    let mut grid = vec![EMPTY; nx * ny];
    let mut points: Vec<[f64; 2]> = Vec::new();
    let mut active: Vec<u32> = Vec::new();
    let r2 = r * r;
    let first = [rng.random::<f64>() * w, rng.random::<f64>() * h];
    grid[cell(first[1], inv, ny) * nx + cell(first[0], inv, nx)] = 0;
    points.push(first);
    active.push(0);
    while !active.is_empty() {
        let i = rng.random_range(0..active.len());
        let p = points[active[i] as usize];
        let mut found = false;
        for _ in 0..k {
            let c = loop {
                let d = [
                    (rng.random::<f64>() * 2.0 - 1.0) * 2.0 * r,
                    (rng.random::<f64>() * 2.0 - 1.0) * 2.0 * r,
                ];
                let d2 = d[0] * d[0] + d[1] * d[1];
                if d2 >= r2 && d2 < 4.0 * r2 {
                    break [p[0] + d[0], p[1] + d[1]];
                }
            };
            if !(c[0] >= 0.0 && c[0] < w && c[1] >= 0.0 && c[1] < h) {
                continue;
            }
            let (cx, cy) = (cell(c[0], inv, nx), cell(c[1], inv, ny));
            let mut ok = true;
            'search: for y in cy.saturating_sub(2)..=(cy + 2).min(ny - 1) {
                for x in cx.saturating_sub(2)..=(cx + 2).min(nx - 1) {
                    let j = grid[y * nx + x];
                    if j != EMPTY {
                        let q = points[j as usize];
                        let (dx, dy) = (q[0] - c[0], q[1] - c[1]);
                        if dx * dx + dy * dy < r2 {
                            ok = false;
                            break 'search;
                        }
                    }
                }
            }
            if ok {
                let index = u32::try_from(points.len()).expect("fewer than 2^32 points");
                grid[cy * nx + cx] = index;
                points.push(c);
                active.push(index);
                found = true;
                break;
            }
        }
        if !found {
            active.swap_remove(i);
        }
    }
    points
}

/// Textbook Bridson in the box `[0, w) × [0, h) × [0, d)`.
pub(crate) fn textbook_3d<R: Rng>(extent: [f64; 3], r: f64, k: u32, rng: &mut R) -> Vec<[f64; 3]> {
    let side = r / 3f64.sqrt();
    let inv = 1.0 / side;
    let n = extent.map(|e| cell_count(e, side));
    let mut grid = vec![EMPTY; n[0] * n[1] * n[2]];
    let mut points: Vec<[f64; 3]> = Vec::new();
    let mut active: Vec<u32> = Vec::new();
    let r2 = r * r;
    let index_of = |c: [usize; 3]| (c[2] * n[1] + c[1]) * n[0] + c[0];
    let cell_of = |p: &[f64; 3]| [0, 1, 2].map(|a| cell(p[a], inv, n[a]));
    let first = extent.map(|e| rng.random::<f64>() * e);
    grid[index_of(cell_of(&first))] = 0;
    points.push(first);
    active.push(0);
    while !active.is_empty() {
        let i = rng.random_range(0..active.len());
        let p = points[active[i] as usize];
        let mut found = false;
        for _ in 0..k {
            let c = loop {
                let d = [0, 1, 2].map(|_| (rng.random::<f64>() * 2.0 - 1.0) * 2.0 * r);
                let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if d2 >= r2 && d2 < 4.0 * r2 {
                    break [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
                }
            };
            if !(0..3).all(|a| c[a] >= 0.0 && c[a] < extent[a]) {
                continue;
            }
            let cc = cell_of(&c);
            let mut ok = true;
            'search: for z in cc[2].saturating_sub(2)..=(cc[2] + 2).min(n[2] - 1) {
                for y in cc[1].saturating_sub(2)..=(cc[1] + 2).min(n[1] - 1) {
                    for x in cc[0].saturating_sub(2)..=(cc[0] + 2).min(n[0] - 1) {
                        let j = grid[index_of([x, y, z])];
                        if j != EMPTY {
                            let q = points[j as usize];
                            let (dx, dy, dz) = (q[0] - c[0], q[1] - c[1], q[2] - c[2]);
                            if dx * dx + dy * dy + dz * dz < r2 {
                                ok = false;
                                break 'search;
                            }
                        }
                    }
                }
            }
            if ok {
                let index = u32::try_from(points.len()).expect("fewer than 2^32 points");
                grid[index_of(cc)] = index;
                points.push(c);
                active.push(index);
                found = true;
                break;
            }
        }
        if !found {
            active.swap_remove(i);
        }
    }
    points
}

#[expect(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "benchmark sizes"
)]
fn cell_count(extent: f64, side: f64) -> usize {
    ((extent / side).ceil() as usize).max(1)
}
