//! The `camera` fuzz target's logic (the renderer-side API: the
//! `PixelSampler` trait, `PoissonPixelSampler` and `CameraPixels`), shared
//! with `tests/fuzz_corpus.rs`.
//!
//! Plain Rust on std and `bridson` only (no `arbitrary`), so that the
//! regular test suite replays the committed corpus through exactly the
//! assertions the fuzzer runs. It shares the byte reader
//! (`fuzz/common/bytes.rs`) and the naive oracle's distance
//! (`tests/common/mod.rs`) with the other targets, and no code with the
//! library; the including crate declares both as `mod bytes;` and
//! `mod common;`.
//!
//! Every byte string decodes to a full set of inputs: reads past the end
//! give zeros. The first byte picks one of two halves.
//!
//! **`PoissonPixelSampler`** (even first byte): a sample count (mostly 1 to
//! 8, sometimes up to 64; sometimes 0, just past [`MAX_SAMPLES_PER_PIXEL`]
//! or up to `u32::MAX`; rarely a large valid one, up to 4096, whose bank is
//! built once per thread: see [`new_sampler`]), a seed, an optional image
//! size (sides 0 to `u32::MAX`, mostly up to 24), then one operation
//! per input byte (at most [`OP_LIMIT`]): `start_pixel_sample` with pixels,
//! indices and dimensions biased to sit on either side of the limits,
//! `get_1d`, `get_2d`, `get_pixel_2d`, `camera_sample`, a draw from a
//! clone, a whole pixel at once, `with_resolution` and `with_seed`. A model
//! follows the sampler: `new` fails exactly as its `# Errors` says;
//! `start_pixel_sample` fails exactly as the trait's `# Errors` says (the
//! index first, as listed) and leaves the sampler where it was on error;
//! the getters follow the model after every operation (`get_1d` moves the
//! dimension on by 1, `get_2d` by 2, `camera_sample` by 3, all wrapping,
//! `get_pixel_2d` by 0); every value is finite, in `[0, 1)` and a multiple
//! of 2⁻³²; a value is a pure function of (seed, pixel, sample index,
//! dimension, kind), so every revisit, clone and seed switched back to
//! gives the same bits, `camera_sample` gives what `get_pixel_2d`,
//! `get_1d` and `get_2d` give at the same place, and (on a quarter of the
//! inputs, small counts) a fresh `new(spp, seed)` replays every value seen
//! for that seed; over all indices of one pixel, the film offsets, a 1-D
//! and a 2-D dimension are each `spp` points no two closer (on the unit
//! torus) than `min_distance_1d` (1-D) or `min_distance_2d` (2-D), which
//! are `None` exactly for one sample per pixel.
//!
//! **`CameraPixels`** (odd first byte): a `Tiled` raster up to 8 × 8,
//! exact mode (mostly 1 to 16 points a pixel; sometimes 0, up to 4096,
//! just past it, `u32::MAX`) or natural counts (a radius mostly of 0.3 to 4
//! pixels, or samples per pixel giving one; sometimes within a few ulps of
//! the `√2/64` limit or far below it), either scheme and candidate
//! distribution, a seed and `extra_dims` (mostly 0 to 8, sometimes up to
//! `u32::MAX`). `new` fails exactly as its `# Errors` says; otherwise, if
//! the stream is cheap (see [`EXACT_LIMIT`], [`RADIUS_LIMIT`],
//! [`EXTRA_LIMIT`]), every pixel comes in scan order, `len()` right, with
//! one sample per film point of the `Tiled` stream for the same seed (so
//! exactly `n` in exact mode), film offsets in `[0, 1)²` that put the
//! stream's point back exactly (`x + film[0]`), `extra_dims` further values
//! per sample, every value finite in `[0, 1)`, the pixel's time, lens and
//! each further dimension spread no closer than the pixel sampler's bound
//! for that count (see [`bounds`]), the same top-ups as the stream; and (a quarter of the
//! inputs) the seed reproduces the whole stream bit for bit.

use crate::bytes::{Bytes, log_uniform, ulps};
use crate::common;
use bridson::{
    CameraPixel, CameraPixels, CameraSample, Candidates, Error, MAX_SAMPLES_PER_PIXEL,
    PixelSampler, PoissonPixelSampler, Scheme, Tiled,
};
use core::f64::consts::SQRT_2;
use std::cell::RefCell;
use std::collections::HashMap;

/// Most operations per `PoissonPixelSampler` input: one per input byte up
/// to this many (bytes past the end decode as zeros: `get_1d`).
const OP_LIMIT: usize = 64;

/// `2³²`: values are multiples of its inverse.
const TWO_32: f64 = 4_294_967_296.0;

/// The largest count for which a whole pixel is drawn and its sets'
/// minimum distances checked, by all pairs.
const WHOLE_LIMIT: u32 = 256;

/// Most point pairs the whole-pixel checks of one input compare (three
/// sets of `spp (spp - 1) / 2` pairs per check): about a millisecond.
const PAIR_BUDGET: u64 = 300_000;

/// The largest count whose sampler is built by `new` for every input;
/// see [`new_sampler`].
const FRESH_LIMIT: u32 = 64;

