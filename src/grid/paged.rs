//! The paged background grid: Bridson's dense cells, allocated a page at a
//! time where points land.
//!
//! The box's cells (side `<= r/√N`, a `u32` point index each, as in
//! [`Dense`](super::dense::Dense)) are cut into pages of `2^shift` cells a
//! side. A page is allocated when the first point lands in it or within
//! its halo, so memory follows the points, not the box: a huge box with a
//! small region or a point cap holds only the pages around its points.
//!
//! Each page carries a halo of `pad` cells on every side that copies its
//! neighbours' edge cells, so a search never leaves its page: it is the
//! dense grid's branch-free stencil scan on the page's own array, after
//! one look-up of the page. The invariant that makes that exact: a point
//! is written into every page whose cells or halo hold its cell, and every
//! such page is allocated when the point is stored. A page that does not
//! exist therefore has no point within its halo, and a candidate in it has
//! no neighbour closer than `r`.
//!
//! Bounded axes only: on a periodic axis a point's images would have to be
//! written into pages across the period, and a periodic box the dense grid
//! cannot hold is left to the sparse grid.

use super::dense::{EMPTY, Near, Searches, StencilShape, locate, parts, wide_seed_rows};
use super::paged_bricks;
use super::sparse::{CellHasher, table_bytes};
use super::{DensePlan, NeighbourGrid};
use crate::budget::{bytes_of, reserve_one, vec_bytes};
use crate::domain::Domain;
use core::hash::BuildHasherDefault;
use std::collections::HashMap;

/// Cells a page side holds on axes long enough to be cut, by dimension:
/// 4 096 cells a page in 1-D and 2-D (16 KiB of `u32`), 32 768 in 3-D
/// (128 KiB), so that the halo adds 19 % in 2-D and 42 % in 3-D; smaller
/// pages add more halo, larger ones waste more memory at a region's edge.
const fn page_shift(n: usize) -> u32 {
    match n {
        1 => 12,
        2 => 6,
        _ => 5,
    }
}

/// Index 0 of `points` is this sentinel, which every empty cell points to.
const FAR: f64 = f64::INFINITY;

/// The widest reach of the 2-D seed ([`wide_seed`](super::dense::wide_seed)): 3 cells.
const WIDE_SEED_PAD: usize = 3;

/// The paged grid's geometry: the dense plan's cells and the page shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PagedPlan<const N: usize> {
    pub(crate) dense: DensePlan<N>,
    /// Cells a page side holds, as a power of two, per axis.
    pub(crate) shift: [u32; N],
    /// Halo cells on each side of a page, per axis.
    pub(crate) pad: [usize; N],
    /// What the grid allocates before its first point (the stencils), plus
    /// what the first point takes (the pages around it, the directory, the
    /// sentinel and the point, an active entry).
    pub(crate) bytes: u64,
    /// The most bytes the directory may take as an array (0: a table).
    pub(crate) directory: u64,
}

impl<const N: usize> PagedPlan<N> {
    /// The page shape for a dense geometry, and what the grid takes before
    /// its first point, with an array directory where it takes at most a
    /// sixteenth of `budget`; `None` if a page cannot be addressed.
    pub(crate) fn new(dense: DensePlan<N>, budget: u64) -> Option<Self> {
        let wide = N == 2 && dense.reach.iter().all(|&p| p == 2);
        let mut shift = [0u32; N];
        let mut pad = [0usize; N];
        let mut page_len = 1usize;
        for ((s, p), (&m, &reach)) in shift
            .iter_mut()
            .zip(&mut pad)
            .zip(dense.cells.iter().zip(&dense.reach))
        {
            // An axis shorter than a page is one page: no halo is ever
            // written across it, however wide.
            *s = page_shift(N).min(m.next_power_of_two().trailing_zeros());
            *p = if wide { WIDE_SEED_PAD } else { reach };
            page_len = page_len.checked_mul((1usize << *s).checked_add(p.checked_mul(2)?)?)?;
        }
        let bricked = paged_bricks::applies(&dense.reach);
        let window: u64 = dense
            .reach
            .iter()
            .map(|&p| 2 * p as u64 + 1)
            .try_fold(1u64, u64::checked_mul)?;
        let (page, stencils, list) = if bricked {
            (
                paged_bricks::page_bytes::<N>(),
                paged_bricks::stencil_bytes::<N>(),
                paged_bricks::list_bytes::<N>(8),
            )
        } else {
            (
                bytes_of::<u32>(page_len),
                window.checked_mul(super::dense::stencil_bytes_per_cell(N))?,
                bytes_of::<Box<[u32]>>(8),
            )
        };
        // The least the first point takes: its page (more where it lies in
        // a neighbour's halo), its entries in the page list and the
        // directory, the sentinel, the point, an active entry. So a plan
        // over the budget is a run that cannot store one point.
        let mut pages = 1u64;
        for (&m, &sh) in dense.cells.iter().zip(&shift) {
            let side = if bricked {
                paged_bricks::pages_for(m)
            } else {
                m.div_ceil(1 << sh)
            };
            pages = pages.saturating_mul(u64::try_from(side).ok()?);
        }
        let array = pages.saturating_mul(4);
        let (directory, directory_bytes) = if array <= MAX_ARRAY_DIRECTORY_BYTES.min(budget / 16) {
            (array, array)
        } else {
            (0, table_bytes(1, entry_bytes::<N>()))
        };
        let point = (8 * N) as u64;
        let bytes = stencils
            .checked_add(page)?
            .checked_add(directory_bytes)?
            .checked_add(list)?
            .checked_add(3 * point)?;
        Some(Self {
            dense,
            shift,
            pad,
            bytes,
            directory,
        })
    }
}

