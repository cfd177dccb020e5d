//! Where candidates are thrown around an active point.

use crate::random::{symmetric, symmetric_pair, unit};
use crate::vector::{norm_squared, scale};
use rand::Rng;

/// How candidate points are drawn around an active point.
///
/// Both give a valid Poisson disk set; they differ in how densely it is
/// packed and in how much each attempt costs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Candidates {
    /// Bridson's original: uniform **in volume** over the annulus (shell)
    /// `r <= |d| < 2r` around the active point. In 2-D drawn directly (radius
    /// `r·√(1 + 3u)`, uniform angle), elsewhere by rejection from the cube
    /// `[-2r, 2r)^N`. Gives the classic pattern: in 2-D with `k = 30`,
    /// a relative radius ρ ≈ 0.73 (see [`relative_radius`](crate::relative_radius)).
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
            Candidates::Annulus if N == 2 => {
                // One draw, no branch: 32 bits of radius, 32 of angle.
                // √(1 + 3u)·r is uniform in area over r..2r.
                let x = rng.next_u64();
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "splitting the word into its two 32-bit halves"
                )]
                let (high, low) = ((x >> 32) as u32, x as u32);
                let u = f64::from(high) * TWO_POW_M32;
                let (dx, dy) = angle_direction(low);
                let rho = self.radius * (1.0 + 3.0 * u).sqrt();
                let mut d = [0.0; N];
                if let [x, y] = d.as_mut_slice() {
                    (*x, *y) = (rho * dx, rho * dy);
                }
                d
            }
            Candidates::Annulus => loop {
                // Uniform in the cube [-2r, 2r)^N, kept if r <= |d| < 2r:
                // uniform in volume over the shell. Acceptance: 59 % in 2-D,
                // 46 % in 3-D, 1.6 % in 8-D (still cheap next to the search).
                let d: [f64; N] = cube_point(rng, 2.0 * self.radius);
                let n2 = norm_squared(&d);
                if n2 >= self.radius_squared && n2 < 4.0 * self.radius_squared {
                    return d;
                }
            },
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

/// A uniform direction on the unit sphere, by rejection from the cube and
/// normalisation (`sqrt` is correctly rounded, so this is reproducible).
#[inline(always)]
fn unit_direction<const N: usize, R: Rng + ?Sized>(rng: &mut R) -> [f64; N] {
    if N == 1 {
        return [if unit(rng) < 0.5 { -1.0 } else { 1.0 }; N];
    }
    loop {
        let v: [f64; N] = cube_point(rng, 1.0);
        let n2 = norm_squared(&v);
        // Tiny vectors are dropped so normalising loses no precision.
        if (1.0 / 64.0..1.0).contains(&n2) {
            return scale(&v, 1.0 / n2.sqrt());
        }
    }
}

const TWO_POW_M32: f64 = 1.0 / 4_294_967_296.0;

/// Signed permutations taking `(cos t, sin t)` to the direction at angle
/// `q·π/2 + t`, for quadrant `q`: `(m[0]·c + m[1]·s, m[2]·c + m[3]·s)`.
const QUADRANTS: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, 1.0],
    [0.0, -1.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0, -1.0],
    [0.0, 1.0, -1.0, 0.0],
];

/// The unit direction at angle `2π · bits / 2³²`, without a branch: the top
/// two bits pick the quadrant, the other 30 the angle inside it.
#[inline(always)]
fn angle_direction(bits: u32) -> (f64, f64) {
    const QUARTER_PER_UNIT: f64 = core::f64::consts::FRAC_PI_2 / (1u32 << 30) as f64;
    let t = f64::from(bits & ((1 << 30) - 1)) * QUARTER_PER_UNIT;
    let (c, s) = quarter_cos_sin(t);
    #[expect(
        clippy::indexing_slicing,
        reason = "bits >> 30 < 4 for a u32, and QUADRANTS has 4 rows"
    )]
    let m = QUADRANTS[(bits >> 30) as usize];
    (m[0] * c + m[1] * s, m[2] * c + m[3] * s)
}

/// `(cos t, sin t)` for `0 <= t < π/2` by Taylor polynomials (through
/// `t¹⁴` and `t¹³`), evaluated in Estrin form to keep the dependency chain
/// short: basic arithmetic only, so bit-identical on every platform; error
/// below 1e-9, far finer than matters for a direction.
#[inline(always)]
fn quarter_cos_sin(t: f64) -> (f64, f64) {
    // (-1)^k / (2k)! and (-1)^k / (2k+1)!.
    const C: [f64; 8] = [
        1.0,
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40_320.0,
        -1.0 / 3_628_800.0,
        1.0 / 479_001_600.0,
        -1.0 / 87_178_291_200.0,
    ];
    const S: [f64; 7] = [
        1.0,
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362_880.0,
        -1.0 / 39_916_800.0,
        1.0 / 6_227_020_800.0,
    ];
    let x = t * t;
    let x2 = x * x;
    let x4 = x2 * x2;
    let c = (C[0] + C[1] * x)
        + x2 * (C[2] + C[3] * x)
        + x4 * ((C[4] + C[5] * x) + x2 * (C[6] + C[7] * x));
    let s = (S[0] + S[1] * x) + x2 * (S[2] + S[3] * x) + x4 * ((S[4] + S[5] * x) + x2 * S[6]);
    (c, t * s)
}

/// `(cos θ, sin θ)` for `0 <= θ <= 2π`, by a fixed Taylor series in basic
/// arithmetic only, so it is bit-identical on every platform. Accurate to
/// about 1e-15, ample for spacing candidate directions.
fn cos_sin(theta: f64) -> (f64, f64) {
    // Reduce to |x| <= π/4 by quarter turns, then sum the series.
    let quarter = core::f64::consts::FRAC_PI_2;
    let turns = (theta / quarter).round();
    let x = theta - turns * quarter;
    let x2 = x * x;
    let (mut c, mut s) = (1.0, x);
    let (mut tc, mut ts) = (1.0, x);
    for n in 1..12 {
        let n = f64::from(n);
        tc *= -x2 / ((2.0 * n - 1.0) * (2.0 * n));
        ts *= -x2 / ((2.0 * n) * (2.0 * n + 1.0));
        c += tc;
        s += ts;
    }
    // `turns` is 0..=4 here, so the rem_euclid result fits any integer.
    match turns.rem_euclid(4.0) {
        0.0 => (c, s),
        1.0 => (-s, c),
        2.0 => (-c, -s),
        _ => (s, -c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::seeded_rng;

    #[test]
    fn angle_direction_matches_libm() {
        for i in 0..=256u64 {
            let bits = u32::try_from((i << 24).min(u64::from(u32::MAX))).unwrap();
            let theta = core::f64::consts::TAU * f64::from(bits) / 4_294_967_296.0;
            let (c, s) = angle_direction(bits);
            assert!((c - theta.cos()).abs() < 1e-9, "cos({theta}) = {c}");
            assert!((s - theta.sin()).abs() < 1e-9, "sin({theta}) = {s}");
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