/// The largest count for which a second bank is built (`new(spp, seed)`
/// again) to replay the values seen: a bank costs about 0.1 ms per sample
/// per pixel, optimised (see `PoissonPixelSampler`'s `# Performance`).
const TWIN_LIMIT: u32 = 16;

/// Exact mode: the largest `n` whose stream is pulled. `CameraPixels`
/// builds a bank for `n` (in the fuzz build about 2 ms plus 0.3 ms per
/// sample: 20 ms at 64) and exact mode thins about `1.16 n` points a
/// pixel.
const EXACT_LIMIT: u32 = 16;

/// Natural counts: the smallest radius whose stream is pulled. At 0.3 a
/// pixel holds up to 25 points and the counts met, each of which builds a
/// bank, vary from about 2 to 12.
const RADIUS_LIMIT: f64 = 0.3;

/// The largest `extra_dims` whose stream is pulled: a pixel of `c` samples
/// holds `c · extra_dims` further values.
const EXTRA_LIMIT: u32 = 64;

/// `CameraPixels::new`'s documented limit for natural counts, "a radius
/// below about 0.022 pixels": below [`ABOUT_LOW`] it must refuse, above
/// [`ABOUT_HIGH`] accept, in between either.
const ABOUT_LOW: f64 = 0.0213;
const ABOUT_HIGH: f64 = 0.0227;

/// Decodes one input and checks it; panics (with a readable message) if
/// the renderer-side API breaks its contract.
pub(crate) fn run(data: &[u8]) {
    let mut b = Bytes::new(data);
    if b.u8().is_multiple_of(2) {
        run_sampler(&mut b, data.len().min(OP_LIMIT));
    } else {
        run_camera(&mut b);
    }
}

// ---------------------------------------------------------------------
// PoissonPixelSampler
// ---------------------------------------------------------------------

/// A sample count: mostly (11 times in 16) 1 to 8, the ones `new` refuses
/// (0, just past [`MAX_SAMPLES_PER_PIXEL`], up to `u32::MAX`) three times
/// in 16, larger valid ones more rarely, because `new` builds a bank, which in the fuzz
/// build costs about 2 ms plus 0.3 ms per sample (20 ms at 64, 60 ms at
/// 256, 1 s at 4096): the neighbours of powers of two up to 64 one time in
/// 16, 9 to 64 one time in 17, 65 to 256 one time in 257, and the large
/// counts of `tests/render.rs` (1000 to 4096) one time in 65 536 (and
/// above [`FRESH_LIMIT`], one bank per count and thread: see
/// [`new_sampler`]).
fn spp(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 16 {
        0 => 0,
        1 => [
            MAX_SAMPLES_PER_PIXEL + 1,
            MAX_SAMPLES_PER_PIXEL + 2,
            5000,
            1 << 16,
            1 << 31,
            u32::MAX - 1,
            u32::MAX,
        ][usize::from(b.u8()) % 7],
        // Any count above the limit.
        2 => (MAX_SAMPLES_PER_PIXEL + 1).saturating_add(b.u32()),
        // Not on zeros (the bytes past the end): the larger, the rarer.
        3 => match b.u8() % 16 {
            15 if b.u8() == 0xff => [1000, 2049, MAX_SAMPLES_PER_PIXEL - 1, MAX_SAMPLES_PER_PIXEL]
                [usize::from(b.u8()) % 4],
            15 => 65 + u32::from(b.u8()) % 192,
            _ => 9 + u32::from(b.u8() % 56),
        },
        4 => [1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 31, 32, 33, 63, 64][usize::from(b.u8()) % 16],
        _ => 1 + u32::from(b.u8() % 8),
    }
}

/// An image side: mostly 0 to 24, sometimes a limit or any `u32`.
fn side(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 8 {
        0 => b.u32(),
        1 => [0, 1, 2, 1 << 31, u32::MAX - 1, u32::MAX][usize::from(b.u8()) % 6],
        _ => u32::from(b.u8() % 25),
    }
}

fn resolution(b: &mut Bytes<'_>) -> [u32; 2] {
    [side(b), side(b)]
}

/// A pixel coordinate: mostly 0 to 15; a limit; one of `side - 1`,
/// `side`, `side + 1` (wrapping) for the image's side on that axis, when
/// the sampler knows it; or any `u32`.
fn coordinate(b: &mut Bytes<'_>, side: Option<u32>) -> u32 {
    match b.u8() % 8 {
        0 => b.u32(),
        1 => [0, 1, 1 << 31, u32::MAX - 1, u32::MAX][usize::from(b.u8()) % 5],
        2 => {
            let step = u32::from(b.u8() % 3);
            side.map_or(step, |s| s.wrapping_add(step).wrapping_sub(1))
        }
        _ => u32::from(b.u8() % 16),
    }
}

/// A sample index for `spp` samples (`spp >= 1`): valid three times in
/// four; else `spp - 1`, `spp`, `spp + 1`, `u32::MAX`, or any `u32`.
fn index(b: &mut Bytes<'_>, spp: u32) -> u32 {
    match b.u8() % 8 {
        0 => b.u32(),
        1 => [spp - 1, spp, spp.saturating_add(1), u32::MAX][usize::from(b.u8()) % 4],
        _ => u32::from(b.u16()) % spp,
    }
}

