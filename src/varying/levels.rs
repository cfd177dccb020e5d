//! The main index of a varying radius: one dense grid per band of radii.
//!
//! Level `j` holds the points whose radius lies in `[t_j, t_j·2^(3/4))` (the
//! last band up to `r_max`), on a grid of cells of side just under
//! `top_j/√N`, the band's top, as Bridson's grid is sized to its radius:
//! a search at the band's own radii reaches as far in cells as the fixed
//! radius's. Its points being only `t_j` apart, a cell can hold more than
//! one (a few at most): a cell is a `u32`, the index plus one of the point
//! filed last (0 is empty), whose top bit ([`MORE`]) says that the cell's
//! earlier points follow in a chain, one link per point. Few cells hold
//! two points, and a lone point's cell reads no link. A coarse grid (cells
//! of side `r_max`) keeps, for
//! the 3^N cells around each, which levels hold a point there and the
//! largest radius stored there: a candidate `c` of radius `r(c)` searches
//! only those levels, level `j` out to `ρ = max(r(c), min(top_j, largest))`,
//! which bounds `max(r(c), r(q))` for every point `q` of that level that
//! could be too close. The search runs over a stencil of the first radius
//! past `ρ` in a family `t_j·2^(3m/4)` (built on first use, cut by the part
//! of the cell the candidate lies in, as in `grid/dense.rs`, with the
//! rounding margin of the level's grid), and of that stencil, nearest cells
//! first, only the prefix that reaches `ρ`, to one of [`CUTS`] steps
//! between the family's radii; near a face, over the whole box of cells
//! within the reach, wrapping on periodic axes.
//!
//! With a smooth field, the points near a candidate share its level, so a
//! search is about the fixed radius's stencil, a little wider at the
//! band's foot. The levels' grids together take about half the cells one
//! grid at `r_min` would in 2-D, a quarter in 3-D (cells `2^(3/4)` wider
//! per axis than at the band's floor, bands in that ratio): allocated
//! zeroed, a level's pages are touched where its band of the field lies
//! (along the grid's fastest axis, that is every page).

use super::coarse::Coarse;
use super::{Stored, too_close};
use crate::domain::Domain;
use crate::grid::dense::{
    EMPTY, Stencil, StencilShape, locate, occupied, part_gap, parts, stencil_bytes_per_cell,
};
use crate::grid::rounding_margin;

/// The ratio of a level's band of radii, `2^(3/4)`: with cells sized to
/// the band's top, wider bands mean fewer and smaller grids (less memory,
/// fewer bands around a candidate) but searches wider than the radius
/// needs at the band's foot. `2^(3/4)` ran 3 to 8 % faster than `√2`
/// (with a third less memory), `4^(1/3)` 2 % slower than `2^(3/4)`, and
/// `2` as fast as `√2` in 3-D at `r_max / r_min = 4` but 11 % slower at 2
/// (the journal).
const LEVEL_STEP: f64 = 1.681_792_830_507_429;
/// The ratio between consecutive search radii of a level's stencils: the
/// band's own ratio, so that a search in its own band always takes the
/// stencil of the band's top (a prefix of it, [`CUTS`]). Finer steps make
/// more distinct stencils, whose offsets then compete for the cache: with
/// bands of `√2`, `2^(1/4)` ran 5 % slower, `2^(1/8)` and `2^(1/16)`
/// slower still (the journal).
const STENCIL_STEP: f64 = LEVEL_STEP;
/// The largest `r_max / r_min` served (6 levels): past it the lowest
/// levels' stencils, at up to `r_max` in cells of `2^(3/4)·r_min/√N`, grow as the
/// ratio to the power `N`, and the lists ([`Lists`](super::lists::Lists))
/// serve instead.
pub(super) const MAX_RATIO: f64 = 16.0;
/// The most dimensions served: past 4-D the stencils' windows grow too
/// large (as for the fixed radius, which turns to a hash grid there).
pub(super) const MAX_DIM: usize = 4;
/// Cells gathered before their points are checked (as `grid/dense.rs`).
const CHUNK: usize = 8;
/// The most occupied cells a seed collects: a stencil at a band's top
/// holds about 20 points in 3-D, and the cache keeps at most 15.
const SEED_MAX: usize = 32;
/// Steps between consecutive stencil radii at which a stencil's
/// nearest-first offsets are cut: a search of radius `ρ` reads the
/// prefix of the first cut at or past `ρ`, not the whole stencil.
const CUTS: usize = 8;

