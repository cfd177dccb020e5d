//! Where candidates are thrown around an active point: the candidate
//! distributions, the sampler that draws them, and offsets drawn eight
//! ahead ([`OffsetBatch`]; 32 in `f32` for the batch sampler's 2-D and
//! 3-D, in [`wide`]). The tables behind them are in [`tables`]; the
//! annulus in odd dimensions from 5-D up, drawn ahead, in [`shell`].

mod shell;
mod tables;
mod wide;

use wide::WIDE;

use tables::{
    TWO_POW_M32, angle_direction, angle_directions, cos_sin, cube_entry, cube_root_near, cube_step,
};

use crate::random::{symmetric, symmetric_pair, unit};
use crate::vector::{norm_squared, scale};
use rand::Rng;

/// How candidate points are drawn around an active point.
///
/// Both give a valid Poisson disk set; they differ in how densely it is
/// packed and in how much each attempt costs. With the `serde` feature the
/// values are `"annulus"` and `"sphere"`, as on the `points` command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
#[non_exhaustive]
pub enum Candidates {
    /// Bridson's original: uniform **in volume** over the annulus (shell)
    /// `r <= |d| < 2r` around the active point. In 2-D and 3-D drawn directly
    /// (radius `r·√(1 + 3u)` or `r·∛(1 + 7u)`, uniform direction); from
    /// 4-D up uniform in the ball of radius `2r` (Archimedes' projection of
    /// a sphere two dimensions up), kept if `|d| >= r`; in 1-D by rejection
    /// from `[-2r, 2r)`. Gives the classic pattern: in 2-D with `k = 30`, a
    /// relative radius ρ ≈ 0.73 (see [`relative_radius`](crate::relative_radius)).
    #[default]
    Annulus,
    /// On the sphere of radius `r·(1 + 1e-7)` around the active point
    /// (Roberts 2019): in 2-D the `k` attempts are evenly spaced in angle
    /// from a random start, in other dimensions the directions are uniform
    /// on the sphere. Packs denser (2-D ρ ≈ 0.87 with `k = 30`) and wastes
    /// fewer attempts, at some cost in the isotropy of the spectrum.
    Sphere,
}

/// Relative gap between `r` and the on-sphere candidate distance; large
/// enough that rounding never puts the candidate closer than `r` to its
/// parent for coordinates within ~10⁸·r of each other.
const SPHERE_SLACK: f64 = 1e-7;

/// Draws candidate offsets for one sampler; holds what can be precomputed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CandidateSampler<const N: usize> {
    kind: Candidates,
    radius: f64,
    radius_squared: f64,
    /// Rotation by `2π/k`, for the evenly spaced 2-D sphere variant.
    step: (f64, f64),
}

impl<const N: usize> CandidateSampler<N> {
    pub(crate) fn new(kind: Candidates, radius: f64, attempts: u32) -> Self {
        let step = cos_sin(core::f64::consts::TAU / f64::from(attempts));
        Self {
            kind,
            radius,
            radius_squared: radius * radius,
            step,
        }
    }

    /// Starts the attempts around one active point; returns the state that
    /// [`Self::offset`] advances (only used by the 2-D sphere variant).
    #[inline(always)]
    pub(crate) fn start<R: Rng + ?Sized>(&self, rng: &mut R) -> [f64; N] {
        if N == 2 && self.kind == Candidates::Sphere {
            unit_direction(rng)
        } else {
            [0.0; N]
        }
    }