/// A dimension: mostly 0 to 15; a few below `u32::MAX` (the counter
/// wraps); or any `u32`.
fn dimension(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 8 {
        0 => b.u32(),
        1 => u32::MAX - u32::from(b.u8() % 4),
        _ => u32::from(b.u8() % 16),
    }
}

/// The `PoissonPixelSampler` half's inputs, before the operations.
#[derive(Clone, Copy, Debug)]
struct SamplerInputs {
    spp: u32,
    seed: u64,
    /// `Some`: `with_resolution` right after `new`.
    resolution: Option<[u32; 2]>,
    /// Replay the values seen with a fresh `new(spp, seed)` at the end
    /// (counts up to [`TWIN_LIMIT`] only).
    twin: bool,
}

impl SamplerInputs {
    fn decode(b: &mut Bytes<'_>) -> Self {
        let spp = spp(b);
        let seed = b.u64();
        let resolution = if b.u8().is_multiple_of(2) {
            None
        } else {
            Some(resolution(b))
        };
        // Not on zeros (the bytes past the end): it builds a second bank.
        let twin = b.u8() % 4 == 3;
        Self {
            spp,
            seed,
            resolution,
            twin,
        }
    }
}

/// One operation on the sampler.
#[derive(Clone, Copy, Debug)]
enum Op {
    /// `start_pixel_sample(pixel, index, dimension)`.
    Start {
        pixel: [u32; 2],
        index: u32,
        dimension: u32,
    },
    Get1d,
    Get2d,
    GetPixel2d,
    CameraSample,
    /// `camera_sample` on a clone: the same values, the original unmoved.
    CloneDraw,
    /// Every sample of the current pixel at this dimension, on a clone:
    /// the film offsets, `get_1d` and `get_2d`.
    WholePixel {
        dimension: u32,
    },
    /// `with_resolution`: the same sampler, told this image size.
    Resolution([u32; 2]),
    /// `with_seed`: this seed, the same bank, back at the start.
    Seed(u64),
}

/// A pixel sampler's minimum distance bounds, `(min_distance_1d,
/// min_distance_2d)`: `None` for one sample per pixel.
type Bounds = (Option<f64>, Option<f64>);

/// What kind of draw a value came from: the film offset (apart from the
/// dimension counter), a 1-D value or a 2-D pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Kind {
    Film,
    One,
    Two,
}

/// Where a value was drawn: per the `PixelSampler` contract, its bits are
/// a pure function of this (the film offset's dimension is always 0: it
/// comes "from its own set, apart from the dimension counter").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Key {
    seed: u64,
    kind: Kind,
    pixel: [u32; 2],
    index: u32,
    dimension: u32,
}

/// What the sampler should be, found independently, and every value seen.
struct Model {
    spp: u32,
    /// The seed given to `new`.
    first_seed: u64,
    seed: u64,
    resolution: Option<[u32; 2]>,
    pixel: [u32; 2],
    index: u32,
    dimension: u32,
    /// The value bits drawn at each place (a 1-D value in `[0]`).
    seen: HashMap<Key, [u64; 2]>,
    /// Point pairs the whole-pixel checks may still compare.
    pairs_left: u64,
}

impl Model {
    /// The place of the current sample's next draw of `kind`, `ahead`
    /// dimensions on.
    fn key(&self, kind: Kind, ahead: u32) -> Key {
        Key {
            seed: self.seed,
            kind,
            pixel: self.pixel,
            index: self.index,
            dimension: match kind {
                Kind::Film => 0,
                Kind::One | Kind::Two => self.dimension.wrapping_add(ahead),
            },
        }
    }

    /// Records the value drawn at `key`, or checks it against the one
    /// drawn there before: the same bits.
    fn record(&mut self, ctx: &str, key: Key, value: &[f64]) {
        for &v in value {
            check_unit(ctx, &key, v);
        }
        let bits = [value[0].to_bits(), value.get(1).map_or(0, |v| v.to_bits())];
        let first = *self.seen.entry(key).or_insert(bits);
        assert_eq!(
            bits, first,
            "{ctx}: {key:?} gave {value:?}, not the value drawn there before ({first:x?})"
        );
    }

    /// The result `start_pixel_sample` must give, per the trait's
    /// `# Errors`, in the order listed (the index is checked first).
    fn expected_start(&self, pixel: [u32; 2], index: u32) -> Result<(), Error> {
        if index >= self.spp {
            return Err(Error::SampleIndexOutOfRange {
                index,
                spp: self.spp,
            });
        }
        if let Some(resolution) = self.resolution
            && (pixel[0] >= resolution[0] || pixel[1] >= resolution[1])
        {
            return Err(Error::PixelOutOfImage { pixel, resolution });
        }
        Ok(())
    }