/// The bit of a cell's value (and of a chain link) saying that another
/// point of the same cell follows, in [`Levels::next`]: the rest of the
/// value is the point's index plus one.
const MORE: u32 = 1 << 31;

/// Calls `hit` on the index of each point of the cell whose value is `v`
/// (not [`EMPTY`]), newest first, until it returns `true`; returns that
/// point. Most cells hold one point: its value has no [`MORE`] bit and
/// `next` is not read.
#[inline(always)]
fn chain(next: &[u32], mut v: u32, mut hit: impl FnMut(usize) -> bool) -> Option<usize> {
    loop {
        let i = (v & !MORE).wrapping_sub(1) as usize;
        if hit(i) {
            return Some(i);
        }
        if v & MORE == 0 {
            return None;
        }
        v = next.get(i).copied().unwrap_or(EMPTY);
        if v == EMPTY {
            return None;
        }
    }
}

/// A stencil, the reach it was cut with, and its prefixes.
#[derive(Debug)]
struct Built<const N: usize> {
    stencil: Stencil,
    reach: [usize; N],
    /// `cuts[k]`: how many of the offsets (nearest first) it takes to
    /// cover every cell within the level's `sub[m][k]` of the part.
    cuts: [u32; CUTS],
}

impl<const N: usize> Built<N> {
    /// The offsets a search of radius `rho` needs, given the stencil's
    /// cut radii `sub` (rising): the prefix of the first cut at or past
    /// `rho`, the whole stencil past the last.
    #[inline(always)]
    fn within(&self, sub: &[f64; CUTS], rho: f64) -> &[isize] {
        let k = sub.iter().take_while(|&&r| r < rho).count();
        let len = self.cuts.get(k).map_or(usize::MAX, |&n| n as usize);
        let offsets = &self.stencil.offsets;
        offsets.get(..len).unwrap_or(offsets)
    }
}

/// One band of radii and its grid.
#[derive(Debug)]
struct Level<const N: usize> {
    /// The smallest radius of the band, `t_j`.
    floor: f64,
    /// Every radius of the band is below this (or equal, for the last).
    top: f64,
    side: [f64; N],
    inv_side: [f64; N],
    /// Cells per axis in the box.
    counts: [usize; N],
    /// Empty cells past each face of a bounded axis (none on periodic
    /// ones): the widest reach, so that a stencil never leaves the array.
    pad: [usize; N],
    /// Of the padded array.
    stride: [usize; N],
    eta: f64,
    /// Per cell: the index of its point plus one, or [`EMPTY`].
    cells: Vec<u32>,
    /// The search radii of the stencils, rising, the last `>= r_max`.
    radii: Vec<f64>,
    /// Per stencil radius `radii[m]`: the radii its offsets are cut at,
    /// evenly spaced from the previous radius (0 for the first) to it.
    sub: Vec<[f64; CUTS]>,
    /// Per (radius, part), `m·parts^N + part`: built on first use.
    stencils: Vec<Option<Built<N>>>,
}

/// Parts per axis that a cell is cut into for the stencils.
const PARTS: usize = parts(MAX_DIM);

