//! The dense grid in bricks, with the points stored in their brick (3-D).
//!
//! The same cells as [`super::dense::Dense`] (side `<= r/√N`, at most one
//! point each, padded by the reach, ghosts across periodic faces) and the
//! same part stencils, in another layout. In 3-D at a million points a
//! pick's 5×5×5 neighbourhood in the `u32` grid is 25 rows of indices in
//! 25 to 35 cache lines, and each occupied cell then sends it to a point
//! somewhere in a vector of 24 MB, a second miss that cannot start before
//! the first ends. Here
//!
//! - cells are grouped in bricks of 4×4×4, and a neighbourhood (within 2
//!   cells, 5 wide) always spans 2×2×2 bricks;
//! - a brick is a 64-bit mask of its occupied cells (bit `x + 4y + 16z`,
//!   the cell's place) followed by its points in the order of those
//!   places, up to [`CAPACITY`] of them (five lines in all), the rest in a
//!   spill chunk of its own (in the unit cube at 1 M points no brick holds
//!   more than 13); a cell's point is at its rank among the occupied
//!   places, so there is no per-cell array at all;
//!
//! so every line a search can need is known from the candidate's cell alone
//! and can be asked for at once. The grid takes 5 bytes a cell (4 for the
//! `u32` grid) but holds the points in them.
//!
//! With a reach of 2 (every box over 4 cells a side) the seed and the
//! searches AND the 8 bricks' masks with the stencil's cells in each brick
//! (tabled per part and per place of the window in its brick) and visit
//! only the occupied cells: a search goes brick by brick, the candidate's
//! own first, rather than nearest cell first (the journal's "3-D seed and
//! searches from the bricks' occupancy masks"). Other reaches scan the
//! stencil cell by cell, reading each cell's bit.
//!
//! A cell's address is a sum of one term per axis (its brick's offset along
//! that axis plus its place inside the brick), read from a table per axis;
//! a stencil entry is a triple of indices into the candidate's window of
//! those terms, so one stencil serves every position inside a brick.

use super::dense::{Stencil, StencilShape, closer, for_each_image, locate, part_of, parts};
use super::{DensePlan, NeighbourGrid};
use crate::budget::{bytes_of, vec_bytes};
use crate::domain::Domain;

/// Cells in a brick: the bits of its occupancy mask.
pub(super) const BRICK_CELLS: usize = 64;
/// Points a brick stores itself. 13 fill five lines with the occupancy mask
/// (8 + 13 × 24 = 320 bytes; the spill chunk's index lives beside the
/// bricks, in [`Bricks::spill_starts`]); in the
/// unit cube at `k = 30` a brick holds 6.7 points on average and at most 13
/// (1 M points, seed 1).
pub(crate) const CAPACITY: usize = 13;
/// A brick's spill chunk: room for every cell it has beyond [`CAPACITY`].
pub(super) const SPILL: usize = BRICK_CELLS - CAPACITY;
/// The largest reach (in cells) the windows hold: 3-D needs at most 3 (2 in
/// any box over 4 cells a side; see `grid::needed_reach`).
pub(crate) const MAX_REACH: usize = 3;
/// A window's length on one axis: `2·MAX_REACH + 1`, rounded up to 8 so
/// that an index masked with 7 needs no bounds check.
const WINDOW: usize = 8;
/// As in [`super::dense`]: cells looked up before their points are checked.
const SCAN_CHUNK: usize = 8;
/// As in [`super::dense`]: the most occupied cells the seed collects.
const SEED_MAX: usize = 32;
/// Never a valid address (found-cell slots start with it).
const NOWHERE: usize = usize::MAX;

/// Whether the sampler uses bricks in `n` dimensions: in 3-D only, where
/// the grid outgrows the caches (2-D's 1 M-point grid mostly fits them;
/// from 4-D a 64-cell brick is 2 cells wide).
pub(crate) const fn applies(n: usize) -> bool {
    n == 3
}

/// Bits of a cell coordinate inside its brick, per axis: 2 in 3-D (4
/// cells), so that a brick holds [`BRICK_CELLS`] cells (the only
/// dimension [`applies`] allows; 1-D and 2-D would take 6 and 3).
const fn brick_bits(n: usize) -> usize {
    match n {
        1 => 6,
        2 => 3,
        _ => 2,
    }
}

/// The points of one brick of cells, its occupancy mask first: `insert`
/// and the searches read it, and the first line is the one a search has
/// asked for.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Brick<const N: usize> {
    /// A bit per cell, set where the cell holds a point (bit `x + 4y +
    /// 16z`, the cell's place in the brick); its population is the count
    /// of points stored (home and ghosts).
    pub(super) occupied: u64,
    /// The first [`CAPACITY`] points, in the order of their cells' places.
    pub(super) points: [[f64; N]; CAPACITY],
}

impl<const N: usize> Brick<N> {
    pub(super) const EMPTY: Self = Self {
        occupied: 0,
        points: [[f64::INFINITY; N]; CAPACITY],
    };

    /// Points stored (home and ghosts), at most [`BRICK_CELLS`].
    pub(super) fn count(&self) -> usize {
        self.occupied.count_ones() as usize
    }
}

