//! The paged grid in 3-D: the bricks of [`super::bricks`], allocated a page
//! of 8×8×8 bricks at a time where points land.
//!
//! The `u32` pages of [`super::paged`] send every occupied cell a search
//! meets to a point in a vector of 24 MB at a million points, a second
//! miss after the cell's; in 3-D that made them 0.5× the bricks' speed.
//! Here a page holds bricks (a 64-bit occupancy mask and the points of its
//! 4×4×4 cells, as the dense bricks), so a search reads the same few lines
//! as in the dense bricks, after one look-up of the page (up to 8 where
//! the search's 2×2×2 bricks straddle pages).
//!
//! No halo: a brick in a page that does not exist reads as empty, which it
//! is, since storing a point allocates its page first. So a point is
//! written once, where the `u32` pages copy it into the halos of up to 8.
//!
//! Cells are the dense grid's (side `<= r/√3`), padded by the reach of 2
//! as in the dense bricks, so that the window of a cell `c` (its padded
//! cells `c ..= c + 4` on each axis) starts at coordinate `c`. Bounded
//! boxes with a reach of 2 on every axis only (every box over 4 cells a
//! side); [`super::paged::Paged`] takes the others.

use super::NeighbourGrid;
use super::bricks::{BRICK_CELLS, Brick, CAPACITY, SPILL, Windowed, masked_walk, masks, put, rank};
use super::dense::{closer, locate, parts};
use super::paged::{Directory, PagedPlan};
use crate::budget::{bytes_of, vec_bytes};
use crate::domain::Domain;

/// Bricks a page side holds, as a power of two: 8 (32 cells), so that a
/// page is 512 bricks, 160 KiB; a search's bricks straddle pages on an
/// axis once in 8.
const PAGE_BITS: usize = 3;
/// Bricks in a page.
pub(super) const PAGE_BRICKS: usize = 1 << (3 * PAGE_BITS);
/// Cells a brick side holds, as a power of two (the bricks' 4).
const BRICK_BITS: usize = 2;
/// The reach every axis must have: the window's 5 cells span 2 bricks.
const REACH: usize = 2;

/// Whether a dense geometry is paged in bricks: 3-D with a reach of 2 on
/// every axis, as the bricks' masks need.
pub(crate) fn applies<const N: usize>(reach: &[usize; N]) -> bool {
    N == 3 && reach.iter().all(|&r| r == REACH)
}

/// Bytes of one page: its bricks and their spill marks.
pub(super) fn page_bytes<const N: usize>() -> u64 {
    bytes_of::<Brick<N>>(PAGE_BRICKS).saturating_add(bytes_of::<u32>(PAGE_BRICKS))
}

/// What the masks take, and a bound on the stencils they are made from
/// while they are built: 27 parts' and the seed's, of at most 125 cells.
pub(super) fn stencil_bytes<const N: usize>() -> u64 {
    let parts = 28 * BRICK_CELLS as u64 * 64;
    parts.saturating_add(29 * 125 * N as u64)
}

/// Bytes of the page list with room for `pages`.
pub(super) fn list_bytes<const N: usize>(pages: usize) -> u64 {
    bytes_of::<Page<N>>(pages)
}

/// Pages a side for `cells` cells on an axis (the padding included).
pub(super) fn pages_for(cells: usize) -> usize {
    (cells + 2 * REACH)
        .div_ceil(1 << BRICK_BITS)
        .div_ceil(1 << PAGE_BITS)
}

/// One page: its bricks, and per brick `1 +` the start of its spill chunk
/// (as [`super::bricks::Bricks`] keeps them), or 0.
#[derive(Debug)]
struct Page<const N: usize> {
    bricks: Box<[Brick<N>]>,
    spill_starts: Box<[u32]>,
}

/// A brick a search reads, with its spill mark; `None` where its page
/// does not exist (an empty brick).
type Seen<'a, const N: usize> = Option<(&'a Brick<N>, u32)>;

#[derive(Debug)]
pub(crate) struct PagedBricks<const N: usize> {
    pages: Vec<Page<N>>,
    /// Page coordinates to the page's index in `pages`.
    directory: Directory<N>,
    /// Points past [`CAPACITY`] in a brick, in chunks of [`SPILL`].
    spill: Vec<[f64; N]>,
    lo: [f64; N],
    inv_side: [f64; N],
    last: [usize; N],
    /// As [`super::bricks::Bricks`]'s: per part and place, and for the seed.
    part_masks: Vec<[u64; 8]>,
    seed_masks: Vec<[u64; 8]>,
    stencil_bytes: u64,
    radius_squared: f64,
}