impl<const N: usize> Level<N> {
    /// The level of band `[floor, top)` over `domain`, and the bound on
    /// the bytes its stencils can take; `None` if the grid has too many
    /// cells to index.
    fn new(domain: &Domain<N>, floor: f64, top: f64, r_max: f64) -> Option<(Self, u64)> {
        // Cells sized to the band's top, as the fixed radius's grid to its
        // radius: a search of the band's own radii reaches as few cells.
        // A cell can then hold more than one point (up to 4 up to 3-D,
        // the band's points being only `floor` apart): the extra ones
        // are chained ([`MORE`]).
        #[expect(clippy::cast_precision_loss, reason = "N is small")]
        let max_side = top / (N as f64).sqrt() * (1.0 - 1e-6);
        let mut counts = [0usize; N];
        let mut side = [0.0; N];
        for ((count, s), e) in counts.iter_mut().zip(&mut side).zip(domain.extent()) {
            let cells = (e / max_side).ceil();
            // NaN (an infinite box) fails too.
            if cells.is_nan() || cells > 2f64.powi(31) {
                return None;
            }
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a whole number in 0..=2^31"
            )]
            let mut m = (cells as usize).max(1);
            #[expect(clippy::cast_precision_loss, reason = "m <= 2^31 + 1")]
            if e / m as f64 > max_side {
                m += 1;
            }
            *count = m;
            #[expect(clippy::cast_precision_loss, reason = "m <= 2^31 + 1")]
            let width = e / m as f64;
            *s = width;
        }
        #[expect(clippy::cast_precision_loss, reason = "a bound")]
        let eta = rounding_margin(counts.iter().copied().max().unwrap_or(1) as f64);
        let mut radii = vec![floor];
        let mut r = floor;
        while r < r_max {
            r *= STENCIL_STEP;
            radii.push(r);
        }
        let mut below = 0.0;
        let sub = radii
            .iter()
            .map(|&r| {
                #[expect(clippy::cast_precision_loss, reason = "a few steps")]
                let cut =
                    core::array::from_fn(|k| below + (r - below) * (k + 1) as f64 / CUTS as f64);
                below = r;
                cut
            })
            .collect();
        let mut level = Self {
            floor,
            top,
            side,
            inv_side: side.map(|s| 1.0 / s),
            counts,
            pad: [0; N],
            stride: [0; N],
            eta,
            cells: Vec::new(),
            radii,
            sub,
            stencils: Vec::new(),
        };
        // The widest reach is the last radius's.
        let widest = level.reach(r, &domain.periodic());
        let mut total = 1usize;
        let axes = counts.iter().zip(&widest).zip(domain.periodic());
        for ((s, p), ((&m, &w), periodic)) in level.stride.iter_mut().zip(&mut level.pad).zip(axes)
        {
            *p = if periodic { 0 } else { w };
            *s = total;
            total = total.checked_mul(m.checked_add(p.checked_mul(2)?)?)?;
        }
        let parts_n = PARTS.pow(u32::try_from(N).ok()?);
        let mut stencil_bytes = 0u64;
        for &r in &level.radii {
            let window: u64 = level
                .reach(r, &domain.periodic())
                .iter()
                .map(|&p| u64::try_from(2 * p + 1).unwrap_or(u64::MAX))
                .fold(1, u64::saturating_mul);
            stencil_bytes =
                stencil_bytes.saturating_add(window.saturating_mul(stencil_bytes_per_cell(N)));
        }
        level.stencils = (0..level.radii.len().checked_mul(parts_n)?)
            .map(|_| None)
            .collect();
        let cells = u64::try_from(total).ok()?;
        Some((level, stencil_bytes.saturating_add(cells.saturating_mul(4))))
    }

    /// Cells on each side that can hold a point closer than `r` to a point
    /// of the centre cell, counting the rounding margin, up to what the
    /// axis holds (every cell on a bounded axis, an image of every cell on
    /// a periodic one).
    fn reach(&self, r: f64, periodic: &[bool; N]) -> [usize; N] {
        let mut reach = [0usize; N];
        let axes = self.side.iter().zip(&self.counts).zip(periodic);
        for (p, ((&s, &m), &periodic)) in reach.iter_mut().zip(axes) {
            let needed = (r / s + self.eta).ceil();
            let bound = if periodic { m } else { m - 1 };
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                clippy::cast_precision_loss,
                reason = "compared with the bound (<= 2^31) before the cast"
            )]
            let cells = if needed < bound as f64 {
                needed as usize
            } else {
                bound
            };
            *p = cells;
        }
        reach
    }

    /// The cell of a point of the box, and the part of it the point lies
    /// in ([`PARTS`] per axis), as `Dense::locate`.
    #[inline(always)]
    fn locate(&self, p: &[f64; N], lo: &[f64; N]) -> ([usize; N], usize) {
        let last = self.counts.map(|m| m.saturating_sub(1));
        locate(p, lo, &self.inv_side, &last, PARTS)
    }

    /// For a search of radius `radius` around `p`: `p`'s cell, its part,
    /// and the index `m` of the smallest stencil radius that covers
    /// `radius` (the largest there is if none does), that stencil built
    /// for the part if it was not yet. [`Self::stencil`]`(m, part)` then
    /// gives it.
    #[inline(always)]
    fn prepare(
        &mut self,
        p: &[f64; N],
        radius: f64,
        lo: &[f64; N],
        periodic: &[bool; N],
    ) -> ([usize; N], usize, usize) {
        let m = self
            .radii
            .iter()
            .position(|&x| x >= radius)
            .unwrap_or(self.radii.len().saturating_sub(1));
        let (cell, part) = self.locate(p, lo);
        self.build(m, part, periodic);
        (cell, part, m)
    }

    /// Builds the stencil of radius `radii[m]` for part `part`, unless
    /// built already (the usual case, checked inline).
    #[inline(always)]
    fn build(&mut self, m: usize, part: usize, periodic: &[bool; N]) {
        let slot = m * PARTS.pow(u32::try_from(N).unwrap_or(0)) + part;
        if self.stencils.get(slot).is_some_and(Option::is_none) {
            self.build_slot(slot, m, part, periodic);
        }
    }

    /// [`Self::build`]'s work, into `slot`.
    #[cold]
    #[inline(never)]
    fn build_slot(&mut self, slot: usize, m: usize, part: usize, periodic: &[bool; N]) {
        let radius = self.radii.get(m).copied().unwrap_or(f64::INFINITY);
        let reach = self.reach(radius, periodic);
        let mut part_of = [0usize; N];
        let mut rest = part;
        for p in &mut part_of {
            *p = rest % PARTS;
            rest /= PARTS;
        }
        let shape = StencilShape {
            reach,
            side: self.side,
            eta: self.eta,
            radius,
        };
        let sub = self.sub.get(m).copied().unwrap_or([f64::INFINITY; CUTS]);
        let built = Stencil::new(&shape, &self.stride, &part_of, PARTS).map(|stencil| {
            let cuts = self.cuts(&stencil.offsets, &reach, &part_of, &sub);
            Built {
                stencil,
                reach,
                cuts,
            }
        });
        if let Some(s) = self.stencils.get_mut(slot) {
            *s = built;
        }
    }

    /// Per cut radius `sub[k]`, the length of the shortest prefix of
    /// `offsets` (a stencil of part `part`, reach `reach`, nearest first)
    /// that holds every cell within `sub[k]` of the part, the rounding
    /// margin counted as `Stencil::new` counts it: the cell's gap to the
    /// part, per axis less `η` cells, summed in squares. Each offset is
    /// decoded into its cell steps; where the padded axes are too short
    /// for that to be unique (a periodic axis narrower than the window,
    /// whose stencils serve no search), nothing is cut. The gap is
    /// `Stencil::new`'s own (`dense::part_gap`): `Stencil` keeps no gaps,
    /// so they are computed again here, by the same function.
    fn cuts(
        &self,
        offsets: &[isize],
        reach: &[usize; N],
        part: &[usize; N],
        sub: &[f64; CUTS],
    ) -> [u32; CUTS] {
        let whole = u32::try_from(offsets.len()).unwrap_or(u32::MAX);
        let mut cuts = [whole; CUTS];
        let unique = reach
            .iter()
            .zip(&self.counts)
            .zip(&self.pad)
            .all(|((&p, &m), &pad)| 2 * p < m + 2 * pad);
        if !unique {
            return cuts;
        }
        cuts = [0; CUTS];
        #[expect(clippy::cast_precision_loss, reason = "a few parts")]
        let parts = PARTS as f64;
        for (i, &o) in offsets.iter().enumerate() {
            // Highest axis first: the lower axes' steps add up to less
            // than half its stride, so rounding to the nearest multiple
            // gives its step.
            let mut rest = o;
            let mut gap2 = 0.0;
            for ((&s, &k), &side) in self.stride.iter().zip(part).zip(&self.side).rev() {
                let s = isize::try_from(s).unwrap_or(isize::MAX);
                let d = (rest + (s - 1) / 2).div_euclid(s);
                rest -= d * s;
                #[expect(clippy::cast_precision_loss, reason = "small steps and parts")]
                let (d, k) = (d as f64, k as f64);
                let gap = part_gap(d, k, parts, self.eta, side);
                gap2 += gap * gap;
            }
            let len = u32::try_from(i + 1).unwrap_or(u32::MAX);
            for (cut, &r) in cuts.iter_mut().zip(sub) {
                if gap2 < r * r {
                    *cut = len;
                }
            }
        }
        cuts
    }

    /// The stencil of radius `radii[m]` for part `part`, if built.
    fn stencil(&self, m: usize, part: usize) -> Option<&Built<N>> {
        let slot = m * PARTS.pow(u32::try_from(N).unwrap_or(0)) + part;
        self.stencils.get(slot)?.as_ref()
    }

    /// Whether a stencil of `reach` fits around `cell` without wrapping:
    /// bounded axes are padded, periodic ones must not wrap.
    fn fits(&self, cell: &[usize; N], reach: &[usize; N], periodic: &[bool; N]) -> bool {
        cell.iter()
            .zip(reach)
            .zip(self.counts.iter().zip(periodic))
            .all(|((&c, &p), (&m, &periodic))| !periodic || (c >= p && c + p < m))
    }

    /// The index in the padded array of a cell of the box.
    fn linear(&self, cell: &[usize; N]) -> usize {
        cell.iter()
            .zip(&self.pad)
            .zip(&self.stride)
            .map(|((c, p), s)| (c + p) * s)
            .sum()
    }
}

