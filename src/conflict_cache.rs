//! The points that turned away recent candidates around the current active
//! point: a tiny cache checked before the grid.
//!
//! Most of Bridson's attempts fail, and the attempts around one active point
//! keep failing on the same few neighbours. So each pick starts with the
//! active point's nearest neighbours from the grid (the points of its
//! stencil), adds every point a grid search returns, and
//! checks each new candidate against them first, all slots at once without
//! a branch; only a candidate they do not block goes to the grid. Of 36.7
//! attempts per point, the cache settles 35.5 in 2-D (whose seed reads the
//! cells within `2r`, `grid/dense.rs`; 1.13 grid searches a point, 1 of them
//! the accepted candidate's) and 29 in 3-D.
//!
//! It changes no decision: a remembered point is a real point, and
//! "blocked" is said only when the grid's exact test would find it closer
//! than `r` too (by a quick `f32` test with a margin that covers its
//! rounding, on a torus against each point's image nearest the active
//! point, which is never nearer than the toroidal distance; past
//! [`NEAR_ORIGIN`] radii from the origin by the exact formula); anything
//! else falls through to the full grid search. The output for a seed is the
//! same with or without the cache.

/// Far away: a slot holding it never blocks anything.
const FAR: f64 = f64::INFINITY;

/// What the quick test accepts as surely closer than `r`: a squared distance
/// below `1 - 2⁻¹²` in units of `r²`. Its rounding error is far smaller
/// (see [`ConflictCache::block`]); a pair in between is left to the exact grid
/// search.
const SURELY_INSIDE: f32 = 1.0 - 1.0 / 4096.0;

/// Up to this many radii from the origin (`2²⁸`), a candidate is its offset
/// from the active point to within `2⁻²⁵·r` per axis, well inside what
/// [`ConflictCache::block_relative`] allows.
pub(crate) const NEAR_ORIGIN: f64 = 268_435_456.0;

/// The last `B` points found closer than `r` to a candidate around the
/// current active point, stored axis-major so that one check runs over all
/// slots at once without a branch.
///
/// Each point is kept twice: exactly (`f64`, for toroidal distances) and
/// relative to the active point in units of `r` as `f32`, for the quick
/// test of bounded domains, which then runs four slots to a vector
/// instead of two.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConflictCache<const N: usize, const B: usize> {
    coords: [[f64; B]; N],
    near: [[f32; B]; N],
    origin: [f64; N],
    inv_radius: f64,
    next: usize,
}

impl<const N: usize, const B: usize> ConflictCache<N, B> {
    /// An empty cache for the candidates around `origin` (the active
    /// point), for radius `r`.
    pub(crate) fn new(origin: [f64; N], radius: f64) -> Self {
        Self {
            coords: [[FAR; B]; N],
            near: [[f32::INFINITY; B]; N],
            origin,
            inv_radius: 1.0 / radius,
            next: 0,
        }
    }