/// Bytes a bricked grid allocates before its first point, for a plan with
/// `padded` cells per axis (the padding included), or `None` on overflow.
/// The stencils are counted by the caller, as for the `u32` grid.
pub(crate) fn bytes_for<const N: usize>(padded: &[u64; N]) -> Option<u64> {
    let side = 1u64 << brick_bits(N);
    let mut bricks = 1u64;
    let mut tables = 0u64;
    for &m in padded {
        bricks = bricks.checked_mul(m.div_ceil(side))?;
        tables = tables.checked_add(m.checked_add(WINDOW as u64)?)?;
    }
    bricks
        .checked_mul(size_of::<Brick<N>>() as u64 + 4)?
        .checked_add(tables.checked_mul(size_of::<usize>() as u64)?)
}

/// Where cells are: the address tables and the padding, and what the
/// ghosts need.
#[derive(Debug)]
struct Geometry<const N: usize> {
    /// Per axis, the address term of each padded coordinate `c`, at index
    /// `c + MAX_REACH` (zeros around), so that `c`'s window is
    /// `tables[axis][c..c + WINDOW]`.
    tables: [Vec<usize>; N],
    /// Cells per axis inside the box.
    counts: [usize; N],
    pad: [usize; N],
    periods: [f64; N],
    any_periodic: bool,
}

#[derive(Debug)]
pub(crate) struct Bricks<const N: usize> {
    /// The points of each brick, with its occupancy mask.
    bricks: Vec<Brick<N>>,
    /// Points past [`CAPACITY`] in a brick, in chunks of [`SPILL`].
    spill: Vec<[f64; N]>,
    /// Per brick, `1 +` the start of its chunk in [`Self::spill`], or 0:
    /// beside the bricks, so that a brick's header is its occupancy mask
    /// alone and 13 points still fill five lines.
    spill_starts: Vec<u32>,
    geometry: Geometry<N>,
    lo: [f64; N],
    inv_side: [f64; N],
    last: [usize; N],
    /// The whole cell's stencil (the pick's prefetch and the seed's cells).
    full: Vec<[u8; N]>,
    /// The parts' stencils, as [`super::dense::Dense`]'s.
    parts: Vec<Vec<[u8; N]>>,
    /// The full stencil without the centre, in address order of the `u32`
    /// grid (axis 2, then 1, then 0), as [`super::dense::Dense`] seeds.
    seed: Vec<[u8; N]>,
    /// With a reach of 2 on every axis, the address steps from a window's
    /// first brick to each of its `2^N` bricks; else empty.
    corners: Vec<usize>,
    /// The window entries of the reach box's `2^N` corners.
    corner_entries: Vec<[u8; N]>,
    /// With a reach of 2 on every axis in 3-D, per part and per place of
    /// the window's low corner in its brick (`part · 64 + place`), the
    /// cells of the part's stencil in each of the window's 8 bricks (as
    /// [`Self::corners`] orders them), as bit masks; else empty.
    part_masks: Vec<[u64; 8]>,
    /// As [`Self::part_masks`] for the seed's cells (the whole stencil but
    /// the centre), per place; empty with them.
    seed_masks: Vec<[u64; 8]>,
    stencil_bytes: u64,
    periods: [f64; N],
    any_periodic: bool,
    radius_squared: f64,
}

/// A stencil's offsets as window indices: `Stencil::new` is given strides
/// `8^i`, so an offset `Σ d_i·8^i` with `|d_i| <= 3` decodes to
/// `d_i + MAX_REACH` per axis.
fn entries<const N: usize>(stencil: &Stencil) -> Option<Vec<[u8; N]>> {
    let bias: isize = (0..N).map(|i| 3isize << (3 * i)).sum();
    let mut out = Vec::new();
    out.try_reserve_exact(stencil.offsets.len()).ok()?;
    for &o in &stencil.offsets {
        let u = usize::try_from(o + bias).ok()?;
        let mut e = [0u8; N];
        for (i, x) in e.iter_mut().enumerate() {
            *x = u8::try_from((u >> (3 * i)) & 7).ok()?;
        }
        out.push(e);
    }
    Some(out)
}

/// A bricked grid's stencils as window entries (see [`entries`]): the
/// whole cell's, the seed's (the whole one but the centre, in the `u32`
/// grid's address order) and each part's.
pub(super) struct Windowed<const N: usize> {
    pub(super) full: Vec<[u8; N]>,
    pub(super) seed: Vec<[u8; N]>,
    pub(super) parts: Vec<Vec<[u8; N]>>,
}

impl<const N: usize> Windowed<N> {
    pub(super) fn new(plan: &DensePlan<N>, radius: f64) -> Option<Self> {
        let shape = StencilShape {
            reach: plan.reach,
            side: plan.side,
            eta: plan.eta,
            radius,
        };
        let stride: [usize; N] = core::array::from_fn(|i| 1 << (3 * i));
        let full = entries(&Stencil::new(&shape, &stride, &[0; N], 1)?)?;
        let centre = [u8::try_from(MAX_REACH).ok()?; N];
        let mut seed: Vec<[u8; N]> = full.iter().copied().filter(|&e| e != centre).collect();
        // Address order of the `u32` grid: the last axis slowest.
        seed.sort_unstable_by(|a, b| a.iter().rev().cmp(b.iter().rev()));
        let count = parts(N).checked_pow(u32::try_from(N).ok()?)?;
        let mut stencils = Vec::new();
        stencils.try_reserve_exact(count).ok()?;
        for k in 0..count {
            let part = part_of::<N>(k);
            stencils.push(entries(&Stencil::new(&shape, &stride, &part, parts(N))?)?);
        }
        Some(Self {
            full,
            seed,
            parts: stencils,
        })
    }
}