/// Bytes of one directory entry: a page's coordinates and its number.
fn entry_bytes<const N: usize>() -> u64 {
    bytes_of::<([usize; N], u32)>(1)
}

/// The most bytes an array directory may take: 16 MiB, 4 M pages (in 2-D
/// 6.9·10¹⁰ cells). Past it the box is huge against `r`, and the hash
/// table, whose memory follows the pages made, takes over.
const MAX_ARRAY_DIRECTORY_BYTES: u64 = 16 << 20;

/// An absent page in the array directory.
const NO_PAGE: u32 = u32::MAX;

/// Page coordinates to page numbers.
///
/// An array over every page of the box where it is small (its bytes are
/// in the plan): a look-up is then one load, where hashing the page's
/// coordinates cost 2.3× the dense grid's time in 3-D (a look-up a
/// search). A hash table of the pages made in a huge box.
#[derive(Debug)]
pub(super) enum Directory<const N: usize> {
    Array {
        numbers: Vec<u32>,
        stride: [usize; N],
    },
    Table(HashMap<[usize; N], u32, BuildHasherDefault<CellHasher>>),
}

impl<const N: usize> Directory<N> {
    /// The array over `pages` pages a side, if its bytes are at most
    /// `most` and it can be allocated; else the empty table.
    pub(super) fn new(pages: &[usize; N], most: u64) -> Self {
        let table = || Self::Table(HashMap::default());
        let mut stride = [0usize; N];
        let mut total = 1usize;
        for (s, &m) in stride.iter_mut().zip(pages) {
            *s = total;
            let Some(t) = total.checked_mul(m) else {
                return table();
            };
            total = t;
        }
        if bytes_of::<u32>(total) > most {
            return table();
        }
        let mut numbers = Vec::new();
        if numbers.try_reserve_exact(total).is_err() {
            return table();
        }
        numbers.resize(total, NO_PAGE);
        Self::Array { numbers, stride }
    }

    #[inline(always)]
    pub(super) fn get(&self, page: &[usize; N]) -> Option<u32> {
        match self {
            Self::Array { numbers, stride } => {
                let at: usize = page.iter().zip(stride).map(|(p, s)| p * s).sum();
                numbers.get(at).copied().filter(|&n| n != NO_PAGE)
            }
            Self::Table(map) => map.get(page).copied(),
        }
    }

    pub(super) fn bytes(&self) -> u64 {
        match self {
            Self::Array { numbers, .. } => vec_bytes(numbers),
            Self::Table(map) => table_bytes(map.capacity(), entry_bytes::<N>()),
        }
    }

    /// The bytes that making room for `more` entries takes at its peak
    /// (a table's old and new blocks are both held while it grows).
    pub(super) fn growth(&self, more: usize) -> u64 {
        match self {
            Self::Array { .. } => 0,
            Self::Table(map) => {
                let wanted = map.len().saturating_add(more);
                if wanted > map.capacity() {
                    table_bytes(
                        map.capacity().saturating_mul(2).max(wanted),
                        entry_bytes::<N>(),
                    )
                } else {
                    0
                }
            }
        }
    }

