//! Bridson's dense background grid.
//!
//! Each cell has side `<= r/√N`, so it can hold at most one point of a valid
//! set; the cell stores that point's `u32` index into the point vector, whose
//! slot 0 is a sentinel at infinity that every empty cell points to. A
//! neighbour check is then a run over a precomputed list of linear cell
//! offsets, nearest first, for the half-cell the candidate lies in: eight
//! cells' indices at a time without a branch, then the points of the
//! occupied ones. Indices, not coordinates, live in the cells: most cells
//! are empty (89 % in 3-D), so inline coordinates would multiply the grid's
//! memory for no speed (`docs/performance-journal.md`).
//!
//! The grid is padded by the search reach on every side, so offsets never
//! leave the array. On a periodic axis the padding holds ghost entries for
//! the points near the opposite face (the same index, so the original
//! coordinates: the distance itself wraps), so the same branch-free scan
//! serves toroidal domains.

use super::{DensePlan, NeighbourGrid};
use crate::budget::{reserve_one, vec_bytes};
use crate::domain::Domain;
use crate::vector::{distance_squared, periodic_distance_squared};

/// Index 0 of `points` is this sentinel, infinitely far from everything:
/// empty cells hold index 0, so real points are indexed from 1 and an empty
/// cell needs no flag of its own.
const FAR: f64 = f64::INFINITY;
pub(crate) const EMPTY: u32 = 0;
/// The most occupied cells [`Dense::seed`] collects (a 3-D stencil holds
/// about 14 points in its 125 cells; the cache keeps at most 16).
const SEED_MAX: usize = 32;
/// Cells a search looks up before checking the points they hold: fewer
/// cost a branch more often, more look up cells past the conflict; 8 ran
/// the fewest instructions in 2-D and 3-D (the journal has the counts).
const SCAN_CHUNK: usize = 8;

#[derive(Debug)]
pub(crate) struct Dense<const N: usize> {
    /// Index into `points` of the point in each cell; [`EMPTY`] if none.
    cells: Vec<u32>,
    /// The points, in insertion order, after the sentinel at index 0.
    points: Vec<[f64; N]>,
    lo: [f64; N],
    inv_side: [f64; N],
    /// Cells per axis inside the box.
    counts: [usize; N],
    /// `counts - 1`: the last cell index inside the box on each axis.
    last: [usize; N],
    pad: [usize; N],
    stride: [usize; N],
    /// Linear index of the first cell inside the box: `Σ pad[i]·stride[i]`.
    pad_base: usize,
    /// The search stencil of a whole cell: every cell that can hold a
    /// point closer than `r` to a point of the centre cell. The seed and the
    /// pick's prefetch use it.
    full: Stencil,
    /// The stencils of the parts of a cell ([`parts`] per axis, part `Σ
    /// k_i·parts^i`; none with whole cells): a candidate is searched with the stencil of the part
    /// it lies in, which leaves out the cells that only the rest of its
    /// cell can reach. On average 16 cells instead of 25 in 2-D, 91
    /// instead of 125 in 3-D, 504 instead of 841 in 4-D.
    parts: Vec<Stencil>,
    /// The cells the seed reads, in address order: in 2-D the cells within
    /// `2r` of the centre cell ([`wide_seed`]), in 1-D and 3-D the full
    /// stencil; never the centre cell; none from 4-D.
    seed_offsets: Vec<isize>,
    /// Whether the seed is [`wide_seed`]'s (2-D, reach 2).
    wide_seed: bool,
    /// Heap bytes of the stencils, kept for [`NeighbourGrid::bytes`].
    stencil_bytes: u64,
    periods: [f64; N],
    any_periodic: bool,
    radius_squared: f64,
}

impl<const N: usize> Dense<N> {
    /// Allocates the grid, or `None` if the allocation fails.
    pub(crate) fn try_new(plan: &DensePlan<N>, domain: &Domain<N>, radius: f64) -> Option<Self> {
        let pad = plan.reach;
        let mut stride = [0usize; N];
        let mut total = 1usize;
        let mut pad_base = 0usize;
        for ((s, &cells), &p) in stride.iter_mut().zip(&plan.cells).zip(&pad) {
            *s = total;
            pad_base = pad_base.checked_add(p.checked_mul(total)?)?;
            total = total.checked_mul(cells.checked_add(p.checked_mul(2)?)?)?;
        }
        let mut cells = Vec::new();
        cells.try_reserve_exact(total).ok()?;
        // Before the first write: pages get their size when first touched.
        crate::huge_pages::advise(&cells);
        cells.resize(total, EMPTY);
        // The sentinel; the points grow as they come, within the budget
        // ([`NeighbourGrid::reserve`]).
        let mut points = Vec::new();
        points.try_reserve_exact(1).ok()?;
        points.push([FAR; N]);
        let shape = StencilShape {
            reach: plan.reach,
            side: plan.side,
            eta: plan.eta,
            radius,
        };
        let Searches {
            full,
            parts: stencils,
            seed_offsets,
            wide_seed: wide,
            bytes: stencil_bytes,
        } = Searches::new(&shape, &stride)?;
        Some(Self {
            cells,
            points,
            stencil_bytes,
            lo: domain.lo(),
            inv_side: plan.side.map(|s| 1.0 / s),
            counts: plan.cells,
            // Cell counts are at least 1 (`cell_count`).
            last: plan.cells.map(|m| m.saturating_sub(1)),
            pad,
            stride,
            pad_base,
            full,
            parts: stencils,
            seed_offsets,
            wide_seed: wide,
            periods: domain.periods(),
            any_periodic: domain.any_periodic(),
            radius_squared: radius * radius,
        })
    }