    /// The offset of the next candidate from its active point.
    #[inline(always)]
    pub(crate) fn offset<R: Rng + ?Sized>(&self, rng: &mut R, state: &mut [f64; N]) -> [f64; N] {
        match self.kind {
            Candidates::Annulus if N == 2 || N == 3 => self.direct_annulus(rng),
            Candidates::Annulus if N == 1 => loop {
                // Uniform in [-2r, 2r), kept if r <= |d| < 2r.
                let d: [f64; N] = cube_point(rng, 2.0 * self.radius);
                let n2 = norm_squared(&d);
                if n2 >= self.radius_squared && n2 < 4.0 * self.radius_squared {
                    return d;
                }
            },
            Candidates::Annulus => {
                // Uniform in the ball of radius 2r, kept if |d| >= r:
                // uniform in volume over the shell. Acceptance 1 - 2^-N
                // (even N) or about half that (odd N); a cube would keep
                // 30 % in 4-D and 1.6 % in 8-D.
                let (v, _) = ball_point::<N, R>(rng, 0.25);
                scale(&v, 2.0 * self.radius)
            }
            Candidates::Sphere => {
                let distance = self.radius * (1.0 + SPHERE_SLACK);
                let here = *state;
                // Matches exactly when N == 2: the next of k evenly spaced
                // directions.
                if let [x, y] = state.as_mut_slice() {
                    let (c, s) = self.step;
                    let (hx, hy) = (*x, *y);
                    (*x, *y) = (c * hx - s * hy, s * hx + c * hy);
                    scale(&here, distance)
                } else {
                    scale(&unit_direction::<N, R>(rng), distance)
                }
            }
        }
    }

    /// Whether offsets come from [`OffsetBatch`]: annulus offsets in 2-D
    /// and 3-D, which need no per-pick state and no rejection loop, and in
    /// odd dimensions from 5-D up, whose ball draws reject about half their
    /// tries: drawn ahead, the rejections take no branch ([`shell`]). Even
    /// dimensions from 4-D up reject `2^-N` of their tries, and draw one by
    /// one faster than ahead (odd ones the other way round; the journal's
    /// "odd dimensions' offsets drawn ahead"). Up to 63-D, where the cache's
    /// quick check on the offsets drawn ahead holds
    /// (`ConflictCache::block_relative`).
    pub(crate) fn reads_ahead(&self) -> bool {
        self.kind == Candidates::Annulus && (N == 2 || N == 3 || (N >= 5 && N <= 63 && N % 2 == 1))
    }