    pub(super) fn try_reserve(&mut self, more: usize) -> bool {
        match self {
            Self::Array { .. } => true,
            Self::Table(map) => map.try_reserve(more).is_ok(),
        }
    }

    pub(super) fn insert(&mut self, page: [usize; N], number: u32) {
        match self {
            Self::Array { numbers, stride } => {
                let at: usize = page.iter().zip(&*stride).map(|(p, s)| p * s).sum();
                if let Some(slot) = numbers.get_mut(at) {
                    *slot = number;
                }
            }
            Self::Table(map) => {
                map.insert(page, number);
            }
        }
    }
}

/// The pages a cell is written into on one axis: its own, and the ones
/// whose halo holds it (at most one either side), with the cell's
/// coordinate in each page's padded cells.
type AxisPages = ([(usize, usize); 3], usize);

#[derive(Debug)]
pub(crate) struct Paged<const N: usize> {
    /// The pages, each `Π (2^shift + 2·pad)` cells in padded order.
    pages: Vec<Box<[u32]>>,
    /// Page coordinates to the page's index in `pages`.
    directory: Directory<N>,
    /// The points, in insertion order, after the sentinel at index 0.
    points: Vec<[f64; N]>,
    lo: [f64; N],
    inv_side: [f64; N],
    /// The last cell index inside the box on each axis.
    last: [usize; N],
    /// The last page index on each axis.
    last_page: [usize; N],
    shift: [u32; N],
    pad: [usize; N],
    /// Strides of a page's padded cells.
    stride: [usize; N],
    page_len: usize,
    /// The stencils and the seed's cells, for a page's strides.
    searches: Searches,
    radius_squared: f64,
}

impl<const N: usize> Paged<N> {
    /// The grid with its stencils and no page yet, or `None` if the
    /// stencils cannot be allocated or the domain has a periodic axis.
    pub(crate) fn try_new(plan: &PagedPlan<N>, domain: &Domain<N>, radius: f64) -> Option<Self> {
        if domain.any_periodic() {
            return None;
        }
        let d = &plan.dense;
        let mut stride = [0usize; N];
        let mut page_len = 1usize;
        for ((s, &shift), &pad) in stride.iter_mut().zip(&plan.shift).zip(&plan.pad) {
            *s = page_len;
            page_len = page_len.checked_mul((1usize << shift).checked_add(pad.checked_mul(2)?)?)?;
        }
        let mut points = Vec::new();
        points.try_reserve_exact(1).ok()?;
        points.push([FAR; N]);
        let shape = StencilShape {
            reach: d.reach,
            side: d.side,
            eta: d.eta,
            radius,
        };
        let searches = Searches::new(&shape, &stride)?;
        let last = d.cells.map(|m| m.saturating_sub(1));
        let mut last_page = [0usize; N];
        for ((lp, &l), &s) in last_page.iter_mut().zip(&last).zip(&plan.shift) {
            *lp = l >> s;
        }
        Some(Self {
            pages: Vec::new(),
            directory: Directory::new(&last_page.map(|p| p + 1), plan.directory),
            points,
            lo: domain.lo(),
            inv_side: d.side.map(|s| 1.0 / s),
            last,
            last_page,
            shift: plan.shift,
            pad: plan.pad,
            stride,
            page_len,
            searches,
            radius_squared: radius * radius,
        })
    }

    /// The page a cell lies in, and the cell's linear index in it.
    #[inline(always)]
    fn page_of(&self, cell: &[usize; N]) -> ([usize; N], usize) {
        let mut page = [0usize; N];
        let mut base = 0;
        let axes = self.shift.iter().zip(&self.pad).zip(&self.stride);
        for ((pg, &c), ((&shift, &pad), &stride)) in page.iter_mut().zip(cell).zip(axes) {
            *pg = c >> shift;
            base += ((c & ((1 << shift) - 1)) + pad) * stride;
        }
        (page, base)
    }