    /// Cell of a point inside the box, clamped against rounding at `hi`
    /// ([`Self::locate`] without the part).
    #[inline(always)]
    fn cell_of(&self, p: &[f64; N]) -> [usize; N] {
        self.locate(p).0
    }

    /// Linear index of a cell in padded coordinates.
    #[inline(always)]
    fn index(&self, padded: &[usize; N]) -> usize {
        padded.iter().zip(&self.stride).map(|(c, s)| c * s).sum()
    }

    /// Linear index of a cell inside the box (as from [`Self::cell_of`]).
    #[inline(always)]
    fn base(&self, cell: &[usize; N]) -> usize {
        self.index(cell) + self.pad_base
    }

    /// The cell of a candidate, and the part of it ([`parts`] per axis)
    /// that it lies in. The part is from the same rounded position as the
    /// cell, so off by no more than the rounding margin the stencils allow.
    #[inline(always)]
    fn locate(&self, p: &[f64; N]) -> ([usize; N], usize) {
        locate(p, &self.lo, &self.inv_side, &self.last, parts(N))
    }

    /// Asks for the cells of `stencil` around cell `base`, row by row: the
    /// first and last cell of each row (at most 20 bytes in 3-D, so at most
    /// two cache lines). Up to 3-D, as [`NeighbourGrid::seed`].
    #[inline(always)]
    fn prefetch_stencil(&self, base: usize, stencil: &Stencil) {
        if N > 3 {
            return;
        }
        for &[first, last] in &stencil.rows {
            crate::prefetch::prefetch(&self.cells, base.wrapping_add_signed(first));
            crate::prefetch::prefetch(&self.cells, base.wrapping_add_signed(last));
        }
    }

    #[inline(always)]
    fn scan<const PERIODIC: bool>(
        &self,
        base: usize,
        stencil: &Stencil,
        p: &[f64; N],
    ) -> Option<[f64; N]> {
        let near = Near {
            cells: &self.cells,
            points: &self.points,
            base,
        };
        near.conflict::<PERIODIC>(stencil, p, &self.periods, self.radius_squared)
    }

    /// Writes `p` into every ghost cell that stands for its cell across a
    /// periodic face (several when the period is shorter than the padding).
    fn write_images(&mut self, cell: &[usize; N], index: u32) {
        let (stride, cells) = (self.stride, &mut self.cells);
        for_each_image(cell, &self.pad, &self.counts, &self.periods, |at| {
            let at_index: usize = at.iter().zip(&stride).map(|(c, s)| c * s).sum();
            if let Some(slot) = cells.get_mut(at_index) {
                *slot = index;
            }
        });
    }
}

/// Whether `q` is closer than `r` to `p` (squared: `radius_squared`),
/// toroidally on the axes with a period if `PERIODIC`: the grids' exact
/// test.
#[inline(always)]
pub(crate) fn closer<const PERIODIC: bool, const N: usize>(
    p: &[f64; N],
    q: &[f64; N],
    periods: &[f64; N],
    radius_squared: f64,
) -> bool {
    let d2 = if PERIODIC {
        periodic_distance_squared(p, q, periods)
    } else {
        distance_squared(p, q)
    };
    d2 < radius_squared
}

/// Calls `f` with the padded coordinates of every ghost cell that stands
/// for `cell` (a cell inside the box) across periodic faces: several on an
/// axis whose period is shorter than the padding, none on a bounded box.
/// Shared by [`Dense`] and the bricked grid.
pub(crate) fn for_each_image<const N: usize>(
    cell: &[usize; N],
    pad: &[usize; N],
    counts: &[usize; N],
    periods: &[f64; N],
    mut f: impl FnMut(&[usize; N]),
) {
    // Per axis, in padded coordinates: the home cell, the first image and
    // the end of the images (step `counts`); bounded axes have one.
    let mut home = [0usize; N];
    let mut first = [0usize; N];
    let mut limit = [0usize; N];
    let axes = cell.iter().zip(pad).zip(counts.iter().zip(periods));
    for (((h, fst), l), ((&c, &pad), (&m, &period))) in
        home.iter_mut().zip(&mut first).zip(&mut limit).zip(axes)
    {
        *h = c + pad;
        (*fst, *l) = if period > 0.0 {
            (*h % m, m + 2 * pad)
        } else {
            (*h, *h + 1)
        };
    }
    let mut at = first;
    loop {
        if at != home {
            f(&at);
        }
        // Odometer over the images of every axis: step the first axis that
        // has another image, resetting the axes before it.
        let mut stepped = false;
        let axes = first.iter().zip(&limit).zip(counts.iter().zip(periods));
        for (a, ((&fst, &l), (&m, &period))) in at.iter_mut().zip(axes) {
            *a += m;
            if *a < l && period > 0.0 {
                stepped = true;
                break;
            }
            *a = fst;
        }
        if !stepped {
            return;
        }
    }
}

impl<const N: usize> NeighbourGrid<N> for Dense<N> {
    const WIDE_SEED: bool = true;