impl<const N: usize> PagedBricks<N> {
    /// The grid with its masks and no page yet, or `None` if it does not
    /// apply (see [`applies`]) or the masks cannot be allocated.
    pub(crate) fn try_new(plan: &PagedPlan<N>, domain: &Domain<N>, radius: f64) -> Option<Self> {
        let d = &plan.dense;
        if domain.any_periodic() || !applies(&d.reach) {
            return None;
        }
        let windowed = Windowed::new(d, radius)?;
        let (part_masks, seed_masks) = masks(&windowed.parts, &windowed.seed)?;
        let stencil_bytes = vec_bytes(&part_masks).saturating_add(vec_bytes(&seed_masks));
        Some(Self {
            pages: Vec::new(),
            directory: Directory::new(&d.cells.map(pages_for), plan.directory),
            spill: Vec::new(),
            lo: domain.lo(),
            inv_side: d.side.map(|s| 1.0 / s),
            last: d.cells.map(|m| m.saturating_sub(1)),
            part_masks,
            seed_masks,
            stencil_bytes,
            radius_squared: radius * radius,
        })
    }

    /// The page and the brick's index in it of brick coordinates `b`.
    #[inline(always)]
    fn split(b: &[usize; N]) -> ([usize; N], usize) {
        let mut page = [0usize; N];
        let mut inner = 0;
        for (axis, (pg, &c)) in page.iter_mut().zip(b).enumerate() {
            *pg = c >> PAGE_BITS;
            inner |= (c & ((1 << PAGE_BITS) - 1)) << (PAGE_BITS * axis);
        }
        (page, inner)
    }

    #[inline(always)]
    fn page(&self, page: &[usize; N]) -> Option<&Page<N>> {
        let id = self.directory.get(page)?;
        self.pages.get(id as usize)
    }

