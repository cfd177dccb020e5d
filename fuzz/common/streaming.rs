//! The `streaming` fuzz target's logic (the streaming mode, `bridson::Tiled`),
//! shared with `tests/fuzz_corpus.rs`.
//!
//! Plain Rust on std and `bridson` only (no `arbitrary`), so that the
//! regular test suite replays the committed corpus through exactly the
//! assertions the fuzzer runs. It shares the byte reader
//! (`fuzz/common/bytes.rs`) and the naive oracle (`tests/common/mod.rs`)
//! with the `batch` target, and no code with the library; the including
//! crate declares both as `mod bytes;` and `mod common;`.
//!
//! Every byte string decodes to a full set of streaming inputs: reads past
//! the end give zeros. Each value has several decodings picked by a few
//! bits, so both hostile inputs (raster sides 0 or up to `u32::MAX`, raw
//! `f64` bit patterns for the radius or the samples per pixel: NaN,
//! infinities, subnormals, values one ulp either side of a limit; exact
//! counts 0 or up to `u32::MAX`; `k` 0 or huge; tiny and huge budgets) and
//! useful ones (rasters up to 24 × 24, radii of 0.1 to 4 pixels, up to 16
//! samples per pixel, 0 to 8 exact points per pixel) are common.
//!
//! For every input: `build()` either fails with the error the inputs call
//! for, or succeeds, keeping the raster, the radius it documents and its
//! budget. Then, if the stream fits the limits below (lowering `k` and the
//! number of pixels pulled first, never the raster), it is rebuilt with
//! `k <= 64` and a smaller budget, and at most 1024 pixels are pulled: they
//! must come in scan order, every point finite and inside its pixel
//! (`x <= p[0] < x + 1`, `y <= p[1] < y + 1`), and the union of all pulled
//! points must have no pair closer than the radius (exact mode: exactly
//! `n` points in every pixel, and the distance only where no top-up dart
//! was placed, as `TiledBuilder::exact` documents).

use crate::bytes::{Bytes, log_uniform, ulps};
use crate::common;
use bridson::{
    Candidates, DEFAULT_ATTEMPTS, DEFAULT_MAX_WINDOW_BYTES, EXACT_ATTEMPTS, Error, MAX_ATTEMPTS,
    Scheme, Tiled,
};
use core::f64::consts::SQRT_2;

/// Most pixels pulled per execution.
const PIXEL_LIMIT: u64 = 1024;

/// Most attempts `k` used for generation. Larger `k` is still passed to
/// `build()`, but a stream costs about `2·n·k` candidate throws.
const ATTEMPT_LIMIT: u32 = 64;

/// Window budget used for generation: allocating and zeroing a 256 MiB
/// window per execution would make fuzzing crawl. The inputs' own budget is
/// checked by `build()` first.
const BUDGET_LIMIT: u64 = 4 << 20;

/// Most work per execution, in elementary steps (a distance computed, a
/// dart thrown), as estimated by [`cost`]: a few milliseconds.
const COST_LIMIT: f64 = 3e6;

/// Points per `r²` the docs give for `per_pixel` (`r = sqrt(d / n)`) at
/// `k = 30`; at other `k` the docs scale it by count mode's measured
/// factor, which lies in [`DENSITY_FACTOR`].
const DENSITY_ANNULUS: f64 = 0.62;
const DENSITY_SPHERE: f64 = 0.88;
/// The range of count mode's density factor over `k` in 2-D (its table's
/// ends, `k = 3` and `k = 1000`, rounded outward).
const DENSITY_FACTOR: core::ops::RangeInclusive<f64> = 0.80..=1.12;
/// The radii `build()` accepts, as its docs give them.
const VALID_RADIUS: core::ops::RangeInclusive<f64> = 1e-150..=1e150;

/// Values that sit on or next to a documented limit, for the radius and
/// the samples per pixel.
const SPECIAL: [f64; 20] = [
    0.0,
    -0.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    5e-324,
    -5e-324,
    f64::MIN_POSITIVE,
    1e-300,
    1e-151,
    1e-150,
    1e150,
    1e151,
    1e300,
    f64::MAX,
    -1.0,
    1e-6,
    1e6,
    1e9,
    0.62e300,
];