    #[inline(always)]
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]> {
        let (cell, part) = self.locate(p);
        let base = self.base(&cell);
        let stencil = self.parts.get(part).unwrap_or(&self.full);
        // Ask for the whole stencil first: the scan exits at the first
        // conflict, but a candidate that gets this far often has none
        // nearby, and then every row is read.
        self.prefetch_stencil(base, stencil);
        if self.any_periodic {
            self.scan::<true>(base, stencil, p)
        } else {
            self.scan::<false>(base, stencil, p)
        }
    }

    /// The points around `p` (its nearest neighbours, the ones that block
    /// most of its annulus), until the cache is full: in 2-D those of the
    /// cells within `2r` ([`wide_seed`]), in 1-D and 3-D those of its
    /// search stencil. Two
    /// passes, so that the memory loads go out together: the cells in
    /// address order (each row of the stencil is one or two cache lines),
    /// collecting the indices of occupied cells without a branch; then
    /// those points. Up to 3-D only: the 4-D stencil has 841 cells.
    #[inline(always)]
    fn seed(&self, p: &[f64; N], limit: usize, take: impl FnMut(&[f64; N])) {
        if N > 3 {
            return;
        }
        let near = Near {
            cells: &self.cells,
            points: &self.points,
            base: self.base(&self.cell_of(p)),
        };
        near.seed(&self.seed_offsets, limit, take);
    }

    #[inline(always)]
    fn prefetch(&self, p: &[f64; N]) {
        let base = self.base(&self.cell_of(p));
        match self.stride.get(1) {
            // The seed's 7 rows (its outer ones are beyond the stencil's
            // 5): on an AMD EPYC host 5 % less time in 2-D than the
            // stencil's rows (`docs/performance-journal.md`, "The 2-D seed
            // out to 2r").
            Some(&row) if self.wide_seed => {
                for [first, last] in wide_seed_rows(row) {
                    crate::prefetch::prefetch(&self.cells, base.wrapping_add_signed(first));
                    crate::prefetch::prefetch(&self.cells, base.wrapping_add_signed(last));
                }
            }
            _ => self.prefetch_stencil(base, &self.full),
        }
    }

    fn bytes(&self) -> u64 {
        vec_bytes(&self.cells)
            .saturating_add(self.stencil_bytes)
            .saturating_add(vec_bytes(&self.points))
    }

    fn reserve(&mut self, _p: &[f64; N], spare: u64) -> bool {
        let capacity = self.points.capacity();
        let grown = reserve_one(&mut self.points, spare).is_some();
        if self.points.capacity() != capacity {
            // Moved to a larger allocation: ask again.
            crate::huge_pages::advise(&self.points);
        }
        grown
    }

    #[inline(always)]
    fn insert(&mut self, p: [f64; N]) -> bool {
        let cell = self.cell_of(&p);
        let base = self.base(&cell);
        // More than u32::MAX - 1 points cannot be indexed: refuse the
        // candidate (the set stays valid, the run ends there).
        let Ok(index) = u32::try_from(self.points.len()) else {
            return false;
        };
        if index == u32::MAX {
            return false;
        }
        match self.cells.get_mut(base) {
            // Occupied only if rounding put two valid points in one cell:
            // drop the newcomer, the set stays valid.
            Some(slot) if *slot == EMPTY => *slot = index,
            _ => return false,
        }
        self.points.push(p);
        if self.any_periodic {
            self.write_images(&cell, index);
        }
        true
    }
}

/// A candidate's neighbourhood in an array of `u32` cells (the dense
/// grid's, or one page of the paged grid's): the cells, the points they
/// index, and the candidate's cell.
pub(crate) struct Near<'a, const N: usize> {
    pub(crate) cells: &'a [u32],
    pub(crate) points: &'a [[f64; N]],
    pub(crate) base: usize,
}

impl<const N: usize> Near<'_, N> {
    /// The first point of `stencil`'s cells closer than `r` to `p`: in
    /// chunks, nearest first, the occupied cells' indices without a branch
    /// (most cells are empty), then only those points.
    #[inline(always)]
    pub(crate) fn conflict<const PERIODIC: bool>(
        &self,
        stencil: &Stencil,
        p: &[f64; N],
        periods: &[f64; N],
        radius_squared: f64,
    ) -> Option<[f64; N]> {
        let mut found = [EMPTY; SCAN_CHUNK];
        for chunk in stencil.offsets.chunks(SCAN_CHUNK) {
            let n = occupied(self.cells, self.base, chunk, &mut found);
            for &index in found.iter().take(n) {
                let Some(q) = self.points.get(index as usize) else {
                    continue;
                };
                if closer::<PERIODIC, N>(p, q, periods, radius_squared) {
                    return Some(*q);
                }
            }
        }
        None
    }

    /// Hands up to `limit` points of the cells at `offsets` to `take`.
    #[inline(always)]
    pub(crate) fn seed(&self, offsets: &[isize], limit: usize, mut take: impl FnMut(&[f64; N])) {
        let mut found = [EMPTY; SEED_MAX];
        let n = occupied(self.cells, self.base, offsets, &mut found);
        for &index in found.iter().take(n.min(limit)) {
            if let Some(q) = self.points.get(index as usize) {
                take(q);
            }
        }
    }
}