#[derive(Debug)]
pub(super) struct Levels<const N: usize> {
    coarse: Coarse<N>,
    lo: [f64; N],
    periodic: [bool; N],
    /// Per coarse cell: bit `j` is set if a point of level `j` lies in
    /// the 3^N cells around it.
    masks: Vec<u32>,
    /// Per coarse cell: the largest radius stored in the 3^N cells around
    /// it (0 if none).
    largest: Vec<f64>,
    levels: Vec<Level<N>>,
    /// Per point: the value of the cell it was filed in before it (the
    /// next of the cell's chain), or [`EMPTY`].
    next: Vec<u32>,
}

impl<const N: usize> Levels<N> {
    /// The index for radii `r_min ..= r_max` over `domain`, and the bytes
    /// it can take (its cells and every stencil it may build); `None`
    /// past [`MAX_RATIO`] or [`MAX_DIM`], if it needs more than `budget`
    /// bytes, or if a level has too many cells.
    pub(super) fn new(
        coarse: Coarse<N>,
        domain: &Domain<N>,
        r_min: f64,
        r_max: f64,
        budget: u64,
    ) -> Result<(Self, u64), Coarse<N>> {
        if N == 0 || N > MAX_DIM || r_max > r_min * MAX_RATIO {
            return Err(coarse);
        }
        let mut floors = vec![r_min];
        let mut t = r_min;
        while t * LEVEL_STEP < r_max {
            t *= LEVEL_STEP;
            floors.push(t);
        }
        let per_coarse = u64::try_from(size_of::<u32>() + size_of::<f64>()).unwrap_or(u64::MAX);
        let mut bytes = u64::try_from(coarse.count())
            .unwrap_or(u64::MAX)
            .saturating_mul(per_coarse);
        let mut levels = Vec::new();
        for (j, &floor) in floors.iter().enumerate() {
            let top = floors.get(j + 1).copied().unwrap_or(r_max);
            let Some((level, needed)) = Level::new(domain, floor, top, r_max) else {
                return Err(coarse);
            };
            bytes = bytes.saturating_add(needed);
            levels.push(level);
        }
        if bytes > budget {
            return Err(coarse);
        }
        for level in &mut levels {
            let total = level
                .counts
                .iter()
                .zip(&level.pad)
                .map(|(m, p)| m + 2 * p)
                .product();
            // Zeroed memory: pages are touched only where the level's
            // points are.
            level.cells = vec![EMPTY; total];
            // Before the first write, as the fixed radius's grid: fewer
            // TLB misses over these large, sparsely read arrays.
            crate::huge_pages::advise(&level.cells);
        }
        Ok((
            Self {
                masks: vec![0; coarse.count()],
                largest: vec![0.0; coarse.count()],
                coarse,
                lo: domain.lo(),
                periodic: domain.periodic(),
                levels,
                next: Vec::new(),
            },
            bytes,
        ))
    }

