//! The rounds of one query: every cell of a window of level-0 cells, dart
//! by dart, with what lies outside the window tracked as unknown.
//!
//! Three-valued bookkeeping makes a window's answer exact or absent, never
//! approximate: a point is *known* only when every input of its decision
//! is known, and everything a decision could learn from outside the window
//! is *unknown* ("tainted"). A query succeeds when the cells it asks about
//! are settled (no live cell left) before any unknown reaches them;
//! otherwise the caller retries with a wider window.

#![expect(
    clippy::indexing_slicing,
    reason = "indices are axes `< N` of `[_; N]` arrays; cell indices come from the window's own geometry (`lin` of a `rel` inside it, or a stencil offset from an interior cell), dart and point indices from their own vectors"
)]

use super::hash::{dart_key, unit, word};
use super::lattice::{Axis, Lattice};
use super::region::FieldRegion;
use crate::error::Error;

/// No point, no dart: the empty slot of a grid.
const NONE: u32 = u32::MAX;

/// A dart's state in its round: within `r` of a point.
const REJECTED: u8 = 0;
/// Might be kept or not: an input of its decision is unknown.
const UNKNOWN: u8 = 2;
/// Kept: no point, and no kept dart of its round that outranks it, lies
/// within `r`.
const ACCEPTED: u8 = 3;
/// Not yet decided: a rival within `r` that outranks it is undecided.
const PENDING: u8 = 4;

/// Rounds thrown at level 0 before cells start to split.
pub(crate) const LEVEL0_ROUNDS: u32 = 2;
/// The deepest level: cells `2^-MAX_LEVEL` of a level-0 cell on a side.
pub(crate) const MAX_LEVEL: u32 = 30;
/// How many times a cell that no single disk covers is halved on every
/// axis to prove that several disks together cover it (`union_covers`).
const UNION_DEPTH: u32 = 2;
/// Up to this dimension the rival scans use half-cell stencils.
const HALF_STENCIL_DIMS: usize = 3;
/// The last round. The process is settled long before in practice (see the
/// module docs of `field`); the cap keeps a run finite on any input.
pub(crate) const MAX_ROUNDS: u32 = LEVEL0_ROUNDS + MAX_LEVEL + 8;

/// A live cell: its level-0 cell (window-relative), its sub-cell at the
/// round's level, and whether it is only possibly live.
#[derive(Clone, Copy, Debug)]
struct Live<const N: usize> {
    rel: [u32; N],
    sub: [u32; N],
    unknown: bool,
    /// The points that may lie within `r` of the cell: `near[a..a + n]`
    /// of the round's list, shared by the live cells of one level-0 cell.
    near_at: u32,
    near_len: u32,
}

/// One dart of a round.
#[derive(Clone, Copy, Debug)]
struct Dart<const N: usize> {
    x: [f64; N],
    /// Priority, then the key as tie-break: the larger wins.
    prio: (u64, u64),
    rel: [u32; N],
    cell: u32,
    next: u32,
    /// Whether an input of its decision is unknown (outside the window).
    doubt: bool,
    /// The half-cell of its level-0 cell it lies in (see `half_stencils`).
    half: u8,
}

/// Whether dart `a` comes before dart `b` in the round's order when their
/// priorities tie: by key, then by position (distinct darts differ).
fn outranks<const N: usize>(a: &Dart<N>, b: &Dart<N>) -> bool {
    if a.prio != b.prio {
        return a.prio > b.prio;
    }
    let bits = |d: &Dart<N>| d.x.map(f64::to_bits);
    bits(a) > bits(b)
}

/// Where a stencil offset from a cell lands.
enum Slot {
    /// A window cell, by linear index.
    Cell(usize),
    /// Outside the window, inside the domain: unknown.
    Outer,
    /// Outside the domain: nothing.
    Empty,
}

/// One axis of the window: level-0 cells `a .. a + len` (absolute,
/// unwrapped), whether the window wraps (a whole period), whether each side
/// is cut (unknown beyond) and which cells the query asks about.
struct WinAxis {
    a: i64,
    len: usize,
    wrap: bool,
    cut_lo: bool,
    cut_hi: bool,
    in_query: Vec<bool>,
}