fn special(b: &mut Bytes<'_>) -> f64 {
    SPECIAL[usize::from(b.u8()) % SPECIAL.len()]
}

/// A raster side.
fn side(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 8 {
        0 => b.u32(),
        1 => [
            0,
            1,
            2,
            255,
            1000,
            1 << 16,
            1 << 20,
            1 << 31,
            u32::MAX - 1,
            u32::MAX,
        ][usize::from(b.u8()) % 10],
        _ => u32::from(b.u8() % 25),
    }
}

/// How the spacing is given.
#[derive(Clone, Copy, Debug)]
enum Spacing {
    Radius(f64),
    PerPixel(f64),
    /// Neither setter called.
    Missing,
}

fn radius(b: &mut Bytes<'_>) -> f64 {
    match b.u8() % 8 {
        0 => b.f64_bits(),
        1 => special(b),
        // A few ulps either side of a limit: the radius range, the finest
        // grid (65 536 cells per pixel), the tallest window (1e9 rows).
        2 => {
            let limit = [1e-150, 1e150, SQRT_2 / 65536.0, 1.25e8][usize::from(b.u8() % 4)];
            ulps(limit, i8::from_le_bytes([b.u8()]) % 3)
        }
        // Dyadic, 1/8 to 4 pixels: pixel and cell borders hit exactly.
        3 => 2f64.powi(2 - i32::from(b.u8() % 6)),
        _ => log_uniform(b, 0.1, 4.0),
    }
}

fn per_pixel(b: &mut Bytes<'_>) -> f64 {
    match b.u8() % 8 {
        0 => b.f64_bits(),
        1 => special(b),
        2 => 2f64.powi(i32::from(b.u8() % 8) - 3),
        _ => log_uniform(b, 0.05, 16.0),
    }
}

fn exact(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 8 {
        0 => b.u32(),
        1 => [0, 1, 1 << 16, 1 << 20, 1 << 28, 1 << 30, u32::MAX][usize::from(b.u8()) % 7],
        _ => u32::from(b.u8() % 9),
    }
}

/// `None`: not set (the default, 30).
fn attempts(b: &mut Bytes<'_>) -> Option<u32> {
    match b.u8() % 8 {
        0 => Some(b.u32()),
        1 => Some([0, 1, 2, u32::MAX, u32::MAX - 1, 1 << 31][usize::from(b.u8()) % 6]),
        2 => None,
        _ => Some(1 + u32::from(b.u8() % 64)),
    }
}

/// `None`: not set (the default, 256 MiB).
fn budget(b: &mut Bytes<'_>) -> Option<u64> {
    match b.u8() % 4 {
        0 => None,
        1 => Some(b.u64()),
        2 => Some(1 << (b.u8() % 64)),
        _ => Some(u64::from(b.u16())),
    }
}

/// The decoded inputs.
#[derive(Clone, Copy, Debug)]
struct Inputs {
    width: u32,
    height: u32,
    spacing: Spacing,
    exact: Option<u32>,
    scheme: Scheme,
    attempts: Option<u32>,
    candidates: Candidates,
    budget: Option<u64>,
    seed: u64,
    /// Also check that the seed reproduces the stream, through `next_into`.
    repeat: bool,
}

impl Inputs {
    fn decode(b: &mut Bytes<'_>) -> Self {
        let width = side(b);
        let height = side(b);
        let spacing = match b.u8() % 8 {
            0..=3 => Spacing::Radius(radius(b)),
            4 | 5 => Spacing::PerPixel(per_pixel(b)),
            _ => Spacing::Missing,
        };
        let exact = if b.u8().is_multiple_of(4) {
            Some(exact(b))
        } else {
            None
        };
        let scheme = if b.u8().is_multiple_of(2) {
            Scheme::Sweep
        } else {
            Scheme::Paper
        };
        let attempts = attempts(b);
        let candidates = if b.u8().is_multiple_of(2) {
            Candidates::Annulus
        } else {
            Candidates::Sphere
        };
        let budget = budget(b);
        let seed = b.u64();
        let repeat = b.u8().is_multiple_of(4);
        Self {
            width,
            height,
            spacing,
            exact,
            scheme,
            attempts,
            candidates,
            budget,
            seed,
            repeat,
        }
    }