/// With a reach of 2 in 3-D, the part stencils' masks per part and place
/// of the window's low corner (`part · 64 + place`) and the seed's per
/// place (see [`stencil_masks`]).
pub(super) type Masks = (Vec<[u64; 8]>, Vec<[u64; 8]>);

pub(super) fn masks<const N: usize>(stencils: &[Vec<[u8; N]>], seed: &[[u8; N]]) -> Option<Masks> {
    let mut part_masks = Vec::new();
    part_masks
        .try_reserve_exact(stencils.len().checked_mul(BRICK_CELLS)?)
        .ok()?;
    for stencil in stencils {
        for place in 0..BRICK_CELLS {
            part_masks.push(stencil_masks(stencil, place));
        }
    }
    let mut seed_masks = Vec::new();
    seed_masks.try_reserve_exact(BRICK_CELLS).ok()?;
    for place in 0..BRICK_CELLS {
        seed_masks.push(stencil_masks(seed, place));
    }
    Some((part_masks, seed_masks))
}

impl<const N: usize> Geometry<N> {
    /// The address of a cell inside the box.
    fn home(&self, cell: &[usize; N]) -> usize {
        self.address_of(&core::array::from_fn(|i| {
            cell.get(i).copied().unwrap_or(0) + self.pad.get(i).copied().unwrap_or(0)
        }))
    }

    /// The address of a padded cell.
    fn address_of(&self, padded: &[usize; N]) -> usize {
        padded
            .iter()
            .zip(&self.tables)
            .map(|(&c, t)| t.get(c + MAX_REACH).copied().unwrap_or(0))
            .sum()
    }

    /// Calls `f` with the address of every cell `p`'s cell is stored in:
    /// its own, then its ghosts across periodic faces (several when the
    /// period is shorter than the padding), as [`super::dense::Dense`]
    /// writes them.
    fn placements(&self, cell: &[usize; N], mut f: impl FnMut(usize)) {
        f(self.home(cell));
        if self.any_periodic {
            for_each_image(cell, &self.pad, &self.counts, &self.periods, |at| {
                f(self.address_of(at));
            });
        }
    }
}

/// Whether the cell at `address` holds a point.
#[inline(always)]
fn is_occupied<const N: usize>(bricks: &[Brick<N>], address: usize) -> bool {
    bricks
        .get(address / BRICK_CELLS)
        .is_some_and(|b| b.occupied >> (address % BRICK_CELLS) & 1 == 1)
}

/// The rank of place `bit` among a brick's occupied cells: where its
/// point is stored (points are kept in the order of their cells' places).
#[inline(always)]
pub(super) fn rank(occupied: u64, bit: usize) -> usize {
    (occupied & ((1u64 << bit) - 1)).count_ones() as usize
}

impl<const N: usize> Bricks<N> {
    /// Allocates the grid, or `None` if the allocation fails or the plan's
    /// reach is past [`MAX_REACH`] (the caller then builds the `u32` grid).
    pub(crate) fn try_new(plan: &DensePlan<N>, domain: &Domain<N>, radius: f64) -> Option<Self> {
        if !applies(N) || plan.reach.iter().any(|&r| r > MAX_REACH) {
            return None;
        }
        let bits = brick_bits(N);
        let side = 1usize << bits;
        let mut tables: [Vec<usize>; N] = core::array::from_fn(|_| Vec::new());
        let mut brick_stride = 1usize;
        for (axis, (table, (&m, &pad))) in tables
            .iter_mut()
            .zip(plan.cells.iter().zip(&plan.reach))
            .enumerate()
        {
            let padded = m.checked_add(pad.checked_mul(2)?)?;
            table.try_reserve_exact(padded.checked_add(WINDOW)?).ok()?;
            table.resize(MAX_REACH, 0);
            for c in 0..padded {
                let brick = (c >> bits).checked_mul(brick_stride)?;
                let inside = (c & (side - 1)) << (bits * axis);
                table.push(brick.checked_mul(BRICK_CELLS)?.checked_add(inside)?);
            }
            table.resize(padded + WINDOW, 0);
            brick_stride = brick_stride.checked_mul(padded.div_ceil(side))?;
        }
        let mut bricks = Vec::new();
        bricks.try_reserve_exact(brick_stride).ok()?;
        crate::huge_pages::advise(&bricks);
        bricks.resize(brick_stride, Brick::EMPTY);
        let mut spill_starts = Vec::new();
        spill_starts.try_reserve_exact(brick_stride).ok()?;
        spill_starts.resize(brick_stride, 0);
        let Windowed {
            full,
            seed,
            parts: stencils,
        } = Windowed::new(plan, radius)?;
        let mut corners = Vec::new();
        let mut corner_entries = Vec::new();
        corner_entries.try_reserve_exact(1 << N).ok()?;
        for corner in 0..1usize << N {
            let mut entry = [0u8; N];
            let mut step = 0usize;
            let mut bricks_before = 1usize;
            for (axis, (e, (&r, &m))) in entry
                .iter_mut()
                .zip(plan.reach.iter().zip(&plan.cells))
                .enumerate()
            {
                let high = corner >> axis & 1 == 1;
                *e = u8::try_from(if high { MAX_REACH + r } else { MAX_REACH - r }).ok()?;
                if high {
                    step += bricks_before * BRICK_CELLS;
                }
                bricks_before *= (m + 2 * r).div_ceil(side);
            }
            corner_entries.push(entry);
            corners.push(step);
        }
        if plan.reach.iter().any(|&r| r != 2) {
            corners = Vec::new();
        }
        let (part_masks, seed_masks) = if N == 3 && !corners.is_empty() {
            masks(&stencils, &seed)?
        } else {
            (Vec::new(), Vec::new())
        };
        let stencil_bytes = stencils
            .iter()
            .chain([&full, &seed])
            .map(vec_bytes)
            .sum::<u64>()
            .saturating_add(vec_bytes(&stencils))
            .saturating_add(vec_bytes(&corners))
            .saturating_add(vec_bytes(&corner_entries))
            .saturating_add(vec_bytes(&part_masks))
            .saturating_add(vec_bytes(&seed_masks));
        Some(Self {
            bricks,
            spill: Vec::new(),
            spill_starts,
            geometry: Geometry {
                tables,
                counts: plan.cells,
                pad: plan.reach,
                periods: domain.periods(),
                any_periodic: domain.any_periodic(),
            },
            lo: domain.lo(),
            inv_side: plan.side.map(|s| 1.0 / s),
            last: plan.cells.map(|m| m.saturating_sub(1)),
            full,
            parts: stencils,
            seed,
            corners,
            corner_entries,
            part_masks,
            seed_masks,
            stencil_bytes,
            periods: domain.periods(),
            any_periodic: domain.any_periodic(),
            radius_squared: radius * radius,
        })
    }