    /// The level of radius `r`: the last whose floor is at most `r`.
    #[inline(always)]
    fn level_of(&self, r: f64) -> usize {
        self.levels
            .iter()
            .skip(1)
            .take_while(|l| l.floor <= r)
            .count()
    }

    /// A stored point closer to `c` than `max(rc, its radius)`, if any.
    #[inline(always)]
    pub(super) fn blocked(
        &mut self,
        points: &[Stored<N>],
        periods: &[f64; N],
        c: &[f64; N],
        rc: f64,
    ) -> Option<usize> {
        let at = self.coarse.linear(&self.coarse.cell_of(c));
        let mut mask = self.masks.get(at).copied().unwrap_or(u32::MAX);
        let largest = self.largest.get(at).copied().unwrap_or(f64::INFINITY);
        // Its own level first: the likeliest to hold a close point.
        let own = self.level_of(rc);
        let own_bit = 1u32
            .checked_shl(u32::try_from(own).unwrap_or(u32::MAX))
            .unwrap_or(0);
        if mask & own_bit != 0 {
            mask &= !own_bit;
            if let Some(i) = self.search(own, points, periods, c, rc, largest) {
                return Some(i);
            }
        }
        while mask != 0 {
            let j = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if let Some(i) = self.search(j, points, periods, c, rc, largest) {
                return Some(i);
            }
        }
        None
    }