    /// The builder for these inputs, with `k` and the budget replaced if
    /// given.
    fn builder(&self, k: Option<u32>, budget: Option<u64>) -> bridson::TiledBuilder {
        let mut builder = Tiled::builder(self.width, self.height)
            .scheme(self.scheme)
            .candidates(self.candidates);
        match self.spacing {
            Spacing::Radius(r) => builder = builder.radius(r),
            Spacing::PerPixel(n) => builder = builder.per_pixel(n),
            Spacing::Missing => {}
        }
        if let Some(n) = self.exact {
            builder = builder.exact(n);
        }
        if let Some(k) = k.or(self.attempts) {
            builder = builder.attempts(k);
        }
        if let Some(bytes) = budget.or(self.budget) {
            builder = builder.max_window_bytes(bytes);
        }
        builder
    }

    fn k(&self) -> u32 {
        let default = if self.exact.is_some() {
            EXACT_ATTEMPTS
        } else {
            DEFAULT_ATTEMPTS
        };
        self.attempts.unwrap_or(default)
    }

    /// `per_pixel`'s radius at `k = 30`, for a per-pixel spacing.
    fn radius_at_30(&self) -> Option<f64> {
        match (self.exact, self.spacing) {
            (None, Spacing::PerPixel(n)) if n > 0.0 => {
                let density = match self.candidates {
                    Candidates::Sphere => DENSITY_SPHERE,
                    _ => DENSITY_ANNULUS,
                };
                Some((density / n).sqrt())
            }
            _ => None,
        }
    }

    /// Where the radius lies for samples per pixel at `k != 30`, whose
    /// exact value the docs leave to count mode's density factor (within
    /// [`DENSITY_FACTOR`]): `r30 · sqrt(factor)` over the factor's range.
    fn radius_range(&self) -> Option<(f64, f64)> {
        if self.documented_radius().is_some() {
            return None;
        }
        let at30 = self.radius_at_30()?;
        Some((
            at30 * DENSITY_FACTOR.start().sqrt(),
            at30 * DENSITY_FACTOR.end().sqrt(),
        ))
    }

    /// Whether [`Error::InvalidRadius`] is a right answer though not the
    /// one [`Self::expected_error`] names: the radius range straddles a
    /// limit, so the radius may be out of range.
    fn radius_may_be_invalid(&self) -> bool {
        self.radius_range()
            .is_some_and(|(lo, hi)| lo < *VALID_RADIUS.start() || hi > *VALID_RADIUS.end())
    }

    fn budget(&self) -> u64 {
        self.budget.unwrap_or(DEFAULT_MAX_WINDOW_BYTES)
    }

    /// The radius the docs give, if they give it exactly: `Some(NaN)` for
    /// an invalid one, `None` in exact mode (about `2n` points per pixel:
    /// valid for every `n >= 1`).
    fn documented_radius(&self) -> Option<f64> {
        match (self.exact, self.spacing) {
            (Some(0), _) => Some(f64::NAN),
            (Some(_), _) => None,
            (None, Spacing::Radius(r)) => Some(r),
            // At another k the factor is count mode's: checked by range.
            (None, Spacing::PerPixel(n)) if n > 0.0 && self.k() != DEFAULT_ATTEMPTS => None,
            (None, Spacing::PerPixel(n)) if n > 0.0 => self.radius_at_30(),
            (None, Spacing::PerPixel(_) | Spacing::Missing) => Some(f64::NAN),
        }
    }