    /// The address terms around a cell inside the box, per axis: entry `e`
    /// is the term of the cell `e - MAX_REACH` away.
    #[inline(always)]
    fn window(&self, cell: &[usize; N]) -> [&[usize; WINDOW]; N] {
        const ZERO: [usize; WINDOW] = [0; WINDOW];
        core::array::from_fn(|axis| {
            let c = cell.get(axis).copied().unwrap_or(0)
                + self.geometry.pad.get(axis).copied().unwrap_or(0);
            self.geometry
                .tables
                .get(axis)
                .and_then(|t| t.get(c..c + WINDOW))
                .and_then(|w| <&[usize; WINDOW]>::try_from(w).ok())
                .unwrap_or(&ZERO)
        })
    }

    /// The address of a stencil entry in a window.
    #[inline(always)]
    fn address(window: &[&[usize; WINDOW]; N], entry: &[u8; N]) -> usize {
        window
            .iter()
            .zip(entry)
            .map(|(w, &e)| w.get(usize::from(e) & (WINDOW - 1)).copied().unwrap_or(0))
            .sum()
    }

    /// Whether the cell at `address` holds a point.
    #[inline(always)]
    fn is_occupied(&self, address: usize) -> bool {
        is_occupied(&self.bricks, address)
    }

    /// The point in the cell at `address`, if any: its brick's points are
    /// in the order of their cells' places, so the cell's rank among the
    /// occupied ones says where.
    #[inline(always)]
    fn point(&self, address: usize) -> Option<&[f64; N]> {
        let brick = self.bricks.get(address / BRICK_CELLS)?;
        let bit = address % BRICK_CELLS;
        if brick.occupied >> bit & 1 == 0 {
            return None;
        }
        let at = rank(brick.occupied, bit);
        if at < CAPACITY {
            brick.points.get(at)
        } else {
            let mark = *self.spill_starts.get(address / BRICK_CELLS)?;
            let start = usize::try_from(mark).ok()?.checked_sub(1)?;
            self.spill.get(start + at - CAPACITY)
        }
    }

    /// Asks for the bricks of a window within `reach`: per brick the three
    /// lines that hold its mask and first 7 points (a brick holds 6.7 on
    /// average). With a
    /// reach of 2 (every box over 4 cells a side) the window spans exactly
    /// 2 bricks per axis, found from the first by [`Self::corners`]; else
    /// the bricks of the reach box's corners.
    #[inline(always)]
    fn prefetch_window(&self, window: &[&[usize; WINDOW]; N]) {
        let ask = |address: usize| {
            if let Some(b) = self.bricks.get(address / BRICK_CELLS) {
                crate::prefetch::prefetch(&b.points, 0);
                crate::prefetch::prefetch(&b.points, 3);
                crate::prefetch::prefetch(&b.points, 6);
            }
        };
        if self.corners.is_empty() {
            for entry in &self.corner_entries {
                ask(Self::address(window, entry));
            }
        } else {
            let first = Self::address(window, &[1; N]) & !(BRICK_CELLS - 1);
            for &step in &self.corners {
                ask(first + step);
            }
        }
    }

    /// As [`super::dense::Dense`]'s: the addresses of the occupied cells
    /// among `entries`, in order, into `found`, without a branch.
    #[inline(always)]
    fn occupied<const M: usize>(
        &self,
        window: &[&[usize; WINDOW]; N],
        entries: &[[u8; N]],
        found: &mut [usize; M],
    ) -> usize {
        let mut n = 0;
        for entry in entries {
            n = self.note(Self::address(window, entry), found, n);
        }
        n
    }