/// What a grid of `u32` cells laid out with fixed strides searches with:
/// the whole cell's stencil, one per part of a cell ([`parts`] per axis,
/// part `Σ k_i·parts^i`; none with whole cells), and the seed's cells.
/// Shared by [`Dense`] and the paged grid, whose pages have strides too.
#[derive(Debug)]
pub(crate) struct Searches {
    pub(crate) full: Stencil,
    pub(crate) parts: Vec<Stencil>,
    /// The cells the seed reads, in address order: in 2-D with a reach of
    /// 2 the cells within `2r` ([`wide_seed`]), up to 3-D the full stencil
    /// but the centre, none from 4-D.
    pub(crate) seed_offsets: Vec<isize>,
    /// Whether the seed is [`wide_seed`]'s.
    pub(crate) wide_seed: bool,
    /// Heap bytes of all of it.
    pub(crate) bytes: u64,
}

impl Searches {
    /// The stencils for cells of `shape` laid out with `stride`, or `None`
    /// if their memory cannot be had.
    pub(crate) fn new<const N: usize>(
        shape: &StencilShape<N>,
        stride: &[usize; N],
    ) -> Option<Self> {
        let full = Stencil::new(shape, stride, &[0; N], 1)?;
        let wide = <&[usize; 2]>::try_from(stride.as_slice())
            .ok()
            .filter(|_| shape.reach.iter().all(|&p| p == 2));
        let mut seed_offsets: Vec<isize> = if let Some(stride) = wide {
            wide_seed(stride)?
        } else if N <= 3 {
            full.offsets.iter().copied().filter(|&o| o != 0).collect()
        } else {
            Vec::new()
        };
        seed_offsets.sort_unstable();
        // With whole cells (from 5-D) every search uses `full`: no copy.
        let count = if parts(N) > 1 {
            parts(N).checked_pow(u32::try_from(N).ok()?)?
        } else {
            0
        };
        let mut stencils = Vec::new();
        stencils.try_reserve_exact(count).ok()?;
        for k in 0..count {
            stencils.push(Stencil::new(shape, stride, &part_of::<N>(k), parts(N))?);
        }
        let bytes = stencils
            .iter()
            .chain([&full])
            .map(Stencil::bytes)
            .sum::<u64>()
            .saturating_add(vec_bytes(&stencils))
            .saturating_add(vec_bytes(&seed_offsets));
        Some(Self {
            full,
            parts: stencils,
            seed_offsets,
            wide_seed: wide.is_some(),
            bytes,
        })
    }
}

/// Part `k` of a cell as its index on each axis (`k = Σ k_i·parts^i`).
pub(crate) fn part_of<const N: usize>(k: usize) -> [usize; N] {
    let mut part = [0; N];
    let mut rest = k;
    for p in &mut part {
        *p = rest % parts(N);
        rest /= parts(N);
    }
    part
}

/// The 2-D seed's cells, as linear offsets for `stride`: the 7×7 cells
/// around the centre cell less its four corners and the centre, 44 cells,
/// which are those within `2r` of the centre cell where cells are `r/√2`
/// wide (the corners are exactly `2r` away); `None` if their memory
/// cannot be had.
///
/// Why `2r`, not the search's `r`: a candidate lies `r` to `2r` from its
/// active point, so what can turn it away lies within `3r`, and the search
/// stencil (the cells within `r`) leaves out the points `2r` to `3r` away,
/// behind about two of a point's three grid searches. These cells hold
/// about 14 points, which the cache's 16 slots take, checked in two
/// vectors of eight. That is faster than the stencil's 20 cells and 8
/// slots, and than more cells (the 9×9 within `3r`), fewer (36), or 24
/// slots (`docs/performance-journal.md`, "The 2-D seed out to 2r").
///
/// For grids padded by the search's reach of 2 cells (the streaming
/// window's too): offsets past the padding land on a padding cell of the
/// next or previous row, or on no cell at all (`get` finds nothing);
/// either hands the cache nothing or a real point, and the cache keeps
/// any real point without changing a decision. The 44 offsets take 352
/// bytes, within the 16 bytes a cell of the search's 25-cell window that
/// the grid's budget charges for the seed ([`stencil_bytes_per_cell`]).
pub(crate) fn wide_seed(&[s0, s1]: &[usize; 2]) -> Option<Vec<isize>> {
    const REACH: isize = WIDE_SEED_REACH;
    let (s0, s1) = (isize::try_from(s0).ok()?, isize::try_from(s1).ok()?);
    let mut offsets = Vec::new();
    offsets.try_reserve_exact(44).ok()?;
    for dy in -REACH..=REACH {
        for dx in -REACH..=REACH {
            let corner = dx.abs() == REACH && dy.abs() == REACH;
            if (dx, dy) != (0, 0) && !corner {
                offsets.push(dx * s0 + dy * s1);
            }
        }
    }
    Some(offsets)
}

/// How far [`wide_seed`] reaches from the centre cell on each axis.
const WIDE_SEED_REACH: isize = 3;