    /// An annulus offset drawn directly, without rejection: 2-D and 3-D.
    #[inline(always)]
    fn direct_annulus<R: Rng + ?Sized>(&self, rng: &mut R) -> [f64; N] {
        if N == 2 {
            // One draw, no branch: 32 bits of radius, 32 of angle.
            // √(1 + 3u)·r is uniform in area over r..2r.
            let x = rng.next_u64();
            #[expect(
                clippy::cast_possible_truncation,
                reason = "splitting the word into its two 32-bit halves"
            )]
            let (high, low) = ((x >> 32) as u32, x as u32);
            let (dx, dy) = angle_direction(low);
            let mut d = [0.0; N];
            place_2d(&mut d, self.area_radius(high), dx, dy);
            d
        } else {
            // Two draws, no branch: radius r·∛(1 + 7u) (uniform in
            // volume over r..2r), height z uniform in [-1, 1) and a
            // uniform angle (Archimedes: uniform on the sphere).
            let x = rng.next_u64();
            let w = rng.next_u64();
            #[expect(
                clippy::cast_possible_truncation,
                reason = "splitting words into their 32-bit halves"
            )]
            let (high, z, angle) = ((x >> 32) as u32, x as u32, (w >> 32) as u32);
            let (c, s) = angle_direction(angle);
            let mut d = [0.0; N];
            place_3d(&mut d, self.volume_radius(high), height(z), c, s);
            d
        }
    }

    /// `r·√(1 + 3u)` for `u = bits / 2³²`: uniform in area over `r..2r`.
    #[inline(always)]
    fn area_radius(&self, bits: u32) -> f64 {
        self.radius * (1.0 + 3.0 * (f64::from(bits) * TWO_POW_M32)).sqrt()
    }

    /// `r·∛(1 + 7u)` for `u = bits / 2³²`: uniform in volume over `r..2r`.
    #[inline(always)]
    fn volume_radius(&self, bits: u32) -> f64 {
        self.volume_radius_from(cube_entry(bits), cube_step(bits))
    }

    /// [`Self::volume_radius`] for [`AHEAD`] draws, step by step over all of
    /// them (the look-ups, then the arithmetic), bit for bit the same.
    #[inline(always)]
    fn volume_radii(&self, bits: &[u32; AHEAD]) -> [f64; AHEAD] {
        let entries = lanes(bits, cube_entry);
        let steps = lanes(bits, cube_step);
        let mut rho = [0.0; AHEAD];
        for ((rho, &entry), &d) in rho.iter_mut().zip(&entries).zip(&steps) {
            *rho = self.volume_radius_from(entry, d);
        }
        rho
    }

    /// The arithmetic of [`Self::volume_radius`], from the draw's
    /// [`CUBE_ROOTS`](tables::CUBE_ROOTS) entry and its [`cube_step`].
    #[inline(always)]
    fn volume_radius_from(&self, (root, scale): (f64, f64), step: f64) -> f64 {
        self.radius * cube_root_near(root, step * scale)
    }

    /// [`AHEAD`] offsets of [`Self::direct_annulus`], bit for bit: the
    /// generator words are drawn first, in the same order, then each step
    /// runs over all offsets at once, which the compiler turns into vector
    /// instructions (the arithmetic per offset is the same, so are the
    /// results).
    #[inline(always)]
    fn fill_direct_annulus<R: Rng + ?Sized>(&self, rng: &mut R, out: &mut [[f64; N]; AHEAD]) {
        #[expect(
            clippy::cast_possible_truncation,
            reason = "splitting words into their 32-bit halves"
        )]
        if N == 2 {
            let mut words = [0u64; AHEAD];
            for w in &mut words {
                *w = rng.next_u64();
            }
            let rho = lanes(&words, |x| self.area_radius((x >> 32) as u32));
            let (c, s) = angle_directions(&lanes(&words, |x| x as u32));
            for (((d, &rho), &c), &s) in out.iter_mut().zip(&rho).zip(&c).zip(&s) {
                place_2d(d, rho, c, s);
            }
        } else {
            let mut x = [0u64; AHEAD];
            let mut w = [0u64; AHEAD];
            for (x, w) in x.iter_mut().zip(&mut w) {
                *x = rng.next_u64();
                *w = rng.next_u64();
            }
            let rho = self.volume_radii(&lanes(&x, |x| (x >> 32) as u32));
            let z = lanes(&x, |x| height(x as u32));
            let (c, s) = angle_directions(&lanes(&w, |w| (w >> 32) as u32));
            let lanes = rho.iter().zip(&z).zip(c.iter().zip(&s));
            for (d, ((&rho, &z), (&c, &s))) in out.iter_mut().zip(lanes) {
                place_3d(d, rho, z, c, s);
            }
        }
    }
}

/// `f` applied to each lane, as a plain loop: `array::map` was left out of
/// line at 16 lanes (12 % of a 2-D run's samples in `try_map`).
#[inline(always)]
pub(super) fn lanes<T: Copy, U: Copy + Default, const L: usize>(
    x: &[T; L],
    f: impl Fn(T) -> U,
) -> [U; L] {
    let mut out = [U::default(); L];
    for (o, &x) in out.iter_mut().zip(x) {
        *o = f(x);
    }
    out
}

/// A height uniform in `[-1, 1)` from 32 bits read as a signed integer.
#[inline(always)]
fn height(bits: u32) -> f64 {
    #[expect(clippy::cast_possible_wrap, reason = "the bits as a signed integer")]
    let signed = bits as i32;
    f64::from(signed) * (2.0 * TWO_POW_M32)
}

/// The 2-D offset at distance `rho` in direction `(c, s)`.
#[inline(always)]
fn place_2d<const N: usize>(d: &mut [f64; N], rho: f64, c: f64, s: f64) {
    if let [x, y] = d.as_mut_slice() {
        (*x, *y) = (rho * c, rho * s);
    }
}

/// The 3-D offset at distance `rho`, height `z·rho` and azimuth `(c, s)`
/// (Archimedes: `z` uniform gives a direction uniform on the sphere).
#[inline(always)]
fn place_3d<const N: usize>(d: &mut [f64; N], rho: f64, z: f64, c: f64, s: f64) {
    let ring = rho * (1.0 - z * z).sqrt();
    if let [x, y, h] = d.as_mut_slice() {
        (*x, *y, *h) = (ring * c, ring * s, rho * z);
    }
}