    /// Notes the cell at `address` in `found` after the `n` occupied
    /// ones, without a branch; returns `n + 1` if it is occupied, else `n`
    /// (so the next cell overwrites it). Past `M` occupied cells, later
    /// ones overwrite earlier ones, which only the seed can meet, and any
    /// subset suits it.
    #[inline(always)]
    fn note<const M: usize>(&self, address: usize, found: &mut [usize; M], n: usize) -> usize {
        let occupied = self.is_occupied(address);
        if let Some(f) = found.get_mut(n % M) {
            *f = address;
        }
        n + usize::from(occupied)
    }

    #[inline(always)]
    fn scan<const PERIODIC: bool>(
        &self,
        window: &[&[usize; WINDOW]; N],
        stencil: &[[u8; N]],
        p: &[f64; N],
    ) -> Option<[f64; N]> {
        let mut found = [NOWHERE; SCAN_CHUNK];
        for chunk in stencil.chunks(SCAN_CHUNK) {
            let n = self.occupied(window, chunk, &mut found);
            for &address in found.iter().take(n) {
                let Some(q) = self.point(address) else {
                    continue;
                };
                if closer::<PERIODIC, N>(p, q, &self.periods, self.radius_squared) {
                    return Some(*q);
                }
            }
        }
        None
    }

    /// [`Self::scan`] from the bricks' occupancy masks (a reach of 2 in
    /// 3-D), through [`Self::first_masked`]. (Without masks for this part
    /// and place, which `try_new` always builds, the cell-by-cell scan of
    /// `stencil`: never a silent "no conflict".)
    #[inline(always)]
    fn scan_masks<const PERIODIC: bool>(
        &self,
        window: &[&[usize; WINDOW]; N],
        part: usize,
        stencil: &[[u8; N]],
        p: &[f64; N],
    ) -> Option<[f64; N]> {
        let low = Self::address(window, &[1; N]);
        let Some(masks) = self.part_masks.get(part * BRICK_CELLS + low % BRICK_CELLS) else {
            return self.scan::<PERIODIC>(window, stencil, p);
        };
        self.first_masked(low, masks, |q| {
            closer::<PERIODIC, N>(p, q, &self.periods, self.radius_squared)
        })
    }

    /// [`masked_walk`] over this grid's bricks: the window whose low
    /// corner is at `low` spans 8 bricks, found from the first by
    /// [`Self::corners`].
    #[inline(always)]
    fn first_masked(
        &self,
        low: usize,
        masks: &[u64; 8],
        stop: impl FnMut(&[f64; N]) -> bool,
    ) -> Option<[f64; N]> {
        let first = low & !(BRICK_CELLS - 1);
        let at = |corner: usize| first + self.corners.get(corner).copied().unwrap_or(0);
        masked_walk(
            low % BRICK_CELLS,
            masks,
            |corner| {
                self.corners.get(corner)?;
                self.bricks.get(at(corner) / BRICK_CELLS)
            },
            |corner, _, bit| self.point(at(corner) + bit),
            stop,
        )
    }

    /// Spill slots that storing a point in `cell` may open: a chunk for
    /// each placement whose brick has none and could fill past
    /// [`CAPACITY`] (bricks met twice counted twice: an upper bound).
    fn spill_needed(&self, cell: &[usize; N]) -> usize {
        if !self.geometry.any_periodic {
            let home = self.geometry.home(cell) / BRICK_CELLS;
            return match (self.bricks.get(home), self.spill_starts.get(home)) {
                (Some(b), Some(0)) if b.count() >= CAPACITY => SPILL,
                _ => 0,
            };
        }
        let mut total = 0usize;
        self.geometry.placements(cell, |_| total += 1);
        let mut needed = 0usize;
        self.geometry.placements(cell, |address| {
            let brick = address / BRICK_CELLS;
            if let (Some(b), Some(0)) = (self.bricks.get(brick), self.spill_starts.get(brick))
                && b.count() + total > CAPACITY
            {
                needed += SPILL;
            }
        });
        needed
    }
}

/// The points of the occupied cells among `masks` (a window of a reach of
/// 2 in 3-D, whose low corner lies at `place` in its brick, spans 8
/// bricks; a mask per brick, bit `a` of its index the next brick along
/// axis `a`), brick by brick, the one holding the window's centre first,
/// each brick's in cell order, handed to `stop` until it says so: then
/// that point. `brick(corner)` is a corner's brick (`None`: empty), and
/// `point(corner, brick, bit)` the point of its occupied cell `bit`. The
/// dense and the paged bricks both search through it, so they visit the
/// points in one order and make the same set.
#[inline(always)]
pub(super) fn masked_walk<'a, const N: usize>(
    place: usize,
    masks: &[u64; 8],
    brick: impl Fn(usize) -> Option<&'a Brick<N>>,
    point: impl Fn(usize, &'a Brick<N>, usize) -> Option<&'a [f64; N]>,
    mut stop: impl FnMut(&[f64; N]) -> bool,
) -> Option<[f64; N]> {
    // The centre is 2 past the low corner on every axis.
    let own = ((place & 3) + 2) >> 2
        | (((place >> 2 & 3) + 2) >> 2) << 1
        | (((place >> 4) + 2) >> 2) << 2;
    for k in 0..8 {
        let corner = k ^ own;
        let (Some(b), Some(&mask)) = (brick(corner), masks.get(corner)) else {
            continue;
        };
        let mut m = b.occupied & mask;
        while m != 0 {
            let bit = m.trailing_zeros() as usize;
            m &= m - 1;
            if let Some(q) = point(corner, b, bit)
                && stop(q)
            {
                return Some(*q);
            }
        }
    }
    None
}

