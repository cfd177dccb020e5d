//! The `batch` fuzz target's logic, shared with `tests/fuzz_corpus.rs`.
//!
//! Plain Rust on std and `bridson` only (no `arbitrary`), so that the
//! regular test suite replays the committed corpus through exactly the
//! assertions the fuzzer runs. The including crate must also declare
//! `mod common;` (the oracle in `tests/common/mod.rs`) and `mod bytes;`
//! (the reader in `fuzz/common/bytes.rs`).
//!
//! Every byte string decodes to a full set of sampler inputs: reads past the
//! end give zeros. Each value has several decodings picked by a few bits, so
//! both hostile inputs (raw `f64` bit patterns: NaN, infinities, subnormals,
//! `±1e308`, one-ulp boxes, huge `k` and budgets) and useful ones (a box a
//! few radii wide, dyadic grid-aligned values) are common.
//!
//! For every input: `build()` either fails with the error the inputs call
//! for, or succeeds; then the sampler is rebuilt with a point cap (so an
//! execution stays fast), generated, and every point is checked with the
//! naive oracle: no pair closer than `r`, every point in `lo <= x < hi`.

use crate::bytes::Bytes;
use crate::common;
use bridson::{Candidates, Domain, Error, GridLayout, MAX_ATTEMPTS, PoissonDisk};

/// Most points generated per execution, by dimension (index `N - 1`): the
/// O(n²) oracle and the sampler together stay within a few milliseconds.
const POINT_LIMIT: [u64; 8] = [2000, 2000, 1000, 500, 200, 100, 100, 100];

/// Most attempts `k` used for generation. Larger `k` is still passed to
/// `build()`, but a run costs up to about `2·n·k` candidate throws, so it
/// is lowered before generating (see the `# Limits` section of the crate
/// docs).
const ATTEMPT_LIMIT: u32 = 64;

/// Grid memory budget used for generation: allocating and zeroing a 1 GiB
/// grid per execution would make fuzzing crawl. The inputs' own budget is
/// checked by `build()` first.
const BUDGET_LIMIT: u64 = 16 << 20;

/// Values that sit on or next to a documented limit.
const SPECIAL: [f64; 24] = [
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
    1.000_000_000_000_000_2e150,
    1e200,
    1e308,
    -1e308,
    0.8e308,
    -0.8e308,
    f64::MAX,
    f64::MIN,
    1.0,
    -1.0,
    1e15,
    -1e15,
];

fn special(b: &mut Bytes<'_>) -> f64 {
    SPECIAL[usize::from(b.u8()) % SPECIAL.len()]
}

/// `2^-e · (1 + m/2^16)`: from about 1e-3 to 2.
fn reasonable_radius(b: &mut Bytes<'_>) -> f64 {
    let e = i32::from(b.u8() % 11);
    let m = f64::from(b.u16()) / 65536.0;
    2f64.powi(-e) * (1.0 + m)
}

fn radius(b: &mut Bytes<'_>) -> f64 {
    match b.u8() % 8 {
        0 => b.f64_bits(),
        1 => special(b),
        // Dyadic: cell faces and distances of exactly r are hit exactly.
        2 | 3 => 2f64.powi(-i32::from(b.u8() % 9)),
        _ => reasonable_radius(b),
    }
}

/// `x` moved by `steps` ulps towards +∞ (finite `x` only).
fn ulps_up(x: f64, steps: u64) -> f64 {
    let mut y = x;
    for _ in 0..steps {
        y = y.next_up();
    }
    y
}

/// The bounds of one axis, given the radius (which may be garbage).
fn axis(b: &mut Bytes<'_>, r: f64) -> (f64, f64) {
    // A scale that is finite and positive even when `r` is not.
    let unit = if r.is_finite() && r > 0.0 { r } else { 0.125 };
    let mode = b.u8();
    match mode % 10 {
        // Raw bit patterns.
        0 => (b.f64_bits(), b.f64_bits()),
        // Limits on either side.
        1 => (special(b), special(b)),
        // A special lower bound, a few radii wide.
        2 => {
            let lo = special(b);
            (lo, lo + unit * f64::from(b.u8() % 16 + 1))
        }
        // A one- to 255-ulp wide box somewhere.
        3 => {
            let lo = if b.u8().is_multiple_of(2) {
                special(b)
            } else {
                f64::from(b.u16()) / 256.0 - 64.0
            };
            let steps = u64::from(b.u8());
            if lo.is_finite() {
                (lo, ulps_up(lo, steps))
            } else {
                (lo, lo)
            }
        }
        // Far from the origin: few bits left below r.
        4 => {
            let shift = 2f64.powi(i32::from(b.u8() % 64));
            let lo = if b.u8().is_multiple_of(2) {
                shift
            } else {
                -shift
            };
            (lo, lo + unit * (0.1 + f64::from(b.u16()) / 4096.0))
        }
        // Grid-aligned: an integer offset, a whole number of radii.
        5 | 6 => {
            let lo = f64::from(i8::from_le_bytes([b.u8()]));
            (lo, lo + unit * f64::from(b.u8() % 24 + 1))
        }
        // Useful: 0.05 to about 24 radii wide, some thinner than r.
        _ => {
            let lo = f64::from(i16::from_le_bytes(b.u16().to_le_bytes())) / 64.0;
            (lo, lo + unit * (0.05 + f64::from(b.u16()) / 2731.0))
        }
    }
}