/// Offsets drawn [`AHEAD`] (or [`WIDE`]) at a time. Each offset is a chain
/// of some 20 dependent operations (generator, polynomial, square root,
/// products); drawn one by one after the previous attempt's checks and
/// branches, that chain is the critical path, while the batch's
/// independent chains overlap. An annulus offset does not depend on its
/// active point, so offsets left over at the end of a pick serve the next
/// one: the offsets used are the generator's draws in order, and only the
/// interleaving with the pick draws differs from drawing them one by one.
///
/// A wide batch (the batch sampler's, 2-D and 3-D) draws its offsets in
/// `f32` in units of `r` (`wide.rs`), and an offset is that widened and
/// scaled by `r` when a candidate needs it; every other batch draws in
/// `f64` and keeps an `f32` copy in units of `r` for the quick check.
#[derive(Clone, Copy, Debug)]
pub(crate) struct OffsetBatch<const N: usize, const WIDE_IF_DIRECT: bool = false> {
    /// The offsets drawn in `f64` (not by a wide batch).
    offsets: [[f64; N]; AHEAD],
    /// The offsets in units of `r`, as `f32`: the quick cache check's
    /// candidate position relative to the active point (see
    /// `ConflictCache::block_relative`).
    units: [[f32; N]; WIDE],
    used: usize,
    /// In odd dimensions from 5-D up, the tries kept and not yet used.
    queue: shell::Queue<N>,
}

/// Offsets a batch draws at once by default: eight lanes to each vector
/// step.
const AHEAD: usize = 8;

impl<const N: usize, const WIDE_IF_DIRECT: bool> OffsetBatch<N, WIDE_IF_DIRECT> {
    /// Offsets a refill draws: [`WIDE`] where `WIDE_IF_DIRECT` (the batch
    /// sampler's) and the annulus is drawn directly (2-D and 3-D),
    /// [`AHEAD`] otherwise (the streaming sweep, the varying radius, every
    /// other dimension).
    const LEN: usize = if WIDE_IF_DIRECT && (N == 2 || N == 3) {
        WIDE
    } else {
        AHEAD
    };

    pub(crate) const fn new() -> Self {
        Self {
            offsets: [[0.0; N]; AHEAD],
            units: [[0.0; N]; WIDE],
            used: Self::LEN,
            queue: shell::Queue::new(),
        }
    }

    /// The next offset, and the same in units of `r` as `f32`, drawing a
    /// batch more when all are used.
    #[inline(always)]
    pub(crate) fn next<R: Rng + ?Sized>(
        &mut self,
        sampler: &CandidateSampler<N>,
        rng: &mut R,
    ) -> ([f64; N], [f32; N]) {
        let (j, unit) = self.next_unit(sampler, rng);
        (self.offset(j, sampler), unit)
    }

    /// The next offset's place in the batch and the offset in units of `r`
    /// as `f32`, drawing a batch more when all are used: what the quick
    /// check needs. The offset itself is [`Self::offset`] of that place,
    /// asked only for the candidates the check lets through.
    #[inline(always)]
    pub(crate) fn next_unit<R: Rng + ?Sized>(
        &mut self,
        sampler: &CandidateSampler<N>,
        rng: &mut R,
    ) -> (usize, [f32; N]) {
        if self.used >= Self::LEN {
            self.refill(sampler, rng);
        }
        let j = self.used;
        self.used += 1;
        (j, self.units.get(j).copied().unwrap_or([f32::NAN; N]))
    }

    /// Offset `j` of the batch: a wide batch's `f32` draw widened and
    /// scaled by `r` (so `j`'s unit is exactly this offset over `r`, to
    /// the product's rounding), else the `f64` draw.
    #[inline(always)]
    pub(crate) fn offset(&self, j: usize, sampler: &CandidateSampler<N>) -> [f64; N] {
        if Self::LEN == WIDE {
            let unit = self.units.get(j).copied().unwrap_or([f32::NAN; N]);
            let mut offset = [0.0; N];
            for (o, &u) in offset.iter_mut().zip(&unit) {
                *o = f64::from(u) * sampler.radius;
            }
            offset
        } else {
            self.offsets.get(j).copied().unwrap_or([0.0; N])
        }
    }