/// A stencil's cells (window entries, reach 2) as bit masks over the 8
/// bricks of a window whose low corner lies at `place` in its brick (bit
/// `a` of the brick's index: the next brick along axis `a`).
fn stencil_masks<const N: usize>(stencil: &[[u8; N]], place: usize) -> [u64; 8] {
    let lows = [place & 3, place >> 2 & 3, place >> 4];
    let mut masks = [0u64; 8];
    for entry in stencil {
        let mut corner = 0;
        let mut bit = 0;
        for (axis, (&e, &low)) in entry.iter().zip(&lows).enumerate() {
            // Entry 1 is the low corner (an offset of -2).
            let at = low + usize::from(e).saturating_sub(1);
            corner |= (at >> 2) << axis;
            bit |= (at & 3) << (2 * axis);
        }
        if let Some(m) = masks.get_mut(corner) {
            *m |= 1 << bit;
        }
    }
    masks
}

impl<const N: usize> NeighbourGrid<N> for Bricks<N> {
    #[inline(always)]
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]> {
        let (cell, part) = locate(p, &self.lo, &self.inv_side, &self.last, parts(N));
        let window = self.window(&cell);
        let stencil = self.parts.get(part).unwrap_or(&self.full);
        self.prefetch_window(&window);
        if !self.part_masks.is_empty() {
            return if self.any_periodic {
                self.scan_masks::<true>(&window, part, stencil, p)
            } else {
                self.scan_masks::<false>(&window, part, stencil, p)
            };
        }
        if self.any_periodic {
            self.scan::<true>(&window, stencil, p)
        } else {
            self.scan::<false>(&window, stencil, p)
        }
    }

    /// As [`super::dense::Dense`]'s seed: the cells of the whole stencil
    /// in the `u32` grid's address order, the occupied ones' addresses
    /// first, then their points.
    #[inline(always)]
    fn seed(&self, p: &[f64; N], limit: usize, mut take: impl FnMut(&[f64; N])) {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        let window = self.window(&cell);
        // With a reach of 2 on every axis, the window's 2 × 2 × 2 bricks,
        // each brick's occupied cells from its mask.
        let low = Self::address(&window, &[1; N]);
        if let Some(masks) = self.seed_masks.get(low % BRICK_CELLS) {
            let mut taken = 0;
            self.first_masked(low, masks, |q| {
                take(q);
                taken += 1;
                taken == limit
            });
            return;
        }
        let mut found = [NOWHERE; SEED_MAX];
        let n = self.occupied(&window, &self.seed, &mut found);
        let mut taken = 0;
        for &address in found.iter().take(n) {
            if taken == limit {
                break;
            }
            if let Some(q) = self.point(address) {
                take(q);
                taken += 1;
            }
        }
    }

    #[inline(always)]
    fn prefetch(&self, p: &[f64; N]) {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        self.prefetch_window(&self.window(&cell));
    }

    fn bytes(&self) -> u64 {
        let tables = self
            .geometry
            .tables
            .iter()
            .map(vec_bytes)
            .fold(0u64, u64::saturating_add);
        vec_bytes(&self.bricks)
            .saturating_add(vec_bytes(&self.spill))
            .saturating_add(vec_bytes(&self.spill_starts))
            .saturating_add(tables)
            .saturating_add(self.stencil_bytes)
    }

    fn reserve(&mut self, p: &[f64; N], spare: u64) -> bool {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        let needed = self.spill_needed(&cell);
        let (len, capacity) = (self.spill.len(), self.spill.capacity());
        if capacity - len >= needed {
            return true;
        }
        // Double, or as much as the budget allows; the old block is held
        // while the new one is filled, so the new one alone must fit.
        let fits = usize::try_from(spare / bytes_of::<[f64; N]>(1).max(1)).unwrap_or(usize::MAX);
        let wanted = capacity.saturating_mul(2).max(len + needed).min(fits);
        if wanted < len + needed {
            return false;
        }
        self.spill.try_reserve_exact(wanted - len).is_ok()
    }

    #[inline(always)]
    fn insert(&mut self, p: [f64; N]) -> bool {
        let (cell, _) = locate(&p, &self.lo, &self.inv_side, &self.last, 1);
        let home = self.geometry.home(&cell);
        // Occupied only if rounding put two valid points in one cell: drop
        // the newcomer, the set stays valid. Every placement is checked for
        // room before any is written, so a point is stored with all its
        // ghosts or not at all.
        if self.is_occupied(home) {
            return false;
        }
        let needed = self.spill_needed(&cell);
        if self.spill.capacity() - self.spill.len() < needed {
            return false;
        }
        let Self {
            bricks,
            spill,
            spill_starts,
            geometry,
            ..
        } = self;
        let mut stored = true;
        geometry.placements(&cell, |a| {
            if !is_occupied(bricks, a) {
                stored &= put(bricks, (spill, spill_starts), a, &p);
            }
        });
        stored
    }
}