    /// The sampler's getters agree with the model.
    fn check_state(&self, ctx: &str, s: &PoissonPixelSampler) {
        assert_eq!(
            (s.pixel(), s.sample_index(), s.dimension()),
            (self.pixel, self.index, self.dimension),
            "{ctx}: (pixel, sample_index, dimension)"
        );
        assert_eq!(
            (s.seed(), s.resolution(), s.samples_per_pixel()),
            (self.seed, self.resolution, self.spp),
            "{ctx}: (seed, resolution, samples_per_pixel)"
        );
    }
}

/// A value is finite, in `[0, 1)` and (`PoissonPixelSampler`'s guarantee
/// 2: fixed point, shifted by wrapping integer addition) a multiple of
/// 2⁻³².
fn check_unit(ctx: &str, key: &Key, v: f64) {
    assert!(
        v.is_finite() && (0.0..1.0).contains(&v) && (v * TWO_32).fract() == 0.0,
        "{ctx}: {key:?} gave {v:e} ({:#x}), not a multiple of 2^-32 in [0, 1)",
        v.to_bits()
    );
}

/// The `PoissonPixelSampler` half: `new`, then `ops` operations, each
/// checked against the model, then (for `twin`) the replay.
fn run_sampler(b: &mut Bytes<'_>, ops: usize) {
    let inputs = SamplerInputs::decode(b);
    let ctx = format!("{inputs:?}");
    let spp = inputs.spp;
    let built = new_sampler(spp, inputs.seed);
    // `new`'s `# Errors`: exactly for 0 or above the limit.
    let mut s = if (1..=MAX_SAMPLES_PER_PIXEL).contains(&spp) {
        built.unwrap_or_else(|e| panic!("{ctx}: new() refused a valid count: {e:?}"))
    } else {
        assert_eq!(
            built.err(),
            Some(Error::InvalidSamplesPerPixel {
                spp,
                max: MAX_SAMPLES_PER_PIXEL
            }),
            "{ctx}: new() and an invalid count"
        );
        return;
    };
    if let Some(resolution) = inputs.resolution {
        s = s.with_resolution(resolution);
    }
    // The bounds are `None` exactly for one sample per pixel.
    let bounds = (s.min_distance_1d(), s.min_distance_2d());
    assert!(
        bounds.0.is_none() == (spp == 1) && bounds.1.is_none() == (spp == 1),
        "{ctx}: minimum distance bounds {bounds:?}"
    );
    // `new` starts at pixel [0, 0], sample 0, dimension 0.
    let mut m = Model {
        spp,
        first_seed: inputs.seed,
        seed: inputs.seed,
        resolution: inputs.resolution,
        pixel: [0, 0],
        index: 0,
        dimension: 0,
        seen: HashMap::new(),
        pairs_left: PAIR_BUDGET,
    };
    m.check_state(&format!("{ctx}, new"), &s);
    for i in 0..ops {
        let op = decode_op(b, &m);
        let ctx = format!("{ctx}, op #{i} {op:?}");
        apply(&ctx, op, &mut s, &mut m, bounds);
        m.check_state(&ctx, &s);
    }
    // `with_seed(seed)` equals `new(spp, seed)` in its values, and banks
    // are a pure function of the count: a fresh sampler replays every
    // value seen for the first seed and for the last.
    if inputs.twin && spp <= TWIN_LIMIT {
        let mut seeds = vec![inputs.seed];
        if m.seed != inputs.seed {
            seeds.push(m.seed);
        }
        for seed in seeds {
            let Ok(mut fresh) = PoissonPixelSampler::new(spp, seed) else {
                panic!("{ctx}: new({spp}, {seed}) refused, after accepting it");
            };
            for (key, bits) in m.seen.iter().filter(|(k, _)| k.seed == seed) {
                replay(&ctx, &mut fresh, key, *bits);
            }
        }
    }
}

/// `PoissonPixelSampler::new(spp, seed)`, except for a valid count above
/// [`FRESH_LIMIT`] that an earlier input on this thread built: then
/// `with_seed(seed)` of that sampler (which `new` documents as the way to
/// get another seed, sharing the bank), so that a fuzzer drawn to a large
/// count does not pay 60 ms to 1 s for the same bank again and again (the
/// bank is a pure function of the count; `tests/render.rs` checks those of
/// 1000, 2049 and 4096).
fn new_sampler(spp: u32, seed: u64) -> Result<PoissonPixelSampler, Error> {
    thread_local! {
        static LARGE: RefCell<HashMap<u32, PoissonPixelSampler>> = RefCell::new(HashMap::new());
    }
    if spp <= FRESH_LIMIT || spp > MAX_SAMPLES_PER_PIXEL {
        return PoissonPixelSampler::new(spp, seed);
    }
    LARGE.with(|cache| {
        if let Some(first) = cache.borrow().get(&spp) {
            return Ok(first.with_seed(seed));
        }
        let s = PoissonPixelSampler::new(spp, seed)?;
        cache.borrow_mut().insert(spp, s.clone());
        Ok(s)
    })
}