    /// Draws the next batch.
    #[inline(always)]
    fn refill<R: Rng + ?Sized>(&mut self, sampler: &CandidateSampler<N>, rng: &mut R) {
        if Self::LEN == WIDE {
            // 2-D or 3-D, by `LEN`.
            wide::fill(rng, &mut self.units);
        } else {
            if N <= 3 {
                sampler.fill_direct_annulus(rng, &mut self.offsets);
            } else {
                self.queue.fill(rng, sampler.radius, &mut self.offsets);
            }
            let inv_radius = 1.0 / sampler.radius;
            for (unit, offset) in self.units.iter_mut().zip(&self.offsets) {
                for (u, &o) in unit.iter_mut().zip(offset) {
                    #[expect(
                        clippy::cast_possible_truncation,
                        reason = "f32 on purpose: the quick check has a margin"
                    )]
                    let v = (o * inv_radius) as f32;
                    *u = v;
                }
            }
        }
        self.used = 0;
    }
}

/// A uniform point in the cube `[-half, half)^N`, two coordinates per
/// generator call.
#[inline(always)]
fn cube_point<const N: usize, R: Rng + ?Sized>(rng: &mut R, half: f64) -> [f64; N] {
    let mut d = [0.0; N];
    let (pairs, rest) = d.as_chunks_mut::<2>();
    for [x, y] in pairs {
        let (a, b) = symmetric_pair(rng);
        *x = a * half;
        *y = b * half;
    }
    for last in rest {
        *last = symmetric(rng) * half;
    }
    d
}

/// A uniform point in the unit ball, from 4-D up, and its squared norm,
/// drawn again until that norm is at least `min_norm_squared` (no other
/// rejection for even `N`, about half kept for odd `N`).
///
/// Archimedes in any dimension: the first `n` coordinates of a uniform
/// point on the sphere `S^{n+1}` (in `n + 2` dimensions) are uniform in the
/// ball `B^n`. For even `n + 2 = 2m`, a uniform point on that sphere is `m`
/// uniform planar directions scaled by `√s_j`, where `(s_1 … s_m)` is
/// uniform on the simplex: the spacings of `m - 1` sorted uniforms (the
/// squared lengths of Gaussian pairs are exponential, and normalised
/// exponentials are uniform on the simplex). Keeping `n/2` of the pairs
/// gives the point in `B^n`, of squared norm `1 - s_m`, the largest of the
/// sorted uniforms. No `ln`, `sin` or root of a math library: directions
/// come from the crate's table ([`angle_direction`]), lengths from `sqrt`,
/// so every platform draws the same bits. Odd `N` draws `B^{N-1}` so and a
/// last coordinate uniform in `[-1, 1)`, kept inside the ball.
///
/// A try draws its numbers first, in the stream's order (the uniforms, the
/// angles, the last coordinate), and decides from them alone: the norm is
/// the largest uniform, plus the last coordinate's square. A try thrown
/// away costs no sort, root or rotation.
#[inline(always)]
fn ball_point<const N: usize, R: Rng + ?Sized>(
    rng: &mut R,
    min_norm_squared: f64,
) -> ([f64; N], f64) {
    let pairs = N / 2;
    loop {
        let mut sorted = [0.0; N];
        let ends = sorted.get_mut(..pairs).unwrap_or_default();
        for u in ends.iter_mut() {
            *u = unit(rng);
        }
        let mut angles = [0u32; N];
        let angles = angles.get_mut(..pairs).unwrap_or_default();
        for a in angles.iter_mut() {
            *a = rng.next_u32();
        }
        // The largest uniform, the squared norm of the pairs (`unit` is
        // never NaN or -0, so `max` agrees with the sort).
        let largest = ends.iter().fold(0.0, |m: f64, &u| m.max(u));
        let (last, n2) = if N.is_multiple_of(2) {
            (0.0, largest)
        } else {
            let z = symmetric(rng);
            (z, largest + z * z)
        };
        if n2 >= 1.0 || n2 < min_norm_squared {
            continue;
        }
        sort_few(ends);
        let mut v = [0.0; N];
        let mut start = 0.0;
        for ((pair, &end), &angle) in v.chunks_exact_mut(2).zip(ends.iter()).zip(angles.iter()) {
            let length = (end - start).sqrt();
            start = end;
            let (c, s) = angle_direction(angle);
            if let [x, y] = pair {
                *x = length * c;
                *y = length * s;
            }
        }
        if !N.is_multiple_of(2)
            && let Some(slot) = v.last_mut()
        {
            *slot = last;
        }
        return (v, n2);
    }
}