    /// A point of level `j` closer to `c` than `max(rc, its radius)`.
    #[inline(always)]
    fn search(
        &mut self,
        j: usize,
        points: &[Stored<N>],
        periods: &[f64; N],
        c: &[f64; N],
        rc: f64,
        largest: f64,
    ) -> Option<usize> {
        let (lo, periodic) = (self.lo, self.periodic);
        let next = &self.next;
        let level = self.levels.get_mut(j)?;
        // Every point of this level within the coarse cells around has a
        // radius at most `min(top, largest)`.
        let rho = rc.max(level.top.min(largest));
        let (cell, part, m) = level.prepare(c, rho, &lo, &periodic);
        let level = &*level;
        let built = level.stencil(m, part)?;
        if level.fits(&cell, &built.reach, &periodic) {
            let base = level.linear(&cell);
            let mut found = [EMPTY; CHUNK];
            let sub = level.sub.get(m)?;
            // Ask for every row first, as the fixed radius's search: a
            // candidate that gets this far often has no conflict nearby.
            if N <= 3 {
                for &[first, last] in &built.stencil.rows {
                    crate::prefetch::prefetch(&level.cells, base.wrapping_add_signed(first));
                    crate::prefetch::prefetch(&level.cells, base.wrapping_add_signed(last));
                }
            }
            for chunk in built.within(sub, rho).chunks(CHUNK) {
                let n = occupied(&level.cells, base, chunk, &mut found);
                for &v in found.iter().take(n) {
                    let hit = chain(next, v, |i| too_close(points, periods, c, rc, i));
                    if hit.is_some() {
                        return hit;
                    }
                }
            }
            return None;
        }
        // Near a face: every cell of the box of cells within the reach,
        // wrapped on periodic axes, skipped past bounded faces.
        let reach = built.reach;
        let mut d = reach.map(|p| -isize::try_from(p).unwrap_or(0));
        loop {
            let mut at = 0usize;
            let mut inside = true;
            let axes = cell.iter().zip(&level.counts).zip(&level.stride);
            for ((((&ci, &m), &s), &pad), (&di, &p)) in
                axes.zip(&level.pad).zip(d.iter().zip(&periodic))
            {
                let (ci, m) = (
                    isize::try_from(ci).unwrap_or(0),
                    isize::try_from(m).unwrap_or(1),
                );
                let mut k = ci + di;
                if p {
                    k = k.rem_euclid(m);
                } else if k < 0 || k >= m {
                    inside = false;
                    break;
                }
                at += (usize::try_from(k).unwrap_or(0) + pad) * s;
            }
            if inside {
                let v = level.cells.get(at).copied().unwrap_or(EMPTY);
                if v != EMPTY {
                    let hit = chain(next, v, |i| too_close(points, periods, c, rc, i));
                    if hit.is_some() {
                        return hit;
                    }
                }
            }
            // Odometer over -reach..=reach on every axis.
            let mut stepped = false;
            for (x, &p) in d.iter_mut().zip(&reach) {
                let p = isize::try_from(p).unwrap_or(0);
                if *x < p {
                    *x += 1;
                    stepped = true;
                    break;
                }
                *x = -p;
            }
            if !stepped {
                return None;
            }
        }
    }

    /// The level of radius `r`, the cell of `p` in it (its index) and the
    /// stencil of radius `r` (its band's top) around it, if that needs no
    /// periodic wrap: where [`Self::seed`] and [`Self::prefetch`] look.
    fn around(
        &mut self,
        p: &[f64; N],
        r: f64,
    ) -> Option<(&Level<N>, usize, &Built<N>, &[f64; CUTS])> {
        let (lo, periodic) = (self.lo, self.periodic);
        let j = self.level_of(r);
        let level = self.levels.get_mut(j)?;
        let (cell, part, m) = level.prepare(p, r, &lo, &periodic);
        let level = &*level;
        let built = level.stencil(m, part)?;
        if !level.fits(&cell, &built.reach, &periodic) {
            return None;
        }
        Some((level, level.linear(&cell), built, level.sub.get(m)?))
    }

