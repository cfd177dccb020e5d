//! Exact mode: exactly `n` points in every pixel, thinned from a sweep run
//! at a radius that gives about `s·n` points per pixel (`s`, the
//! oversampling, [`DEFAULT_OVERSAMPLE`] unless set), one row at a time.
//!
//! When row `y` is complete, the points of rows `y` and `y + 1` (the band)
//! are gathered, and row `y` is settled in three steps:
//!
//! 1. **Dead points.** A band point closer than the sweep's radius `r` to a
//!    final point of the rows above (a dart placed there, step 2) is out.
//! 2. **Short pixels.** A pixel of row `y` left with fewer than `n` points
//!    gets darts. A dart is valid only if it lies at least `r` from every
//!    point that stays: of 32 uniform darts in the pixel, the one with the
//!    fewest *blockers* (band points closer than `r`, at most four) is
//!    taken and its blockers removed. Every blocker must lie in another
//!    pixel, and a final point of a row above or another dart is never
//!    removed. Which pixels may lose a blocker widens in stages, each
//!    tried only if the previous found no dart: a pixel that keeps at
//!    least `n` points; or one not yet mended, right of it in row `y` or in
//!    row `y + 1`, which gets its own darts in turn (then with 256 darts);
//!    then any pixel, a pixel of row `y` left short being mended on the
//!    next pass over the row (up to four passes). So points move across a
//!    pixel border, one out near it on one side and one in near it on the
//!    other: the density along the borders is kept. The dart goes into the
//!    sweep's grid, so that points the sweep still makes below keep their
//!    distance from it too. Only if all that fails (not seen at the
//!    default oversampling: `examples/stream.rs` reports it) the best of
//!    the darts by distance is taken: a *top-up*, which may come closer
//!    than `r`; [`Pixels::top_ups`] counts them.
//! 3. **Excess.** Pixels of row `y` with more than `n` points lose the
//!    excess, by the [`ExactMethod`]:
//!    - [`ExactMethod::Eliminate`]: weighted sample elimination (Yuksel
//!      2015, "Sample Elimination for Generating Poisson Disk Sample
//!      Sets") of row `y`: the point with the largest weight
//!      `Σ sⱼ·(1 - d/2rₑ)⁸` over neighbours `j` closer than `2rₑ` is
//!      removed, again and again, except from pixels already down to `n`,
//!      where `rₑ = sqrt(1 / (2√3·n))` is the spacing of `n` points per
//!      pixel on a hexagonal lattice. The neighbours are the band's live
//!      points and the final points above. Row `y + 1` is thinned later,
//!      so a term from one of its points counts with `sⱼ = n / c`, the
//!      share of its pixel's `c` points that will stay (`sⱼ = 1` for the
//!      others). Until 2026-11-24 (ninth session) the two rows were
//!      eliminated together and row `y + 1`'s result thrown away: each
//!      row was weighed twice, for the same image error in the tracer
//!      study (within ±0.2 % in all 12 cells, `docs/trace.md`) at
//!      1.12–1.17× the time at `n = 4` and 16
//!      (`docs/performance-journal.md`, "Exact mode: one row eliminated").
//!    - [`ExactMethod::Random`]: the excess points of each pixel are picked
//!      uniformly at random, blind to where they lie.
//!
//! Every kept point is a sweep point or a valid dart, so the set's minimum
//! distance is at least the sweep's radius, [`Tiled::radius`], except
//! around top-ups. The scratch arrays live in [`Exact`] and are reused from
//! row to row: after the first rows, thinning allocates nothing.
//!
//! [`Pixels::top_ups`]: super::Pixels::top_ups
//! [`Tiled::radius`]: super::Tiled::radius

use super::window::Window;
use crate::random::{below, unit};
use crate::vector::distance_squared;
use rand::Rng;
use std::collections::BinaryHeap;

/// Points per pixel the sweep makes, relative to the `n` kept, unless
/// [`TiledBuilder::exact_oversample`](super::TiledBuilder::exact_oversample)
/// says otherwise. The kept set's ρ is about the sweep's over `√s`: 0.705
/// at [`EXACT_ATTEMPTS`], so 0.655 here, the radius of the former default
/// (`s = 1.25` at `k = 30`, where the sweep's ρ is 0.73) to within 0.3 %.
/// A larger `s` gives elimination more to choose from at the cost of the
/// minimum distance and of speed (`docs/performance-journal.md` has the
/// trade-off).
pub(crate) const DEFAULT_OVERSAMPLE: f64 = 1.16;

/// The attempts `k` exact mode's sweep runs with unless
/// [`TiledBuilder::attempts`](super::TiledBuilder::attempts) says
/// otherwise. A third of the usual 30: thinning, not the sweep's
/// saturation, shapes the kept set, and the sweep's retiring picks (their
/// `k` failed throws) are a third of its time. At `k = 10` the sweep makes
/// 0.93 of the points per `r²` it makes at 30; `DEFAULT_OVERSAMPLE` is
/// counted at this `k`. The journal has the measurements (exact mode at
/// `k = 6` to `30`).
pub const EXACT_ATTEMPTS: u32 = 10;

/// Exponent of the elimination weight (Yuksel's α).
const ALPHA: i32 = 8;

/// Darts thrown per point a short pixel needs, first and at most.
const DARTS: usize = 32;
const DARTS_MORE: usize = 256;
/// Further rounds of [`DARTS_MORE`] fresh darts, taking from any pixel the
/// pass allows, before a short pixel gets a top-up: its room can be a
/// sliver. At exact mode's `k = 10` the last stage's 256 darts missed it
/// about once per 10⁶ points (ten top-ups in sixteen runs of 512² at
/// `n = 4`); with 2 048 darts in all, none in fourteen.
const RESCUE_ROUNDS: usize = 7;

/// A dart with more blockers than this is not taken.
const MAX_BLOCKERS: usize = 4;

/// How exact mode chooses, in a pixel with more than `n` points, which
/// points to drop. Set with
/// [`TiledBuilder::exact_method`](super::TiledBuilder::exact_method); both
/// methods give exactly `n` points per pixel with the same minimum distance
/// and mend short pixels the same way (see [`Tiled`](super::Tiled)).
///
/// They differ in what the set looks like. Elimination spreads the kept
/// points best, but the per-pixel caps leave a faint pixel pattern; random
/// dropping leaves none but adds a little white noise (a thinned Poisson
/// disk set). README's streaming table has both, measured.
///
/// In renders, elimination gives the lower error, hence the default: in
/// the tracer study (`examples/trace.rs`, `docs/trace.md`, 2026-11-24:
/// four scenes at 4, 16 and 64 samples per pixel, one exact stream over
/// the image as a renderer runs it), random dropping's RMSE was 0–12 %
/// higher: beyond the noise on the checkerboard, the moving sphere and
/// (from 16 samples) the lit figure, level on the depth-of-field scene;
/// with the sweep at `k = 10` (its third study), 0.1–7.8 % higher.
/// Elimination now weighs one row at a time (the fourth study: RMSE
/// within ±0.2 % of the two-row form it replaced, random dropping's
/// −0.1 % to +7.8 % above it). Random dropping still samples faster:
/// 0.73–0.78 of elimination's time at `n` = 4, 16 and 64
/// (`examples/stream.rs`, 2026-11-24); a renderer whose sampling costs
/// more than its shading may prefer it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
#[non_exhaustive]
pub enum ExactMethod {
    /// Weighted sample elimination (Yuksel 2015) of each row, the row
    /// below counted as it will be once thinned: the most crowded point
    /// goes first.
    #[default]
    Eliminate,
    /// Drops each pixel's excess points uniformly at random.
    Random,
}