fn attempts(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 8 {
        0 => b.u32(),
        1 => [0, 1, 2, u32::MAX, u32::MAX - 1, 1 << 31][usize::from(b.u8()) % 6],
        _ => 1 + u32::from(b.u8() % 64),
    }
}

fn budget(b: &mut Bytes<'_>) -> u64 {
    match b.u8() % 4 {
        0 => b.u64(),
        1 => 1 << (b.u8() % 64),
        2 => u64::from(b.u16()),
        _ => bridson::DEFAULT_MAX_GRID_BYTES,
    }
}

fn max_points(b: &mut Bytes<'_>, limit: u64) -> Option<u64> {
    match b.u8() % 4 {
        0 => None,
        1 => Some(b.u64()),
        _ => Some(u64::from(b.u16()) % (limit + 1)),
    }
}

/// Decodes one set of inputs and checks them; panics (with a readable
/// message) if the sampler breaks its contract.
pub(crate) fn run(data: &[u8]) {
    let mut b = Bytes::new(data);
    match b.u8() % 8 {
        0 => run_n::<1>(&mut b),
        1 => run_n::<2>(&mut b),
        2 => run_n::<3>(&mut b),
        3 => run_n::<4>(&mut b),
        4 => run_n::<5>(&mut b),
        5 => run_n::<6>(&mut b),
        6 => run_n::<7>(&mut b),
        _ => run_n::<8>(&mut b),
    }
}

/// The error `Domain::new` must report, found independently: the first
/// axis with a non-finite bound, an empty range or an overflowing extent.
fn expected_domain_error<const N: usize>(lo: &[f64; N], hi: &[f64; N]) -> Option<Error> {
    for (axis, (&l, &h)) in lo.iter().zip(hi).enumerate() {
        if !l.is_finite() || !h.is_finite() {
            return Some(Error::NonFiniteBound { axis });
        }
        if l >= h {
            return Some(Error::EmptyBox { axis });
        }
        if !(h - l).is_finite() {
            return Some(Error::ExtentOverflow { axis });
        }
    }
    None
}

fn run_n<const N: usize>(b: &mut Bytes<'_>) {
    let limit = POINT_LIMIT[N - 1];
    let r = radius(b);
    let mut lo = [0.0; N];
    let mut hi = [0.0; N];
    for (l, h) in lo.iter_mut().zip(hi.iter_mut()) {
        (*l, *h) = axis(b, r);
    }
    let periodic_bits = b.u8();
    let periodic: [bool; N] = core::array::from_fn(|i| periodic_bits >> i & 1 == 1);
    let k = attempts(b);
    let candidates = if b.u8().is_multiple_of(2) {
        Candidates::Annulus
    } else {
        Candidates::Sphere
    };
    let layout = [
        GridLayout::Auto,
        GridLayout::Dense,
        GridLayout::Sparse,
        GridLayout::Auto,
        GridLayout::Paged,
    ][usize::from(b.u8() % 5)];
    let budget = budget(b);
    let cap = max_points(b, limit);
    let seed = b.u64();
    let compare_layouts = b.u8().is_multiple_of(4);

    let ctx = format!(
        "N = {N}, lo = {lo:?}, hi = {hi:?}, periodic = {periodic:?}, r = {r:e} ({:#x}), \
         k = {k}, {candidates:?}, {layout:?}, budget = {budget}, cap = {cap:?}, seed = {seed}",
        r.to_bits()
    );

    let domain = match Domain::new(lo, hi) {
        Ok(d) => {
            assert_eq!(
                expected_domain_error(&lo, &hi),
                None,
                "{ctx}: Domain::new accepted a bad box"
            );
            assert_eq!((d.lo(), d.hi()), (lo, hi), "{ctx}: the box was altered");
            d.with_periodic(periodic)
        }
        Err(e) => {
            assert_eq!(
                Some(e),
                expected_domain_error(&lo, &hi),
                "{ctx}: Domain::new gave the wrong error"
            );
            return;
        }
    };
    let builder = PoissonDisk::builder(domain, r)
        .attempts(k)
        .candidates(candidates)
        .layout(layout)
        .max_grid_bytes(budget)
        .max_points(cap.unwrap_or(u64::MAX));
    let sampler = match builder.build() {
        Ok(s) => s,
        Err(e) => {
            check_build_error(&ctx, e, r, k, budget);
            return;
        }
    };
    assert!(
        (1e-150..=1e150).contains(&r),
        "{ctx}: accepted a radius outside 1e-150..=1e150"
    );
    assert!(k >= 1, "{ctx}: accepted k = 0");
    assert!(k <= MAX_ATTEMPTS, "{ctx}: accepted k = {k}");
    assert!(
        sampler.grid_bytes() <= budget,
        "{ctx}: planned {} bytes, over the budget",
        sampler.grid_bytes()
    );
    assert_eq!(sampler.to_builder(), builder, "{ctx}: settings not kept");

    // Lowering k or the cap never turns an accepted sampler into an error.
    let gen_cap = cap.map_or(limit, |c| c.min(limit));
    let lowered = sampler
        .to_builder()
        .attempts(k.min(ATTEMPT_LIMIT))
        .max_points(gen_cap)
        .build();
    let Ok(lowered) = lowered else {
        panic!("{ctx}: lowering k and the cap made build() fail: {lowered:?}");
    };
    // A smaller budget may not fit; then there is nothing to generate.
    let Ok(small) = lowered
        .to_builder()
        .max_grid_bytes(budget.min(BUDGET_LIMIT))
        .build()
    else {
        return;
    };
    let (points, complete) = check_generate(&ctx, &small, seed, gen_cap);

    // The layout never changes the points.
    if compare_layouts {
        for other in [GridLayout::Dense, GridLayout::Paged, GridLayout::Sparse] {
            if other == small.resolved_layout() {
                continue;
            }
            // A run cut short by the budget stops at a point that depends
            // on the layout's memory, so only complete runs compare.
            if let Ok(s) = small.to_builder().layout(other).build()
                && complete
                && let Ok(again) = s.generate_seeded(seed)
            {
                assert!(
                    again == points,
                    "{ctx}: {other:?} gives other points than {:?} ({} vs {})",
                    small.resolved_layout(),
                    again.len(),
                    points.len()
                );
            }
        }
    }
}