/// Stores `p` in the (empty) cell at `address`, at its rank among the
/// brick's occupied cells (later ranks move up one, into the brick's
/// spill chunk past [`CAPACITY`]); `false` if the brick needs a spill
/// chunk there is no room for.
pub(super) fn put<const N: usize>(
    bricks: &mut [Brick<N>],
    (spill, spill_starts): (&mut Vec<[f64; N]>, &mut [u32]),
    address: usize,
    p: &[f64; N],
) -> bool {
    let (Some(brick), Some(spill_start)) = (
        bricks.get_mut(address / BRICK_CELLS),
        spill_starts.get_mut(address / BRICK_CELLS),
    ) else {
        return false;
    };
    let bit = address % BRICK_CELLS;
    let count = brick.count();
    if brick.occupied >> bit & 1 == 1 || count >= BRICK_CELLS {
        return false;
    }
    if count >= CAPACITY && *spill_start == 0 {
        let start = spill.len();
        // `reserve` made the room: this never allocates.
        if spill.capacity() - start < SPILL {
            return false;
        }
        let Ok(mark) = u32::try_from(start + 1) else {
            return false;
        };
        spill.resize(start + SPILL, [f64::INFINITY; N]);
        *spill_start = mark;
    }
    let start = usize::try_from(*spill_start).unwrap_or(0).saturating_sub(1);
    let at = rank(brick.occupied, bit);
    // Ranks `at..count` move up one, the highest first.
    for i in (at..count).rev() {
        let moved = if i < CAPACITY {
            brick.points.get(i).copied()
        } else {
            spill.get(start + i - CAPACITY).copied()
        };
        let to = if i + 1 < CAPACITY {
            brick.points.get_mut(i + 1)
        } else {
            spill.get_mut(start + i + 1 - CAPACITY)
        };
        if let (Some(q), Some(to)) = (moved, to) {
            *to = q;
        }
    }
    let slot = if at < CAPACITY {
        brick.points.get_mut(at)
    } else {
        spill.get_mut(start + at - CAPACITY)
    };
    match slot {
        Some(q) => *q = *p,
        None => return false,
    }
    brick.occupied |= 1 << bit;
    true
}

#[cfg(test)]
mod tests {
    use super::super::{GridLayout, GridPlan, plan};
    use super::*;
    use crate::vector::{distance_squared, periodic_distance_squared};

    fn bricks(domain: &Domain<3>, r: f64) -> Bricks<3> {
        match plan(domain, r, GridLayout::Dense, 1 << 30, None, None) {
            Ok(GridPlan::Dense(p)) => {
                assert!(p.bricked, "3-D plans bricks");
                Bricks::try_new(&p, domain, r).expect("allocates")
            }
            other => panic!("no dense plan: {other:?}"),
        }
    }

    #[test]
    fn a_brick_is_five_cache_lines() {
        assert_eq!(
            size_of::<Brick<3>>(),
            320,
            "13 points and the occupancy mask"
        );
        assert_eq!(align_of::<Brick<3>>(), 64, "line-aligned");
    }

    /// Every cell of the padded grid has its own address, and the cells of
    /// a brick share one line.
    #[test]
    fn addresses_are_distinct_and_bricked() {
        let g = bricks(&Domain::from_extent([1.0, 0.3, 0.5]).unwrap(), 0.1);
        let padded: [usize; 3] =
            core::array::from_fn(|i| g.geometry.counts[i] + 2 * g.geometry.pad[i]);
        let mut seen = vec![false; g.bricks.len() * BRICK_CELLS];
        for z in 0..padded[2] {
            for y in 0..padded[1] {
                for x in 0..padded[0] {
                    let a = g.geometry.address_of(&[x, y, z]);
                    assert!(!seen[a], "address {a} twice");
                    seen[a] = true;
                    let corner = g.geometry.address_of(&[x & !3, y & !3, z & !3]);
                    assert_eq!(a / BRICK_CELLS, corner / BRICK_CELLS, "({x}, {y}, {z})");
                }
            }
        }
    }

    /// As the `u32` grid's test: a conflict is found exactly when a brute
    /// force over every stored point finds one, for candidates on cell and
    /// part faces, a hair either side, and at random; in boxes with a reach
    /// of 1, 2 and 3 cells, bounded and periodic (ghosts).
    #[test]
    fn conflicts_agree_with_brute_force() {
        fn check(domain: Domain<3>, r: f64, seed: u64) -> [usize; 3] {
            let mut g = bricks(&domain, r);
            let mut rng = crate::random::seeded_rng(seed);
            let mut stored: Vec<[f64; 3]> = Vec::new();
            let side = g.inv_side.map(|s| 1.0 / s);
            let counts = g.geometry.counts;
            let periods = domain.periods();
            let coordinate = |axis: usize, rng: &mut crate::random::DefaultRng| {
                super::super::dense::probe(
                    rng,
                    domain.lo()[axis],
                    domain.hi()[axis],
                    side[axis],
                    counts[axis],
                )
            };
            let (mut hits, mut misses) = (0, 0);
            for _ in 0..3000 {
                let p: [f64; 3] = core::array::from_fn(|axis| coordinate(axis, &mut rng));
                let brute = stored
                    .iter()
                    .any(|q| periodic_distance_squared(&p, q, &periods) < r * r);
                assert_eq!(g.conflict(&p).is_some(), brute, "{p:?}, r = {r}");
                if brute {
                    hits += 1;
                } else {
                    misses += 1;
                    assert!(g.reserve(&p, u64::MAX), "reserve");
                    if g.insert(p) {
                        stored.push(p);
                    }
                }
            }
            assert!(hits > 300 && misses >= 5, "{hits} hits, {misses} misses");
            g.geometry.pad
        }
        let unit = Domain::from_extent([1.0, 0.8, 0.6]).unwrap();
        assert_eq!(check(unit, 0.1, 3), [2; 3], "reach");
        check(unit.with_periodic([true, false, true]), 0.1, 4);
        // Reach 3 (4 cells a side), and 1 (2 cells).
        let reach = check(Domain::from_extent([0.0101; 3]).unwrap(), 0.0058, 5);
        assert_eq!(reach, [3; 3], "reach");
        let reach = check(Domain::from_extent([0.5, 0.4, 0.3]).unwrap(), 0.3, 6);
        assert_eq!(reach, [2, 2, 1], "reach");
        // Periods shorter than the padding: several ghosts a point.
        check(
            Domain::from_extent([0.15, 1.0, 0.1])
                .unwrap()
                .with_periodic([true, false, true]),
            0.1,
            7,
        );
    }

