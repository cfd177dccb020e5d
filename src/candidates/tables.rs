//! The tables and short series behind the candidate offsets: 2-D
//! directions from a 256-entry `(cos, sin)` table plus a small rotation,
//! and the 3-D annulus radius's cube root from a 256-entry table plus a
//! binomial series. Compile-time tables and correctly rounded arithmetic
//! only, so every platform draws the same bits.

use super::AHEAD;

pub(super) const TWO_POW_M32: f64 = 1.0 / 4_294_967_296.0;

/// Entries in [`DIRECTIONS`] and [`CUBE_ROOTS`]; the top `log2` of a
/// draw's 32 bits pick one.
pub(super) const TABLE_BITS: u32 = 8;

/// `(cos, sin)` of `2π·i/256`, computed at compile time by [`series`]: basic
/// arithmetic only, so the same bits on every platform.
pub(super) const DIRECTIONS: [(f64, f64); 1 << TABLE_BITS] = directions();

pub(super) const fn directions() -> [(f64, f64); 1 << TABLE_BITS] {
    const QUARTER: usize = 1 << (TABLE_BITS - 2);
    let mut table = [(0.0, 0.0); 1 << TABLE_BITS];
    let mut i = 0;
    while i < table.len() {
        // Each quadrant from [0, π/2) by a quarter turn, so the series only
        // ever sees small angles.
        #[expect(clippy::cast_precision_loss, reason = "i < 64")]
        let t = (i % QUARTER) as f64 * (core::f64::consts::TAU / (1 << TABLE_BITS) as f64);
        let (c, s) = series(t);
        #[expect(
            clippy::indexing_slicing,
            reason = "i < table.len() by the loop condition (compile time only)"
        )]
        let entry = &mut table[i];
        *entry = match i / QUARTER {
            0 => (c, s),
            1 => (-s, c),
            2 => (-c, -s),
            _ => (s, -c),
        };
        i += 1;
    }
    table
}

/// [`DIRECTIONS`] rounded to `f32`, for the batch sampler's `f32` draws
/// (`wide.rs`).
pub(super) const DIRECTIONS_F32: [(f32, f32); 1 << TABLE_BITS] = rounded(&DIRECTIONS, 1.0);

/// `table` rounded to `f32`, each entry's second value first times
/// `second_scale` (a power of two, so exactly).
const fn rounded(
    table: &[(f64, f64); 1 << TABLE_BITS],
    second_scale: f64,
) -> [(f32, f32); 1 << TABLE_BITS] {
    let mut out = [(0.0, 0.0); 1 << TABLE_BITS];
    let mut i = 0;
    while i < out.len() {
        #[expect(
            clippy::indexing_slicing,
            reason = "i < out.len() == table.len() by the loop condition (compile time only)"
        )]
        let ((a, b), entry) = (table[i], &mut out[i]);
        #[expect(clippy::cast_possible_truncation, reason = "rounded to f32 on purpose")]
        let pair = (a as f32, (b * second_scale) as f32);
        *entry = pair;
        i += 1;
    }
    out
}

/// The unit direction at angle `2π · bits / 2³²`, without a branch: the top
/// 8 bits pick a table entry, the other 24 a rotation by `δ < 2π/256`, whose
/// cosine and sine short Taylor polynomials give to within 1e-17.
#[inline(always)]
pub(super) fn angle_direction(bits: u32) -> (f64, f64) {
    rotate(table_direction(bits), rotation(bits))
}

/// [`angle_direction`] for [`AHEAD`] angles at once, step by step over all
/// of them (the table look-ups, then the polynomials), bit for bit the same.
#[inline(always)]
pub(super) fn angle_directions(bits: &[u32; AHEAD]) -> ([f64; AHEAD], [f64; AHEAD]) {
    let table = super::lanes(bits, table_direction);
    let delta = super::lanes(bits, rotation);
    let mut c = [0.0; AHEAD];
    let mut s = [0.0; AHEAD];
    for (((c, s), &t), &d) in c.iter_mut().zip(&mut s).zip(&table).zip(&delta) {
        (*c, *s) = rotate(t, d);
    }
    (c, s)
}

/// The table entry for the top 8 bits of an angle.
#[inline(always)]
pub(super) fn table_direction(bits: u32) -> (f64, f64) {
    by_top_bits(&DIRECTIONS, bits)
}

/// The entry of a [`TABLE_BITS`]-bit table that the top bits of a 32-bit
/// draw select (`bits >> 24 < 256`: never the fallback).
#[inline(always)]
pub(super) fn by_top_bits(table: &[(f64, f64); 1 << TABLE_BITS], bits: u32) -> (f64, f64) {
    table
        .get((bits >> (32 - TABLE_BITS)) as usize)
        .copied()
        .unwrap_or((1.0, 0.0))
}

/// The rest of the angle, `δ < 2π/256`, from the low 24 bits.
#[inline(always)]
pub(super) fn rotation(bits: u32) -> f64 {
    const DELTA_PER_UNIT: f64 = core::f64::consts::TAU * TWO_POW_M32;
    f64::from(bits & ((1 << (32 - TABLE_BITS)) - 1)) * DELTA_PER_UNIT
}

/// `(c, s)` rotated by `delta`, whose cosine and sine come from short
/// Taylor polynomials.
#[inline(always)]
pub(super) fn rotate((c, s): (f64, f64), delta: f64) -> (f64, f64) {
    let x = delta * delta;
    let x2 = x * x;
    // Estrin's scheme: two short chains instead of one long one.
    let cd = (1.0 - 0.5 * x) + x2 * (1.0 / 24.0 - x * (1.0 / 720.0));
    let sd = delta * ((1.0 - x * (1.0 / 6.0)) + x2 * (1.0 / 120.0 - x * (1.0 / 5040.0)));
    (c * cd - s * sd, s * cd + c * sd)
}