    /// The neighbourhood of `cell` in its page; `None` if that page has
    /// not been allocated (then no point lies within its halo).
    #[inline(always)]
    fn near(&self, cell: &[usize; N]) -> Option<Near<'_, N>> {
        let (page, base) = self.page_of(cell);
        let id = self.directory.get(&page)?;
        let cells = self.pages.get(id as usize)?;
        Some(Near {
            cells,
            points: &self.points,
            base,
        })
    }

    /// Per axis, the pages whose cells or halo hold `cell`.
    fn axis_pages(&self, cell: &[usize; N]) -> [AxisPages; N] {
        let mut out = [([(0, 0); 3], 0); N];
        let axes = self.shift.iter().zip(&self.pad).zip(&self.last_page);
        for ((slots, len), (&c, ((&shift, &pad), &last_page))) in
            out.iter_mut().zip(cell.iter().zip(axes))
        {
            let side = 1usize << shift;
            let home = c >> shift;
            let at = c & (side - 1);
            let mut push = |page: usize, local: usize| {
                if let Some(slot) = slots.get_mut(*len) {
                    *slot = (page, local);
                    *len += 1;
                }
            };
            push(home, at + pad);
            if at < pad && home > 0 {
                push(home - 1, at + side + pad);
            }
            if at + pad >= side && home < last_page {
                push(home + 1, at + pad - side);
            }
        }
        out
    }

    /// Calls `f` with every page (coordinates) whose cells or halo hold
    /// `cell`, and the cell's linear index in it.
    fn for_each_page(&self, cell: &[usize; N], mut f: impl FnMut(&[usize; N], usize)) {
        let axes = self.axis_pages(cell);
        let mut pick = [0usize; N];
        loop {
            let mut page = [0usize; N];
            let mut index = 0;
            for (((pg, &k), (slots, _)), &stride) in
                page.iter_mut().zip(&pick).zip(&axes).zip(&self.stride)
            {
                let (p, local) = slots.get(k).copied().unwrap_or_default();
                *pg = p;
                index += local * stride;
            }
            f(&page, index);
            // Odometer over each axis's pages.
            let mut stepped = false;
            for (k, (_, len)) in pick.iter_mut().zip(&axes) {
                if *k + 1 < *len {
                    *k += 1;
                    stepped = true;
                    break;
                }
                *k = 0;
            }
            if !stepped {
                return;
            }
        }
    }

    fn page_bytes(&self) -> u64 {
        bytes_of::<u32>(self.page_len)
    }
}

impl<const N: usize> NeighbourGrid<N> for Paged<N> {
    const WIDE_SEED: bool = true;