    /// Hands up to `limit` points of `p`'s level near `p` to `take`,
    /// nearest cells first: those within about `r` (the stencil of its
    /// band's top), where no periodic wrap is needed. Two passes, as the
    /// fixed radius's seed, so that the points' loads go out together:
    /// the occupied cells without a branch, then their points.
    #[inline(always)]
    pub(super) fn seed(
        &mut self,
        points: &[Stored<N>],
        p: &[f64; N],
        r: f64,
        limit: usize,
        mut take: impl FnMut(&[f64; N]),
    ) {
        let mut found = [EMPTY; SEED_MAX];
        let n = match self.around(p, r) {
            Some((level, base, built, _)) => {
                occupied(&level.cells, base, &built.stencil.offsets, &mut found)
            }
            None => return,
        };
        let mut left = limit;
        for &v in found.iter().take(n.min(SEED_MAX)) {
            let full = chain(&self.next, v, |i| {
                if let Some((q, _)) = points.get(i) {
                    take(q);
                }
                left = left.saturating_sub(1);
                left == 0
            });
            if full.is_some() {
                return;
            }
        }
    }

    /// Starts loading the cells [`Self::seed`] will read around `p`, row
    /// by row, and the band masks and largest radii of the coarse cells
    /// around, which its candidates' searches look up (up to 3-D); a hint
    /// only.
    pub(super) fn prefetch(&mut self, p: &[f64; N], r: f64) {
        if N > 3 {
            return;
        }
        // The coarse cells a search of its candidates looks up.
        let cell = self.coarse.cell_of(p);
        for at in self.coarse.rows_around(&cell) {
            crate::prefetch::prefetch(&self.masks, at);
            crate::prefetch::prefetch(&self.largest, at);
        }
        let Some((level, base, built, _)) = self.around(p, r) else {
            return;
        };
        for &[first, last] in &built.stencil.rows {
            crate::prefetch::prefetch(&level.cells, base.wrapping_add_signed(first));
            crate::prefetch::prefetch(&level.cells, base.wrapping_add_signed(last));
        }
    }