/// The edge correction `[βx, βy, γ, δ, ε]` (see [`Exact::edge_factor`]) at
/// the default oversampling and `k` ([`DEFAULT_OVERSAMPLE`],
/// [`EXACT_ATTEMPTS`]). `ε` (2026-11-24, eighth session) cancels a
/// left-right tilt at `n = 4` that only rasters of 10⁶ pixels resolve: a
/// short pixel is mended left to right, its darts free to take points
/// from the unsettled pixels on its right, not the settled ones on its
/// left, so the left half of each pixel kept less (the in-pixel first
/// harmonic's `sin` term in `x` −0.0016 to −0.0021 at 1024², seeds 1 to
/// 4, both methods; pixel-frequency power 2.7–4.9 in `x` where 3 is the
/// goal). Linear in `ε`: at `ε = −0.05` the term was +0.0059 to +0.0061
/// (elimination) and +0.0029 to +0.0030 (random dropping), seeds 1 and
/// 2, so `ε = −0.012` and `−0.019` zero it; at `n = 8` (724²) the term
/// was 0.0000 and +0.0001 already, so `ε` falls to 0 there. Afterwards,
/// 1024², seeds 1 to 4: the `sin` term within ±0.0006, power in `x` at
/// most 0.53 and 0.36. In the same session random dropping's `γ` and `βy`
/// at `n = 16` were set again from 512² (4 M points; they had left power
/// 17.7–22.6 in `y` at 1024²), and its `βx` and `βy` at `n = 8` from 1024²
/// (power 2.97–4.45 in `x` there), the same way. In the ninth session
/// elimination came to weigh one row (the module docs), which moved the
/// `sin` term in `y` (+0.0019 at `n = 8` and 16, power 1.0–2.4 in `y`): its
/// `βy` and `γ` at `n` = 4, 8 and 16 were solved again from two settings
/// each (512², 362², 256², seeds 1 and 2; `βy` at 16 from 512²), leaving
/// power at most 1.09 at 1024² (`n = 4`, seeds 1 and 2; `n = 16`, seed 1)
/// and 724² (`n = 8`); at `n = 64` the sets are the same as before.
///
/// `δ` lifts the top band, which the rows above
/// deplete (their darts kill points near it, and elimination sees their
/// final points): at `n = 4` it was 0.93–0.94 of the interior without it
/// (elimination; random dropping 0.95–0.96). It was set by hand, trying
/// 0 to 0.6 with a throwaway build that read it from the environment (0.2:
/// top bands 0.96–0.97 for elimination, 0.95–0.97 for random dropping, 512²
/// and 256², three seeds); at `n >= 16` the bands are within 1–3 % without
/// it (at `n = 8` interpolating the rest gave power 4–9, hence its row).
/// Then, with `δ` fixed, `[βx, βy, γ]` zero the first harmonic of the
/// kept density across a pixel, measured with `examples/stream.rs --exact
/// N --method M --bias ...` on about 10⁶ points (512², 362², 256², 128²
/// pixels for `n` = 4, 8, 16, 64, `δ` 0.2, 0.1, 0, 0; seeds 1 and 2
/// averaged; the harmonic is linear in
/// each): β from two settings, then γ from two (the script and its runs
/// are in the journal, "Exact mode at k = 10"). Linear in `n` between
/// those, the `n = 4` values below (at `n = 1` no β helps: a quarter of
/// the pixels are short there), the `n = 64` values above. `y` differs
/// from `x` because rows are settled in order and columns together: darts
/// take room from the row below, and elimination sees the rows above
/// settled and the row below oversampled. Other oversamplings and `k`
/// keep these values, which then fit less well
/// (`docs/images/exact-tradeoff.png`).
fn calibrated_bias(method: ExactMethod, n: usize) -> [f64; 5] {
    let table: [(f64, [f64; 5]); 4] = match method {
        ExactMethod::Eliminate => [
            (4.0, [0.193, 0.072, -0.044, 0.2, -0.012]),
            (8.0, [0.113, 0.066, 0.009, 0.1, 0.0]),
            (16.0, [0.072, 0.077, 0.022, 0.0, 0.0]),
            (64.0, [0.007, 0.034, 0.017, 0.0, 0.0]),
        ],
        ExactMethod::Random => [
            (4.0, [0.314, 0.138, -0.074, 0.2, -0.019]),
            (8.0, [0.130, 0.070, -0.008, 0.1, 0.0]),
            (16.0, [0.048, 0.053, -0.002, 0.0, 0.0]),
            (64.0, [0.0, 0.0, 0.0, 0.0, 0.0]),
        ],
    };
    #[expect(clippy::cast_precision_loss, reason = "a count per pixel")]
    let n = n as f64;
    let mut beta = table[0].1;
    for pair in table.windows(2) {
        if let [(n0, b0), (n1, b1)] = pair
            && n > *n0
        {
            let t = ((n - n0) / (n1 - n0)).min(1.0);
            for (b, (lo, hi)) in beta.iter_mut().zip(b0.iter().zip(b1)) {
                *b = lo + t * (hi - lo);
            }
        }
    }
    beta
}

/// Uniform darts in the pixel whose corner is `(fx, fy)`.
fn throw_darts<R: Rng + ?Sized>(darts: &mut [[f64; 2]], (fx, fy): (f64, f64), rng: &mut R) {
    for d in darts {
        *d = [fx + unit(rng), fy + unit(rng)];
        // Rounding onto the far edge: the pixel's corner instead.
        if d[0] >= fx + 1.0 || d[1] >= fy + 1.0 {
            *d = [fx, fy];
        }
    }
}

/// The depth of a pixel's top band that the calibrated correction's `δ`
/// term favours (see [`Exact::edge_factor`]), in pixels.
const TOP_BAND: f64 = 0.2;

/// Pixel column `x` and its neighbours inside a raster `width` wide: all
/// the columns a point of column `x` can be closer than `r` to, as `r < 1`.
fn columns_around(x: usize, width: usize) -> core::ops::RangeInclusive<usize> {
    x.saturating_sub(1)..=(x + 1).min(width.saturating_sub(1))
}

/// A heap entry: a point's weight when pushed (stale if it changed since)
/// and its index, packed into one integer whose order is the weights'
/// `total_cmp`, ties going to the lower index: the heap then compares
/// integers (its pops were 6 % of exact mode's instructions at `n = 4`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Entry(u128);

/// The sign bit of an `f64`'s bits.
const SIGN: u64 = 1 << 63;

impl Entry {
    fn new(weight: f64, index: u32) -> Self {
        // `total_cmp`'s order as unsigned integers: negative weights have
        // every bit flipped, the others only the sign bit.
        let bits = weight.to_bits();
        let key = if bits & SIGN == 0 { bits | SIGN } else { !bits };
        Self((u128::from(key) << 32) | u128::from(u32::MAX - index))
    }

    fn parts(self) -> (f64, u32) {
        #[expect(clippy::cast_possible_truncation, reason = "the two halves")]
        let (key, low) = ((self.0 >> 32) as u64, self.0 as u32);
        let bits = if key & SIGN == 0 { !key } else { key & !SIGN };
        (f64::from_bits(bits), u32::MAX - low)
    }
}