/// What a window run returns.
pub(crate) struct Run<const N: usize> {
    /// The points of the query's cells, in no particular order, or `None`
    /// if unknowns reached them (retry wider).
    pub(crate) points: Option<Vec<[f64; N]>>,
    /// The rounds run.
    pub(crate) rounds: u32,
}

/// The query's cells `[qa, qb)` grown by `margin` cells on each side and
/// fitted to the lattice. `None` if the window would be empty.
fn window_axes<const N: usize>(
    lat: &Lattice<N>,
    qa: &[i64; N],
    qb: &[i64; N],
    margin: i64,
) -> Option<[WinAxis; N]> {
    let mut out: [Option<WinAxis>; N] = core::array::from_fn(|_| None);
    for axis in 0..N {
        let (mut a, mut b) = (qa[axis] - margin, qb[axis] + margin);
        let (mut wrap, mut cut_lo, mut cut_hi) = (false, true, true);
        match lat.axes[axis] {
            Axis::Bounded { n, .. } => {
                cut_lo = a > 0;
                cut_hi = b < n;
                a = a.max(0);
                b = b.min(n);
            }
            Axis::Periodic { n, .. } => {
                if b - a >= n {
                    (a, b) = (0, n);
                    (wrap, cut_lo, cut_hi) = (true, false, false);
                }
            }
            Axis::Unbounded => {}
        }
        if b <= a {
            return None;
        }
        let len = usize::try_from(b - a).ok()?;
        let in_query = (0..len)
            .map(|r| {
                #[expect(clippy::cast_possible_wrap, reason = "len < 2^42")]
                let i = a + r as i64;
                match lat.axes[axis] {
                    Axis::Periodic { n, .. } if wrap => {
                        // Any image of the cell in the query's range.
                        (qb[axis] - qa[axis] >= n)
                            || (qa[axis]..qb[axis]).any(|q| q.rem_euclid(n) == i)
                    }
                    _ => qa[axis] <= i && i < qb[axis],
                }
            })
            .collect();
        out[axis] = Some(WinAxis {
            a,
            len,
            wrap,
            cut_lo,
            cut_hi,
            in_query,
        });
    }
    let mut result = Vec::with_capacity(N);
    for o in out {
        result.push(o?);
    }
    result.try_into().ok()
}

/// The engine of one window.
struct Window<'l, const N: usize> {
    lat: &'l Lattice<N>,
    r2: f64,
    axes: [WinAxis; N],
    stride: [usize; N],
    /// Offsets to every level-0 cell that can hold a point within `r` of a
    /// point of the centre cell, nearest first, with their linear offsets.
    stencil: Vec<([i64; N], isize)>,
    /// For a point in half-cell `k` of the centre cell (bit `a` of `k` set:
    /// the upper half on axis `a`), the offsets of the stencil's cells that
    /// can hold a point within `r` of it: about 2/3 of the stencil in 2-D
    /// and 3/4 in 3-D.
    half_stencils: Vec<Vec<([i64; N], isize)>>,
    reach: [i64; N],
    point_of: Vec<u32>,
    taint: Vec<bool>,
    dart_head: Vec<u32>,
    points: Vec<[f64; N]>,
    point_cell: Vec<u32>,
    /// Whether some axis is periodic (distances then wrap).
    periodic: bool,
}