/// For each interval `i` of `u = bits / 2³²` that the top 8 bits select,
/// `(∛a₀, 7·2⁻³²/a₀)` at its midpoint `a₀ = 1 + 7·(i + ½)/256`: the cube
/// root there, and the scale that turns the low 24 bits' distance from the
/// midpoint into `t = (a - a₀)/a₀`. Computed at compile time with basic
/// arithmetic (Halley steps), so the same bits on every platform.
pub(super) const CUBE_ROOTS: [(f64, f64); 1 << TABLE_BITS] = cube_roots();

/// [`CUBE_ROOTS`] rounded to `f32`, the scale for a 16-bit step (`2⁸`
/// times the 24-bit one, exactly), for the batch sampler's `f32` draws
/// (`wide.rs`).
pub(super) const CUBE_ROOTS_F32: [(f32, f32); 1 << TABLE_BITS] = rounded(&CUBE_ROOTS, 256.0);

pub(super) const fn cube_roots() -> [(f64, f64); 1 << TABLE_BITS] {
    let mut table = [(0.0, 0.0); 1 << TABLE_BITS];
    let mut i = 0;
    while i < table.len() {
        #[expect(clippy::cast_precision_loss, reason = "i < 256")]
        let a = 1.0 + 7.0 * (i as f64 + 0.5) / (1 << TABLE_BITS) as f64;
        // Halley's iteration from 1.5 (error under 0.5 for 1 <= a < 8)
        // cubes the error each step: 8 steps are far more than enough.
        let mut y = 1.5;
        let mut step = 0;
        while step < 8 {
            let y3 = y * y * y;
            y *= (y3 + 2.0 * a) / (2.0 * y3 + a);
            step += 1;
        }
        #[expect(
            clippy::indexing_slicing,
            reason = "i < table.len() by the loop condition (compile time only)"
        )]
        let entry = &mut table[i];
        *entry = (y, 7.0 * TWO_POW_M32 / a);
        i += 1;
    }
    table
}

/// The [`CUBE_ROOTS`] entry for the top 8 bits of a radius draw.
#[inline(always)]
pub(super) fn cube_entry(bits: u32) -> (f64, f64) {
    by_top_bits(&CUBE_ROOTS, bits)
}

/// The low 24 bits' signed distance from their interval's midpoint, in
/// units of `2⁻³²` of `u`: `-2²³ ..= 2²³ - 1`.
#[inline(always)]
pub(super) fn cube_step(bits: u32) -> f64 {
    const LOW: u32 = (1 << (32 - TABLE_BITS)) - 1;
    const HALF: i32 = 1 << (31 - TABLE_BITS);
    #[expect(clippy::cast_possible_wrap, reason = "24 bits fit an i32")]
    let low = (bits & LOW) as i32;
    f64::from(low - HALF)
}

/// `root·∛(1 + t)` for `|t| <= 7/512`, by the binomial series of `∛(1 + t)`
/// through `t⁷` (the first term left out is below `2e-17`), as
/// `root + root·(t·(…))` so that only the last addition rounds at the
/// result's scale, and in Estrin's form: shorter chains than Horner's.
/// With [`CUBE_ROOTS`] it needs no division, which the 3-D loop would wait
/// on (the journal, `docs/performance-journal.md`, has the profile).
#[inline(always)]
pub(super) fn cube_root_near(root: f64, t: f64) -> f64 {
    const C: [f64; 7] = [
        1.0 / 3.0,
        -1.0 / 9.0,
        5.0 / 81.0,
        -10.0 / 243.0,
        22.0 / 729.0,
        -154.0 / 6561.0,
        374.0 / 19683.0,
    ];
    let [c1, c2, c3, c4, c5, c6, c7] = C;
    let t2 = t * t;
    let t4 = t2 * t2;
    let q = ((c1 + c2 * t) + t2 * (c3 + c4 * t)) + t4 * ((c5 + c6 * t) + t2 * c7);
    root + root * (t * q)
}

/// `(cos x, sin x)` by their Taylor series through `x²⁴` and `x²⁵`: within
/// an ulp or two for `|x| <= π/2`. A `const fn`, so [`DIRECTIONS`] is built by
/// the compiler.
pub(super) const fn series(x: f64) -> (f64, f64) {
    let x2 = x * x;
    let (mut c, mut s) = (1.0, x);
    let (mut tc, mut ts) = (1.0, x);
    let mut m = 1.0;
    while m < 13.0 {
        tc *= -x2 / ((2.0 * m - 1.0) * (2.0 * m));
        ts *= -x2 / ((2.0 * m) * (2.0 * m + 1.0));
        c += tc;
        s += ts;
        m += 1.0;
    }
    (c, s)
}

/// `(cos θ, sin θ)` for `0 <= θ <= 2π`, by [`series`] after reduction to
/// `|x| <= π/4`: bit-identical on every platform, accurate to about 1e-15,
/// ample for spacing candidate directions.
pub(super) fn cos_sin(theta: f64) -> (f64, f64) {
    let quarter = core::f64::consts::FRAC_PI_2;
    let turns = (theta / quarter).round();
    let (c, s) = series(theta - turns * quarter);
    // `turns` is 0..=4 here, so the rem_euclid result fits any integer.
    match turns.rem_euclid(4.0) {
        0.0 => (c, s),
        1.0 => (-s, c),
        2.0 => (-c, -s),
        _ => (s, -c),
    }
}