/// Passes over a row that mend short pixels (see [`Take::Any`]).
const MEND_PASSES: usize = 4;

/// Which pixels a dart may take points from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Take {
    /// Pixels that keep at least `n` points afterwards.
    Excess,
    /// Those, and pixels not yet mended (right of the dart's in its row,
    /// or in the row below), which may fall short: they get darts in turn.
    Unsettled,
    /// Any other pixel of the band; a pixel of the row left short is
    /// mended on the next pass.
    Any,
}

/// What a dart would cost: the band points closer than `r` to it.
#[derive(Clone, Copy, Debug)]
struct Blockers {
    count: usize,
    items: [u32; MAX_BLOCKERS],
}

/// A live band point in the local grid's order, for
/// [`Exact::pair_weights`].
#[derive(Clone, Copy, Debug)]
struct ByCell {
    p: [f64; 2],
    over: bool,
    scale: f64,
    weight: f64,
}

/// What the darts of one short pixel are checked against
/// ([`Exact::best_dart`]), copied out once since nothing changes until one
/// is placed: the darts already placed in the columns around, the final
/// points above near it, and the live band points of the pixels around
/// with their index and pixel, in [`Exact::near_pixel`]'s order.
#[derive(Debug, Default)]
struct DartScratch {
    darts: Vec<[f64; 2]>,
    above: Vec<[f64; 2]>,
    near: Vec<([f64; 2], u32, u32)>,
}

/// Exact mode's settings and its scratch arrays, reused from row to row.
#[derive(Debug)]
pub(crate) struct Exact {
    n: usize,
    method: ExactMethod,
    /// `[βx, βy, γ]` of [`Self::edge_factor`].
    bias: [f64; 3],
    /// Its `δ`: 0 when the caller set the correction.
    top: f64,
    /// Its `ε`: 0 when the caller set the correction.
    side: f64,
    /// `2rₑ`: the reach of the elimination weight, and its inverse.
    reach: f64,
    inv_reach: f64,
    /// The sweep's radius squared: what darts must keep from every point.
    radius_squared: f64,
    /// Cells per pixel side of the band's local grid: cells are about half
    /// the search distance wide (a 5 × 5 block of them is searched, 1.8
    /// pixels² at `n = 4` where whole pixels would search 9), and
    /// neighbours lie within `cell_reach` cells.
    cells: usize,
    cell_reach: usize,
    /// Pixel rows above searched for final points (`ceil(reach)`).
    rows_up: usize,
    /// Band points: gathered pixel by pixel in generation order, darts
    /// appended; their band pixel (`row · width + x`); whether they stay.
    points: Vec<[f64; 2]>,
    pixel: Vec<u32>,
    alive: Vec<bool>,
    /// Where each band pixel's gathered points start in `points`.
    start: Vec<usize>,
    /// Live points per band pixel.
    count: Vec<usize>,
    /// Indices of `points` by local grid cell, and each point's cell.
    cell_start: Vec<usize>,
    cell_of: Vec<usize>,
    cell_items: Vec<u32>,
    /// [`Self::pair_weights`]' copy of the live points in the local grid's
    /// order (`cell_items`): coordinates, whether elimination may remove
    /// it, its pixel's `scale`, and its weight so far.
    by_cell: Vec<ByCell>,
    /// What a short pixel's darts are checked against
    /// ([`Self::gather_blockers`]), reused from pixel to pixel.
    dart_scratch: DartScratch,
    /// Elimination: weights and edge factors ([`Self::edge_factor`]).
    weight: Vec<f64>,
    factor: Vec<f64>,
    /// Whether each point is in a pixel of the row settled that is over
    /// `n` as elimination starts: the points elimination may remove.
    over: Vec<bool>,
    /// What the weight terms of each band pixel's points count for on
    /// the others' weights: `n / c` for a pixel of row `y + 1` with
    /// `c > n` points (the share of them that will stay), else 1.
    scale: Vec<f64>,
    /// A removed point's live neighbours and their weight terms.
    neighbours: Vec<(u32, f64)>,
    heap: BinaryHeap<Entry>,
    /// The weights elimination starts from, largest first.
    sorted: Vec<Entry>,
    /// Darts placed in this band (indices into `points`).
    darts: Vec<u32>,
    /// The same darts by pixel column, for [`Self::blockers`]: a dart
    /// closer than `r` to a point of pixel `x` lies in column `x - 1`,
    /// `x` or `x + 1` (darts are all in row `y`, and `r < 1`: at most
    /// `sqrt(0.88 / (s·n))` with `s, n >= 1`), so a dart is checked
    /// against a few darts, not against every dart of a row as wide as the
    /// image.
    dart_columns: Vec<Vec<u32>>,
    /// The darts kept in the row settled last, by pixel column: the only
    /// final points a band point can be closer than `r` to (step 1; every
    /// other final point is a sweep point, as the band's points are, and
    /// `r < 1` keeps older rows out of reach).
    darts_above: Vec<Vec<[f64; 2]>>,
    /// The final points of the row settled last (`strip_row`) within
    /// `2rₑ` of its bottom edge (with a margin), by pixel column, in the
    /// order of the pixels' final points: the only ones whose weight
    /// terms on the band's points are not zero, when `2rₑ <= 1` (`rows_up`
    /// 1). Elimination adds their terms in that order, skipping only
    /// zeros, which leaves the sums' bits as they were.
    strip: Vec<Vec<[f64; 2]>>,
    strip_row: Option<usize>,
    /// Whether the local grid holds this band's points.
    indexed: bool,
}

