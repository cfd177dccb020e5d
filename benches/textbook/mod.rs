//! The textbook Bridson kept as the speed baseline, written to the recipe of
//! the yardstick in `../shared/baseline` (its `src/reference.rs`), so that
//! "× the textbook" means "× a careful textbook Bridson":
//!
//! - candidates uniform in the annulus `r..2r` by rejection from the cube of
//!   side `4r`, each coordinate `(u·4 − 2)·r` with `u` from the top 53 bits
//!   of one `u64`;
//! - a flat grid of `u32` point indices, cell side `r/√N`, padded by the
//!   reach `m = ceil(√N)` cells on every side so that no neighbour lookup
//!   needs a bounds test of its own;
//! - the neighbour cells, only those whose nearest face is closer than `r`
//!   (21 of the 5×5 block in 2-D), scanned in memory order with an exit on
//!   the first conflict (as runs along axis 0, one slice per row);
//! - the active point picked by a multiply-shift of one `u64`, retired by
//!   swap-remove after `k` failures.
//!
//! Unlike the yardstick it has no `unsafe` (the padded grid keeps every index
//! in range; the bounds checks stay) and it takes the caller's generator.
//! It is a baseline, not a sampler: the reach `ceil(√N)` cells carries no
//! margin for rounding, and the grid is sized without a budget (the callers
//! pass benchmark sizes; `textbook` refuses a grid over `MAX_CELLS`).

use rand::Rng;

const EMPTY: u32 = u32::MAX;

/// The largest padded grid `textbook` allocates (1 GiB of `u32`).
pub(crate) const MAX_CELLS: usize = 1 << 28;

/// A uniform `f64` in `[0, 1)` from the top 53 bits of one draw.
#[expect(clippy::cast_precision_loss, reason = "53 bits convert exactly")]
fn unit<R: Rng>(rng: &mut R) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform index in `0..n` by multiply-shift (bias below `n / 2⁶⁴`).
#[expect(
    clippy::cast_possible_truncation,
    reason = "the product's high word is below n"
)]
fn below<R: Rng>(rng: &mut R, n: usize) -> usize {
    ((u128::from(rng.next_u64()) * n as u128) >> 64) as usize
}

/// The padded grid: strides, cell counts and the neighbour offsets.
struct Layout<const N: usize> {
    inv_side: f64,
    reach: usize,
    counts: [usize; N],
    strides: [usize; N],
    total: usize,
    /// The neighbour cells as runs along axis 0: (offset of the run's first
    /// cell from the home cell, its length), in memory order.
    runs: Vec<(isize, usize)>,
}

impl<const N: usize> Layout<N> {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        clippy::cast_precision_loss,
        clippy::cast_possible_wrap,
        reason = "benchmark sizes: a few cells per axis up to MAX_CELLS in all"
    )]
    fn new(extent: [f64; N], r: f64) -> Option<Self> {
        let root_n = (N as f64).sqrt();
        let side = r / root_n;
        let reach = root_n.ceil() as usize;
        let counts = extent.map(|e| ((e / side).ceil() as usize).max(1));
        let mut strides = [0; N];
        let mut total = 1usize;
        for (stride, count) in strides.iter_mut().zip(counts) {
            *stride = total;
            total = total.checked_mul(count.checked_add(2 * reach)?)?;
        }
        if total > MAX_CELLS {
            return None;
        }
        // Every offset in the (2m+1)^N block whose nearest face lies closer
        // than r, in memory order (axis 0 fastest).
        let width = 2 * reach + 1;
        let block = width.checked_pow(u32::try_from(N).ok()?)?;
        // Axis 0 runs fastest and its cells are adjacent in memory, so the
        // kept cells of each row form one run: one slice, one bounds check.
        let mut runs: Vec<(isize, usize)> = Vec::new();
        let mut previous = None;
        for code in 0..block {
            let (mut rest, mut linear, mut gap_squared) = (code, 0isize, 0.0);
            for stride in strides {
                let d = (rest % width) as isize - reach as isize;
                rest /= width;
                linear += d * stride as isize;
                let gap = (d.unsigned_abs().saturating_sub(1)) as f64 * side;
                gap_squared += gap * gap;
            }
            if gap_squared < r * r {
                match runs.last_mut() {
                    Some((_, length)) if previous == Some(code - 1) && code % width != 0 => {
                        *length += 1;
                    }
                    _ => runs.push((linear, 1)),
                }
                previous = Some(code);
            }
        }
        Some(Self {
            inv_side: 1.0 / side,
            reach,
            counts,
            strides,
            total,
            runs,
        })
    }

    /// The padded cell of a point inside the box.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "coordinates are inside the box"
    )]
    fn cell(&self, p: &[f64; N]) -> usize {
        let mut index = 0;
        for ((&x, &count), &stride) in p.iter().zip(&self.counts).zip(&self.strides) {
            let c = ((x * self.inv_side) as usize).min(count - 1);
            index += (c + self.reach) * stride;
        }
        index
    }
}

/// Textbook Bridson in the box `[0, extent)`; `None` if the padded grid
/// would hold more than `MAX_CELLS` cells.
pub(crate) fn textbook<const N: usize, R: Rng>(
    extent: [f64; N],
    r: f64,
    k: u32,
    rng: &mut R,
) -> Option<Vec<[f64; N]>> {
    let grid = Layout::new(extent, r)?;
    let mut cells = vec![EMPTY; grid.total];
    // Room for a typical set up front, as the yardstick does.
    let volume: f64 = extent.iter().product();
    let expected = volume / (0..N).fold(1.0, |p, _| p * r) * 0.8;
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a capacity hint, at most MAX_CELLS"
    )]
    let mut points: Vec<[f64; N]> = Vec::with_capacity((expected as usize).min(MAX_CELLS) + 16);
    let mut active: Vec<u32> = Vec::with_capacity(1024);
    let r_squared = r * r;
    let first: [f64; N] = extent.map(|e| unit(rng) * e);
    cells[grid.cell(&first)] = 0;
    points.push(first);
    active.push(0);
    while !active.is_empty() {
        let slot = below(rng, active.len());
        let centre = points[active[slot] as usize];
        let mut placed = false;
        for _ in 0..k {
            let candidate = loop {
                let offset: [f64; N] = core::array::from_fn(|_| (unit(rng) * 4.0 - 2.0) * r);
                let d_squared: f64 = offset.iter().map(|d| d * d).sum();
                if d_squared >= r_squared && d_squared < 4.0 * r_squared {
                    break core::array::from_fn(|a| centre[a] + offset[a]);
                }
            };
            if !(0..N).all(|a| candidate[a] >= 0.0 && candidate[a] < extent[a]) {
                continue;
            }
            let home = grid.cell(&candidate);
            let clear = grid.runs.iter().all(|&(offset, length)| {
                let first = home.wrapping_add_signed(offset);
                cells[first..first + length].iter().all(|&j| {
                    j == EMPTY || {
                        let q = &points[j as usize];
                        let mut d_squared = 0.0;
                        for a in 0..N {
                            let d = q[a] - candidate[a];
                            d_squared += d * d;
                        }
                        d_squared >= r_squared
                    }
                })
            });
            if clear {
                let index = u32::try_from(points.len()).ok()?;
                cells[home] = index;
                points.push(candidate);
                active.push(index);
                placed = true;
                break;
            }
        }
        if !placed {
            active.swap_remove(slot);
        }
    }
    Some(points)
}