/// Draws the value at `key` from `fresh` (which knows no resolution):
/// the bits seen before.
fn replay(ctx: &str, fresh: &mut PoissonPixelSampler, key: &Key, bits: [u64; 2]) {
    let started = fresh.start_pixel_sample(key.pixel, key.index, key.dimension);
    assert_eq!(started, Ok(()), "{ctx}: a fresh sampler at {key:?}");
    let value = match key.kind {
        Kind::Film => fresh.get_pixel_2d(),
        Kind::One => [fresh.get_1d(), 0.0],
        Kind::Two => fresh.get_2d(),
    };
    let again = [
        value[0].to_bits(),
        if key.kind == Kind::One {
            0
        } else {
            value[1].to_bits()
        },
    ];
    assert_eq!(
        again, bits,
        "{ctx}: a fresh new() at {key:?} gives {value:?}, not the value seen ({bits:x?})"
    );
}

/// The next operation: a start seven times in 16, a draw (or a clone's)
/// six, a whole pixel, a resolution and a seed once each. Its arguments
/// lean on the model's count and image size.
fn decode_op(b: &mut Bytes<'_>, m: &Model) -> Op {
    match b.u8() % 16 {
        // Zeros past the end: the cheapest draw.
        0 => Op::Get1d,
        1 => Op::Get2d,
        2 => Op::GetPixel2d,
        3 | 4 => Op::CameraSample,
        10 => Op::CloneDraw,
        11 => Op::WholePixel {
            dimension: dimension(b),
        },
        12 => Op::Resolution(resolution(b)),
        13 => Op::Seed(match b.u8() % 4 {
            // Back to the first seed: its values must come back.
            0 => m.first_seed,
            1 => b.u64(),
            2 => m.seed.wrapping_add(1),
            _ => [0, u64::MAX][usize::from(b.u8() % 2)],
        }),
        _ => Op::Start {
            pixel: [
                coordinate(b, m.resolution.map(|r| r[0])),
                coordinate(b, m.resolution.map(|r| r[1])),
            ],
            index: index(b, m.spp),
            dimension: dimension(b),
        },
    }
}

/// Applies one operation to the sampler and the model, checking every
/// value and result on the way.
fn apply(ctx: &str, op: Op, s: &mut PoissonPixelSampler, m: &mut Model, bounds: Bounds) {
    match op {
        Op::Start {
            pixel,
            index,
            dimension,
        } => {
            let expected = m.expected_start(pixel, index);
            let got = s.start_pixel_sample(pixel, index, dimension);
            assert_eq!(got, expected, "{ctx}: start_pixel_sample");
            // On error the sampler stays where it was (the caller checks
            // the getters against the unchanged model).
            if got.is_ok() {
                (m.pixel, m.index, m.dimension) = (pixel, index, dimension);
            }
        }
        Op::Get1d => {
            let key = m.key(Kind::One, 0);
            let v = s.get_1d();
            m.record(ctx, key, &[v]);
            m.dimension = m.dimension.wrapping_add(1);
        }
        Op::Get2d => {
            let key = m.key(Kind::Two, 0);
            let v = s.get_2d();
            m.record(ctx, key, &v);
            m.dimension = m.dimension.wrapping_add(2);
        }
        Op::GetPixel2d => {
            let key = m.key(Kind::Film, 0);
            let v = s.get_pixel_2d();
            m.record(ctx, key, &v);
        }
        Op::CameraSample => {
            let cs = s.camera_sample();
            record_camera(ctx, m, &cs);
            m.dimension = m.dimension.wrapping_add(3);
        }
        Op::CloneDraw => {
            let mut c = s.clone();
            let cs = c.camera_sample();
            record_camera(ctx, m, &cs);
            assert_eq!(
                c.dimension(),
                m.dimension.wrapping_add(3),
                "{ctx}: the clone's dimension after camera_sample"
            );
        }
        Op::WholePixel { dimension } => whole_pixel(ctx, s, m, dimension, bounds),
        Op::Resolution(resolution) => {
            // The same sampler, told the image size: it stays where it is.
            *s = s.clone().with_resolution(resolution);
            m.resolution = Some(resolution);
        }
        Op::Seed(seed) => {
            // Another seed, the same bank, back at pixel [0, 0], sample 0,
            // dimension 0, with the same resolution.
            let other = s.with_seed(seed);
            assert_eq!(
                (other.min_distance_1d(), other.min_distance_2d()),
                bounds,
                "{ctx}: with_seed does not share the bank"
            );
            *s = other;
            (m.seed, m.pixel, m.index, m.dimension) = (seed, [0, 0], 0, 0);
        }
    }
}

/// A camera sample: the film offset, then the time at the current
/// dimension and the lens at the next two, as the provided method draws
/// them (`PoissonPixelSampler` documents the same values).
fn record_camera(ctx: &str, m: &mut Model, cs: &CameraSample) {
    let film = m.key(Kind::Film, 0);
    m.record(ctx, film, &cs.film);
    let time = m.key(Kind::One, 0);
    m.record(ctx, time, &[cs.time]);
    let lens = m.key(Kind::Two, 1);
    m.record(ctx, lens, &cs.lens);
}