/// The first and last offset of each row of [`wide_seed`]'s cells, in a
/// grid whose rows are `row` apart (axis 0's stride is 1): what the next
/// pick's prefetch asks for. Its centre row counts the centre cell, which
/// the seed leaves out.
pub(crate) fn wide_seed_rows(row: usize) -> impl Iterator<Item = [isize; 2]> {
    let row = isize::try_from(row).unwrap_or(0);
    (-WIDE_SEED_REACH..=WIDE_SEED_REACH).map(move |dy| {
        let reach = if dy.abs() == WIDE_SEED_REACH {
            WIDE_SEED_REACH - 1
        } else {
            WIDE_SEED_REACH
        };
        [dy * row - reach, dy * row + reach]
    })
}

/// The cell of `p` in a grid whose cells start at `lo`, are `1/inv_side`
/// wide and run to `last` per axis (clamped into it), and which of
/// `parts` equal slices per axis of that cell it lies in, numbered axis 0
/// first: what a part stencil is chosen by. Shared by [`Dense`] and the
/// varying radius's band grids.
#[inline(always)]
pub(crate) fn locate<const N: usize>(
    p: &[f64; N],
    lo: &[f64; N],
    inv_side: &[f64; N],
    last: &[usize; N],
    parts: usize,
) -> ([usize; N], usize) {
    let mut cell = [0usize; N];
    let mut part = 0;
    let mut weight = 1;
    let axes = lo.iter().zip(inv_side).zip(last);
    for ((c, x), ((lo, inv_side), &last)) in cell.iter_mut().zip(p).zip(axes) {
        let t = (x - lo) * inv_side;
        // The cell through i64 (one instruction on x86-64; f64 -> usize
        // takes several), saturating, then clamped into the grid; then
        // the position inside the cell, clamped (rounding or the clamp
        // at `hi` can leave it a hair outside).
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            clippy::cast_precision_loss,
            clippy::cast_possible_wrap,
            reason = "saturating float-to-int casts, clamped; cells <= 2^40 convert exactly; parts is a few"
        )]
        let (i, k) = {
            let i = ((t as i64).max(0) as usize).min(last);
            let k = (((t - i as f64) * parts as f64) as i64).clamp(0, parts as i64 - 1);
            (i, k as usize)
        };
        *c = i;
        part += k * weight;
        weight *= parts;
    }
    (cell, part)
}

/// How many parts each axis of a cell is cut into for the search stencils,
/// in `n` dimensions:
/// 2 up to 4-D (16 stencils of up to 841 cells there); whole cells above,
/// where `2^N` stencils of thousands of cells would cost more memory than
/// they save scanning.
pub(crate) const fn parts(n: usize) -> usize {
    if n <= 4 { 2 } else { 1 }
}

/// A bound on the heap bytes the stencils of an `n`-dimensional grid take,
/// per cell of the `Π (2·reach + 1)` window they are cut from, at the peak
/// of their construction: each kept stencil holds at most one offset (8
/// bytes) and, in its row list grown by doubling, 32 bytes per cell; the
/// seed list, grown by doubling too, 16 more; and the one stencil being built has a 24-byte entry
/// per cell, the stable sort's buffer of half as many, and 16-byte row
/// keys.
pub(crate) fn stencil_bytes_per_cell(n: usize) -> u64 {
    let parts_stencils = if parts(n) > 1 {
        (parts(n) as u64).saturating_pow(u32::try_from(n).unwrap_or(u32::MAX))
    } else {
        0
    };
    parts_stencils
        .saturating_add(1)
        .saturating_mul(8 + 32)
        .saturating_add(16 + 24 + 12 + 16)
}

/// What a stencil is cut from: the search reach in cells on each axis, the
/// cell sides, the rounding margin `η` (in cells) and the radius.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StencilShape<const N: usize> {
    pub(crate) reach: [usize; N],
    pub(crate) side: [f64; N],
    pub(crate) eta: f64,
    pub(crate) radius: f64,
}

/// The cells a candidate in one part of its cell must be checked against.
/// Shared with the streaming window (`tiled/grid.rs`), whose rows are laid
/// out with a fixed stride too.
#[derive(Debug)]
pub(crate) struct Stencil {
    /// Linear offsets, nearest first, so that a conflict is usually found
    /// in the first few.
    pub(crate) offsets: Vec<isize>,
    /// The first and last offset of each row along axis 0 (up to 3-D): what
    /// [`Dense::prefetch_stencil`] asks for.
    pub(crate) rows: Vec<[isize; 2]>,
}