    /// Files point `index` (the points filed so far), at `p` with radius
    /// `r`, at the head of its cell's chain; `false` (and nothing filed)
    /// if the index does not fit a cell's value (2³¹ - 1 points).
    pub(super) fn insert(&mut self, index: u32, p: &[f64; N], r: f64) -> bool {
        let value = index.wrapping_add(1);
        if value == 0 || value >= MORE || self.next.len() != index as usize {
            return false;
        }
        let j = self.level_of(r);
        let lo = self.lo;
        let Some(level) = self.levels.get_mut(j) else {
            return false;
        };
        let (cell, _) = level.locate(p, &lo);
        let at = level.linear(&cell);
        let Some(slot) = level.cells.get_mut(at) else {
            return false;
        };
        self.next.push(*slot);
        *slot = if *slot == EMPTY { value } else { value | MORE };
        let bit = 1u32
            .checked_shl(u32::try_from(j).unwrap_or(u32::MAX))
            .unwrap_or(0);
        let Self {
            coarse,
            masks,
            largest,
            ..
        } = self;
        coarse.find_around(&coarse.cell_of(p), |k| {
            if let Some(m) = masks.get_mut(k) {
                *m |= bit;
            }
            if let Some(l) = largest.get_mut(k) {
                *l = l.max(r);
            }
            None::<()>
        });
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{seeded_rng, unit};

    /// A cut of a stencil holds every cell that a point closer than the
    /// cut's radius to a point of the stencil's part can lie in, for every
    /// radius and part of a level: random pairs, their cells' offset looked
    /// up in the prefix.
    #[expect(clippy::cast_possible_truncation, reason = "cells of a small window")]
    fn cuts_cover<const N: usize>(periodic: bool, seed: u64) {
        let domain = Domain::from_extent([1.0; N])
            .unwrap()
            .with_periodic([periodic; N]);
        let (floor, r_max) = (0.03, 0.12);
        let (mut level, _) = Level::new(&domain, floor, floor * LEVEL_STEP, r_max).unwrap();
        let axes = domain.periodic();
        let mut rng = seeded_rng(seed);
        let mut checked = 0;
        for m in 0..level.radii.len() {
            for part in 0..PARTS.pow(u32::try_from(N).unwrap()) {
                level.build(m, part, &axes);
                let built = level.stencil(m, part).unwrap();
                let sub = level.sub[m];
                assert_eq!(
                    built.within(&sub, f64::INFINITY),
                    &built.stencil.offsets[..]
                );
                for _ in 0..300 {
                    // Positions in cells, the centre cell being 0..1.
                    let mut rest = part;
                    let mut d2 = 0.0;
                    let mut offset = 0isize;
                    for i in 0..N {
                        let k = (rest % PARTS) as f64;
                        rest /= PARTS;
                        let x = (k + unit(&mut rng)) / PARTS as f64;
                        let reach = built.reach[i] as f64;
                        let y = -reach + unit(&mut rng) * (2.0 * reach + 1.0);
                        offset += (y.floor() as isize) * level.stride[i] as isize;
                        let d = (x - y) * level.side[i];
                        d2 += d * d;
                    }
                    for (k, &r) in sub.iter().enumerate() {
                        if d2 < r * r {
                            checked += 1;
                            assert!(
                                built.within(&sub, r).contains(&offset),
                                "{N}-D m {m} part {part} cut {k}: offset {offset} missing"
                            );
                        }
                    }
                }
            }
        }
        assert!(checked > 1000, "{N}-D: {checked} pairs checked");
    }

    /// The index finds a point too close to a candidate exactly when one
    /// is, cells holding many points (random points, not a Poisson disk
    /// set: long chains), bounded and periodic; a seed hands out distinct
    /// points, at most as many as asked.
    fn finds_like_brute_force<const N: usize>(periodic: bool, seed: u64) {
        let domain = Domain::from_extent([1.0; N])
            .unwrap()
            .with_periodic([periodic; N]);
        let (r_min, r_max) = (0.02, 0.02 * 3.7);
        let coarse = Coarse::new(&domain, r_max).unwrap();
        let (mut levels, _) = Levels::new(coarse, &domain, r_min, r_max, 1 << 30).unwrap();
        let periods = [if periodic { 1.0 } else { 0.0 }; N];
        let mut rng = seeded_rng(seed);
        let mut points: Vec<Stored<N>> = Vec::new();
        let count = [0, 20, 100, 300, 600][N];
        for i in 0..count {
            // Half of them a hair from an earlier point: crowded cells.
            let near = points
                .get(crate::random::below(&mut rng, 2 * i + 1))
                .map(|(q, _)| *q);
            let p = core::array::from_fn(|k| match near {
                Some(q) => (q[k] + 0.01 * unit(&mut rng)).min(0.999),
                None => unit(&mut rng),
            });
            let r = r_min + (r_max - r_min) * unit(&mut rng);
            assert!(levels.insert(u32::try_from(i).unwrap(), &p, r));
            points.push((p, r));
        }
        // Cells of two points, and (from 2-D) of three or more.
        assert!(levels.next.iter().any(|&v| v != EMPTY), "{N}-D: no chain");
        let long = levels.next.iter().any(|&v| v & MORE != 0);
        assert!(N == 1 || long, "{N}-D: no chain of three");
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..2000 {
            // Half of them near a point, where conflicts are.
            let near = points
                .get(crate::random::below(&mut rng, 2 * points.len()))
                .map(|(q, _)| *q);
            let c: [f64; N] = core::array::from_fn(|k| match near {
                Some(q) => (q[k] + 0.05 * (unit(&mut rng) - 0.5)).clamp(0.0, 0.999),
                None => unit(&mut rng),
            });
            let rc = r_min + (r_max - r_min) * unit(&mut rng);
            let near = (0..points.len()).any(|i| too_close(&points, &periods, &c, rc, i));
            match levels.blocked(&points, &periods, &c, rc) {
                Some(i) => {
                    assert!(
                        too_close(&points, &periods, &c, rc, i),
                        "{N}-D: {i} not close"
                    );
                    hits += 1;
                }
                None => {
                    assert!(!near, "{N}-D: a close point missed around {c:?}");
                    misses += 1;
                }
            }
            let mut seen = Vec::new();
            levels.seed(&points, &c, rc, 7, |q| seen.push(*q));
            assert!(seen.len() <= 7);
            for (k, q) in seen.iter().enumerate() {
                assert!(!seen[..k].contains(q), "{N}-D: a seed point twice");
            }
        }
        assert!(
            hits > 200 && misses > 200,
            "{N}-D: {hits} hits, {misses} misses"
        );
    }

    #[test]
    fn chained_cells_find_like_brute_force() {
        finds_like_brute_force::<1>(false, 1);
        finds_like_brute_force::<1>(true, 2);
        finds_like_brute_force::<2>(false, 3);
        finds_like_brute_force::<2>(true, 4);
        finds_like_brute_force::<3>(false, 5);
        finds_like_brute_force::<3>(true, 6);
        finds_like_brute_force::<4>(false, 7);
        finds_like_brute_force::<4>(true, 8);
    }

    #[test]
    fn cuts_hold_every_cell_within_their_radius() {
        cuts_cover::<1>(false, 1);
        cuts_cover::<2>(false, 2);
        cuts_cover::<2>(true, 3);
        cuts_cover::<3>(false, 4);
        cuts_cover::<4>(true, 5);
    }
}