impl<const N: usize> Window<'_, N> {
    fn lin(&self, rel: &[u32; N]) -> usize {
        rel.iter()
            .zip(&self.stride)
            .map(|(&r, &s)| r as usize * s)
            .sum()
    }

    fn in_query(&self, rel: &[u32; N]) -> bool {
        rel.iter()
            .zip(&self.axes)
            .all(|(&r, ax)| ax.in_query.get(r as usize).copied().unwrap_or(false))
    }

    #[expect(clippy::needless_range_loop, reason = "three arrays by axis")]
    fn rel_of(&self, lin: usize) -> [u32; N] {
        let mut rel = [0; N];
        for axis in 0..N {
            #[expect(clippy::cast_possible_truncation, reason = "window sides fit u32")]
            let r = ((lin / self.stride[axis]) % self.axes[axis].len) as u32;
            rel[axis] = r;
        }
        rel
    }

    /// Whether every stencil offset from `rel` stays in the window.
    fn interior(&self, rel: &[u32; N]) -> bool {
        (0..N).all(|axis| {
            let r = i64::from(rel[axis]);
            #[expect(clippy::cast_possible_wrap, reason = "len < 2^42")]
            let len = self.axes[axis].len as i64;
            r >= self.reach[axis] && r + self.reach[axis] < len
        })
    }

    /// Where offset `d` from cell `rel` lands (the slow path, near edges).
    fn slot(&self, rel: &[u32; N], d: &[i64; N]) -> Slot {
        let mut lin = 0;
        let mut outer = false;
        for axis in 0..N {
            let ax = &self.axes[axis];
            #[expect(clippy::cast_possible_wrap, reason = "len < 2^42")]
            let len = ax.len as i64;
            let mut r = i64::from(rel[axis]) + d[axis];
            if r < 0 || r >= len {
                if ax.wrap {
                    r = r.rem_euclid(len);
                } else if (r < 0 && ax.cut_lo) || (r >= len && ax.cut_hi) {
                    outer = true;
                    continue;
                } else {
                    return Slot::Empty;
                }
            }
            let Ok(r) = usize::try_from(r) else {
                return Slot::Empty;
            };
            lin += r * self.stride[axis];
        }
        if outer { Slot::Outer } else { Slot::Cell(lin) }
    }

    /// Calls `f` on every stencil slot around `rel`, nearest first, until
    /// it returns `false`.
    #[inline(always)]
    fn each_slot(&self, rel: &[u32; N], f: impl FnMut(Slot) -> bool) {
        self.each_slot_of(&self.stencil, rel, f);
    }

    /// Calls `f` on every slot of `stencil` around `rel`, in its order,
    /// until it returns `false`.
    #[inline(always)]
    fn each_slot_of(
        &self,
        stencil: &[([i64; N], isize)],
        rel: &[u32; N],
        mut f: impl FnMut(Slot) -> bool,
    ) {
        if self.interior(rel) {
            let base = self.lin(rel);
            for &(_, off) in stencil {
                #[expect(clippy::cast_sign_loss, reason = "interior: in range")]
                let at = base.wrapping_add(off as usize);
                if !f(Slot::Cell(at)) {
                    return;
                }
            }
        } else {
            for (d, _) in stencil {
                if !f(self.slot(rel, d)) {
                    return;
                }
            }
        }
    }

    /// The absolute, canonical level-0 index of window cell `rel`.
    fn canonical(&self, rel: &[u32; N]) -> [i64; N] {
        core::array::from_fn(|axis| {
            self.lat
                .canonical(axis, self.axes[axis].a + i64::from(rel[axis]))
        })
    }

    /// The box of sub-cell `sub` at `level` of canonical cell `c`, clipped
    /// to the domain on bounded axes.
    fn sub_box(&self, c: &[i64; N], sub: &[u32; N], level: u32) -> ([f64; N], [f64; N]) {
        let scale = 1.0 / f64::from(1u32 << level);
        let mut lo = [0.0; N];
        let mut hi = [0.0; N];
        for axis in 0..N {
            let s = f64::from(sub[axis]);
            lo[axis] = self.lat.coord(axis, c[axis], s * scale);
            hi[axis] = self.lat.coord(axis, c[axis], (s + 1.0) * scale);
            if let Axis::Bounded { hi: top, .. } = self.lat.axes[axis] {
                hi[axis] = hi[axis].min(top);
            }
        }
        (lo, hi)
    }

    /// Distance squared, as [`Lattice::dist2`], with a fast path when no
    /// axis is periodic (the same operations, so the same bits).
    #[inline(always)]
    fn dist2(&self, a: &[f64; N], b: &[f64; N]) -> f64 {
        if self.periodic {
            return self.lat.dist2(a, b);
        }
        let mut s = 0.0;
        for axis in 0..N {
            let d = (a[axis] - b[axis]).abs();
            s += d * d;
        }
        s
    }

    /// Coordinate `axis` of `p`, moved by a period on a periodic axis to
    /// the image nearest `centre`.
    #[inline(always)]
    fn image(&self, p: &[f64; N], axis: usize, centre: f64) -> f64 {
        let mut q = p[axis];
        if let Axis::Periodic { lo: l, hi: h, .. } = self.lat.axes[axis] {
            let period = h - l;
            if q - centre > 0.5 * period {
                q -= period;
            } else if centre - q > 0.5 * period {
                q += period;
            }
        }
        q
    }

    /// Whether the disks around the points `near` together cover the box
    /// `[lo, hi]`, proved by splitting it in halves on every axis down to
    /// `depth` times until each piece lies in one disk. `false` means not
    /// proved: the box may still be covered. Dropping a covered cell never
    /// changes the points (no dart in it could ever be kept), only the work.
    fn union_covers(&self, lo: &[f64; N], hi: &[f64; N], near: &[u32], depth: u32) -> bool {
        let mut kept = [0u32; 32];
        let mut n = 0;
        let inner = self.r2 * (1.0 - 1e-12);
        let outer = self.r2 * (1.0 + 1e-9);
        for &p in near {
            let x = &self.points[p as usize];
            // Farthest and nearest points of the box from `x`, squared.
            let (mut far2, mut gap2) = (0.0, 0.0);
            for axis in 0..N {
                let q = if self.periodic {
                    self.image(x, axis, 0.5 * (lo[axis] + hi[axis]))
                } else {
                    x[axis]
                };
                let far = (q - lo[axis]).abs().max((hi[axis] - q).abs());
                let gap = (lo[axis] - q).max(q - hi[axis]).max(0.0);
                far2 += far * far;
                gap2 += gap * gap;
            }
            if far2 <= inner {
                return true;
            }
            if gap2 <= outer && n < kept.len() {
                kept[n] = p;
                n += 1;
            }
        }
        if depth == 0 || n < 2 {
            return false;
        }
        let kept = &kept[..n];
        let mid: [f64; N] = core::array::from_fn(|a| 0.5 * (lo[a] + hi[a]));
        (0..1u32 << N).all(|k| {
            let (mut a, mut b) = (*lo, *hi);
            for axis in 0..N {
                if (k >> axis) & 1 == 0 {
                    b[axis] = mid[axis];
                } else {
                    a[axis] = mid[axis];
                }
            }
            self.union_covers(&a, &b, kept, depth - 1)
        })
    }
}