    /// The error `build()` must report before sizing the window, found
    /// independently, in the order the docs list them.
    fn expected_error(&self) -> Option<Error> {
        if self.width == 0 {
            return Some(Error::EmptyRaster { axis: 0 });
        }
        if self.height == 0 {
            return Some(Error::EmptyRaster { axis: 1 });
        }
        let per_pixel_ok = match (self.exact, self.spacing) {
            (Some(n), _) => n > 0,
            (None, Spacing::PerPixel(n)) => n > 0.0 && n.is_finite(),
            _ => true,
        };
        if !per_pixel_ok {
            return Some(Error::InvalidPerPixel);
        }
        if self
            .documented_radius()
            .is_some_and(|r| !VALID_RADIUS.contains(&r))
        {
            return Some(Error::InvalidRadius);
        }
        // Samples per pixel at another k: the radius is only known within
        // the density factor's range, but one wholly out of range is
        // refused before k is looked at (k = 0 included: the docs check
        // the radius first).
        if self
            .radius_range()
            .is_some_and(|(lo, hi)| hi < *VALID_RADIUS.start() || lo > *VALID_RADIUS.end())
        {
            return Some(Error::InvalidRadius);
        }
        if self.k() == 0 {
            return Some(Error::ZeroAttempts);
        }
        if self.k() > MAX_ATTEMPTS {
            return Some(Error::TooManyAttempts { max: MAX_ATTEMPTS });
        }
        None
    }
}

/// Decodes one set of inputs and checks them; panics (with a readable
/// message) if the streaming mode breaks its contract.
pub(crate) fn run(data: &[u8]) {
    let inputs = Inputs::decode(&mut Bytes::new(data));
    let ctx = format!("{inputs:?}");
    let expected = inputs.expected_error();
    let builder = inputs.builder(None, None);
    let tiled = match builder.build() {
        Ok(t) => t,
        // Checked after the raster and the samples per pixel, before k.
        Err(Error::InvalidRadius)
            if inputs.radius_may_be_invalid()
                && !matches!(
                    expected,
                    Some(Error::EmptyRaster { .. } | Error::InvalidPerPixel)
                ) =>
        {
            return;
        }
        Err(e) => {
            check_build_error(&ctx, e, expected, inputs.budget());
            return;
        }
    };
    assert_eq!(expected, None, "{ctx}: build() accepted it");
    let r = tiled.radius();
    let ctx = format!("{ctx}, radius {r:e} ({:#x})", r.to_bits());
    match inputs.documented_radius() {
        Some(documented) => assert_eq!(
            r.to_bits(),
            documented.to_bits(),
            "{ctx}: not the documented radius {documented:e}"
        ),
        None => {
            assert!(
                VALID_RADIUS.contains(&r),
                "{ctx}: exact mode's radius is out of range"
            );
            // per_pixel at k != 30: the density scaled by a factor below 1
            // for smaller k, above for larger.
            if let Some(at30) = inputs.radius_at_30() {
                let factor = (r / at30) * (r / at30);
                assert!(
                    DENSITY_FACTOR.contains(&factor) && (factor < 1.0) == (inputs.k() < 30),
                    "{ctx}: density factor {factor} at k = {}",
                    inputs.k()
                );
            }
        }
    }
    assert_eq!(
        (tiled.width(), tiled.height(), tiled.scheme()),
        (inputs.width, inputs.height, inputs.scheme),
        "{ctx}: settings not kept"
    );
    let bytes = tiled.window_bytes();
    assert!(
        bytes <= inputs.budget(),
        "{ctx}: a window of {bytes} bytes, over the budget"
    );
    // The budget is exact: the window's own size fits, a byte less does not.
    let at = |b: u64| inputs.builder(None, Some(b)).build();
    assert!(
        at(bytes).is_ok(),
        "{ctx}: a budget of exactly {bytes} bytes is refused"
    );
    if let Some(less) = bytes.checked_sub(1) {
        assert_eq!(
            at(less).err(),
            Some(Error::WindowTooLarge {
                needed: bytes,
                budget: less
            }),
            "{ctx}: a budget one byte short of the window"
        );
    }
    // With an explicit radius `k` does not size the window: lowering it
    // never breaks build(). With per_pixel or exact, the radius follows the
    // density at k, so a lower k may need a larger window.
    let Some((pixels, k)) = plan(&inputs, r) else {
        return;
    };
    let lowered = inputs.builder(Some(k), None).build();
    if inputs.exact.is_none() && matches!(inputs.spacing, Spacing::Radius(_)) {
        let Ok(lowered) = &lowered else {
            panic!("{ctx}: lowering k to {k} made build() fail: {lowered:?}");
        };
        assert_eq!(lowered.window_bytes(), bytes, "{ctx}: k changed the window");
    } else if lowered.is_err() {
        return;
    }
    // A smaller budget may not fit; then there is nothing to generate.
    let budget = inputs.budget().min(BUDGET_LIMIT);
    let Ok(small) = inputs.builder(Some(k), Some(budget)).build() else {
        return;
    };
    let ctx = format!("{ctx}, generated with k = {k}, {pixels} pixels");
    check_stream(&ctx, &inputs, &small, pixels);
}