/// Every sample of the current pixel, on a clone, at `dimension`: film
/// offsets, a 1-D value at `dimension` and a 2-D pair at the next. Each
/// set has `spp` points, no two closer on the unit torus than the bank's
/// bound (`PoissonPixelSampler`'s guarantee 3) and none repeated. The
/// distance is the oracle's (`tests/common/mod.rs`), the bank's formula
/// operation for operation, so the comparison is exact.
fn whole_pixel(
    ctx: &str,
    s: &PoissonPixelSampler,
    m: &mut Model,
    dimension: u32,
    (bound_1d, bound_2d): Bounds,
) {
    let spp = m.spp;
    let pairs = 3 * u64::from(spp) * u64::from(spp - 1) / 2;
    if spp > WHOLE_LIMIT || pairs > m.pairs_left {
        return;
    }
    m.pairs_left -= pairs;
    let mut c = s.clone();
    let pixel = m.pixel;
    let (mut film, mut one, mut two) = (Vec::new(), Vec::new(), Vec::new());
    for index in 0..spp {
        let expected = m.expected_start(pixel, index);
        let got = c.start_pixel_sample(pixel, index, dimension);
        assert_eq!(got, expected, "{ctx}: start_pixel_sample, index {index}");
        if got.is_err() {
            return;
        }
        let seed = m.seed;
        let key = |kind, dimension| Key {
            seed,
            kind,
            pixel,
            index,
            dimension,
        };
        let f = c.get_pixel_2d();
        m.record(ctx, key(Kind::Film, 0), &f);
        let u = c.get_1d();
        m.record(ctx, key(Kind::One, dimension), &[u]);
        let p = c.get_2d();
        m.record(ctx, key(Kind::Two, dimension.wrapping_add(1)), &p);
        film.push(f);
        one.push([u]);
        two.push(p);
    }
    check_spread(ctx, "film offsets", &film, bound_2d);
    check_spread(ctx, "1-D values", &one, bound_1d);
    check_spread(ctx, "2-D pairs", &two, bound_2d);
}

/// No two of `points` closer on the unit torus than `bound` (the sampler's
/// or the bank's, for this count), and none repeated.
fn check_spread<const N: usize>(ctx: &str, what: &str, points: &[[f64; N]], bound: Option<f64>) {
    for (j, b) in points.iter().enumerate() {
        for (i, a) in points.iter().enumerate().take(j) {
            let d = common::distance_squared(a, b, &[0.0; N], &[1.0; N], &[true; N]).sqrt();
            assert!(
                d > 0.0 && bound.is_none_or(|bound| d >= bound),
                "{ctx}: {what} #{i} {a:?} and #{j} {b:?} are {d:e} apart on the torus, \
                 below the bound {bound:?}"
            );
        }
    }
}

// ---------------------------------------------------------------------
// CameraPixels
// ---------------------------------------------------------------------

/// How the `Tiled` raster's spacing is given.
#[derive(Clone, Copy, Debug)]
enum Spacing {
    Exact(u32),
    Radius(f64),
    PerPixel(f64),
}

/// Exact mode's `n`: mostly 1 to 16; any count up to the pixel sampler's
/// limit (whose stream is not pulled: see [`EXACT_LIMIT`]); or 0 (refused
/// by `build`), the limit and past it.
fn exact(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 8 {
        0 => [
            0,
            MAX_SAMPLES_PER_PIXEL,
            MAX_SAMPLES_PER_PIXEL + 1,
            5000,
            1 << 16,
            u32::MAX,
        ][usize::from(b.u8()) % 6],
        1 => 1 + u32::from(b.u16()) % MAX_SAMPLES_PER_PIXEL,
        _ => 1 + u32::from(b.u8() % 16),
    }
}

/// A natural-count radius: mostly 0.3 to 4 pixels; a few ulps either side
/// of `√2/64`, where a pixel could first hold more than 4096 points; a
/// radius below or above that, or a huge one; log-uniform from the
/// smallest `build` accepts (about `2.2e-5`) to 0.3; any bit pattern
/// (`build` refuses most).
fn radius(b: &mut Bytes<'_>) -> f64 {
    match b.u8() % 16 {
        0 | 1 => ulps(SQRT_2 / 64.0, i8::from_le_bytes([b.u8()]) % 4),
        2 | 3 => [
            0.01, 0.02, ABOUT_LOW, 0.022, ABOUT_HIGH, 0.03, 0.1, 1e3, 1e6,
        ][usize::from(b.u8()) % 9],
        4 | 5 => log_uniform(b, 2.2e-5, RADIUS_LIMIT),
        6 => b.f64_bits(),
        _ => log_uniform(b, RADIUS_LIMIT, 4.0),
    }
}

/// `extra_dims`: mostly 0 to 8, sometimes up to `u32::MAX`.
fn extra_dims(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 16 {
        0 => [9, EXTRA_LIMIT, EXTRA_LIMIT + 1, 1 << 16, 1 << 31, u32::MAX][usize::from(b.u8()) % 6],
        _ => u32::from(b.u8() % 9),
    }
}

/// The `CameraPixels` half's inputs.
#[derive(Clone, Copy, Debug)]
struct CameraInputs {
    width: u32,
    height: u32,
    spacing: Spacing,
    scheme: Scheme,
    candidates: Candidates,
    seed: u64,
    extra_dims: u32,
    /// Also check that the seed reproduces the stream.
    repeat: bool,
}

