//! `f32` points that keep the guarantee ([`PoissonDisk::for_f32`]): the
//! sampler runs in `f64` at a radius padded by a bound on what rounding
//! the points to `f32`, and then measuring them in `f32`, can take off a
//! distance.
//!
//! # The bound
//! Write `u = 2⁻²⁴` (half an `f32` ulp, relative), `M_i` the largest
//! `|x|` on axis `i` (`max(|lo_i|, |hi_i|)`), `L_i` its extent, and `t`
//! the exact difference vector of two points `a`, `b` the sampler made at
//! radius `R` (toroidal on periodic axes).
//!
//! 1. The sampler's `f64` test, `Σ fl(t̂_i²) >= fl(R·R)`, gives
//!    `‖t̂‖ >= R·(1 - (N+4)·2⁻⁵²)` for its computed differences `t̂`, each
//!    within `2⁻⁵¹·(M_i + L_i)` of `t_i`.
//! 2. `a as f32` rounds to nearest: `|a'_i - a_i| <= u·M_i + 2⁻¹⁵⁰`
//!    (relative below `f32::MAX`, the `2⁻¹⁵⁰` for subnormals); twice that
//!    for a difference.
//! 3. In `f32`, `d_i = fl(a'_i - b'_i)` is within `u·|d_i|` of the exact
//!    difference of the rounded points. On a periodic axis the user's
//!    `min(d, L' - d)` with `L' = (hi - lo) as f32` adds `|L' - L| + u·L
//!    <= 2u·L_i` and a relative `u` of its own subtraction. So every
//!    axis's computed difference is `c_i >= (t_i - ε_i)·(1 - u)` with
//!    `ε_i = 2(u·M_i + 2⁻¹⁵⁰) + [periodic] 2u·L_i + 2⁻⁵¹(M_i + L_i)`, and
//!    `‖c‖ >= (‖t‖ - E)·(1 - u)` with `E = ‖ε‖`.
//! 4. Squares (`(1 - u)` each), a sum of `N` non-negative terms in order
//!    (`(1 - u)^(N-1)`) and the square root (`(1 - u)`, on the root of
//!    the rest): the computed distance is at least
//!    `(‖t‖ - E)·(1 - u)^((N+4)/2)`, and the computed squared distance at
//!    least `(‖t‖ - E)²·(1 - u)^(N+2)`.
//! 5. The user's `r' = r as f32` is at most `r·(1 + u)`, and `fl(r'·r')`
//!    at most `r'²·(1 + u)`. With `(1 - u)^k >= 1 - k·u`, both tests pass
//!    if `R·(1 - (N+4)·2⁻⁵²) - E >= r·(1 + u) / (1 - (N+4)/2·u)`.
//!
//! [`f32_radius`] takes `R` as that bound, times `1 + 2⁻⁴⁰` for its own
//! `f64` rounding and for squares that underflow `f32` (an absolute
//! `2⁻¹⁴⁹` each: with `r >= 2⁻⁴⁰`, a relative `N·2⁻⁶⁹`). Squares of
//! differences up to `2·M` must not overflow `f32`: `4·N·M² < 2¹²⁶`.

use crate::domain::Domain;
use crate::error::Error;
use crate::sampler::PoissonDisk;

/// Half an `f32` ulp, relative: `2⁻²⁴`.
const U: f64 = 1.0 / 16_777_216.0;
/// The smallest and largest radius taken: squares of distances near them
/// stay normal `f32`.
/// (`2⁻⁴⁰` is also the bound's slack for its own rounding.)
const MIN_F32_RADIUS: f64 = 1.0 / 1_099_511_627_776.0; // 2⁻⁴⁰
const MAX_F32_RADIUS: f64 = 1_152_921_504_606_846_976.0; // 2⁶⁰
/// The padding refused: past it, `f32` cannot hold the radius at these
/// coordinates (the padded radius over `1.25·r`).
const MAX_PAD: f64 = 1.25;