impl Stencil {
    /// The cells `d` with `Σ (max(gap_i - η, 0)·side_i)² < r²`, where
    /// `gap_i` is the distance, in cells, between part `part` of the centre
    /// cell (`[k/parts, (k+1)/parts]` on each axis) and cell `d`: every
    /// cell that can hold a point closer than `r` to a point of that part,
    /// even with each index off by the rounding margin `η`. With one part
    /// this is Bridson's stencil, `gap_i = |d_i| - 1`.
    pub(crate) fn new<const N: usize>(
        shape: &StencilShape<N>,
        stride: &[usize; N],
        part: &[usize; N],
        parts: usize,
    ) -> Option<Self> {
        let r2 = shape.radius * shape.radius;
        let reach: [isize; N] = shape.reach.map(|p| isize::try_from(p).unwrap_or(0));
        let stride: [isize; N] = stride.map(|s| isize::try_from(s).unwrap_or(0));
        #[expect(clippy::cast_precision_loss, reason = "small counts")]
        let (parts_f, part_f) = (parts as f64, part.map(|k| k as f64));
        let window: usize = reach.iter().map(|&p| 2 * p.unsigned_abs() + 1).product();
        let mut cells = Vec::new();
        cells.try_reserve_exact(window).ok()?;
        let mut d = reach.map(|p| -p);
        loop {
            let mut gap2 = 0.0;
            let mut centre2 = 0.0;
            for ((&di, &side), &k) in d.iter().zip(&shape.side).zip(&part_f) {
                #[expect(clippy::cast_precision_loss, reason = "small offsets")]
                let df = di as f64;
                let gap = part_gap(df, k, parts_f, shape.eta, side);
                gap2 += gap * gap;
                // From the part's centre to the cell's: the tie-break.
                let (a, b) = (k / parts_f, (k + 1.0) / parts_f);
                let centre = (df + 0.5 - 0.5 * (a + b)) * side;
                centre2 += centre * centre;
            }
            if gap2 < r2 {
                let linear: isize = d.iter().zip(&stride).map(|(d, s)| d * s).sum();
                cells.push((gap2, centre2, linear));
            }
            // Odometer over -reach..=reach on every axis.
            let mut stepped = false;
            for (x, &p) in d.iter_mut().zip(&reach) {
                if *x < p {
                    *x += 1;
                    stepped = true;
                    break;
                }
                *x = -p;
            }
            if !stepped {
                break;
            }
        }
        cells.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
        // A fresh vector of exactly this length (collecting in place would
        // keep the entries' larger allocation).
        let mut offsets: Vec<isize> = Vec::new();
        offsets.try_reserve_exact(cells.len()).ok()?;
        offsets.extend(cells.iter().map(|c| c.2));
        drop(cells);
        // Rows (up to 3-D): offset `o` is `d0 + Σ d_i·stride_i` with
        // |d0| <= reach0 < stride_1 / 2, so its row is keyed by
        // `o - (o + reach0) mod stride_1`.
        let mut rows: Vec<(isize, isize)> = Vec::new();
        if N <= 3 {
            let reach0 = reach.first().copied().unwrap_or(0);
            let row_stride = stride.get(1).copied();
            rows = offsets
                .iter()
                .map(|&o| {
                    (
                        row_stride.map_or(-reach0, |s| o - (o + reach0).rem_euclid(s)),
                        o,
                    )
                })
                .collect();
            rows.sort_unstable();
        }
        let mut grouped: Vec<[isize; 2]> = Vec::new();
        let mut last_key = None;
        for (key, o) in rows {
            match grouped.last_mut() {
                Some(row) if last_key == Some(key) => row[1] = o,
                _ => grouped.push([o, o]),
            }
            last_key = Some(key);
        }
        Some(Self {
            offsets,
            rows: grouped,
        })
    }

    /// Heap bytes held.
    pub(crate) fn bytes(&self) -> u64 {
        vec_bytes(&self.offsets).saturating_add(vec_bytes(&self.rows))
    }
}

/// A coordinate for the grids' search tests, on an axis from `lo` to `hi`
/// of `cells` cells of side `side`: in a random cell, on its face, on the
/// face between its parts, a hair either side of one, or anywhere.
#[cfg(test)]
pub(crate) fn probe(
    rng: &mut crate::random::DefaultRng,
    lo: f64,
    hi: f64,
    side: f64,
    cells: usize,
) -> f64 {
    let u = crate::random::unit(rng);
    let cell = (u * cells as f64).floor();
    let frac = match crate::random::below(rng, 6) {
        0 => 0.0,
        1 => 0.5,
        2 => 0.5 - 1e-12,
        3 => 1.0 - 1e-12,
        4 => 1e-12,
        _ => crate::random::unit(rng),
    };
    let x = lo + (cell + frac) * side;
    x.clamp(lo, hi - side * 1e-9)
}

/// The grids' search tests' oracle: stored points in slabs of width `r`
/// along axis 0, so that "is a stored point closer than `r`" scans the
/// slab of the candidate and its two neighbours, every point of them
/// checked, and shares nothing with the grids it checks.
#[cfg(test)]
pub(crate) struct Slabs<const N: usize> {
    lo: f64,
    r: f64,
    slabs: std::collections::HashMap<i64, Vec<[f64; N]>>,
}

#[cfg(test)]
impl<const N: usize> Slabs<N> {
    pub(crate) fn new(lo: f64, r: f64) -> Self {
        Self {
            lo,
            r,
            slabs: std::collections::HashMap::new(),
        }
    }

    #[expect(
        clippy::cast_possible_truncation,
        reason = "a whole number far inside i64: boxes of a few units, radii of 1e-4 and up"
    )]
    fn slab(&self, x: f64) -> i64 {
        ((x - self.lo) / self.r).floor() as i64
    }

    pub(crate) fn insert(&mut self, p: [f64; N]) {
        self.slabs.entry(self.slab(p[0])).or_default().push(p);
    }

    /// Every stored point closer than `r` to `p` (and some farther ones):
    /// the points with `|q[0] - p[0]| < r`, and more.
    pub(crate) fn near(&self, p: &[f64; N]) -> impl Iterator<Item = &[f64; N]> {
        let k = self.slab(p[0]);
        (k - 1..=k + 1).flat_map(move |j| self.slabs.get(&j).into_iter().flatten())
    }

    /// Whether `q` is stored (bit for bit).
    pub(crate) fn contains(&self, q: &[f64; N]) -> bool {
        self.slabs
            .get(&self.slab(q[0]))
            .is_some_and(|v| v.iter().any(|s| s.map(f64::to_bits) == q.map(f64::to_bits)))
    }
}