impl CameraInputs {
    fn decode(b: &mut Bytes<'_>) -> Self {
        let width = 1 + u32::from(b.u8() % 8);
        let height = 1 + u32::from(b.u8() % 8);
        let spacing = match b.u8() % 8 {
            0..=2 => Spacing::Exact(exact(b)),
            3..=5 => Spacing::Radius(radius(b)),
            // At most 6 a pixel: a radius of at least 0.32.
            _ => Spacing::PerPixel(log_uniform(b, 0.05, 6.0)),
        };
        let scheme = if b.u8().is_multiple_of(2) {
            Scheme::Sweep
        } else {
            Scheme::Paper
        };
        let candidates = if b.u8().is_multiple_of(2) {
            Candidates::Annulus
        } else {
            Candidates::Sphere
        };
        let seed = b.u64();
        let extra_dims = extra_dims(b);
        // Not on zeros (the bytes past the end): it pulls the stream twice.
        let repeat = b.u8() % 4 == 3;
        Self {
            width,
            height,
            spacing,
            scheme,
            candidates,
            seed,
            extra_dims,
            repeat,
        }
    }

    /// The raster these inputs describe, as `build` gives it.
    fn tiled(&self) -> Result<Tiled, Error> {
        let builder = Tiled::builder(self.width, self.height)
            .scheme(self.scheme)
            .candidates(self.candidates);
        match self.spacing {
            Spacing::Exact(n) => builder.exact(n),
            Spacing::Radius(r) => builder.radius(r),
            Spacing::PerPixel(n) => builder.per_pixel(n),
        }
        .build()
    }
}

/// The minimum distance bounds `(1-D, 2-D)` of the pixel sampler for
/// `count` samples, which are a pure function of the count (its bank is),
/// so they are kept per thread across executions: only the model's banks
/// are cached, `CameraPixels` builds its own every time.
fn bounds(count: u32) -> Bounds {
    thread_local! {
        static BOUNDS: RefCell<HashMap<u32, Bounds>> =
            RefCell::new(HashMap::new());
    }
    BOUNDS.with(|cache| {
        *cache.borrow_mut().entry(count).or_insert_with(|| {
            let Ok(s) = PoissonPixelSampler::new(count, 0) else {
                panic!("PoissonPixelSampler::new({count}, 0) refused a valid count");
            };
            (s.min_distance_1d(), s.min_distance_2d())
        })
    })
}

/// The `CameraPixels` half: `new`'s result, then (if cheap) the stream.
fn run_camera(b: &mut Bytes<'_>) {
    let inputs = CameraInputs::decode(b);
    let ctx = format!("{inputs:?}");
    // `Tiled`'s own errors are the streaming target's to check.
    let Ok(tiled) = inputs.tiled() else {
        return;
    };
    let r = tiled.radius();
    let ctx = format!("{ctx}, radius {r:e} ({:#x})", r.to_bits());
    let made = CameraPixels::new(&tiled, inputs.seed, inputs.extra_dims);
    // `new`'s `# Errors`: exact mode, more than the pixel sampler's limit
    // a pixel (`spp` the count asked for); natural counts, a radius below
    // about 0.022 (`spp` the most a pixel could hold: above the limit).
    let camera = match (tiled.exact(), made) {
        (Some(n), made) if n > MAX_SAMPLES_PER_PIXEL => {
            assert_eq!(
                made.err(),
                Some(Error::InvalidSamplesPerPixel {
                    spp: n,
                    max: MAX_SAMPLES_PER_PIXEL
                }),
                "{ctx}: new() and an exact count past the limit"
            );
            return;
        }
        (None, Err(e)) if r <= ABOUT_HIGH => {
            assert!(
                matches!(
                    e,
                    Error::InvalidSamplesPerPixel { spp, max: MAX_SAMPLES_PER_PIXEL }
                        if spp > MAX_SAMPLES_PER_PIXEL
                ),
                "{ctx}: new() gave {e:?}"
            );
            return;
        }
        (None, Ok(_)) if r < ABOUT_LOW => {
            panic!("{ctx}: new() accepted a radius below about 0.022");
        }
        (_, Ok(camera)) => camera,
        (_, Err(e)) => panic!("{ctx}: new() refused it: {e:?}"),
    };
    let pull = inputs.extra_dims <= EXTRA_LIMIT
        && tiled
            .exact()
            .map_or(r >= RADIUS_LIMIT, |n| n <= EXACT_LIMIT);
    let total = u64::from(inputs.width) * u64::from(inputs.height);
    assert_eq!(
        u64::try_from(camera.len()).ok(),
        Some(total),
        "{ctx}: len() before the first pixel"
    );
    if !pull {
        return;
    }
    let pixels = check_camera(&ctx, &inputs, &tiled, camera);
    // The same tiled, seed and dimensions give the same stream.
    if inputs.repeat {
        let Ok(again) = CameraPixels::new(&tiled, inputs.seed, inputs.extra_dims) else {
            panic!("{ctx}: new() refused what it accepted");
        };
        let again: Vec<CameraPixel> = again.collect();
        assert_eq!(again.len(), pixels.len(), "{ctx}: pixels, again");
        for (a, p) in again.iter().zip(&pixels) {
            assert_eq!(
                pixel_bits(a),
                pixel_bits(p),
                "{ctx}: the seed does not reproduce pixel ({}, {})",
                p.x,
                p.y
            );
        }
    }
}