/// The radius to sample `domain` at so that its points, rounded to `f32`,
/// are at least `r` apart when measured in `f32` (see the module docs).
pub(crate) fn f32_radius<const N: usize>(domain: &Domain<N>, r: f64) -> Result<f64, Error> {
    if !(MIN_F32_RADIUS..=MAX_F32_RADIUS).contains(&r) {
        return Err(Error::InvalidRadius);
    }
    let (lo, hi, periodic) = (domain.lo(), domain.hi(), domain.periodic());
    let mut e2 = 0.0;
    let mut m_max: f64 = 0.0;
    for i in 0..N {
        let (Some(l), Some(h), Some(p)) = (lo.get(i), hi.get(i), periodic.get(i)) else {
            continue;
        };
        let m = l.abs().max(h.abs());
        let extent = h - l;
        m_max = m_max.max(m);
        let wrap = if *p { 2.0 * U * extent } else { 0.0 };
        let eps = 2.0 * (U * m + f64::from(f32::from_bits(1)) / 2.0)
            + wrap
            + (m + extent) * f64::EPSILON / 4.0;
        e2 += eps * eps;
    }
    #[expect(clippy::cast_precision_loss, reason = "N is small")]
    let n = N as f64;
    let ulps = || {
        #[expect(clippy::cast_possible_truncation, reason = "f32 on purpose")]
        let m = m_max as f32;
        let ulp = f64::from(m.next_up() - m);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a count for the message, saturating"
        )]
        let ulps = (r / ulp).floor() as u64;
        Error::F32TooCoarse { ulps }
    };
    if 4.0 * n * m_max * m_max >= f64::from(f32::MIN_POSITIVE).recip() {
        return Err(ulps());
    }
    let a = (1.0 + U) / (1.0 - (n + 4.0) / 2.0 * U);
    let padded = (r * a + e2.sqrt()) * (1.0 + MIN_F32_RADIUS) / (1.0 - (n + 4.0) * f64::EPSILON);
    if padded > MAX_PAD * r {
        return Err(ulps());
    }
    Ok(padded)
}