    /// The seed read from the bricks' occupancy masks gives the points of
    /// the 5 × 5 × 5 box around the cell but its centre, as the cell-by-cell
    /// scan does (bounded and periodic, ghosts included); and each part's
    /// masks hold exactly its stencil's cells.
    #[test]
    fn masks_agree_with_the_cells() {
        for (domain, seed) in [
            (Domain::from_extent([1.0, 0.8, 0.6]).unwrap(), 11),
            (
                Domain::from_extent([0.9, 1.0, 0.7])
                    .unwrap()
                    .with_periodic([true, false, true]),
                12,
            ),
        ] {
            let r = 0.1;
            let mut g = bricks(&domain, r);
            assert_eq!(g.geometry.pad, [2; 3], "reach");
            assert_eq!(g.part_masks.len(), g.parts.len() * BRICK_CELLS, "masks");
            assert_eq!(
                g.seed.len(),
                124,
                "the seed's stencil: the box but its centre"
            );
            let mut rng = crate::random::seeded_rng(seed);
            let mut probes = Vec::new();
            for _ in 0..2000 {
                let p: [f64; 3] = core::array::from_fn(|axis| {
                    domain.lo()[axis]
                        + crate::random::unit(&mut rng) * (domain.hi()[axis] - domain.lo()[axis])
                });
                probes.push(p);
                if g.conflict(&p).is_none() {
                    assert!(g.reserve(&p, u64::MAX), "reserve");
                    g.insert(p);
                }
            }
            let mut checked = 0;
            for p in &probes {
                let mut by_masks = Vec::new();
                g.seed(p, 64, |q| by_masks.push(q.map(f64::to_bits)));
                let (cell, _) = locate(p, &g.lo, &g.inv_side, &g.last, 1);
                let window = g.window(&cell);
                // The box cell by cell: window entries 1..=5 on each axis.
                let mut by_cells = Vec::new();
                for z in 1..=5u8 {
                    for y in 1..=5u8 {
                        for x in 1..=5u8 {
                            if [x, y, z] == [3; 3] {
                                continue;
                            }
                            let a = Bricks::address(&window, &[x, y, z]);
                            if let Some(q) = g.point(a) {
                                by_cells.push(q.map(f64::to_bits));
                            }
                        }
                    }
                }
                by_masks.sort_unstable();
                by_cells.sort_unstable();
                assert_eq!(by_masks, by_cells, "{p:?}");
                checked += by_cells.len();
            }
            assert!(checked > 5000, "{checked} points compared");
            for (k, stencil) in g.parts.iter().enumerate() {
                for place in 0..BRICK_CELLS {
                    let masks = g.part_masks[k * BRICK_CELLS + place];
                    let cells: u32 = masks.iter().map(|m| m.count_ones()).sum();
                    assert_eq!(cells as usize, stencil.len(), "part {k}, place {place}");
                }
            }
        }
    }

    /// A brick filled past its own room spills, and its points are still
    /// found, within the reserved bytes.
    #[test]
    fn full_bricks_spill() {
        let domain = Domain::from_extent([1.0; 3]).unwrap();
        let r = 0.1;
        let mut g = bricks(&domain, r);
        let side = 1.0 / g.inv_side[0];
        let before = g.bytes();
        // Every cell of one brick (cells 2 to 5 a side, padded 4 to 7; not
        // a valid set: the grid stores what it is given).
        assert_eq!(g.geometry.pad, [2; 3], "padding");
        let mut stored = Vec::new();
        for z in 2..6 {
            for y in 2..6 {
                for x in 2..6 {
                    let p = [x, y, z].map(|i| (f64::from(i) + 0.5) * side);
                    assert!(g.reserve(&p, u64::MAX), "reserve");
                    assert!(g.insert(p), "insert {p:?}");
                    stored.push(p);
                }
            }
        }
        assert!(!g.spill.is_empty(), "spilled");
        assert!(g.bytes() > before, "the spill is counted");
        for p in &stored {
            let q = g.conflict(p).expect("found");
            assert!(distance_squared(p, &q) < r * r, "{p:?}");
            let mut n = 0;
            g.seed(p, 32, |_| n += 1);
            assert!(n >= 16, "seed from {p:?}: {n}");
        }
        // No room for a spill chunk: refused before anything is stored.
        let mut h = bricks(&domain, r);
        for p in stored.iter().take(CAPACITY) {
            assert!(h.insert(*p), "within the brick");
        }
        assert!(!h.reserve(&stored[CAPACITY], 0), "no spare bytes");
        assert!(!h.insert(stored[CAPACITY]), "no room reserved");
        assert!(
            h.conflict(&stored[CAPACITY]).is_some(),
            "its neighbours are"
        );
    }
}