/// `build()` failed: the error must be the one the inputs call for, or
/// `WindowTooLarge` with the inputs' budget and a `needed` above it.
fn check_build_error(ctx: &str, e: Error, expected: Option<Error>, budget: u64) {
    if let Some(expected) = expected {
        assert_eq!(e, expected, "{ctx}: the wrong error");
        return;
    }
    match e {
        Error::WindowTooLarge { needed, budget: b } => {
            assert_eq!(b, budget, "{ctx}: the wrong budget reported");
            // u64::MAX: no window can exist at any budget.
            assert!(
                needed > budget || needed == u64::MAX,
                "{ctx}: needed {needed} <= budget {budget}"
            );
        }
        other => panic!("{ctx}: build() gave {other:?} for valid settings"),
    }
}

/// At most how many points a `w × h` pixel region holds at radius `r`:
/// one per grid cell of side `r / √2`.
fn points_bound(w: f64, h: f64, r: f64) -> f64 {
    (w * SQRT_2 / r + 1.0).ceil() * (h * SQRT_2 / r + 1.0).ceil()
}

/// A rough upper bound on the work of pulling `pixels` pixels with `k`
/// attempts: candidate throws times the cells each scans, the naive pair
/// check, and exact mode's elimination.
fn cost(inputs: &Inputs, r: f64, pixels: u64, k: u32) -> f64 {
    let (w, h) = (f64::from(inputs.width), f64::from(inputs.height));
    let pulled = f64::from(u32::try_from(pixels).unwrap_or(u32::MAX));
    let rows_out = (pulled / w).ceil();
    // The sweep makes every point within 8r below the current row before
    // emitting it (see src/tiled/mod.rs), across the whole width.
    let rows_made = (rows_out + (8.0 * r).ceil() + 2.0).min(h);
    let made = points_bound(w, rows_made, r);
    let cells = (SQRT_2 / r).ceil().max(1.0);
    let reach = ((r * cells).ceil() + 1.0).min(w.max(h) * cells);
    let stencil = (2.0 * reach + 1.0).powi(2);
    let darts = f64::from(k) * (2.0 * made + w * rows_made);
    let (kept, thinning) = match inputs.exact {
        // Weights (a square root and a power each) over the neighbours in
        // about 15 pixels of about 2n points each, every row thinned twice;
        // and best-candidate darts where the sweep fell short.
        Some(n) => {
            let n = f64::from(n);
            (pulled * n, made * 100.0 * n)
        }
        None => (points_bound(w.min(pulled), rows_out, r), 0.0),
    };
    let streams = if inputs.repeat { 2.0 } else { 1.0 };
    streams * (darts * stencil + thinning) + kept * kept / 2.0
}

/// How many pixels to pull and with which `k`, within [`COST_LIMIT`]:
/// fewer whole rows first, then a smaller `k`, then part of a row; `None`
/// if even one pixel with `k = 1` costs too much.
fn plan(inputs: &Inputs, r: f64) -> Option<(u64, u32)> {
    let w = u64::from(inputs.width);
    let mut pixels = (w * u64::from(inputs.height)).min(PIXEL_LIMIT);
    let mut k = inputs.k().min(ATTEMPT_LIMIT);
    while cost(inputs, r, pixels, k) > COST_LIMIT {
        if pixels > w {
            pixels = (pixels / 2).max(w);
        } else if k > 1 {
            k /= 2;
        } else if pixels > 1 {
            pixels /= 2;
        } else {
            return None;
        }
    }
    Some((pixels, k))
}