    /// The 8 bricks of the window of `cell` (bit `a` of the index: the
    /// next brick along axis `a`, as the masks order them), and the place
    /// of the window's low corner in its brick.
    #[inline(always)]
    fn window(&self, cell: &[usize; N]) -> ([Seen<'_, N>; 8], usize) {
        let mut place = 0;
        let mut low = [0usize; N];
        let mut straddles = false;
        for (axis, (l, &c)) in low.iter_mut().zip(cell).enumerate() {
            // The window's low corner is padded coordinate `c`.
            *l = c >> BRICK_BITS;
            place |= (c & ((1 << BRICK_BITS) - 1)) << (BRICK_BITS * axis);
            straddles |= *l & ((1 << PAGE_BITS) - 1) == (1 << PAGE_BITS) - 1;
        }
        let mut seen: [Seen<'_, N>; 8] = [None; 8];
        let (page, first) = Self::split(&low);
        if !straddles {
            // The common case (7 in 8 per axis): one page holds all 8.
            let Some(pg) = self.page(&page) else {
                return (seen, place);
            };
            for (corner, s) in seen.iter_mut().enumerate() {
                let mut inner = first;
                for axis in 0..N {
                    inner += (corner >> axis & 1) << (PAGE_BITS * axis);
                }
                *s = Self::seen(pg, inner);
            }
            return (seen, place);
        }
        for (corner, s) in seen.iter_mut().enumerate() {
            let b: [usize; N] = core::array::from_fn(|axis| {
                low.get(axis).copied().unwrap_or(0) + (corner >> axis & 1)
            });
            let (page, inner) = Self::split(&b);
            if let Some(pg) = self.page(&page) {
                *s = Self::seen(pg, inner);
            }
        }
        (seen, place)
    }

    #[inline(always)]
    fn seen(page: &Page<N>, inner: usize) -> Seen<'_, N> {
        Some((
            page.bricks.get(inner)?,
            page.spill_starts.get(inner).copied().unwrap_or(0),
        ))
    }

    /// The point of the occupied cell `bit` of a brick.
    #[inline(always)]
    fn point<'a>(&'a self, brick: &'a Brick<N>, mark: u32, bit: usize) -> Option<&'a [f64; N]> {
        let at = rank(brick.occupied, bit);
        if at < CAPACITY {
            brick.points.get(at)
        } else {
            let start = usize::try_from(mark).ok()?.checked_sub(1)?;
            self.spill.get(start + at - CAPACITY)
        }
    }

    /// [`masked_walk`] over the window's bricks `seen`.
    #[inline(always)]
    fn first_masked(
        &self,
        seen: &[Seen<'_, N>; 8],
        place: usize,
        masks: &[u64; 8],
        stop: impl FnMut(&[f64; N]) -> bool,
    ) -> Option<[f64; N]> {
        let mark = |corner: usize| seen.get(corner).copied().flatten().map_or(0, |(_, m)| m);
        masked_walk(
            place,
            masks,
            |corner| Some(seen.get(corner).copied().flatten()?.0),
            |corner, brick, bit| self.point(brick, mark(corner), bit),
            stop,
        )
    }

    /// Asks for each existing brick's first three lines, as the bricks do.
    #[inline(always)]
    fn prefetch_seen(seen: &[Seen<'_, N>; 8]) {
        for (brick, _) in seen.iter().flatten() {
            crate::prefetch::prefetch(&brick.points, 0);
            crate::prefetch::prefetch(&brick.points, 3);
            crate::prefetch::prefetch(&brick.points, 6);
        }
    }

    /// The home brick of `cell`: its page, its index in the page and the
    /// cell's place in it.
    fn home(cell: &[usize; N]) -> ([usize; N], usize, usize) {
        let mut place = 0;
        let b: [usize; N] = core::array::from_fn(|axis| {
            let c = cell.get(axis).copied().unwrap_or(0) + REACH;
            place |= (c & ((1 << BRICK_BITS) - 1)) << (BRICK_BITS * axis);
            c >> BRICK_BITS
        });
        let (page, inner) = Self::split(&b);
        (page, inner, place)
    }

    /// Spill slots storing a point in `cell` may open: a chunk if its
    /// brick has none and is full.
    fn spill_needed(&self, cell: &[usize; N]) -> usize {
        let (page, inner, _) = Self::home(cell);
        match self.page(&page).and_then(|pg| Self::seen(pg, inner)) {
            Some((b, 0)) if b.count() >= CAPACITY => SPILL,
            _ => 0,
        }
    }
}

impl<const N: usize> NeighbourGrid<N> for PagedBricks<N> {
    #[inline(always)]
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]> {
        let (cell, part) = locate(p, &self.lo, &self.inv_side, &self.last, parts(N));
        let (seen, place) = self.window(&cell);
        Self::prefetch_seen(&seen);
        let masks = self.part_masks.get(part * BRICK_CELLS + place)?;
        self.first_masked(&seen, place, masks, |q| {
            closer::<false, N>(p, q, &[0.0; N], self.radius_squared)
        })
    }

    #[inline(always)]
    fn seed(&self, p: &[f64; N], limit: usize, mut take: impl FnMut(&[f64; N])) {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        let (seen, place) = self.window(&cell);
        let Some(masks) = self.seed_masks.get(place) else {
            return;
        };
        let mut taken = 0;
        self.first_masked(&seen, place, masks, |q| {
            take(q);
            taken += 1;
            taken == limit
        });
    }

    #[inline(always)]
    fn prefetch(&self, p: &[f64; N]) {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        Self::prefetch_seen(&self.window(&cell).0);
    }

    fn bytes(&self) -> u64 {
        page_bytes::<N>()
            .saturating_mul(self.pages.len() as u64)
            .saturating_add(vec_bytes(&self.pages))
            .saturating_add(self.directory.bytes())
            .saturating_add(vec_bytes(&self.spill))
            .saturating_add(self.stencil_bytes)
    }

    /// Allocates `p`'s page if it does not exist yet, then spill room if
    /// its brick is full, if all of it fits in `spare`.
    fn reserve(&mut self, p: &[f64; N], spare: u64) -> bool {
        let (cell, _) = locate(p, &self.lo, &self.inv_side, &self.last, 1);
        let (page, _, _) = Self::home(&cell);
        let mut need = 0u64;
        let missing = self.directory.get(&page).is_none();
        if missing {
            need = page_bytes::<N>().saturating_add(self.directory.growth(1));
            if self.pages.len() == self.pages.capacity() {
                let grown = self.pages.capacity().saturating_mul(2).max(8);
                need = need.saturating_add(bytes_of::<Page<N>>(grown));
            }
        }
        let needed = if missing { 0 } else { self.spill_needed(&cell) };
        let (len, capacity) = (self.spill.len(), self.spill.capacity());
        let mut wanted = capacity;
        if capacity - len < needed {
            // Double, or as much as the budget allows, as the bricks do.
            let left = spare.saturating_sub(need);
            let fits = usize::try_from(left / bytes_of::<[f64; N]>(1).max(1)).unwrap_or(usize::MAX);
            wanted = capacity.saturating_mul(2).max(len + needed).min(fits);
            if wanted < len + needed {
                return false;
            }
            need = need.saturating_add(bytes_of::<[f64; N]>(wanted));
        }
        if need > spare {
            return false;
        }
        if missing {
            let Ok(id) = u32::try_from(self.pages.len()) else {
                return false;
            };
            if !self.directory.try_reserve(1) || self.pages.try_reserve(1).is_err() {
                return false;
            }
            let (mut bricks, mut spill_starts) = (Vec::new(), Vec::new());
            if bricks.try_reserve_exact(PAGE_BRICKS).is_err()
                || spill_starts.try_reserve_exact(PAGE_BRICKS).is_err()
            {
                return false;
            }
            bricks.resize(PAGE_BRICKS, Brick::EMPTY);
            spill_starts.resize(PAGE_BRICKS, 0);
            self.pages.push(Page {
                bricks: bricks.into_boxed_slice(),
                spill_starts: spill_starts.into_boxed_slice(),
            });
            self.directory.insert(page, id);
        }
        wanted <= capacity || self.spill.try_reserve_exact(wanted - len).is_ok()
    }

    fn insert(&mut self, p: [f64; N]) -> bool {
        let (cell, _) = locate(&p, &self.lo, &self.inv_side, &self.last, 1);
        let (page, inner, place) = Self::home(&cell);
        let Some(id) = self.directory.get(&page) else {
            return false;
        };
        let Some(pg) = self.pages.get_mut(id as usize) else {
            return false;
        };
        // Occupied only if rounding put two valid points in one cell: `put`
        // drops the newcomer, the set stays valid. A point is stored in one
        // brick only, so `put`'s own check for room in the spill (made by
        // `reserve`) refuses it before anything is written.
        put(
            &mut pg.bricks,
            (&mut self.spill, &mut pg.spill_starts),
            inner * BRICK_CELLS + place,
            &p,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::dense::{Slabs, probe};
    use super::super::{Grid, GridLayout, GridPlan, plan};
    use super::*;
    use crate::random;
    use crate::vector::distance_squared;

    /// The grid, with its directory an array or (`table`) a hash table.
    fn grid(domain: &Domain<3>, r: f64, table: bool) -> PagedBricks<3> {
        match plan(domain, r, GridLayout::Paged, 1 << 30, None, None) {
            Ok(GridPlan::Paged(mut p)) => {
                if table {
                    p.directory = 0;
                }
                let g = PagedBricks::try_new(&p, domain, r).expect("allocates");
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
    /// several pages a side, so that windows straddling pages and pages
    /// not yet made are exercised; the seed hands out only stored points
    /// within its reach.
    #[test]
    fn conflicts_agree_with_brute_force_across_pages() {
        fn check(domain: Domain<3>, r: f64, seed: u64, table: bool) {
            let mut g = grid(&domain, r, table);
            let mut rng = random::seeded_rng(seed);
            let mut stored = Slabs::<3>::new(domain.lo()[0], r);
            let side = g.inv_side.map(|s| 1.0 / s);
            let counts = g.last.map(|l| l + 1);
            assert!(counts.iter().all(|&m| pages_for(m) >= 2), "{counts:?}");
            let (mut hits, mut misses) = (0, 0);
            for _ in 0..20_000 {
                let p: [f64; 3] = core::array::from_fn(|axis| {
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
                let mut seeded = 0;
                g.seed(&p, 64, |q| {
                    assert!(stored.contains(q), "seeded {q:?}");
                    // Cells that can hold a point within `r` of the cell: at most
                    // `r` plus two cell diagonals (`r` each) away.
                    assert!(distance_squared(&p, q) < 9.0 * r * r, "far {q:?}");
                    seeded += 1;
                });
                if brute {
                    hits += 1;
                    // The seed reads every cell but the candidate's own.
                    let cell = |x: &[f64; 3]| locate(x, &g.lo, &g.inv_side, &g.last, 1).0;
                    let other = stored
                        .near(&p)
                        .any(|q| distance_squared(&p, q) < r * r && cell(q) != cell(&p));
                    assert!(seeded > 0 || !other, "a neighbour the seed missed");
                } else {
                    misses += 1;
                    assert!(g.reserve(&p, u64::MAX), "room");
                    if g.insert(p) {
                        stored.insert(p);
                    }
                }
            }
            assert!(hits > 500 && misses > 100, "{hits} hits, {misses} misses");
            assert!(g.pages.len() >= 8, "{} pages", g.pages.len());
        }
        for table in [false, true] {
            check(
                Domain::from_extent([1.5, 1.5, 1.0]).unwrap(),
                0.03,
                1,
                table,
            );
            check(
                Domain::new([-3.0, 1e6, 5.0], [-1.6, 1e6 + 1.2, 6.1]).unwrap(),
                0.04,
                2,
                table,
            );
        }
    }

    /// A brick past [`CAPACITY`] spills, the spill is counted, and its
    /// points are found; without spare bytes it is refused whole.
    #[test]
    fn full_bricks_spill() {
        let domain = Domain::from_extent([2.0; 3]).unwrap();
        let r = 0.1;
        let mut g = grid(&domain, r, false);
        let side = 1.0 / g.inv_side[0];
        let before = g.bytes();
        // Every cell of one brick (cells 30 to 33 a side, padded 32 to 35:
        // brick 8, the first of the second page on every axis; not a valid
        // set, the grid stores what it is given).
        let mut stored = Vec::new();
        for z in 30..34 {
            for y in 30..34 {
                for x in 30..34 {
                    let p = [x, y, z].map(|i| (f64::from(i) + 0.5) * side);
                    assert!(g.reserve(&p, u64::MAX), "reserve");
                    assert!(g.insert(p), "insert {p:?}");
                    stored.push(p);
                }
            }
        }
        assert_eq!(g.pages.len(), 1, "one page");
        assert!(!g.spill.is_empty(), "spilled");
        assert!(g.bytes() > before, "the spill is counted");
        for p in &stored {
            let q = g.conflict(p).expect("found");
            assert!(distance_squared(p, &q) < r * r, "{p:?}");
            let mut n = 0;
            g.seed(p, 64, |_| n += 1);
            assert!(n >= 16, "seed from {p:?}: {n}");
        }
        // Every point is stored once: the seed from a cell of the brick
        // hands out the other 63.
        let mut all = Vec::new();
        g.seed(&stored[21], 64, |q| all.push(*q));
        all.sort_by(|a, b| a.partial_cmp(b).unwrap());
        all.dedup();
        assert_eq!(all.len(), 63, "distinct points");
        // No room for a spill chunk: refused before anything is stored.
        let mut h = grid(&domain, r, false);
        for p in stored.iter().take(CAPACITY) {
            assert!(h.reserve(p, u64::MAX) && h.insert(*p), "within the brick");
        }
        assert!(!h.reserve(&stored[CAPACITY], 0), "no spare bytes");
        assert!(!h.insert(stored[CAPACITY]), "no room reserved");
        assert!(
            h.conflict(&stored[CAPACITY]).is_some(),
            "its neighbours are"
        );
        // No room for a page: refused, and nothing is made.
        let far = [1.9; 3];
        assert!(!h.reserve(&far, 1000), "a page takes more");
        assert_eq!(h.pages.len(), 1, "no page made");
        assert!(!h.insert(far), "no page");
        assert!(h.conflict(&far).is_none(), "empty there");
    }

    /// A paged plan in 3-D with a reach of 2 builds these pages, not the
    /// `u32` ones.
    #[test]
    fn three_d_pages_are_bricked() {
        let domain = Domain::from_extent([1.2, 1.0, 1.1]).unwrap();
        let p = plan(&domain, 0.04, GridLayout::Paged, 1 << 30, None, None).unwrap();
        assert!(matches!(
            Grid::build(&p, &domain, 0.04),
            Grid::PagedBricks(_)
        ));
    }
}