/// The values of the occupied cells (not [`EMPTY`]) of `cells` among
/// `offsets` around `base`, in order, into `found`, without a branch (most
/// cells are empty); returns how many there were. Past `M` (a power of two)
/// occupied cells, later ones overwrite earlier ones, which only a seed can
/// meet, and any subset suits it. Shared by the `u32` grid and the varying
/// radius's band grids, whose cells hold indices the same way.
#[inline(always)]
pub(crate) fn occupied<const M: usize>(
    cells: &[u32],
    base: usize,
    offsets: &[isize],
    found: &mut [u32; M],
) -> usize {
    let mut n = 0;
    for &off in offsets {
        // Always Some: the padding is as wide as the largest offset.
        let index = cells
            .get(base.wrapping_add_signed(off))
            .copied()
            .unwrap_or(EMPTY);
        // `n % M` needs no bounds check (M is a power of two).
        if let Some(slot) = found.get_mut(n % M) {
            *slot = index;
        }
        n += usize::from(index != EMPTY);
    }
    n
}

/// The gap along one axis, in length, between any point of part `k` (of
/// `parts` per cell side) of a cell and the cell `d` steps away (`d` a
/// whole number), less the rounding margin `eta` (in cells), never below
/// 0: the bound every stencil is cut with. Shared by [`Stencil::new`] and
/// the varying radius's stencil cuts, which must agree with it.
pub(crate) fn part_gap(d: f64, k: f64, parts: f64, eta: f64, side: f64) -> f64 {
    let (a, b) = (k / parts, (k + 1.0) / parts);
    let gap = if d >= 1.0 {
        d - b
    } else if d <= -1.0 {
        a - (d + 1.0)
    } else {
        0.0
    };
    (gap - eta).max(0.0) * side
}

#[cfg(test)]
mod tests {
    use super::super::{GridLayout, GridPlan, plan};
    use super::*;

    fn dense<const N: usize>(domain: &Domain<N>, r: f64) -> Dense<N> {
        match plan(domain, r, GridLayout::Dense, 1 << 30, None, None) {
            Ok(GridPlan::Dense(p)) => Dense::try_new(&p, domain, r).expect("allocates"),
            other => panic!("no dense plan: {other:?}"),
        }
    }

    #[test]
    fn stencil_sizes() {
        // 2-D: the 5×5 block; the four corners are kept because they sit
        // exactly at distance r, where rounding matters.
        let g = dense(&Domain::from_extent([1.0, 1.0]).unwrap(), 0.1);
        assert_eq!(g.full.offsets.len(), 25, "2-D stencil");
        assert_eq!(g.full.offsets[0], 0, "own cell first");
        let g = dense(&Domain::from_extent([1.0; 3]).unwrap(), 0.1);
        assert_eq!(g.full.offsets.len(), 125, "3-D stencil");
        // The parts' stencils: 8 in 3-D, each inside the full one, own
        // cell first, together smaller by about a quarter.
        assert_eq!(g.parts.len(), 8, "3-D parts");
        for part in &g.parts {
            assert_eq!(part.offsets[0], 0, "own cell first");
            assert!(part.offsets.iter().all(|o| g.full.offsets.contains(o)));
        }
        let total: usize = g.parts.iter().map(|p| p.offsets.len()).sum();
        assert!(total <= 8 * 100, "3-D parts hold {total} cells");
    }

    #[test]
    fn stencil_rows_cover_the_stencil() {
        fn check<const N: usize>(g: &Dense<N>) {
            let row = isize::try_from(2 * g.pad[0]).unwrap();
            for stencil in g.parts.iter().chain([&g.full]) {
                for &o in &stencil.offsets {
                    let rows = stencil.rows.iter();
                    let n = rows.filter(|r| (r[0]..=r[1]).contains(&o)).count();
                    assert_eq!(n, 1, "offset {o} lies in {n} rows");
                }
                for r in &stencil.rows {
                    assert!((0..=row).contains(&(r[1] - r[0])), "{N}-D row {r:?}");
                }
            }
            let expected = g.full.offsets.len() / (2 * g.pad[0] + 1);
            assert_eq!(g.full.rows.len(), expected, "{N}-D row count");
        }
        check(&dense(&Domain::from_extent([1.0]).unwrap(), 0.1));
        check(&dense(&Domain::from_extent([1.0, 2.0]).unwrap(), 0.1));
        check(&dense(&Domain::from_extent([1.0, 0.5, 3.0]).unwrap(), 0.07));
    }