/// `build()` failed: the error must be one the inputs call for.
fn check_build_error(ctx: &str, e: Error, r: f64, k: u32, budget: u64) {
    let radius_ok = (1e-150..=1e150).contains(&r);
    match e {
        Error::InvalidRadius => assert!(!radius_ok, "{ctx}: InvalidRadius for a valid radius"),
        Error::ZeroAttempts => {
            assert!(radius_ok, "{ctx}: ZeroAttempts before InvalidRadius");
            assert_eq!(k, 0, "{ctx}: ZeroAttempts for k = {k}");
        }
        Error::TooManyAttempts { max } => {
            assert!(radius_ok, "{ctx}: TooManyAttempts before InvalidRadius");
            assert_eq!(max, MAX_ATTEMPTS, "{ctx}: the wrong maximum");
            assert!(k > max, "{ctx}: TooManyAttempts for k = {k}");
        }
        Error::GridTooLarge { needed, budget: b } => {
            assert!(radius_ok && k > 0, "{ctx}: {e:?} hides a bad radius or k");
            assert_eq!(b, budget, "{ctx}: the wrong budget reported");
            // u64::MAX: no grid of that layout can exist at any budget.
            assert!(
                needed > budget || needed == u64::MAX,
                "{ctx}: needed {needed} <= budget {budget}"
            );
        }
        Error::BoxTooWide { .. } => {
            assert!(radius_ok && k > 0, "{ctx}: {e:?} hides a bad radius or k");
        }
        other => panic!("{ctx}: build() gave {other:?} for a valid domain"),
    }
}

/// Generates and checks the points of `sampler` for `seed`, and the memory
/// the run holds, after every point; returns them and whether the run was
/// complete (not cut short by the budget).
pub(crate) fn check_generate<const N: usize>(
    ctx: &str,
    sampler: &PoissonDisk<N>,
    seed: u64,
    cap: u64,
) -> (Vec<[f64; N]>, bool) {
    let d = sampler.domain();
    let budget = sampler.max_grid_bytes();
    let mut it = sampler.iter_seeded(seed);
    let mut points = Vec::new();
    while let Some(p) = it.next() {
        points.push(p);
        assert!(
            it.heap_bytes() <= budget,
            "{ctx}: {} bytes held, over the budget of {budget}",
            it.heap_bytes()
        );
    }
    let complete = match it.error() {
        None => true,
        Some(Error::MemoryBudgetExceeded {
            points: n,
            budget: b,
        }) => {
            assert_eq!(b, budget, "{ctx}: the wrong budget reported");
            assert_eq!(Ok(n), u64::try_from(points.len()), "{ctx}: wrong count");
            false
        }
        Some(other) => panic!("{ctx}: the run ended with {other:?}"),
    };
    assert!(
        u64::try_from(points.len()).is_ok_and(|n| n <= cap),
        "{ctx}: {} points over the cap {cap}",
        points.len()
    );
    assert!(
        !points.is_empty() || cap == 0 || !complete,
        "{ctx}: not even one point"
    );
    if let Err(report) =
        common::check_points(&points, sampler.radius(), d.lo(), d.hi(), d.periodic())
    {
        panic!("{ctx}, {:?} layout: {report}", sampler.resolved_layout());
    }
    (points, complete)
}