impl<const N: usize> PoissonDisk<N> {
    /// This sampler with its radius padded so that its points, rounded to
    /// `f32` (`p.map(|x| x as f32)`), are never closer than this sampler's
    /// `r` when measured in `f32` as a user would: for every pair `a`,
    /// `b`, with `d_i = a[i] - b[i]` in `f32` (on a periodic axis
    /// `min(|d_i|, L - |d_i|)`, `L = (hi - lo) as f32`), both
    /// `Σ d_i² >= r·r` and `(Σ d_i²).sqrt() >= r`, all in `f32` with `r as
    /// f32`, summing axes in order. Points rounded without the padding can
    /// be closer: at `x ≈ 256 000`, where an `f32` ulp is `1/64`, as close
    /// as `0.996·r` at `r = 4`.
    ///
    /// Every way to run works on the padded sampler ([`iter`](Self::iter),
    /// [`iter_with`](Self::iter_with), [`generate_parallel`](Self::generate_parallel),
    /// …); for a varying radius, sample the field `f32_radius(r(p))` (see
    /// [`f32_radius`](Self::f32_radius)). Count mode pads the radius it
    /// derived, so it makes fewer points than asked. The other settings are
    /// kept. The `f32` points need not stay below `hi` (a coordinate can
    /// round up onto it).
    ///
    /// Cost: the padding is `r·(1 + ~(N/2 + 3)·2⁻²⁴) + ~2√N·2⁻²⁴·M`, for
    /// `M` the largest coordinate magnitude of the box: about `√N` `f32`
    /// ulps at `M`. The density falls by the factor `(r / R)^N`; the speed
    /// per point is unchanged (the same loop, at another radius). Measured
    /// with the `points` example, 2-D, 1000 radii wide, seed 1, release
    /// build, `--format none`, seconds the median of 5 runs alternating
    /// with and without `--f32` (`/usr/bin/time`), ρ at `r`:
    ///
    /// | box | `r` in ulps of `M` | points, `f64` | points, `--f32` | ρ | seconds |
    /// |---|--:|--:|--:|--:|--:|
    /// | `[0, 1000)²`, `r = 1` | 16 384 | 615 751 | 615 510 (−0.04 %) | 0.7302 → 0.7301 | 0.40 → 0.40 |
    /// | `10⁶ + [0, 18 750)²`, `r = 18.75` | 300 | 615 751 | 604 687 (−1.8 %) | 0.7302 → 0.7237 | 0.39 → 0.40 |
    /// | `10⁶ + [0, 1000)²`, `r = 1` | 16 | 615 751 | 450 815 (−26.8 %) | 0.7302 → 0.6248 | 0.41 → 0.29 |
    ///
    /// (`points --dim 2 --radius 18.75 --lo 1e6,1e6 --extent 18750,18750
    /// --seed 1 --format none [--f32]`, and alike.) Sixteen ulps is near the
    /// refusal: at 12 ulps in 2-D the padding is about a fifth of `r`.
    /// Moving the box to the origin (coordinates relative to a corner)
    /// makes the cost vanish.
    ///
    /// # Errors
    /// As [`f32_radius`](Self::f32_radius), for this sampler's radius; and
    /// the errors of [`PoissonDiskBuilder::build`](crate::PoissonDiskBuilder::build)
    /// for the padded radius ([`Error::BoxTooWide`], [`Error::GridTooLarge`]).
    ///
    /// # Example: `f32` points far from the origin
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// let domain = Domain::new([256_000.0, 0.0], [256_200.0, 200.0])?;
    /// let r = 4.0;
    /// let sampler = PoissonDisk2::new(domain, r)?.for_f32()?;
    /// assert!(sampler.radius() > r);
    /// let points: Vec<[f32; 2]> = sampler
    ///     .generate_seeded(1)?
    ///     .into_iter()
    ///     .map(|p| p.map(|x| x as f32))
    ///     .collect();
    /// let r32 = r as f32;
    /// for (i, a) in points.iter().enumerate() {
    ///     for b in &points[..i] {
    ///         let d2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
    ///         assert!(d2 >= r32 * r32 && d2.sqrt() >= r32);
    ///     }
    /// }
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_f32(&self) -> Result<Self, Error> {
        let padded = self.f32_radius(self.radius())?;
        let mut builder = PoissonDisk::builder(*self.domain(), padded)
            .attempts(self.attempts())
            .candidates(self.candidates())
            .layout(self.layout())
            .max_grid_bytes(self.max_grid_bytes());
        if let Some(cap) = self.max_points() {
            builder = builder.max_points(cap);
        }
        builder.build()
    }

    /// The radius to sample this sampler's box at so that its points,
    /// rounded to `f32`, keep `r` apart in `f32` arithmetic, as
    /// [`for_f32`](Self::for_f32) states; a linear function of `r`, so a
    /// varying radius's field can be padded point by point:
    /// `|p| sampler.f32_radius(r(p))`, with `r_min` padded alike (both
    /// checked once, the values between them then pass). The derivation is
    /// in `src/single.rs`.
    ///
    /// # Errors
    /// [`Error::InvalidRadius`] if `r` is outside `2⁻⁴⁰ ..= 2⁶⁰` (about
    /// `9.1e-13 ..= 1.2e18`), where squared distances leave the normal
    /// `f32` range; [`Error::F32TooCoarse`] if the padding would be more
    /// than a quarter of `r` (`r` below about `4√N` `f32` ulps of the box's
    /// largest coordinate magnitude), or that coordinate's squares
    /// overflow `f32` (`4·N·M² >= 2¹²⁶`).
    pub fn f32_radius(&self, r: f64) -> Result<f64, Error> {
        f32_radius(self.domain(), r)
    }
}