/// Every number of a camera pixel, as bits.
fn pixel_bits(p: &CameraPixel) -> (u32, u32, Vec<u64>) {
    let mut bits = Vec::new();
    for s in &p.samples {
        bits.extend(
            s.film
                .iter()
                .chain([&s.time])
                .chain(&s.lens)
                .map(|v| v.to_bits()),
        );
    }
    bits.extend(p.extra.iter().map(|v| v.to_bits()));
    (p.x, p.y, bits)
}

/// Pulls every pixel of `camera` alongside the `Tiled` stream for the
/// same seed, and checks each; returns them.
fn check_camera(
    ctx: &str,
    inputs: &CameraInputs,
    tiled: &Tiled,
    mut camera: CameraPixels,
) -> Vec<CameraPixel> {
    let w = u64::from(inputs.width);
    let total = w * u64::from(inputs.height);
    let e = usize::try_from(inputs.extra_dims).unwrap_or(usize::MAX);
    let mut film = tiled.pixels_seeded(inputs.seed);
    let mut pixels = Vec::new();
    for i in 0..total {
        let (Some(pixel), Some(points)) = (camera.next(), film.next()) else {
            panic!("{ctx}: the stream ended after {i} of {total} pixels");
        };
        let expected = (i % w, i / w);
        assert_eq!(
            (u64::from(pixel.x), u64::from(pixel.y)),
            expected,
            "{ctx}: pixel #{i} out of scan order"
        );
        let ctx = format!("{ctx}, pixel {expected:?}");
        // One sample per film point of the stream "of tiled for seed":
        // exactly n in exact mode.
        let c = pixel.samples.len();
        assert_eq!(c, points.points.len(), "{ctx}: samples per film point");
        if let Some(n) = tiled.exact() {
            assert_eq!(
                u64::try_from(c).ok(),
                Some(u64::from(n)),
                "{ctx}: exact mode"
            );
        }
        assert_eq!(
            Some(pixel.extra.len()),
            c.checked_mul(e),
            "{ctx}: extra_dims values per sample"
        );
        let (x, y) = (f64::from(pixel.x), f64::from(pixel.y));
        for (k, (s, p)) in pixel.samples.iter().zip(&points.points).enumerate() {
            assert!(
                s.film
                    .iter()
                    .chain([&s.time])
                    .chain(&s.lens)
                    .all(|v| v.is_finite() && (0.0..1.0).contains(v)),
                "{ctx}: sample #{k} {s:?} has a value outside [0, 1)"
            );
            // `x + film[0]` is the point's raster coordinate, exactly.
            assert_eq!(
                [(x + s.film[0]).to_bits(), (y + s.film[1]).to_bits()],
                p.map(f64::to_bits),
                "{ctx}: sample #{k}'s film offset {:?} does not give the film point {p:?}",
                s.film
            );
        }
        assert!(
            pixel
                .extra
                .iter()
                .all(|v| v.is_finite() && (0.0..1.0).contains(v)),
            "{ctx}: a further value outside [0, 1): {:?}",
            pixel.extra
        );
        check_pixel_sets(&ctx, &pixel, e);
        assert_eq!(
            u64::try_from(camera.len()).ok(),
            Some(total - i - 1),
            "{ctx}: len()"
        );
        // Exact mode's top-ups, counted as the stream counts them; none
        // with natural counts.
        assert_eq!(
            camera.top_ups(),
            film.top_ups(),
            "{ctx}: top-ups, against the stream's"
        );
        assert!(
            tiled.exact().is_some() || camera.top_ups() == 0,
            "{ctx}: top-ups outside exact mode"
        );
        pixels.push(pixel);
    }
    assert!(camera.next().is_none(), "{ctx}: a pixel past the end");
    assert!(camera.next().is_none(), "{ctx}: not fused");
    pixels
}

/// A pixel's time, lens and each further dimension come from a pixel
/// sampler of as many samples as the pixel has film points: each is a
/// whole Poisson set, its points no closer on the unit torus than that
/// sampler's bound.
fn check_pixel_sets(ctx: &str, pixel: &CameraPixel, extra_dims: usize) {
    let Ok(count) = u32::try_from(pixel.samples.len()) else {
        panic!("{ctx}: {} samples", pixel.samples.len());
    };
    if count < 2 {
        return;
    }
    let (bound_1d, bound_2d) = bounds(count);
    let time: Vec<[f64; 1]> = pixel.samples.iter().map(|s| [s.time]).collect();
    check_spread(ctx, "times", &time, bound_1d);
    let lens: Vec<[f64; 2]> = pixel.samples.iter().map(|s| s.lens).collect();
    check_spread(ctx, "lens points", &lens, bound_2d);
    for d in 0..extra_dims {
        let values: Vec<[f64; 1]> = pixel
            .extra
            .chunks_exact(extra_dims)
            .map(|sample| [sample[d]])
            .collect();
        check_spread(ctx, &format!("further dimension {d}"), &values, bound_1d);
    }
}