impl Exact {
    /// Settings for `n` points per pixel, thinned by `method` from a sweep
    /// of radius `radius`.
    pub(crate) fn new(n: usize, method: ExactMethod, radius: f64, bias: Option<[f64; 3]>) -> Self {
        let (bias, top, side) = match bias {
            Some(b) => (b, 0.0, 0.0),
            None => {
                let [bx, by, g, d, e] = calibrated_bias(method, n);
                ([bx, by, g], d, e)
            }
        };
        #[expect(clippy::cast_precision_loss, reason = "a count per pixel")]
        let r_e = (1.0 / (2.0 * 3f64.sqrt() * n as f64)).sqrt();
        let reach = 2.0 * r_e;
        // Both the weight's reach and the darts' radius must fit in the
        // searched cells; the radius is below the reach for any
        // oversampling above 0.54, but take the larger to be sure.
        let search = reach.max(radius);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to 1 ..= 2^16"
        )]
        let cells = ((2.0 / search).floor().clamp(1.0, 65_536.0)) as usize;
        #[expect(clippy::cast_precision_loss, reason = "cells <= 2^16")]
        let cell_side = 1.0 / cells as f64;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "search / side: a few cells (search < 2 pixels here)"
        )]
        let cell_reach = ((search / cell_side).ceil().clamp(1.0, 1e6)) as usize;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a few pixels"
        )]
        let rows_up = (search.ceil().clamp(1.0, 1e6)) as usize;
        Self {
            n,
            method,
            bias,
            top,
            side,
            reach,
            inv_reach: 1.0 / reach,
            radius_squared: radius * radius,
            cells,
            cell_reach,
            rows_up,
            points: Vec::new(),
            pixel: Vec::new(),
            alive: Vec::new(),
            start: Vec::new(),
            count: Vec::new(),
            cell_start: Vec::new(),
            cell_of: Vec::new(),
            cell_items: Vec::new(),
            by_cell: Vec::new(),
            dart_scratch: DartScratch::default(),
            weight: Vec::new(),
            factor: Vec::new(),
            over: Vec::new(),
            scale: Vec::new(),
            neighbours: Vec::new(),
            heap: BinaryHeap::new(),
            sorted: Vec::new(),
            darts: Vec::new(),
            dart_columns: Vec::new(),
            darts_above: Vec::new(),
            strip: Vec::new(),
            strip_row: None,
            indexed: false,
        }
    }

    /// How readily point `i` is dropped for where it lies in its pixel,
    /// `(u, v)`: `1 - βx·h(u) - βy·h(v) - γ·(2v - 1) - δ·t(v) - ε·(2u - 1)`,
    /// with `h(t) = (2t - 1)² - 1/3` (mean 0 over the pixel, 2/3 at its edges,
    /// -1/3 at its centre) and `t(v) = max(0, 1 - v/w) - w/2` (mean 0, a
    /// ramp over the top band `v < w`, `w =` [`TOP_BAND`]); so positive β
    /// keep points near the edges, a positive γ keeps them near the bottom,
    /// a positive δ near the top and a negative ε in the left half.
    fn edge_factor(&self, i: usize) -> f64 {
        let Some(p) = self.points.get(i) else {
            return 1.0;
        };
        let h = |t: f64| {
            let f = t - t.floor();
            (2.0 * f - 1.0) * (2.0 * f - 1.0) - 1.0 / 3.0
        };
        let u = p[0] - p[0].floor();
        let v = p[1] - p[1].floor();
        // The top band's ramp, minus its mean over the pixel.
        let t = (1.0 - v / TOP_BAND).max(0.0) - TOP_BAND / 2.0;
        1.0 - self.bias[0] * h(p[0])
            - self.bias[1] * h(p[1])
            - self.bias[2] * (2.0 * v - 1.0)
            - self.top * t
            - self.side * (2.0 * u - 1.0)
    }

    /// Whether [`Self::edge_factor`] can differ from 1.
    fn corrects(&self) -> bool {
        self.bias != [0.0; 3] || self.top != 0.0 || self.side != 0.0
    }

    fn weight_of(&self, d2: f64) -> f64 {
        if d2 < self.reach * self.reach {
            self.weight_in_reach(d2)
        } else {
            0.0
        }
    }

    /// [`Self::weight_of`] for `d2` below the reach squared.
    #[inline(always)]
    fn weight_in_reach(&self, d2: f64) -> f64 {
        (1.0 - d2.sqrt() * self.inv_reach).powi(ALPHA)
    }

    /// Settles row `y`: exactly `n` points in each of its pixels, stored as
    /// the row's points and final points. Returns the number of top-ups
    /// (darts closer than the sweep's radius) it needed.
    pub(crate) fn thin_row<R: Rng + ?Sized>(
        &mut self,
        window: &mut Window,
        y: usize,
        (width, height): (usize, usize),
        rng: &mut R,
    ) -> usize {
        let band_rows = if y + 1 < height && window.holds_row(y + 1) {
            2
        } else {
            1
        };
        self.gather(window, y, width, band_rows);
        self.kill_conflicts(y, width);
        let mut top_ups = 0;
        // A dart may, as a last resort, take a point from a pixel of the
        // row already mended, which then gets mended again on the next
        // pass; the last pass may not, so it ends the row.
        for pass in 0..MEND_PASSES {
            let mut short = false;
            for x in 0..width {
                while self.count.get(x).is_some_and(|&c| c < self.n) {
                    short = true;
                    let settled_ok = pass + 1 < MEND_PASSES;
                    top_ups += self.add_dart(window, (x, y), (width, band_rows), settled_ok, rng);
                }
            }
            if !short {
                break;
            }
        }
        match self.method {
            ExactMethod::Eliminate => {
                // The local grid serves elimination only: the darts look
                // through the few pixels around theirs.
                self.index_cells(y, width, band_rows);
                self.eliminate(window, y, width, band_rows);
            }
            ExactMethod::Random => self.drop_at_random(width, rng),
        }
        self.store(window, y, width);
        top_ups
    }

    /// Copies the band's points, pixel by pixel.
    fn gather(&mut self, window: &Window, y: usize, width: usize, band_rows: usize) {
        for &i in &self.darts {
            if let Some(list) = self
                .pixel
                .get(i as usize)
                .and_then(|&x| self.dart_columns.get_mut(x as usize))
            {
                list.clear();
            }
        }
        self.darts.clear();
        self.indexed = false;
        self.dart_columns.resize_with(width, Vec::new);
        self.points.clear();
        self.pixel.clear();
        self.start.clear();
        for row in 0..band_rows {
            for x in 0..width {
                let b = row * width + x;
                self.start.push(self.points.len());
                let list = &window.slot(x, y + row).points;
                self.points.extend_from_slice(list);
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "band pixels: 2 · width < 2^32"
                )]
                self.pixel
                    .extend(core::iter::repeat_n(b as u32, list.len()));
            }
        }
        self.start.push(self.points.len());
        self.alive.clear();
        self.alive.resize(self.points.len(), true);
        self.count.clear();
        self.count.extend(self.start.windows(2).map(|w| match w {
            [a, b] => b - a,
            _ => 0,
        }));
    }

    /// The final points of the rows above row `y` near pixel column `x`
    /// (within `rows_up` pixels).
    fn final_above<'w>(
        &self,
        window: &'w Window,
        y: usize,
        x: usize,
        width: usize,
    ) -> impl Iterator<Item = &'w [f64; 2]> + 'w {
        let reach = self.rows_up;
        (y.saturating_sub(reach)..y)
            .filter(move |&yy| window.holds_row(yy))
            .flat_map(move |yy| {
                (x.saturating_sub(reach)..=(x + reach).min(width - 1))
                    .flat_map(move |xx| window.slot(xx, yy).kept.iter())
            })
    }

    /// Step 1: band points closer than `r` to a final point above are out.
    /// Only darts of row `y - 1` can be: two sweep points keep `r`, and
    /// `r < 1` (at most `sqrt(0.88 / (s·n))`, `s, n >= 1`) puts rows above
    /// `y - 1` out of reach; a band point within `r` of a dart lies in the
    /// dart's column or a next one.
    fn kill_conflicts(&mut self, y: usize, width: usize) {
        if self.darts_above.iter().all(Vec::is_empty) {
            return;
        }
        #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
        let top = y as f64;
        let r2 = self.radius_squared;
        let r = r2.sqrt();
        for i in 0..self.points.len() {
            let (Some(&p), Some(&b)) = (self.points.get(i), self.pixel.get(i)) else {
                continue;
            };
            if p[1] - top >= r {
                continue;
            }
            let x = b as usize % width;
            let near = self
                .darts_above
                .get(columns_around(x, width))
                .unwrap_or(&[])
                .iter()
                .flatten()
                .any(|q| distance_squared(&p, q) < r2);
            if near
                && let (Some(a), Some(c)) = (self.alive.get_mut(i), self.count.get_mut(b as usize))
                && *a
            {
                *a = false;
                *c -= 1;
            }
        }
    }

    /// The local grid cell of `p` (band row `y` at the top).
    fn cell_of(&self, p: &[f64; 2], y: usize, width: usize, band_rows: usize) -> (usize, usize) {
        #[expect(clippy::cast_precision_loss, reason = "small counts")]
        let (m, top) = (self.cells as f64, y as f64);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "saturating casts, clamped to the band"
        )]
        let cx = ((p[0] * m) as usize).min(width * self.cells - 1);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "saturating casts, clamped to the band"
        )]
        let cy = (((p[1] - top) * m).max(0.0) as usize).min(band_rows * self.cells - 1);
        (cx, cy)
    }

    /// Sorts the live points by local grid cell (a counting sort).
    fn index_cells(&mut self, y: usize, width: usize, band_rows: usize) {
        self.indexed = true;
        let columns = width * self.cells;
        let cells = columns * band_rows * self.cells;
        // Each point's cell, or `usize::MAX` for a dead one.
        let mut cell_of = core::mem::take(&mut self.cell_of);
        cell_of.clear();
        cell_of.extend(self.points.iter().zip(&self.alive).map(|(p, &alive)| {
            if alive {
                let (cx, cy) = self.cell_of(p, y, width, band_rows);
                cy * columns + cx
            } else {
                usize::MAX
            }
        }));
        self.cell_start.clear();
        self.cell_start.resize(cells + 1, 0);
        for &c in &cell_of {
            if let Some(count) = c.checked_add(1).and_then(|k| self.cell_start.get_mut(k)) {
                *count += 1;
            }
        }
        let mut sum = 0;
        for c in &mut self.cell_start {
            sum += *c;
            *c = sum;
        }
        self.cell_items.clear();
        self.cell_items.resize(sum, 0);
        // `cell_start[c]` walks up to `cell_start[c + 1]` as cell c fills;
        // shifted back afterwards.
        for (i, &c) in cell_of.iter().enumerate() {
            if let Some(at) = self.cell_start.get_mut(c) {
                #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
                if let Some(slot) = self.cell_items.get_mut(*at) {
                    *slot = i as u32;
                }
                *at += 1;
            }
        }
        self.cell_of = cell_of;
        for c in (1..=cells).rev() {
            let prev = self.cell_start.get(c - 1).copied().unwrap_or(0);
            if let Some(s) = self.cell_start.get_mut(c) {
                *s = prev;
            }
        }
        if let Some(s) = self.cell_start.first_mut() {
            *s = 0;
        }
    }

    /// Calls `visit` with the index of every gathered band point (dead
    /// ones included, darts not) in the band pixels of columns `x - 1` to
    /// `x + 1`, until it returns `false`: all that can lie within `r` of a point of column `x` in row
    /// `y`, as `r < 1`. The darts' search: a short pixel's darts look
    /// through these few pixels' points directly, where sorting the band
    /// into the local grid first cost more (3 % of exact mode's
    /// instructions at `n = 4`, random dropping).
    fn near_pixel(
        &self,
        x: usize,
        width: usize,
        band_rows: usize,
        mut visit: impl FnMut(u32) -> bool,
    ) {
        let columns = columns_around(x, width);
        for row in 0..band_rows {
            let first = row * width + columns.start();
            let last = row * width + columns.end();
            let (Some(&a), Some(&b)) = (self.start.get(first), self.start.get(last + 1)) else {
                continue;
            };
            #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
            for i in a..b {
                if !visit(i as u32) {
                    return;
                }
            }
        }
    }

    /// Calls `visit` with the index of every point indexed in the local
    /// grid within `cell_reach` cells of `p`'s cell (dead ones included:
    /// points die after indexing).
    fn near(
        &self,
        p: &[f64; 2],
        y: usize,
        width: usize,
        band_rows: usize,
        mut visit: impl FnMut(u32),
    ) {
        let (cx, cy) = self.cell_of(p, y, width, band_rows);
        let columns = width * self.cells;
        let rows = band_rows * self.cells;
        let k = self.cell_reach;
        for yy in cy.saturating_sub(k)..=(cy + k).min(rows - 1) {
            let first = yy * columns + cx.saturating_sub(k);
            let last = yy * columns + (cx + k).min(columns - 1);
            let (Some(&a), Some(&b)) = (self.cell_start.get(first), self.cell_start.get(last + 1))
            else {
                continue;
            };
            for &i in self.cell_items.get(a..b).unwrap_or(&[]) {
                visit(i);
            }
        }
    }

    /// Step 2: one more point for the short pixel `(x, y)`; 1 if it had to
    /// be a top-up, else 0.
    fn add_dart<R: Rng + ?Sized>(
        &mut self,
        window: &mut Window,
        (x, y): (usize, usize),
        (width, band_rows): (usize, usize),
        settled_ok: bool,
        rng: &mut R,
    ) -> usize {
        #[expect(clippy::cast_precision_loss, reason = "pixel indices < 2^32")]
        let (fx, fy) = (x as f64, y as f64);
        let mut darts = [[0.0; 2]; DARTS_MORE];
        let mut thrown = 0;
        let mut near = core::mem::take(&mut self.dart_scratch);
        self.gather_blockers(window, (x, y), (width, band_rows), &mut near);
        // Strict with a few darts, then lenient with them, then lenient
        // with many, then (if allowed) taking from any pixel: most short
        // pixels take the first.
        let stages = [
            (Take::Excess, DARTS),
            (Take::Unsettled, DARTS),
            (Take::Unsettled, DARTS_MORE),
            (Take::Any, DARTS_MORE),
        ];
        for (take, count) in stages {
            if take == Take::Any && !settled_ok {
                continue;
            }
            throw_darts(
                darts.get_mut(thrown..count).unwrap_or(&mut []),
                (fx, fy),
                rng,
            );
            thrown = thrown.max(count);
            let found = self.best_dart(&near, darts.get(..count).unwrap_or(&[]), (x, y), take);
            if let Some((d, b)) = found {
                self.dart_scratch = near;
                self.take_dart(window, d, b, x);
                return 0;
            }
        }
        let take = if settled_ok {
            Take::Any
        } else {
            Take::Unsettled
        };
        for _ in 0..RESCUE_ROUNDS {
            throw_darts(&mut darts, (fx, fy), rng);
            if let Some((d, b)) = self.best_dart(&near, &darts, (x, y), take) {
                self.dart_scratch = near;
                self.take_dart(window, d, b, x);
                return 0;
            }
        }
        self.dart_scratch = near;
        // A top-up: the dart farthest from every point that stays, looked
        // for as far as the local grid reaches (built for the first top-up
        // of the band: they are rare).
        if !self.indexed {
            self.index_cells(y, width, band_rows);
        }
        let mut best = (f64::NEG_INFINITY, [fx, fy]);
        for d in &darts {
            let mut nearest = self
                .final_above(window, y, x, width)
                .map(|q| distance_squared(d, q))
                .fold(f64::INFINITY, f64::min);
            self.near(d, y, width, band_rows, |i| {
                if self.alive.get(i as usize) == Some(&true)
                    && let Some(q) = self.points.get(i as usize)
                {
                    nearest = nearest.min(distance_squared(d, q));
                }
            });
            for &i in &self.darts {
                if let Some(q) = self.points.get(i as usize) {
                    nearest = nearest.min(distance_squared(d, q));
                }
            }
            if nearest > best.0 {
                best = (nearest, *d);
            }
        }
        self.push_dart(best.1, x);
        1
    }

    /// The dart of `darts` with the fewest blockers that `take` may remove
    /// (at most [`MAX_BLOCKERS`]), the first such; `None` if none can go.
    fn best_dart(
        &self,
        near: &DartScratch,
        darts: &[[f64; 2]],
        (x, y): (usize, usize),
        take: Take,
    ) -> Option<([f64; 2], Blockers)> {
        let mut best: Option<([f64; 2], Blockers)> = None;
        for d in darts {
            // Only a dart with fewer blockers than the best so far can be
            // taken: the search gives up on the others early.
            let cap = best.map_or(MAX_BLOCKERS, |(_, c)| c.count.saturating_sub(1));
            if let Some(b) = self.blockers(near, d, (x, y), (take, cap))
                && best.is_none_or(|(_, c)| b.count < c.count)
            {
                best = Some((*d, b));
                if b.count == 0 {
                    break;
                }
            }
        }
        best
    }

    /// What the darts of the short pixel `(x, y)` are checked against, into
    /// `near` ([`DartScratch`]): gathered once per dart placed, since
    /// nothing it holds changes until one is.
    fn gather_blockers(
        &self,
        window: &Window,
        (x, y): (usize, usize),
        (width, band_rows): (usize, usize),
        near: &mut DartScratch,
    ) {
        near.darts.clear();
        near.darts.extend(
            self.dart_columns
                .get(columns_around(x, width))
                .unwrap_or(&[])
                .iter()
                .flatten()
                .filter_map(|&i| self.points.get(i as usize).copied()),
        );
        near.above.clear();
        near.above
            .extend(self.final_above(window, y, x, width).copied());
        near.near.clear();
        self.near_pixel(x, width, band_rows, |i| {
            if self.alive.get(i as usize) == Some(&true)
                && let (Some(&q), Some(&b)) =
                    (self.points.get(i as usize), self.pixel.get(i as usize))
            {
                near.near.push((q, i, b));
            }
            true
        });
    }

    /// Places dart `d` in column `x`, its blockers `b` removed.
    fn take_dart(&mut self, window: &mut Window, d: [f64; 2], b: Blockers, x: usize) {
        for &i in b.items.get(..b.count).unwrap_or(&[]) {
            self.kill(i as usize);
        }
        self.push_dart(d, x);
        // The sweep's later points keep their distance from it. Its cell
        // can only hold a point that is out (a blocker, or one thinned
        // before): two points in one cell are closer than r.
        window.replace(d);
    }

    fn kill(&mut self, i: usize) {
        if let (Some(a), Some(&b)) = (self.alive.get_mut(i), self.pixel.get(i))
            && *a
        {
            *a = false;
            if let Some(c) = self.count.get_mut(b as usize) {
                *c -= 1;
            }
        }
    }

    fn push_dart(&mut self, d: [f64; 2], x: usize) {
        #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
        self.darts.push(self.points.len() as u32);
        #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
        if let Some(list) = self.dart_columns.get_mut(x) {
            list.push(self.points.len() as u32);
        }
        self.points.push(d);
        #[expect(clippy::cast_possible_truncation, reason = "x < width < 2^32")]
        self.pixel.push(x as u32);
        self.alive.push(true);
        if let Some(c) = self.count.get_mut(x) {
            *c += 1;
        }
    }

    /// The band points closer than `r` to dart `d` in pixel `(x, y)`, if
    /// they may all be removed: each in another pixel, which `take` allows
    /// to lose it, at most `cap` (and [`MAX_BLOCKERS`]); and no final point
    /// above or dart is that close. `near` holds what these are looked for
    /// among ([`Self::best_dart`]).
    fn blockers(
        &self,
        near: &DartScratch,
        d: &[f64; 2],
        (x, y): (usize, usize),
        (take, cap): (Take, usize),
    ) -> Option<Blockers> {
        let r2 = self.radius_squared;
        if near.darts.iter().any(|q| distance_squared(d, q) < r2) {
            return None;
        }
        #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
        if d[1] - (y as f64) < r2.sqrt() && near.above.iter().any(|q| distance_squared(d, q) < r2) {
            return None;
        }
        let mut found = Blockers {
            count: 0,
            items: [0; MAX_BLOCKERS],
        };
        for &(q, i, b32) in &near.near {
            if distance_squared(d, &q) >= r2 {
                continue;
            }
            let b = b32 as usize;
            // Points this dart already takes from pixel b, this one included.
            let taken = 1 + found
                .items
                .get(..found.count)
                .unwrap_or(&[])
                .iter()
                .filter(|&&j| self.pixel.get(j as usize) == Some(&b32))
                .count();
            let left = self.count.get(b).copied().unwrap_or(0);
            let may = b != x
                && found.count < cap.min(MAX_BLOCKERS)
                && match take {
                    Take::Excess => left >= self.n + taken,
                    Take::Unsettled => left >= self.n + taken || b > x,
                    Take::Any => true,
                };
            match (may, found.items.get_mut(found.count)) {
                (true, Some(slot)) => {
                    *slot = i;
                    found.count += 1;
                }
                _ => return None,
            }
        }
        Some(found)
    }

    /// Step 3's starting weights, without the final points above: for
    /// every point elimination may remove (`over`), the sum of its weight
    /// terms over the live points closer than `2rₑ`, each scaled by the
    /// other end's pixel's `scale`, added in the order of the local grid
    /// (`cell_items`), which is the order [`Self::near`] meets them in.
    /// Each pair is found once, from the end that comes first in that
    /// order, looking only forward: the rest of its own cell row, then the
    /// cell rows below; its term (`distance_squared` is the same both ways
    /// round, bit for bit) is added to both ends at once. Each end still
    /// gets its terms in grid order: first those of the pairs where it is
    /// the later end, as the earlier ends come, then its own. Points of row
    /// `y + 1` are never removed here, so the pairs found from them (all
    /// within row `y + 1`, which comes last in the grid) are not looked for.
    fn pair_weights(&mut self, width: usize, band_rows: usize) {
        let n = self.n;
        self.over.clear();
        self.over
            .extend(self.alive.iter().zip(&self.pixel).map(|(&a, &b)| {
                a && (b as usize) < width && self.count.get(b as usize).is_some_and(|&c| c > n)
            }));
        self.scale.clear();
        self.scale
            .extend(self.count.iter().enumerate().map(|(b, &c)| {
                if b >= width && c > n {
                    #[expect(clippy::cast_precision_loss, reason = "counts per pixel")]
                    let share = n as f64 / c as f64;
                    share
                } else {
                    1.0
                }
            }));
        let reach2 = self.reach * self.reach;
        let columns = width * self.cells;
        let rows = band_rows * self.cells;
        let k = self.cell_reach;
        // The live points in grid order, so that a cell row's points are
        // read in sequence, without the two indirections (point, pixel).
        let mut by_cell = core::mem::take(&mut self.by_cell);
        by_cell.clear();
        by_cell.extend(self.cell_items.iter().map(|&i| {
            let i = i as usize;
            let p = self.points.get(i).copied().unwrap_or([0.0; 2]);
            let over = self.over.get(i) == Some(&true);
            let scale = self
                .pixel
                .get(i)
                .and_then(|&b| self.scale.get(b as usize))
                .copied()
                .unwrap_or(1.0);
            ByCell {
                p,
                over,
                scale,
                weight: 0.0,
            }
        }));
        for (a, &i) in self.cell_items.iter().enumerate() {
            let Some(&c) = self.cell_of.get(i as usize) else {
                continue;
            };
            let (cx, cy) = (c % columns, c / columns);
            if cy >= self.cells {
                // Row `y + 1` from here on.
                break;
            }
            let Some(&ByCell {
                p, over: over_i, ..
            }) = by_cell.get(a)
            else {
                continue;
            };
            let (x0, x1) = (cx.saturating_sub(k), (cx + k).min(columns - 1));
            for yy in cy..=(cy + k).min(rows - 1) {
                let first = if yy == cy {
                    a + 1
                } else {
                    self.cell_start.get(yy * columns + x0).copied().unwrap_or(0)
                };
                let last = self
                    .cell_start
                    .get(yy * columns + x1 + 1)
                    .copied()
                    .unwrap_or(0);
                let Some((head, tail)) = by_cell.split_at_mut_checked(first) else {
                    continue;
                };
                let (Some(this), Some(others)) =
                    (head.get_mut(a), tail.get_mut(..last.saturating_sub(first)))
                else {
                    continue;
                };
                // `i` lies in row `y`, so its own terms count in full on
                // its neighbours' weights (scale 1). Without a branch: a
                // pair out of reach, or with neither end removable, adds a
                // term of +0.0, which leaves every
                // sum's bits as they are (sums of terms >= 0 are never
                // -0.0).
                let mut w = this.weight;
                for q in others {
                    let d2 = distance_squared(&p, &q.p);
                    let term = self.weight_in_reach(d2);
                    let t = if d2 < reach2 && (over_i || q.over) {
                        term
                    } else {
                        0.0
                    };
                    w += t * q.scale;
                    q.weight += t;
                }
                this.weight = w;
            }
        }
        // Back to the points' order; only removable points' weights are
        // read again.
        let mut weight = core::mem::take(&mut self.weight);
        for (&i, q) in self.cell_items.iter().zip(&by_cell) {
            if q.over
                && let Some(slot) = weight.get_mut(i as usize)
            {
                *slot = q.weight;
            }
        }
        self.by_cell = by_cell;
        self.weight = weight;
    }

    /// The live points elimination may remove (`over`) closer than `2rₑ`
    /// to point `i` (one of them), with their weight terms, into
    /// `neighbours`: what `i`'s removal takes from their weights (the same
    /// terms, bit for bit, as [`Self::pair_weights`] added: `i`'s scale
    /// is 1).
    fn neighbours_of(&mut self, i: usize, y: usize, width: usize, band_rows: usize) {
        let mut found = core::mem::take(&mut self.neighbours);
        found.clear();
        if let Some(&p) = self.points.get(i) {
            let reach2 = self.reach * self.reach;
            self.near(&p, y, width, band_rows, |j| {
                if j as usize != i
                    && self.alive.get(j as usize) == Some(&true)
                    && self.over.get(j as usize) == Some(&true)
                    && let Some(q) = self.points.get(j as usize)
                {
                    let d2 = distance_squared(&p, q);
                    if d2 < reach2 {
                        found.push((j, self.weight_of(d2)));
                    }
                }
            });
        }
        self.neighbours = found;
    }

    /// Step 3, [`ExactMethod::Eliminate`]: weighted sample elimination of
    /// row `y` until each of its pixels is down to `n`, the band's other
    /// points and the final points above counted as neighbours.
    fn eliminate(&mut self, window: &Window, y: usize, width: usize, band_rows: usize) {
        #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
        let top = y as f64;
        let total = self.points.len();
        self.weight.clear();
        self.weight.resize(total, 0.0);
        self.factor.clear();
        self.factor.resize(total, 1.0);
        self.pair_weights(width, band_rows);
        let mut entries = core::mem::take(&mut self.sorted);
        entries.clear();
        self.heap.clear();
        for i in 0..total {
            let (Some(&p), Some(true), Some(&b), Some(&w)) = (
                self.points.get(i),
                self.over.get(i).copied(),
                self.pixel.get(i),
                self.weight.get(i),
            ) else {
                continue;
            };
            let mut w = w;
            if p[1] - top < self.reach {
                let x = b as usize % width;
                w += if y > 0 && self.strip_row == Some(y - 1) && window.holds_row(y - 1) {
                    self.strip
                        .get(columns_around(x, width))
                        .unwrap_or(&[])
                        .iter()
                        .flatten()
                        .map(|q| self.weight_of(distance_squared(&p, q)))
                        .sum::<f64>()
                } else {
                    self.final_above(window, y, x, width)
                        .map(|q| self.weight_of(distance_squared(&p, q)))
                        .sum::<f64>()
                };
            }
            let f = self.edge_factor(i);
            if let (Some(slot), Some(g)) = (self.weight.get_mut(i), self.factor.get_mut(i)) {
                *slot = w;
                *g = f;
            }
            #[expect(clippy::cast_possible_truncation, reason = "band points < 2^32")]
            entries.push(Entry::new(w * f, i as u32));
        }
        // Largest first. Most entries are popped before row `y` is done
        // (about 1.1 pops an entry at `n = 4`): sorting them once costs
        // less than a heap of them all; the heap holds only the weights
        // lowered since, and each pop takes the larger of the two fronts.
        // All keys differ (the index is part of them), so the pops come in
        // the order one heap of everything gave.
        entries.sort_unstable_by(|a, b| b.cmp(a));
        self.sorted = entries;
        let mut next = 0;
        // Pixels of row `y` still over `n`: the loop ends when none is.
        let mut left = self
            .count
            .get(..width)
            .unwrap_or(&[])
            .iter()
            .filter(|&&c| c > self.n)
            .count();
        while left > 0
            && let Some(entry) = match (self.sorted.get(next), self.heap.peek()) {
                (Some(&e), Some(&h)) if e > h => {
                    next += 1;
                    Some(e)
                }
                (Some(&e), None) => {
                    next += 1;
                    Some(e)
                }
                _ => self.heap.pop(),
            }
        {
            let (w, i) = entry.parts();
            let i = i as usize;
            let (Some(&is_alive), Some(&current), Some(&f), Some(&b)) = (
                self.alive.get(i),
                self.weight.get(i),
                self.factor.get(i),
                self.pixel.get(i),
            ) else {
                continue;
            };
            if !is_alive
                || w != current * f
                || self.count.get(b as usize).is_none_or(|&c| c <= self.n)
            {
                continue;
            }
            self.kill(i);
            if (b as usize) < width && self.count.get(b as usize) == Some(&self.n) {
                left -= 1;
            }
            // Its neighbours are looked up again, rather than kept from
            // the start: about one point in five is removed.
            self.neighbours_of(i, y, width, band_rows);
            for &(j32, t) in &self.neighbours {
                let j = j32 as usize;
                if let Some(wj) = self.weight.get_mut(j) {
                    *wj -= t;
                    let wj = *wj;
                    let still_over = self
                        .pixel
                        .get(j)
                        .and_then(|&c| self.count.get(c as usize))
                        .is_some_and(|&c| c > self.n);
                    if still_over && let Some(&f) = self.factor.get(j) {
                        self.heap.push(Entry::new(wj * f, j32));
                    }
                }
            }
        }
    }

    /// Step 3, [`ExactMethod::Random`]: each pixel of row `y` drops its
    /// excess points uniformly at random.
    fn drop_at_random<R: Rng + ?Sized>(&mut self, width: usize, rng: &mut R) {
        for x in 0..width {
            let (Some(&a), Some(&z)) = (self.start.get(x), self.start.get(x + 1)) else {
                continue;
            };
            // Darts only go to short pixels, which end at n: an excess
            // pixel's live points are all among its gathered ones.
            if self.count.get(x).is_some_and(|&c| c > self.n) && self.corrects() {
                let mut factors = core::mem::take(&mut self.factor);
                factors.clear();
                factors.extend((a..z).map(|i| self.edge_factor(i)));
                self.factor = factors;
            }
            while let Some(&c) = self.count.get(x)
                && c > self.n
            {
                if !self.corrects() {
                    let mut k = below(rng, c);
                    for i in a..z {
                        if self.alive.get(i) == Some(&true) {
                            if k == 0 {
                                self.kill(i);
                                break;
                            }
                            k -= 1;
                        }
                    }
                } else {
                    let live = |i: usize| self.alive.get(i) == Some(&true);
                    let factor = |i: usize| self.factor.get(i - a).copied().unwrap_or(1.0);
                    let total: f64 = (a..z).filter(|&i| live(i)).map(factor).sum();
                    let mut t = unit(rng) * total;
                    let mut last = None;
                    for i in a..z {
                        if live(i) {
                            last = Some(i);
                            t -= factor(i);
                            if t < 0.0 {
                                break;
                            }
                        }
                    }
                    if let Some(i) = last {
                        self.kill(i);
                    }
                }
            }
        }
    }

    /// Row `y`'s live points, in generation order (darts last), become its
    /// final points, which are also what the pixels emit.
    fn store(&mut self, window: &mut Window, y: usize, width: usize) {
        for x in 0..width {
            let (Some(&a), Some(&z)) = (self.start.get(x), self.start.get(x + 1)) else {
                continue;
            };
            if let Some(slot) = window.slot_mut(x, y) {
                // The sweep's list is spent; the pixel is emitted from
                // `kept`.
                slot.points.clear();
                slot.kept.clear();
                for i in a..z {
                    if self.alive.get(i) == Some(&true)
                        && let Some(&p) = self.points.get(i)
                    {
                        slot.kept.push(p);
                    }
                }
            }
        }
        for list in &mut self.darts_above {
            list.clear();
        }
        self.darts_above.resize_with(width, Vec::new);
        for &i in &self.darts {
            let i = i as usize;
            if self.alive.get(i) == Some(&true)
                && let (Some(&p), Some(&x)) = (self.points.get(i), self.pixel.get(i))
                && let Some(slot) = window.slot_mut(x as usize, y)
            {
                slot.kept.push(p);
                if let Some(list) = self.darts_above.get_mut(x as usize) {
                    list.push(p);
                }
            }
        }
        self.strip_row = None;
        if self.method == ExactMethod::Eliminate && self.rows_up == 1 {
            // Anything lower lies more than `2rₑ` above every point of the
            // rows below (which start at `y + 1`, up to rounding: hence
            // the margin, far above it).
            #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
            let low = (y + 1) as f64 - self.reach - 1e-6;
            self.strip.resize_with(width, Vec::new);
            for (x, list) in self.strip.iter_mut().enumerate() {
                list.clear();
                list.extend(
                    window
                        .slot(x, y)
                        .kept
                        .iter()
                        .filter(|q| q[1] >= low)
                        .copied(),
                );
            }
            self.strip_row = Some(y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::random::seeded_rng;

    /// Elimination's starting weights are, for each point of an over-full
    /// pixel of row `y`, the sum over the live band points closer than
    /// `2rₑ` of their terms, scaled by `n / c` for those of row `y + 1`
    /// (`c` their pixel's live points, when over `n`); and nothing else
    /// gets a weight. A brute-force sum over every pair, against
    /// `pair_weights`' grid search, which looks forward from row `y` only.
    #[test]
    fn starting_weights_are_the_scaled_sums_over_the_band() {
        let (n, width, y, band_rows) = (4, 12, 7, 2);
        let mut exact = Exact::new(n, ExactMethod::Eliminate, 0.3, None);
        let mut rng = seeded_rng(11);
        // Pixels with 2 to 9 points, so some are short, some at n, most over.
        for row in 0..band_rows {
            for x in 0..width {
                exact.start.push(exact.points.len());
                let m = 2 + below(&mut rng, 8);
                for _ in 0..m {
                    #[expect(clippy::cast_precision_loss, reason = "small")]
                    let p = [x as f64 + unit(&mut rng), (y + row) as f64 + unit(&mut rng)];
                    exact.points.push(p);
                    #[expect(clippy::cast_possible_truncation, reason = "small")]
                    exact.pixel.push((row * width + x) as u32);
                }
            }
        }
        exact.start.push(exact.points.len());
        let total = exact.points.len();
        // Every seventh point dead, as a dart's blocker would be.
        exact.alive = (0..total).map(|i| i % 7 != 3).collect();
        exact.count = vec![0; band_rows * width];
        for (i, &b) in exact.pixel.iter().enumerate() {
            if exact.alive[i] {
                exact.count[b as usize] += 1;
            }
        }
        exact.index_cells(y, width, band_rows);
        exact.weight = vec![0.0; total];
        exact.pair_weights(width, band_rows);
        let (mut checked, mut scaled) = (0, 0);
        for i in 0..total {
            let b = exact.pixel[i] as usize;
            let over = exact.alive[i] && b < width && exact.count[b] > n;
            assert_eq!(exact.over[i], over, "point {i}");
            if !over {
                assert_eq!(exact.weight[i], 0.0, "point {i}");
                continue;
            }
            let mut sum = 0.0;
            for j in (0..total).filter(|&j| j != i && exact.alive[j]) {
                let c = exact.pixel[j] as usize;
                let t = exact.weight_of(distance_squared(&exact.points[i], &exact.points[j]));
                #[expect(clippy::cast_precision_loss, reason = "small counts")]
                let s = if c >= width && exact.count[c] > n {
                    n as f64 / exact.count[c] as f64
                } else {
                    1.0
                };
                if t > 0.0 && s < 1.0 {
                    scaled += 1;
                }
                sum += t * s;
            }
            assert!(
                (exact.weight[i] - sum).abs() <= 1e-12 * sum.max(1.0),
                "point {i}: {} against {sum}",
                exact.weight[i]
            );
            checked += 1;
        }
        assert!(
            checked > 30 && scaled > 10,
            "{checked} weights, {scaled} scaled terms"
        );
    }

    /// The packed heap entry orders as `total_cmp` on the weight, the
    /// lower index first on ties, and gives back what it was made from.
    #[test]
    fn entry_order_is_the_weights_then_the_lower_index() {
        let weights = [
            f64::NEG_INFINITY,
            -3.5,
            -1e-300,
            -0.0,
            0.0,
            5e-324,
            1e-300,
            0.25,
            0.250_000_000_000_000_06,
            7.0,
            f64::INFINITY,
        ];
        let indices = [0, 1, 7, u32::MAX - 1, u32::MAX];
        let entries: Vec<(f64, u32)> = weights
            .iter()
            .flat_map(|&w| indices.iter().map(move |&i| (w, i)))
            .collect();
        for &(w, i) in &entries {
            let (w2, i2) = Entry::new(w, i).parts();
            assert_eq!((w2.to_bits(), i2), (w.to_bits(), i));
            for &(v, j) in &entries {
                let expected = w.total_cmp(&v).then(j.cmp(&i));
                assert_eq!(
                    Entry::new(w, i).cmp(&Entry::new(v, j)),
                    expected,
                    "{w} {i} {v} {j}"
                );
            }
        }
    }
}