/// Sorts a few values (`N/2`: up to four in 8-D), each `>= +0.0` and
/// not NaN, as `f64::total_cmp` would: where `min` and `max` order them the
/// same way. Up to eight values by odd-even transposition, `min`/`max`
/// pairs and no branch, since the draws' order is random and a branch on it
/// is mispredicted half the time (the library's sort cost 7 % of a 5-D
/// run's instructions); more by insertion.
#[inline(always)]
fn sort_few(v: &mut [f64]) {
    let n = v.len();
    if n <= 8 {
        for round in 0..n {
            for i in (round % 2..n.saturating_sub(1)).step_by(2) {
                if let Some([a, b]) = v.get_mut(i..i + 2) {
                    (*a, *b) = (a.min(*b), a.max(*b));
                }
            }
        }
        return;
    }
    for i in 1..n {
        let mut j = i;
        while let (Some(a), Some(b)) = (j.checked_sub(1).and_then(|k| v.get(k)), v.get(j)) {
            if a.total_cmp(b).is_le() {
                break;
            }
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// A uniform direction on the unit sphere, by normalising a uniform point
/// of the ball (from the cube up to 3-D, [`ball_point`] above), dropping
/// tiny ones (`sqrt` is correctly rounded, so this is reproducible).
#[inline(always)]
fn unit_direction<const N: usize, R: Rng + ?Sized>(rng: &mut R) -> [f64; N] {
    if N == 1 {
        return [if unit(rng) < 0.5 { -1.0 } else { 1.0 }; N];
    }
    loop {
        let (v, n2) = if N <= 3 {
            let v: [f64; N] = cube_point(rng, 1.0);
            (v, norm_squared(&v))
        } else {
            ball_point::<N, R>(rng, 1.0 / 64.0)
        };
        // Tiny vectors are dropped so normalising loses no precision.
        if (1.0 / 64.0..1.0).contains(&n2) {
            return scale(&v, 1.0 / n2.sqrt());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::{below, seeded_rng};

    /// [`ball_point`] is uniform in the unit ball: `P(|x| < t) = t^N` at
    /// several `t`, each coordinate has mean 0 and second moment
    /// `1/(N + 2)`, and the norm it reports is the point's. Tolerances are
    /// five standard errors of 200 000 draws.
    #[test]
    fn ball_points_are_uniform_in_the_ball() {
        fn check<const N: usize>(seed: u64) {
            let mut rng = seeded_rng(seed);
            let draws = 200_000;
            let ts = [0.5, 0.8, 0.9, 0.97];
            let mut inside = [0usize; 4];
            let mut moments = [[0.0f64; 2]; N];
            for _ in 0..draws {
                let (v, n2) = ball_point::<N, _>(&mut rng, 0.0);
                assert!((n2 - norm_squared(&v)).abs() < 1e-12, "{N}-D norm");
                assert!(n2 < 1.0, "{N}-D inside");
                for (count, t) in inside.iter_mut().zip(ts) {
                    *count += usize::from(n2 < t * t);
                }
                for (m, x) in moments.iter_mut().zip(v) {
                    m[0] += x;
                    m[1] += x * x;
                }
            }
            let n = f64::from(draws);
            for (count, t) in inside.iter().zip(ts) {
                let p = t.powi(i32::try_from(N).unwrap());
                let got = *count as f64 / n;
                let se = (p * (1.0 - p) / n).sqrt();
                assert!(
                    (got - p).abs() < 5.0 * se,
                    "{N}-D P(|x| < {t}): {got} vs {p}"
                );
            }
            let second = 1.0 / (N as f64 + 2.0);
            for (axis, m) in moments.iter().enumerate() {
                let mean = m[0] / n;
                let sq = m[1] / n;
                assert!(
                    mean.abs() < 5.0 * (second / n).sqrt(),
                    "{N}-D axis {axis} mean {mean}"
                );
                assert!(
                    (sq - second).abs() < 5.0 * (2.0 * second / n).sqrt(),
                    "{N}-D axis {axis}: {sq} vs {second}"
                );
            }
        }
        check::<4>(1);
        check::<5>(2);
        check::<6>(3);
        check::<7>(4);
        check::<8>(5);
    }

    /// Offsets drawn [`AHEAD`] at a time are the one-by-one offsets, bit
    /// for bit, and leave the generator in the same state.
    #[test]
    fn sort_few_sorts_as_the_library_does() {
        let mut rng = seeded_rng(5);
        for round in 0..4000 {
            let len = round % 12;
            // Half the rounds few distinct values, so that ties are common.
            let mut v: Vec<f64> = (0..len)
                .map(|_| {
                    if round % 2 == 0 {
                        [0.0, 0.25, 0.5, 1.0][below(&mut rng, 4)]
                    } else {
                        unit(&mut rng)
                    }
                })
                .collect();
            let mut expected = v.clone();
            expected.sort_by(f64::total_cmp);
            sort_few(&mut v);
            let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&v), bits(&expected), "round {round}: {v:?}");
        }
    }

    #[test]
    fn drawn_ahead_equals_drawn_one_by_one() {
        fn check<const N: usize>(radius: f64) {
            let sampler = CandidateSampler::<N>::new(Candidates::Annulus, radius, 30);
            let (mut one, mut all) = (seeded_rng(9), seeded_rng(9));
            let mut ahead = [[0.0; N]; AHEAD];
            for _ in 0..100 {
                sampler.fill_direct_annulus(&mut all, &mut ahead);
                for got in ahead {
                    let want = sampler.direct_annulus(&mut one);
                    assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{N}-D");
                }
            }
            assert_eq!(one.next_u64(), all.next_u64(), "{N}-D generator state");
        }
        check::<2>(0.37);
        check::<3>(1e-3);
    }

    #[test]
    fn angle_direction_matches_libm() {
        for i in 0..=256u64 {
            let bits = u32::try_from((i << 24).min(u64::from(u32::MAX))).unwrap();
            let theta = core::f64::consts::TAU * f64::from(bits) / 4_294_967_296.0;
            let (c, s) = angle_direction(bits);
            assert!((c - theta.cos()).abs() < 1e-15, "cos({theta}) = {c}");
            assert!((s - theta.sin()).abs() < 1e-15, "sin({theta}) = {s}");
        }
        // Inside a table step, where the polynomials do the work.
        for bits in [
            1u32,
            0x00ff_ffff,
            0x1234_5678,
            0x7fff_ffff,
            0xdead_beef,
            u32::MAX,
        ] {
            let theta = core::f64::consts::TAU * f64::from(bits) / 4_294_967_296.0;
            let (c, s) = angle_direction(bits);
            assert!((c - theta.cos()).abs() < 1e-15, "cos({theta}) = {c}");
            assert!((s - theta.sin()).abs() < 1e-15, "sin({theta}) = {s}");
        }
    }

    #[test]
    fn volume_radius_matches_libm() {
        let sampler = CandidateSampler::<3>::new(Candidates::Annulus, 1.0, 30);
        // Interval ends, midpoints and a hair either side, then a sweep.
        let edges = (0..=256u64).flat_map(|i| {
            let at = i << 24;
            [at.wrapping_sub(1), at, at + 1, at + (1 << 23)]
        });
        let sweep = (0..100_000u64).map(|i| i * 42_949);
        for bits in edges.chain(sweep).filter_map(|b| u32::try_from(b).ok()) {
            let want = (1.0 + 7.0 * (f64::from(bits) / 4_294_967_296.0)).cbrt();
            let got = sampler.volume_radius(bits);
            assert!(
                (got - want).abs() <= 2.0 * f64::EPSILON * want,
                "bits {bits:#x}: {got} against {want}"
            );
            let ahead = sampler.volume_radii(&[bits; AHEAD]);
            assert!(ahead.iter().all(|&x| x.to_bits() == got.to_bits()));
        }
    }

    #[test]
    fn cos_sin_matches_libm() {
        for i in 0..=64 {
            let t = core::f64::consts::TAU * f64::from(i) / 64.0;
            let (c, s) = cos_sin(t);
            assert!((c - t.cos()).abs() < 1e-14, "cos({t}) = {c}");
            assert!((s - t.sin()).abs() < 1e-14, "sin({t}) = {s}");
        }
    }

    fn check_offsets<const N: usize>(kind: Candidates) {
        let r = 0.3;
        let sampler = CandidateSampler::<N>::new(kind, r, 30);
        let mut rng = seeded_rng(9);
        let mut state = sampler.start(&mut rng);
        for _ in 0..2000 {
            let d = sampler.offset(&mut rng, &mut state);
            let len = norm_squared(&d).sqrt();
            match kind {
                Candidates::Annulus => {
                    assert!(len >= r * (1.0 - 1e-12) && len < 2.0 * r, "N={N} len {len}");
                }
                Candidates::Sphere => {
                    assert!(
                        (len / r - 1.0 - SPHERE_SLACK).abs() < 1e-9,
                        "N={N} len {len}"
                    );
                }
            }
        }
    }

    #[test]
    fn offsets_have_the_documented_length() {
        for kind in [Candidates::Annulus, Candidates::Sphere] {
            check_offsets::<1>(kind);
            check_offsets::<2>(kind);
            check_offsets::<3>(kind);
            check_offsets::<5>(kind);
            check_offsets::<8>(kind);
        }
    }

    #[test]
    fn annulus_is_uniform_in_volume_3d() {
        // Uniform in volume over r..2r: P(|d| < 1.5r) = (1.5³ - 1) / (8 - 1);
        // uniform in direction: each octant gets 1/8.
        let sampler = CandidateSampler::<3>::new(Candidates::Annulus, 1.0, 30);
        let mut rng = seeded_rng(4);
        let mut state = [0.0; 3];
        let n = 200_000;
        let (mut inner, mut octants) = (0u32, [0u32; 8]);
        for _ in 0..n {
            let d = sampler.offset(&mut rng, &mut state);
            inner += u32::from(norm_squared(&d) < 2.25);
            let octant = d
                .iter()
                .enumerate()
                .map(|(i, &x)| usize::from(x >= 0.0) << i)
                .sum::<usize>();
            octants[octant] += 1;
        }
        let share = f64::from(inner) / f64::from(n);
        assert!(
            (share - 2.375 / 7.0).abs() < 0.005,
            "share inside 1.5r: {share}"
        );
        for (i, &count) in octants.iter().enumerate() {
            let share = f64::from(count) / f64::from(n);
            assert!((share - 0.125).abs() < 0.003, "octant {i}: {share}");
        }
    }

    #[test]
    fn annulus_is_uniform_in_volume_2d() {
        // Uniform in area over r..2r: P(|d| < 1.5r) = (1.5² - 1) / (4 - 1).
        let sampler = CandidateSampler::<2>::new(Candidates::Annulus, 1.0, 30);
        let mut rng = seeded_rng(3);
        let mut state = [0.0; 2];
        let n = 100_000;
        let inner = (0..n)
            .filter(|_| norm_squared(&sampler.offset(&mut rng, &mut state)) < 2.25)
            .count();
        let share = f64::from(u32::try_from(inner).unwrap()) / f64::from(n);
        assert!(
            (share - 1.25 / 3.0).abs() < 0.01,
            "share inside 1.5r: {share}"
        );
    }
}