    /// `p - origin` in units of `r`, as `f32`; with `WRAP`, on each axis
    /// with a period (`periods`, `0.0` for none) the difference to `p`'s
    /// image nearest the origin.
    #[inline(always)]
    fn relative<const WRAP: bool>(&self, p: &[f64; N], periods: &[f64; N]) -> [f32; N] {
        let mut out = [0.0; N];
        for (((o, &x), &c), &l) in out.iter_mut().zip(p).zip(&self.origin).zip(periods) {
            let mut d = x - c;
            if WRAP && l > 0.0 {
                // A whole number of periods off: -1, 0 or 1 for points
                // in the box, so `k·l` is exact and `d - k·l` rounds
                // once.
                d -= (d / l).round() * l;
            }
            #[expect(
                clippy::cast_possible_truncation,
                reason = "f32 on purpose: the quick test has a margin"
            )]
            let v = (d * self.inv_radius) as f32;
            *o = v;
        }
        out
    }

    /// Remembers `q`, forgetting the oldest entry when full.
    #[inline(always)]
    pub(crate) fn push(&mut self, q: &[f64; N]) {
        self.push_image::<false>(q, &[0.0; N]);
    }

    /// [`Self::push`] on a domain with periods (`0.0` for an axis
    /// without): for the quick test ([`Self::block_relative`]), `q`'s
    /// image nearest the origin. Its distance to a candidate is at least
    /// their toroidal distance, so "surely closer than `r`" still means
    /// the grid's toroidal test finds them closer; the image's difference
    /// is off by under `2⁻²⁵·r` for coordinates and periods below
    /// [`NEAR_ORIGIN`] radii, as [`Self::block_relative`] asks.
    #[inline(always)]
    pub(crate) fn push_periodic(&mut self, q: &[f64; N], periods: &[f64; N]) {
        self.push_image::<true>(q, periods);
    }

    #[inline(always)]
    fn push_image<const WRAP: bool>(&mut self, q: &[f64; N], periods: &[f64; N]) {
        let slot = self.next;
        let near = self.relative::<WRAP>(q, periods);
        let columns = self.coords.iter_mut().zip(&mut self.near);
        for ((column, column_near), (&x, &y)) in columns.zip(q.iter().zip(&near)) {
            if let (Some(c), Some(n)) = (column.get_mut(slot), column_near.get_mut(slot)) {
                *c = x;
                *n = y;
            }
        }
        self.next = if slot + 1 >= B { 0 } else { slot + 1 };
    }

    /// Whether some remembered point is surely closer than `r` to `p`: then
    /// the exact test (`f64`, squares summed in axis order, as the grid
    /// decides) says so too. A point within about `r·2⁻¹³` of distance `r`
    /// may not count; the caller's grid search then decides exactly.
    ///
    /// Why the `f32` test cannot err the other way: the points checked here
    /// lie within a few `r` of `origin` (the cache holds the active point's
    /// neighbours and the conflicts of its candidates, thrown at most
    /// `2r·(1 + 10⁻⁷)` away). An `f64` difference `x - c` of two such
    /// coordinates is exact when they are within a factor of two of each
    /// other (Sterbenz) and otherwise both are below a few `r` in
    /// magnitude, so its error is at most a few `r·2⁻⁵³`. Scaling and the
    /// cast to `f32` add `2⁻²⁴` relative on values below about 4; the `f32`
    /// difference, square and sum add a few `2⁻²⁴` relative each. The
    /// squared distance near 1 (in units of `r²`) is thus off by well under
    /// `N·2⁻¹⁸`, far below the `2⁻¹²` margin for every `N` the crate runs
    /// (the sum's error grows with `N`: past 64 axes the exact test is used).
    #[inline(always)]
    pub(crate) fn block(&self, p: &[f64; N], radius_squared: f64) -> bool {
        if N > 64 {
            return self.block_periodic(p, radius_squared, &[0.0; N]);
        }
        self.block_relative(&self.relative::<false>(p, &[0.0; N]))
    }

    /// [`Self::block`] for a candidate given by its position relative to
    /// `origin` in units of `r`, as `f32` (up to 64 axes, as
    /// [`Self::block`]). The caller vouches that `rel` is
    /// within `2⁻²⁰` per axis of the candidate's `(p - origin) / r`: then
    /// the argument of [`Self::block`] holds with room to spare. (An offset
    /// `o` from the active point `c`, scaled: the candidate `fl(c + o)` is
    /// off from `c + o` by half an ulp of its coordinates, so coordinates
    /// below `2²⁸·r` keep that under `2⁻²⁵·r`.)
    #[inline(always)]
    pub(crate) fn block_relative(&self, rel: &[f32; N]) -> bool {
        self.block_relative_scaled(rel, 1.0)
    }

    /// [`Self::block_relative`] against `s·r` instead of `r`, where
    /// `s² = scale_squared` lies in `1 ..= 16` (the varying radius: `r` is
    /// a unit there, `s·r` the candidate's radius). Whether some
    /// remembered point is surely closer than `s·r`. The caller vouches
    /// for `rel` as for [`Self::block_relative`] and for a candidate within
    /// about `4r` of `origin`. The argument of [`Self::block`] then holds,
    /// scaled: a point that decides lies within `s·r <= 4r` of the
    /// candidate, so its coordinates and the candidate's stay below 9
    /// (units of `r`), each off by under `2⁻²⁰` (cast, and the caller's);
    /// the squared distance near `s² >= 1` is then off by under
    /// `(√N·2⁻¹⁸ + N·2⁻²³)·s²`, below the `2⁻¹²` margin up to 64 axes (the
    /// bound `SURELY_INSIDE·s²` rounds once, by `2⁻²⁴`).
    #[inline(always)]
    pub(crate) fn block_relative_scaled(&self, rel: &[f32; N], scale_squared: f32) -> bool {
        let bound = SURELY_INSIDE * scale_squared;
        let mut d2 = [0.0f32; B];
        for (&x, column) in rel.iter().zip(&self.near) {
            for (acc, &y) in d2.iter_mut().zip(column) {
                let d = x - y;
                *acc += d * d;
            }
        }
        d2.iter().fold(false, |hit, &d| hit | (d < bound))
    }

    /// Whether some remembered point is closer than `r` to `p`, exactly as
    /// the grid decides: differences in `f64`, toroidal on axes with a
    /// period (plain where the period is `0.0`), squares summed in axis
    /// order.
    #[inline(always)]
    pub(crate) fn block_periodic(
        &self,
        p: &[f64; N],
        radius_squared: f64,
        periods: &[f64; N],
    ) -> bool {
        let mut d2 = [0.0; B];
        for ((&x, column), &l) in p.iter().zip(&self.coords).zip(periods) {
            for (acc, &y) in d2.iter_mut().zip(column) {
                let mut d = (x - y).abs();
                if l > 0.0 {
                    d = d.min(l - d);
                }
                *acc += d * d;
            }
        }
        d2.iter().fold(false, |hit, &d| hit | (d < radius_squared))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{seeded_rng, symmetric_pair, unit};
    use crate::vector::{distance_squared, periodic_distance_squared};

    /// A random unit vector (normalised from the cube: not uniform on the
    /// sphere, which these tests do not need).
    fn direction<const N: usize>(rng: &mut crate::random::DefaultRng) -> [f64; N] {
        let d: [f64; N] = core::array::from_fn(|_| unit(rng) - 0.5);
        let norm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        d.map(|x| x / norm)
    }

    /// The quick test's promises for one probe whose nearest remembered
    /// point is `nearest²` away: "blocked" only if that is closer than
    /// `r`; and, where every point it should see is in reach (`complete`),
    /// "blocked" whenever one is well inside (its band is 2⁻¹²).
    fn assert_quick(quick: bool, nearest: f64, r2: f64, complete: bool, what: &str) {
        assert!(!quick || nearest < r2, "{what}: blocked from afar");
        assert!(
            !complete || quick || nearest >= r2 * (1.0 - 1.0 / 1024.0),
            "{what}: missed a point well inside"
        );
    }

    #[test]
    fn agrees_with_the_distance_formula() {
        // Remembered points and probes in [-1, 1)², r = 0.3, around the
        // origin: "blocked" only when one of the last B points is closer
        // than r, and always when one is clearly closer (the quick test's
        // band is 2⁻¹²); toroidal distances exactly.
        let (r, periods) = (0.3, [2.0, 0.0]);
        let r2 = r * r;
        let mut rng = seeded_rng(12);
        let mut cache = ConflictCache::<2, 4>::new([0.0, 0.0], r);
        let mut remembered: Vec<[f64; 2]> = Vec::new();
        let (mut blocked, mut clear) = (0, 0);
        for round in 0..2000 {
            let p: [f64; 2] = symmetric_pair(&mut rng).into();
            let recent = &remembered[remembered.len().saturating_sub(4)..];
            let nearest = recent
                .iter()
                .map(|q| distance_squared(&p, q))
                .fold(f64::INFINITY, f64::min);
            let near_periodic = recent
                .iter()
                .any(|q| periodic_distance_squared(&p, q, &periods) < r2);
            let quick = cache.block(&p, r2);
            assert_quick(quick, nearest, r2, true, &format!("round {round}"));
            blocked += usize::from(quick);
            clear += usize::from(nearest >= r2);
            assert_eq!(
                cache.block_periodic(&p, r2, &periods),
                near_periodic,
                "round {round}, periodic"
            );
            if round % 3 == 0 {
                cache.push(&p);
                remembered.push(p);
            }
        }
        assert!(
            blocked > 200 && clear > 200,
            "{blocked} blocked, {clear} clear"
        );
    }

    /// On a torus, points remembered by their image nearest the active
    /// point: the quick test on a candidate's offset blocks only what the
    /// toroidal distance says is closer than `r`, and catches every point
    /// well inside `r` when the period is wide enough that the image
    /// nearest the active point is the one nearest the candidate. Active
    /// points and remembered points anywhere in the box, near its faces
    /// too, so that the images cross them.
    #[test]
    fn periodic_images_block_as_the_toroidal_distance() {
        let r = 0.1;
        let r2 = r * r;
        let mut rng = seeded_rng(13);
        let (mut blocked, mut clear) = (0, 0);
        for period in [1.0, 0.45] {
            let periods = [period, 0.0];
            let wide = period >= 10.0 * r;
            for round in 0..4000 {
                let origin = [unit(&mut rng) * period, unit(&mut rng)];
                let mut cache = ConflictCache::<2, 8>::new(origin, r);
                let mut remembered = Vec::new();
                for _ in 0..6 {
                    // Within 3r of the origin, wrapped into the box.
                    let dir = direction::<2>(&mut rng);
                    let d = 3.0 * r * unit(&mut rng);
                    let mut q = [origin[0] + dir[0] * d, origin[1] + dir[1] * d];
                    q[0] = q[0].rem_euclid(period);
                    cache.push_periodic(&q, &periods);
                    remembered.push(q);
                }
                // A candidate r to 2r from the origin, as its offset.
                let dir = direction::<2>(&mut rng);
                let d = r * (1.0 + unit(&mut rng));
                let offset = [dir[0] * d, dir[1] * d];
                let mut c = [origin[0] + offset[0], origin[1] + offset[1]];
                c[0] = c[0].rem_euclid(period);
                #[expect(clippy::cast_possible_truncation, reason = "f32 on purpose")]
                let rel = offset.map(|x| (x / r) as f32);
                let quick = cache.block_relative(&rel);
                let nearest = remembered
                    .iter()
                    .map(|q| periodic_distance_squared(&c, q, &periods))
                    .fold(f64::INFINITY, f64::min);
                assert_quick(quick, nearest, r2, wide, &format!("{period} round {round}"));
                blocked += usize::from(quick);
                clear += usize::from(nearest >= r2);
            }
        }
        assert!(
            blocked > 1000 && clear > 1000,
            "{blocked} blocked, {clear} clear"
        );
    }

    /// Probes a hair outside `r` (and well inside) of a remembered point,
    /// at coordinates far larger than `r` and at the radius limits: the
    /// quick test never blocks a pair the exact formula keeps.
    #[test]
    fn never_blocks_at_or_past_r() {
        fn check<const N: usize>(origin: [f64; N], r: f64, seed: u64) {
            let mut rng = seeded_rng(seed);
            for _ in 0..500 {
                // A remembered point within 2r of the origin, a probe at
                // distance r·(1 + t) from it, t in ±2⁻²⁰.
                let dir = direction::<N>(&mut rng);
                let q: [f64; N] = core::array::from_fn(|i| origin[i] + dir[i] * r);
                let mut cache = ConflictCache::<N, 8>::new(origin, r);
                cache.push(&q);
                let dir2 = direction::<N>(&mut rng);
                let t = (unit(&mut rng) - 0.5) * 2f64.powi(-19);
                let p: [f64; N] = core::array::from_fn(|i| q[i] + dir2[i] * r * (1.0 + t));
                let exact = distance_squared(&p, &q) < r * r;
                assert!(
                    !cache.block(&p, r * r) || exact,
                    "blocked at distance² {} > r² {}",
                    distance_squared(&p, &q),
                    r * r
                );
                let inside: [f64; N] = core::array::from_fn(|i| q[i] + dir2[i] * r * 0.999);
                assert!(cache.block(&inside, r * r), "0.999 r not blocked");
            }
        }
        check([0.3, 0.7], 0.01, 1);
        check([1e9, -3e9, 7e8], 1e-3, 2);
        check([1e-140; 3], 1e-150, 3);
        check([5e150, -1e150], 1e150, 4);
        check([0.5; 8], 0.2, 5);
        check([123.25], 0.5, 6);
    }

    /// [`ConflictCache::block_relative`] with the candidate given as its offset
    /// from the active point in units of r (what the sampler passes when
    /// coordinates are below 2²⁸·r): never blocks a pair the exact formula
    /// keeps, at coordinates up to the limit. The same for
    /// [`ConflictCache::block_relative_scaled`] as the varying radius calls
    /// it (offsets up to `4r`, a scale `s` in `1 ..= 4`) against `s·r`,
    /// and it blocks a point well inside `s·r`.
    #[test]
    fn offsets_as_positions_never_block_at_or_past_r() {
        fn check<const N: usize>(scale: f64, r: f64, seed: u64, scaled: bool) {
            let mut rng = seeded_rng(seed);
            for _ in 0..500 {
                let origin: [f64; N] =
                    core::array::from_fn(|_| (2.0 * unit(&mut rng) - 1.0) * scale * r);
                let mut cache = ConflictCache::<N, 8>::new(origin, r);
                let (s, far) = if scaled {
                    (1.0 + 3.0 * unit(&mut rng), 4.0 * unit(&mut rng))
                } else {
                    (1.0, 1.0 + unit(&mut rng))
                };
                let offset = direction::<N>(&mut rng).map(|x| x * r * far);
                let candidate: [f64; N] = core::array::from_fn(|i| origin[i] + offset[i]);
                #[expect(clippy::cast_possible_truncation, reason = "as the sampler does")]
                let (rel, s2) = (offset.map(|o| (o * (1.0 / r)) as f32), (s * s) as f32);
                let t = (unit(&mut rng) - 0.5) * 2f64.powi(-18);
                let toward = direction::<N>(&mut rng);
                let q: [f64; N] =
                    core::array::from_fn(|i| candidate[i] + toward[i] * s * r * (1.0 + t));
                cache.push(&q);
                let exact = distance_squared(&candidate, &q) < s * r * s * r;
                let blocked = if scaled {
                    cache.block_relative_scaled(&rel, s2)
                } else {
                    cache.block_relative(&rel)
                };
                assert!(!blocked || exact, "blocked past s·r, s = {s}");
                if scaled {
                    let inside: [f64; N] =
                        core::array::from_fn(|i| candidate[i] + toward[i] * s * r * 0.999);
                    cache.push(&inside);
                    let blocked = cache.block_relative_scaled(&rel, s2);
                    assert!(blocked, "0.999·s·r not blocked, s = {s}");
                }
            }
        }
        // Coordinates up to the sampler's limit, NEAR_ORIGIN radii.
        let limit = NEAR_ORIGIN;
        for scaled in [false, true] {
            check::<2>(limit, 1e-3, 7, scaled);
            check::<3>(limit, 0.25, 8, scaled);
            check::<2>(10.0, 1e-150, 9, scaled);
            check::<3>(1.0, 1e150, 10, scaled);
        }
    }

    #[test]
    fn a_full_cache_forgets_the_oldest() {
        let mut cache = ConflictCache::<2, 2>::new([5.0, 5.0], 0.2);
        for q in [[4.5, 4.5], [5.0, 5.0], [5.5, 5.5]] {
            cache.push(&q);
        }
        assert!(!cache.block(&[4.4, 4.5], 0.04), "oldest forgotten");
        assert!(cache.block(&[5.1, 5.0], 0.04), "second kept");
        assert!(cache.block(&[5.6, 5.5], 0.04), "newest kept");
    }

    #[test]
    fn empty_cache_blocks_nothing() {
        let cache = ConflictCache::<3, 8>::new([0.0; 3], 1e150);
        assert!(!cache.block(&[0.0; 3], f64::MAX), "plain");
        assert!(
            !cache.block_periodic(&[0.0; 3], f64::MAX, &[1.0; 3]),
            "periodic"
        );
    }
}