/// The heap a vector holds, in bytes.
fn bytes_of<T>(v: &Vec<T>) -> u64 {
    (v.capacity() as u64).saturating_mul(size_of::<T>() as u64)
}

/// A sum of byte counts that saturates.
fn heap_bytes(parts: &[u64]) -> u64 {
    parts.iter().fold(0u64, |a, &b| a.saturating_add(b))
}

/// One window's task: the field's parameters, the query's cells
/// `[qa, qb)` and the margin of cells around them.
pub(crate) struct Job<'a, const N: usize, R> {
    pub(crate) lat: &'a Lattice<N>,
    pub(crate) radius: f64,
    pub(crate) seed: u64,
    pub(crate) region: &'a R,
    pub(crate) qa: &'a [i64; N],
    pub(crate) qb: &'a [i64; N],
    pub(crate) margin: i64,
    /// The budget a round's live cells must stay within.
    pub(crate) max_bytes: u64,
}

/// Runs the rounds on the window of the query cells `[qa, qb)` grown by
/// `margin` level-0 cells, and returns the points of the query's cells if
/// they are settled before anything unknown reaches them.
///
/// # Errors
/// [`Error::GridTooLarge`] if a round's live cells outgrow the budget: a
/// region that [`FieldRegion::meets`] boxes ever smaller around places it
/// never admits (one of zero volume). Without a region they never come
/// near it: a round holds at most a few live cells per level-0 cell.
pub(crate) fn run<const N: usize, R: FieldRegion<N>>(job: Job<'_, N, R>) -> Result<Run<N>, Error> {
    let Job {
        lat,
        radius,
        seed,
        region,
        qa,
        qb,
        margin,
        max_bytes,
    } = job;
    let Some(axes) = window_axes(lat, qa, qb, margin) else {
        return Ok(Run {
            points: Some(Vec::new()),
            rounds: 0,
        });
    };
    let mut stride = [0usize; N];
    let mut total = 1usize;
    for axis in 0..N {
        stride[axis] = total;
        total = total.saturating_mul(axes[axis].len);
    }
    let r2 = radius * radius;
    // The stencil: offsets whose cells' nearest points are within r.
    #[expect(clippy::cast_possible_truncation, reason = "r/h is about sqrt(N)")]
    let reach: [i64; N] = core::array::from_fn(|axis| (radius / lat.side[axis]).floor() as i64 + 1);
    let mut stencil = Vec::new();
    let mut d = reach.map(|k| -k);
    loop {
        let mut near = 0.0;
        let mut centre = 0.0;
        #[expect(clippy::needless_range_loop, reason = "offsets and sides by axis")]
        for axis in 0..N {
            #[expect(clippy::cast_precision_loss, reason = "small offsets")]
            let g = (d[axis].abs() - 1).max(0) as f64 * lat.side[axis];
            near += g * g;
            #[expect(clippy::cast_precision_loss, reason = "small offsets")]
            let c = d[axis] as f64 * lat.side[axis];
            centre += c * c;
        }
        if near < r2 * (1.0 + 1e-9) {
            let mut off = 0isize;
            for axis in 0..N {
                #[expect(clippy::cast_possible_truncation, reason = "small offsets")]
                let dd = d[axis] as isize;
                #[expect(clippy::cast_possible_wrap, reason = "window sizes fit isize")]
                let st = stride[axis] as isize;
                off += dd * st;
            }
            stencil.push((centre, d, off));
        }
        let mut axis = 0;
        loop {
            if axis == N {
                break;
            }
            d[axis] += 1;
            if d[axis] <= reach[axis] {
                break;
            }
            d[axis] = -reach[axis];
            axis += 1;
        }
        if axis == N {
            break;
        }
    }
    stencil.sort_by(|a, b| a.0.total_cmp(&b.0));
    let stencil: Vec<([i64; N], isize)> = stencil.into_iter().map(|(_, d, o)| (d, o)).collect();
    // The half-cell stencils: cells whose box comes within r of the half
    // cell (in cell units `[b/2, (b+1)/2]` per axis, widened far beyond
    // rounding), in the stencil's order.
    // Above 3-D the whole stencil serves every half (2^N lists would cost
    // more memory than the scans save).
    let half_stencils: Vec<Vec<([i64; N], isize)>> = if N > HALF_STENCIL_DIMS {
        vec![stencil.clone()]
    } else {
        (0..1usize << N)
            .map(|k| {
                stencil
                    .iter()
                    .filter(|(d, _)| {
                        let mut gap2 = 0.0;
                        for (axis, &off) in d.iter().enumerate() {
                            let b = f64::from(u8::from((k >> axis) & 1 == 1));
                            let (qlo, qhi) = (0.5 * b - 1e-6, 0.5 * (b + 1.0) + 1e-6);
                            #[expect(clippy::cast_precision_loss, reason = "small offsets")]
                            let (clo, chi) = (off as f64, off as f64 + 1.0);
                            let gap = (clo - qhi).max(qlo - chi).max(0.0) * lat.side[axis];
                            gap2 += gap * gap;
                        }
                        gap2 < r2 * (1.0 + 1e-9)
                    })
                    .copied()
                    .collect()
            })
            .collect()
    };
    let mut w = Window {
        lat,
        r2,
        axes,
        stride,
        stencil,
        half_stencils,
        reach,
        point_of: vec![NONE; total],
        taint: vec![false; total],
        dart_head: vec![NONE; total],
        points: Vec::new(),
        point_cell: Vec::new(),
        periodic: lat.axes.iter().any(|a| matches!(a, Axis::Periodic { .. })),
    };

    // Round 0: every level-0 cell of the window is live.
    let mut live: Vec<Live<N>> = Vec::with_capacity(total);
    // Whether anything lies beyond the window: if not (a whole box), no
    // unknown can arise, and the scans for them are skipped.
    let cut = w.axes.iter().any(|a| a.cut_lo || a.cut_hi);
    for lin in 0..total {
        let rel = w.rel_of(lin);
        let mut unknown = false;
        w.each_slot(&rel, |s| {
            if !cut {
                return false;
            }
            if matches!(s, Slot::Outer) {
                unknown = true;
                return false;
            }
            true
        });
        if unknown && w.in_query(&rel) {
            return Ok(Run {
                points: None,
                rounds: 0,
            });
        }
        // A cell the region does not meet is dead from the start.
        let (lo, hi) = w.sub_box(&w.canonical(&rel), &[0; N], 0);
        if !region.meets(&lo, &hi) {
            continue;
        }
        live.push(Live {
            rel,
            sub: [0; N],
            unknown,
            near_at: 0,
            near_len: 0,
        });
    }
    let mut darts: Vec<Dart<N>> = Vec::new();
    let mut rank: Vec<u64> = Vec::new();
    let mut link: Vec<u32> = Vec::new();
    let mut pos: Vec<[f64; N]> = Vec::new();
    let mut state: Vec<u8> = Vec::new();
    let mut outcome: Vec<u8> = Vec::new();
    // Each round's lists of points near live cells (see `Live::near_at`).
    let mut near_pool: Vec<u32> = Vec::new();
    let mut next_pool: Vec<u32> = Vec::new();
    let half0: f64 = lat.side.iter().map(|s| 0.25 * s * s).sum();
    let reach0 = {
        let reach = radius + half0.sqrt();
        reach * reach * (1.0 + 1e-9)
    };
    let mut level = 0u32;
    let mut round = 0u32;
    loop {
        // Throw one dart in every live cell.
        darts.clear();
        let scale = 1.0 / f64::from(1u32 << level);
        for cell in &live {
            let c = w.canonical(&cell.rel);
            let key = dart_key(seed, &c, &cell.sub, level, round);
            let mut x = [0.0; N];
            let mut half = 0u8;
            for axis in 0..N {
                let t = (f64::from(cell.sub[axis]) + unit(word(key, 1 + axis as u64))) * scale;
                x[axis] = lat.coord(axis, c[axis], t);
                if N <= HALF_STENCIL_DIMS && t >= 0.5 {
                    half |= 1 << axis;
                }
            }
            if !lat.inside(&x) || !region.admits(&x) {
                continue;
            }
            // The split before this round gathered every point that may
            // lie within `r` of the cell, and every unknown around it.
            let near = &near_pool[cell.near_at as usize..(cell.near_at + cell.near_len) as usize];
            if near
                .iter()
                .any(|&p| w.dist2(&x, &w.points[p as usize]) < r2)
            {
                continue;
            }
            let unknown = cell.unknown;
            let at = w.lin(&cell.rel);
            #[expect(clippy::cast_possible_truncation, reason = "darts < cells < 2^32")]
            let index = darts.len() as u32;
            #[expect(clippy::cast_possible_truncation, reason = "window cells < 2^32")]
            let cell_lin = at as u32;
            darts.push(Dart {
                x,
                prio: (word(key, 0), key),
                rel: cell.rel,
                cell: cell_lin,
                next: w.dart_head[at],
                doubt: unknown,
                half,
            });
            w.dart_head[at] = index;
        }
        // Greedy in priority order, as if the round's darts were thrown one
        // by one from the highest priority down: a dart is kept if no kept
        // dart that outranks it lies within r. That order is fixed by the
        // hash, so the result is the same for any schedule. Computed in
        // sweeps in the darts' (spatial) order: a dart is decided once every
        // rival within r that outranks it is decided; each decision is final
        // and seen at once by the rest of the sweep. The priorities,
        // positions and states sit in arrays of their own, so that the scan
        // past rivals touches few cache lines.
        rank.clear();
        rank.extend(darts.iter().map(|d| d.prio.0));
        link.clear();
        link.extend(darts.iter().map(|d| d.next));
        pos.clear();
        pos.extend(darts.iter().map(|d| d.x));
        state.clear();
        state.resize(darts.len(), PENDING);
        #[expect(clippy::cast_possible_truncation, reason = "darts < cells < 2^32")]
        let mut pending: Vec<(u32, u32)> = (0..darts.len() as u32).map(|i| (i, NONE)).collect();
        let mut still = Vec::new();
        while !pending.is_empty() {
            still.clear();
            for &(iu, blocker) in &pending {
                // Still waiting on the rival that held it last time.
                if blocker != NONE && state[blocker as usize] == PENDING {
                    still.push((iu, blocker));
                    continue;
                }
                let i = iu as usize;
                let (prio, x, rel) = (darts[i].prio, pos[i], darts[i].rel);
                let around = &w.half_stencils[usize::from(darts[i].half)];
                let mut lost = false;
                let mut wait = NONE;
                let mut doubt = darts[i].doubt;
                w.each_slot_of(around, &rel, |s| {
                    if let Slot::Cell(at) = s {
                        let mut j = w.dart_head[at];
                        while j != NONE {
                            let ju = j as usize;
                            let st = state[ju];
                            if st != REJECTED
                                && rank[ju] >= prio.0
                                && ju != i
                                && w.dist2(&pos[ju], &x) < r2
                                && (rank[ju] > prio.0 || outranks(&darts[ju], &darts[i]))
                            {
                                match st {
                                    ACCEPTED => {
                                        lost = true;
                                        return false;
                                    }
                                    PENDING => wait = j,
                                    _ => doubt = true,
                                }
                            }
                            j = link[ju];
                        }
                    }
                    true
                });
                state[i] = if lost {
                    REJECTED
                } else if wait != NONE {
                    still.push((iu, wait));
                    PENDING
                } else if doubt {
                    UNKNOWN
                } else {
                    ACCEPTED
                };
            }
            core::mem::swap(&mut pending, &mut still);
        }
        outcome.clear();
        outcome.extend_from_slice(&state);
        for (dart, &out) in darts.iter().zip(&outcome) {
            let at = dart.cell as usize;
            w.dart_head[at] = NONE;
            match out {
                ACCEPTED => {
                    #[expect(clippy::cast_possible_truncation, reason = "points < cells < 2^32")]
                    let index = w.points.len() as u32;
                    w.point_of[at] = index;
                    w.points.push(dart.x);
                    w.point_cell.push(dart.cell);
                }
                UNKNOWN => {
                    w.taint[at] = true;
                    if w.in_query(&dart.rel) {
                        return Ok(Run {
                            points: None,
                            rounds: round + 1,
                        });
                    }
                }
                _ => {}
            }
        }
        round += 1;
        // The next round's live cells: the same level, or split.
        let split = round >= LEVEL0_ROUNDS && level < MAX_LEVEL;
        let next_level = if split { level + 1 } else { level };
        let mut next = Vec::with_capacity(if split { live.len() } else { 0 });
        let mut query_live = false;
        next_pool.clear();
        // The level-0 cell whose neighbours were gathered last: its points
        // `next_pool[group..]` and whether an unknown lies around it.
        let mut group_rel: Option<[u32; N]> = None;
        let (mut group_at, mut group_unknown) = (0usize, false);
        for cell in &live {
            // A point in the level-0 cell covers all of it (its diagonal is
            // under r): none of its sub-cells is live.
            if w.point_of[w.lin(&cell.rel)] != NONE {
                continue;
            }
            if group_rel != Some(cell.rel) {
                // The points and unknowns around the level-0 cell, once for
                // all of its live sub-cells: every point within `r` of the
                // cell is within `r` plus half its diagonal of its centre.
                group_rel = Some(cell.rel);
                group_at = next_pool.len();
                group_unknown = false;
                let c0 = w.canonical(&cell.rel);
                let (clo, chi) = w.sub_box(&c0, &[0; N], 0);
                let centre: [f64; N] = core::array::from_fn(|a| 0.5 * (clo[a] + chi[a]));
                w.each_slot(&cell.rel, |slot| {
                    match slot {
                        Slot::Cell(at) => {
                            let p = w.point_of[at];
                            if p != NONE && w.dist2(&w.points[p as usize], &centre) <= reach0 {
                                next_pool.push(p);
                            }
                            group_unknown |= w.taint[at];
                        }
                        Slot::Outer => group_unknown = true,
                        Slot::Empty => {}
                    }
                    true
                });
            }
            let near = &next_pool[group_at..];
            let unknown = cell.unknown || group_unknown;
            let c = w.canonical(&cell.rel);
            // An unknown cell whose level-0 cell is already tainted adds
            // nothing: its darts could only taint that cell again, and every
            // dart within `r` of them already sees the taint.
            let lin = w.lin(&cell.rel);
            let in_query = w.in_query(&cell.rel);
            if unknown && w.taint[lin] && !in_query {
                continue;
            }

            let children: u32 = if split { 1 << N } else { 1 };
            for k in 0..children {
                let sub: [u32; N] = if split {
                    core::array::from_fn(|axis| 2 * cell.sub[axis] + ((k >> axis) & 1))
                } else {
                    cell.sub
                };
                let (lo, hi) = w.sub_box(&c, &sub, next_level);
                if (0..N).any(|axis| lo[axis] >= hi[axis]) || !region.meets(&lo, &hi) {
                    continue;
                }
                if w.union_covers(&lo, &hi, near, UNION_DEPTH) {
                    continue;
                }
                if in_query {
                    if unknown {
                        return Ok(Run {
                            points: None,
                            rounds: round,
                        });
                    }
                    query_live = true;
                }
                #[expect(clippy::cast_possible_truncation, reason = "the pool holds < 2^32")]
                next.push(Live {
                    rel: cell.rel,
                    sub,
                    unknown,
                    near_at: group_at as u32,
                    near_len: near.len() as u32,
                });
            }
        }
        // The rounds' heap against the budget, counted once a round: the
        // window's grids and points, this round's darts (with their sweep
        // lists) and both rounds' live cells and near lists. Without a
        // region, a round's live cells peak at 0.36 of the window's cells
        // in 2-D and 0.68 in 3-D; a region of zero volume would split them
        // without end, and this stops it.
        let needed = heap_bytes(&[
            bytes_of(&w.point_of),
            bytes_of(&w.taint),
            bytes_of(&w.dart_head),
            bytes_of(&w.points),
            bytes_of(&w.point_cell),
            bytes_of(&darts),
            (darts.capacity() as u64).saturating_mul(16),
            bytes_of(&rank),
            bytes_of(&link),
            bytes_of(&pos),
            bytes_of(&state),
            bytes_of(&outcome),
            bytes_of(&live),
            bytes_of(&next),
            bytes_of(&near_pool),
            bytes_of(&next_pool),
        ]);
        if needed > max_bytes {
            return Err(Error::GridTooLarge {
                needed,
                budget: max_bytes,
            });
        }
        core::mem::swap(&mut near_pool, &mut next_pool);
        live = next;
        level = next_level;
        if !query_live || round >= MAX_ROUNDS {
            break;
        }
    }
    let points = w
        .points
        .iter()
        .zip(&w.point_cell)
        .filter(|(_, c)| w.in_query(&w.rel_of(**c as usize)))
        .map(|(p, _)| *p)
        .collect();
    Ok(Run {
        points: Some(points),
        rounds: round,
    })
}