    #[inline(always)]
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]> {
        let (cell, part) = locate(p, &self.lo, &self.inv_side, &self.last, parts(N));
        let near = self.near(&cell)?;
        let stencil = self.searches.parts.get(part).unwrap_or(&self.searches.full);
        near.conflict::<false>(stencil, p, &[0.0; N], self.radius_squared)
    }

    /// As the dense grid's seed, within the point's page.
    #[inline(always)]
    fn seed(&self, p: &[f64; N], limit: usize, take: impl FnMut(&[f64; N])) {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        if let Some(near) = self.near(&cell) {
            near.seed(&self.searches.seed_offsets, limit, take);
        }
    }

    #[inline(always)]
    fn prefetch(&self, p: &[f64; N]) {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        let Some(Near { cells, base, .. }) = self.near(&cell) else {
            return;
        };
        // As the dense grid: the wide seed's 7 rows in 2-D, else the
        // stencil's.
        match self.stride.get(1) {
            Some(&row) if self.searches.wide_seed => {
                for [first, last] in wide_seed_rows(row) {
                    crate::prefetch::prefetch(cells, base.wrapping_add_signed(first));
                    crate::prefetch::prefetch(cells, base.wrapping_add_signed(last));
                }
            }
            _ => {
                for &[first, last] in &self.searches.full.rows {
                    crate::prefetch::prefetch(cells, base.wrapping_add_signed(first));
                    crate::prefetch::prefetch(cells, base.wrapping_add_signed(last));
                }
            }
        }
    }

    fn bytes(&self) -> u64 {
        self.page_bytes()
            .saturating_mul(self.pages.len() as u64)
            .saturating_add(vec_bytes(&self.pages))
            .saturating_add(self.directory.bytes())
            .saturating_add(vec_bytes(&self.points))
            .saturating_add(self.searches.bytes)
    }

    /// Allocates the pages `p` will be written into that do not exist yet,
    /// then room for the point, if all of it fits in `spare`.
    fn reserve(&mut self, p: &[f64; N], spare: u64) -> bool {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        let mut missing: smallvec::SmallVec<[[usize; N]; 4]> = smallvec::SmallVec::new();
        self.for_each_page(&cell, |page, _| {
            if self.directory.get(page).is_none() {
                missing.push(*page);
            }
        });
        let mut need = self.page_bytes().saturating_mul(missing.len() as u64);
        need = need.saturating_add(self.directory.growth(missing.len()));
        if self.pages.len() + missing.len() > self.pages.capacity() {
            let grown = self.pages.capacity().saturating_mul(2).max(8);
            need = need.saturating_add(bytes_of::<Box<[u32]>>(grown));
        }
        if need > spare {
            return false;
        }
        if !missing.is_empty() {
            if !self.directory.try_reserve(missing.len())
                || self.pages.try_reserve(missing.len()).is_err()
            {
                return false;
            }
            for page in missing {
                let Ok(id) = u32::try_from(self.pages.len()) else {
                    return false;
                };
                let mut cells = Vec::new();
                if cells.try_reserve_exact(self.page_len).is_err() {
                    return false;
                }
                cells.resize(self.page_len, EMPTY);
                self.pages.push(cells.into_boxed_slice());
                self.directory.insert(page, id);
            }
        }
        reserve_one(&mut self.points, spare - need).is_some()
    }

    fn insert(&mut self, p: [f64; N]) -> bool {
        let (cell, _) = locate(&p, &self.lo, &self.inv_side, &self.last, 1);
        let Ok(index) = u32::try_from(self.points.len()) else {
            return false;
        };
        if index == u32::MAX {
            return false;
        }
        // Every page must be allocated ([`reserve`](NeighbourGrid::reserve)
        // came first), and the home cell, the first of them, free (rounding
        // can put two valid points in one cell: the newcomer is dropped).
        let mut slots: smallvec::SmallVec<[(usize, usize); 4]> = smallvec::SmallVec::new();
        let mut allocated = true;
        self.for_each_page(&cell, |page, at| match self.directory.get(page) {
            Some(id) => slots.push((id as usize, at)),
            None => allocated = false,
        });
        let home_free = slots
            .first()
            .and_then(|&(id, at)| self.pages.get(id)?.get(at))
            == Some(&EMPTY);
        if !allocated || !home_free {
            return false;
        }
        for (id, at) in slots {
            if let Some(slot) = self.pages.get_mut(id).and_then(|cells| cells.get_mut(at)) {
                *slot = index;
            }
        }
        self.points.push(p);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::dense::{Slabs, probe};
    use super::super::{GridLayout, GridPlan, plan};
    use super::*;
    use crate::vector::distance_squared;
    use crate::{PoissonDisk, random};

    /// The paged grid, with its directory an array or (`table`) a hash
    /// table.
    fn paged<const N: usize>(domain: &Domain<N>, r: f64, table: bool) -> Paged<N> {
        match plan(domain, r, GridLayout::Paged, 1 << 30, None, None) {
            Ok(GridPlan::Paged(mut p)) => {
                if table {
                    p.directory = 0;
                }
                let g = Paged::try_new(&p, domain, r).expect("allocates");
                assert_eq!(matches!(g.directory, Directory::Table(_)), table);
                g
            }
            other => panic!("no paged plan: {other:?}"),
        }
    }

    /// The search finds a conflict exactly when a brute-force check over
    /// every stored point of the candidate's slab and the two beside it
    /// ([`Slabs`]) does, for candidates all over their cells (on cell and
    /// part faces, a hair either side, at random), in boxes of
    /// several pages a side, so that pairs across page borders and the
    /// halos' copies are exercised.
    #[test]
    fn conflicts_agree_with_brute_force_across_pages() {
        fn check<const N: usize>(domain: Domain<N>, r: f64, seed: u64, probes: usize) {
            for table in [false, true] {
                one(domain, r, seed, probes, table);
            }
        }
        fn one<const N: usize>(domain: Domain<N>, r: f64, seed: u64, probes: usize, table: bool) {
            let mut g = paged(&domain, r, table);
            let pages: Vec<usize> = g.last_page.iter().map(|&p| p + 1).collect();
            assert!(pages.iter().any(|&p| p >= 2), "{N}-D: one page only");
            let mut rng = random::seeded_rng(seed);
            let mut stored = Slabs::<N>::new(domain.lo()[0], r);
            let side = g.inv_side.map(|s| 1.0 / s);
            let counts = g.last.map(|l| l + 1);
            let (mut hits, mut misses) = (0, 0);
            for _ in 0..probes {
                let p: [f64; N] = core::array::from_fn(|axis| {
                    probe(
                        &mut rng,
                        domain.lo()[axis],
                        domain.hi()[axis],
                        side[axis],
                        counts[axis],
                    )
                });
                let brute = stored.near(&p).any(|q| distance_squared(&p, q) < r * r);
                assert_eq!(g.conflict(&p).is_some(), brute, "{p:?}");
                if brute {
                    hits += 1;
                } else {
                    misses += 1;
                    assert!(g.reserve(&p, u64::MAX), "room");
                    if g.insert(p) {
                        stored.insert(p);
                    }
                }
            }
            assert!(hits > 500 && misses > 100, "{hits} hits, {misses} misses");
            assert!(
                g.pages.len() >= 4.min(pages.iter().product()),
                "{} pages",
                g.pages.len()
            );
        }
        check(Domain::from_extent([1.0]).unwrap(), 1e-4, 1, 20_000);
        check(Domain::from_extent([2.0, 2.0]).unwrap(), 0.03, 2, 20_000);
        check(
            Domain::new([-3.0, 1e6], [1.0, 1e6 + 0.7]).unwrap(),
            0.02,
            3,
            20_000,
        );
        check(
            Domain::from_extent([1.5, 1.5, 1.0]).unwrap(),
            0.05,
            4,
            20_000,
        );
    }

    /// The paged grid makes the dense grid's points, bit for bit: the
    /// search finds a conflict exactly when the dense one does, and the
    /// sampler's draws depend only on that.
    #[test]
    fn the_same_points_as_the_dense_grid() {
        fn check<const N: usize>(extent: [f64; N], r: f64) {
            let domain = Domain::from_extent(extent).unwrap();
            let run = |layout| {
                let s = PoissonDisk::builder(domain, r)
                    .layout(layout)
                    .build()
                    .unwrap();
                assert_eq!(s.resolved_layout(), layout, "{N}-D");
                let mut it = s.iter_seeded(5);
                let points: Vec<[u64; N]> = it.by_ref().map(|p| p.map(f64::to_bits)).collect();
                assert_eq!(it.layout(), layout, "{N}-D built");
                points
            };
            let dense = run(GridLayout::Dense);
            assert!(dense.len() > 1000, "{N}-D: {} points", dense.len());
            assert!(dense == run(GridLayout::Paged), "{N}-D: the sets differ");
        }
        check([1.0], 2e-4);
        check([2.0, 1.3], 0.01);
        check([1.2, 1.0, 1.1], 0.04);
    }

    /// A huge box whose dense grid no budget holds: `Auto` takes pages, and
    /// a capped run holds memory for its points only.
    #[test]
    fn memory_follows_the_points_in_a_huge_box() {
        fn check<const N: usize>(r: f64, cap: u64, most: u64) {
            let domain = Domain::from_extent([1e6; N]).unwrap();
            let s = PoissonDisk::builder(domain, r)
                .max_points(cap)
                .build()
                .unwrap();
            assert_eq!(s.resolved_layout(), GridLayout::Paged, "{N}-D");
            let mut it = s.iter_seeded(3);
            let n = it.by_ref().count() as u64;
            assert_eq!((n, it.error()), (cap, None), "{N}-D");
            let bytes = it.heap_bytes();
            assert!(bytes <= most * cap, "{N}-D: {bytes} bytes for {cap} points");
        }
        check::<2>(1.0, 100_000, 120);
        check::<3>(1.0, 50_000, 400);
    }

    /// Periodic boxes and 4-D are not paged: `Auto` falls to the sparse
    /// grid, and asking for pages is refused.
    #[test]
    fn pages_are_for_bounded_boxes_up_to_3d() {
        let torus = Domain::from_extent([1e6; 2])
            .unwrap()
            .with_periodic([true; 2]);
        let s = PoissonDisk::builder(torus, 1.0)
            .max_points(10)
            .build()
            .unwrap();
        assert_eq!(s.resolved_layout(), GridLayout::Sparse, "torus");
        let refused = PoissonDisk::builder(torus, 1.0)
            .layout(GridLayout::Paged)
            .build();
        assert!(
            matches!(refused, Err(crate::Error::GridTooLarge { .. })),
            "{refused:?}"
        );
        let four = Domain::from_extent([1.0; 4]).unwrap();
        let refused = PoissonDisk::builder(four, 0.1)
            .layout(GridLayout::Paged)
            .build();
        assert!(
            matches!(refused, Err(crate::Error::GridTooLarge { .. })),
            "{refused:?}"
        );
    }
}