/// Pulls `pixels` pixels of `tiled` and checks them, and the union.
fn check_stream(ctx: &str, inputs: &Inputs, tiled: &Tiled, pixels: u64) {
    let (w, h) = (u64::from(inputs.width), u64::from(inputs.height));
    let total = w * h;
    let mut stream = tiled.pixels_seeded(inputs.seed);
    assert_eq!(
        u64::try_from(stream.len()).ok(),
        Some(total),
        "{ctx}: len() before the first pixel"
    );
    let mut union = Vec::new();
    let mut counts = Vec::new();
    for i in 0..pixels {
        let Some(pixel) = stream.next() else {
            panic!("{ctx}: the stream ended after {i} of {total} pixels");
        };
        let expected = (i % w, i / w);
        assert_eq!(
            (u64::from(pixel.x), u64::from(pixel.y)),
            expected,
            "{ctx}: pixel #{i} out of scan order"
        );
        let (x, y) = (f64::from(pixel.x), f64::from(pixel.y));
        for p in &pixel.points {
            assert!(
                p.iter().all(|c| c.is_finite())
                    && x <= p[0]
                    && p[0] < x + 1.0
                    && y <= p[1]
                    && p[1] < y + 1.0,
                "{ctx}: pixel {expected:?} holds {p:?}, outside it"
            );
        }
        if let Some(n) = inputs.exact {
            assert_eq!(
                u64::try_from(pixel.points.len()).ok(),
                Some(u64::from(n)),
                "{ctx}: exact mode, pixel {expected:?}"
            );
        }
        counts.push(pixel.points.len());
        union.extend_from_slice(&pixel.points);
    }
    assert_eq!(
        u64::try_from(stream.len()).ok(),
        Some(total - pixels),
        "{ctx}: len() after {pixels} pixels"
    );
    if pixels == total {
        assert!(stream.next().is_none(), "{ctx}: a pixel past the end");
        assert!(stream.next().is_none(), "{ctx}: not fused");
    }
    // Exact mode keeps the radius only where no top-up dart was placed.
    let top_ups = stream.top_ups();
    assert!(
        inputs.exact.is_some() || top_ups == 0,
        "{ctx}: {top_ups} top-ups outside exact mode"
    );
    // The oracle's plain (non-periodic) distance: `d² = (a0 - b0)² +
    // (a1 - b1)²` in axis order, a pair violates iff `d² < r²`.
    let raster = [f64::from(inputs.width), f64::from(inputs.height)];
    if top_ups == 0
        && let Some(&(i, j, d2)) =
            common::min_distance_violations(&union, tiled.radius(), [0.0; 2], raster, [false; 2])
                .first()
    {
        panic!(
            "{ctx}: of {} points, #{i} {:?} and #{j} {:?} are closer than r: d² = {d2:e}, r² = {:e}",
            union.len(),
            union[i],
            union[j],
            tiled.radius() * tiled.radius()
        );
    }
    // The same seed gives the same stream, bit for bit; `next_into` agrees
    // with the iterator and drops its buffer's old contents.
    if inputs.repeat {
        let mut again = tiled.pixels_seeded(inputs.seed);
        let mut buffer = vec![[f64::NAN; 2]; 3];
        let mut start = 0;
        for (i, &count) in counts.iter().enumerate() {
            let at = again.next_into(&mut buffer);
            let i = u64::try_from(i).unwrap_or(u64::MAX);
            assert_eq!(
                at.map(|(x, y)| (u64::from(x), u64::from(y))),
                Some((i % w, i / w)),
                "{ctx}: next_into, pixel #{i}"
            );
            let first = &union[start..start + count];
            start += count;
            let bits = |ps: &[[f64; 2]]| -> Vec<[u64; 2]> {
                ps.iter().map(|p| p.map(f64::to_bits)).collect()
            };
            assert_eq!(
                bits(&buffer),
                bits(first),
                "{ctx}: the seed does not reproduce pixel #{i}"
            );
        }
    }
}