    /// The search with the parts' stencils finds a conflict exactly when a
    /// brute-force check over every stored point does, for candidates all
    /// over their cells: on cell faces, on the faces between parts, a hair
    /// either side of them, and at random.
    #[test]
    fn conflicts_agree_with_brute_force() {
        fn check<const N: usize>(domain: Domain<N>, r: f64, seed: u64) {
            let mut g = dense(&domain, r);
            let mut rng = crate::random::seeded_rng(seed);
            let mut stored: Vec<[f64; N]> = Vec::new();
            let side = g.inv_side.map(|s| 1.0 / s);
            let counts = g.counts;
            // A position on one axis: a cell face, a part face, a hair off
            // one, or uniform.
            let coordinate = |axis: usize, rng: &mut crate::random::DefaultRng| {
                probe(
                    rng,
                    domain.lo()[axis],
                    domain.hi()[axis],
                    side[axis],
                    counts[axis],
                )
            };
            let (mut hits, mut misses) = (0, 0);
            for _ in 0..4000 {
                let p: [f64; N] = core::array::from_fn(|axis| coordinate(axis, &mut rng));
                let brute = stored.iter().any(|q| distance_squared(&p, q) < r * r);
                assert_eq!(g.conflict(&p).is_some(), brute, "{p:?}");
                if brute {
                    hits += 1;
                } else {
                    misses += 1;
                    if g.insert(p) {
                        stored.push(p);
                    }
                }
            }
            assert!(hits > 500 && misses > 100, "{hits} hits, {misses} misses");
        }
        check(Domain::from_extent([1.0, 1.0]).unwrap(), 0.05, 1);
        check(
            Domain::new([-3.0, 1e6], [-2.0, 1e6 + 0.7]).unwrap(),
            0.04,
            2,
        );
        check(Domain::from_extent([1.0, 0.8, 0.6]).unwrap(), 0.1, 3);
        check(Domain::from_extent([1.0; 4]).unwrap(), 0.3, 4);
        check(Domain::from_extent([1.0]).unwrap(), 0.001, 5);
        // Whole cells from 5-D: the one full stencil.
        check(Domain::from_extent([1.0; 5]).unwrap(), 0.45, 6);
    }

    #[test]
    fn seed_gathers_the_nearest_neighbours() {
        let mut g = dense(&Domain::from_extent([1.0, 1.0]).unwrap(), 0.1);
        // A point, two neighbours in its stencil, one 1.9r away (beyond the
        // stencil, within the seed's 2r), two further.
        for p in [
            [0.5, 0.5],
            [0.6, 0.5],
            [0.5, 0.62],
            [0.31, 0.5],
            [0.5, 0.25],
            [0.9, 0.9],
        ] {
            assert!(g.insert(p), "insert {p:?}");
        }
        let mut seeded = Vec::new();
        g.seed(&[0.5, 0.5], 8, |q| seeded.push(*q));
        seeded.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(
            seeded,
            [[0.31, 0.5], [0.5, 0.62], [0.6, 0.5]],
            "the three neighbours only"
        );
        let mut one = Vec::new();
        g.seed(&[0.5, 0.5], 1, |q| one.push(*q));
        assert_eq!(one.len(), 1, "up to the limit");
    }

    /// The 2-D seed's cells: the 7×7 around the centre cell less the
    /// corners and the centre, which hold the whole search stencil.
    #[test]
    fn the_wide_seed_reads_7_by_7_cells_less_the_corners() {
        let columns = 100;
        let seed = wide_seed(&[1, columns]).unwrap();
        assert_eq!(seed.len(), 44, "{seed:?}");
        let columns = isize::try_from(columns).unwrap();
        for dy in -4..=4_isize {
            for dx in -4..=4_isize {
                let inside = dx.abs() <= 3 && dy.abs() <= 3;
                let corner = dx.abs() == 3 && dy.abs() == 3;
                let o = dx + dy * columns;
                assert_eq!(
                    seed.contains(&o),
                    inside && !corner && o != 0,
                    "({dx}, {dy})"
                );
            }
        }
        let r = 1.0;
        let shape = StencilShape {
            reach: [2; 2],
            side: [r * core::f64::consts::FRAC_1_SQRT_2 * (1.0 - 1e-9); 2],
            eta: 1e-9,
            radius: r,
        };
        let full = Stencil::new(&shape, &[1, 100], &[0, 0], 1).unwrap();
        assert!(full.offsets.iter().all(|o| *o == 0 || seed.contains(o)));
        // Its rows, as the prefetch asks for them: the same cells and the
        // centre.
        let mut in_rows: Vec<isize> = wide_seed_rows(100)
            .flat_map(|[first, last]| first..=last)
            .filter(|&o| o != 0)
            .collect();
        in_rows.sort_unstable();
        let mut sorted = seed.clone();
        sorted.sort_unstable();
        assert_eq!(in_rows, sorted);
    }

    #[test]
    fn finds_a_neighbour_across_a_periodic_face() {
        let d = Domain::from_extent([1.0, 1.0])
            .unwrap()
            .with_periodic([true, false]);
        let mut g = dense(&d, 0.1);
        assert!(g.insert([0.99, 0.5]), "insert");
        assert!(
            g.conflict(&[0.02, 0.5]).is_some(),
            "wrapped distance 0.03 < 0.1"
        );
        assert!(g.conflict(&[0.2, 0.5]).is_none(), "distance 0.21");
    }

    #[test]
    fn short_period_has_several_images() {
        // Period 0.05 < r: every point conflicts with every other.
        let d = Domain::from_extent([0.05, 1.0])
            .unwrap()
            .with_periodic([true, false]);
        let mut g = dense(&d, 0.1);
        assert!(g.insert([0.01, 0.5]), "insert");
        assert!(
            g.conflict(&[0.04, 0.58]).is_some(),
            "wrapped dx 0.02, dy 0.08"
        );
        assert!(g.conflict(&[0.04, 0.65]).is_none(), "dy 0.15 > r");
    }
}
