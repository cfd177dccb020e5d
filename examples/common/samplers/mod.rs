//! The samplers a renderer uses today, behind the library's
//! [`PixelSampler`] trait, so that the examples can set them against
//! [`PoissonPixelSampler`]: the paper's baselines (pbrt-v2's best-candidate
//! and low-discrepancy samplers), plain and stratified random sampling, and
//! today's usual best, Owen-scrambled Sobol'.
//!
//! They are not library API: they exist to be compared with. Pick one by
//! name with [`by_name`].
//!
//! # Shared contract
//! Every sampler here keeps the [`PixelSampler`] contract:
//! 1. a value is a pure function of (seed, pixel, sample index, dimension):
//!    each draw hashes those with [`hash`] and keeps no other state;
//! 2. every value lies in `[0, 1)`;
//! 3. a pixel gets exactly `spp` samples (indices `0..spp`), and an index
//!    `>= spp` is an [`Error`], not a panic;
//! 4. samplers are `Clone + Send + Sync`; tables are shared through `Arc`.
//!
//! Dimensions are counted as in the library: [`PixelSampler::get_1d`]
//! takes one, [`PixelSampler::get_2d`] two, and the film offset
//! ([`PixelSampler::get_pixel_2d`]) is apart from the counter. So a camera
//! sample's time is dimension 0 and its lens the pair at dimension 1.

#![allow(
    dead_code,
    reason = "shared by several examples and tests, each of which uses a part"
)]

mod best_candidate;
mod independent;
mod low_discrepancy;
mod pmj02bn;
mod poisson_exact;
mod sobol_owen;
mod stratified;
mod zsobol;

pub(crate) use best_candidate::BestCandidateSampler;
pub(crate) use independent::IndependentSampler;
pub(crate) use low_discrepancy::LowDiscrepancySampler;
pub(crate) use pmj02bn::Pmj02bnSampler;
#[allow(unused_imports, reason = "for the tracer's tests of the anchors")]
pub(crate) use pmj02bn::{CANDIDATES, pmj02bn};
pub(crate) use poisson_exact::PoissonExactSampler;
pub(crate) use sobol_owen::SobolOwenSampler;
pub(crate) use stratified::StratifiedSampler;
pub(crate) use zsobol::ZSobolSampler;
#[allow(unused_imports, reason = "for the tracer's tests of the anchors")]
pub(crate) use zsobol::shuffle_index;

use bridson::{Error, NetPixelSampler, PixelSampler, PoissonPixelSampler};

/// The names [`by_name`] accepts, in the order a study lists them.
pub(crate) const NAMES: [&str; 7] = [
    "poisson-pixel",
    "poisson-exact",
    "independent",
    "stratified",
    "best-candidate",
    "low-discrepancy",
    "sobol-owen",
];

/// Samplers [`by_name`] also accepts, kept out of the default lists (and
/// so out of the studies' committed runs) until they are measured in full:
/// `net` is `bridson::NetPixelSampler`, at most 4096 samples per pixel;
/// `zsobol` and `pmj02bn` are pbrt-v4's two best samplers, the anchors of
/// issue 51.
pub(crate) const EXTRA_NAMES: [&str; 3] = ["net", "zsobol", "pmj02bn"];

/// The sampler called `name` (one of [`NAMES`] or [`EXTRA_NAMES`]), with
/// `spp` samples per pixel and `seed`.
///
/// # Errors
/// A message if the name is unknown or the sampler refuses `spp`.
pub(crate) fn by_name(name: &str, spp: u32, seed: u64) -> Result<Box<dyn PixelSampler>, String> {
    let built: Result<Box<dyn PixelSampler>, Error> = match name {
        "poisson-pixel" => PoissonPixelSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "net" => NetPixelSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "independent" => IndependentSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "stratified" => StratifiedSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "best-candidate" => BestCandidateSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "low-discrepancy" => LowDiscrepancySampler::new(spp, seed).map(|s| Box::new(s) as _),
        "sobol-owen" => SobolOwenSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "zsobol" => ZSobolSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "pmj02bn" => Pmj02bnSampler::new(spp, seed).map(|s| Box::new(s) as _),
        "poisson-exact" => PoissonExactSampler::new(spp, seed).map(|s| Box::new(s) as _),
        _ => {
            return Err(format!(
                "unknown sampler {name:?}; known: {}",
                NAMES.join(", ")
            ));
        }
    };
    built.map_err(|e| format!("sampler {name:?} with {spp} samples per pixel: {e}"))
}

/// The largest `spp` the samplers here accept (best-candidate accepts
/// fewer). Sobol' indices are limited to 2¹⁶ by `sobol_burley`; the others
/// share the bound to keep the study's inputs uniform.
pub(crate) const MAX_SPP: u32 = 1 << 16;

/// Separates the hash inputs of draws of different kinds, so that the film
/// offset, a 1-D value and a 2-D pair at the same dimension are unrelated.
pub(crate) const TAG_FILM: u64 = 0x4649_4c4d; // "FILM"
/// See [`TAG_FILM`].
pub(crate) const TAG_1D: u64 = 0x31_44; // "1D"
/// See [`TAG_FILM`].
pub(crate) const TAG_2D: u64 = 0x32_44; // "2D"

/// A bijective 64-bit mixer: the finaliser of Pelle Evensen's "moremur"
/// (xor-shift, multiply, twice, then xor-shift). Every input bit flips about
/// half the output bits.
pub(crate) fn mix(mut x: u64) -> u64 {
    x ^= x >> 27;
    x = x.wrapping_mul(0x3c79_ac49_2ba7_b653);
    x ^= x >> 33;
    x = x.wrapping_mul(0x1c69_b3f7_4ac4_ae35);
    x ^ (x >> 27)
}

/// A hash of a sequence of words: each is folded in by an add of a distinct
/// odd constant and a full [`mix`], so that the order of the words matters
/// and no word can cancel another.
pub(crate) fn hash(words: &[u64]) -> u64 {
    words.iter().fold(0x6a09_e667_f3bc_c908, |h, &w| {
        mix(h.wrapping_add(0x9e37_79b9_7f4a_7c15) ^ w)
    })
}

/// A value in `[0, 1)` from the top 53 bits of a hash: uniform on the grid
/// of step 2⁻⁵³.
pub(crate) fn to_unit(h: u64) -> f64 {
    (h >> 11) as f64 / 9_007_199_254_740_992.0 // 2⁵³
}

/// A jitter in `(0, 1)` from 32 bits of a hash, at the midpoint of a cell
/// of the 2⁻³² grid: `(k + jitter) / n` then lies strictly inside stratum
/// `k`, with room to spare for rounding, for any `n < 2²⁰`.
pub(crate) fn jitter(bits: u32) -> f64 {
    (f64::from(bits) + 0.5) / 4_294_967_296.0 // 2³²
}

/// The high and low 32-bit words of a hash.
pub(crate) fn halves(h: u64) -> [u32; 2] {
    #[expect(
        clippy::cast_possible_truncation,
        reason = "splitting a u64 into its two words"
    )]
    let words = [(h >> 32) as u32, h as u32];
    words
}

/// The element at `index` of the permutation of `0..n` chosen by `key`.
///
/// A keyed bijection of the `b`-bit integers (`2^b >= n` the next power of
/// two) made of invertible steps (xor with a key, multiply by an odd
/// number, xor-shift right, all mod `2^b`), iterated until it lands below
/// `n` ("cycle walking", Black and Rogaway 2002): restricted that way, it
/// is still a bijection of `0..n`, for every `n`, not only powers of two.
/// At most `2^b / n < 2` iterations are needed on average. `index` must be
/// `< n`.
pub(crate) fn permute(index: u32, n: u32, key: u64) -> u32 {
    if n <= 1 {
        return 0;
    }
    let bits = 32 - (n - 1).leading_zeros();
    let mask = (1_u64 << bits) - 1;
    let shift = (bits / 2).max(1);
    let keys = [mix(key), mix(key ^ 0x5851_f42d_4c95_7f2d)];
    let mut x = u64::from(index);
    loop {
        for (round, k) in keys.iter().chain(keys.iter()).enumerate() {
            let odd = (k >> (16 * (round % 2))) | 1;
            x = (x ^ k) & mask;
            x = x.wrapping_mul(odd) & mask;
            x ^= x >> shift;
            x = x.wrapping_mul(0x2545_f491_4f6c_dd1d) & mask;
            x ^= x >> shift;
        }
        if x < u64::from(n) {
            return u32::try_from(x).expect("x < n, and n is a u32");
        }
    }
}

/// The two [`PixelSampler`] methods that every [`Cursor`]-based sampler
/// here writes the same way: `samples_per_pixel` and `start_pixel_sample`,
/// read from and handed to the sampler's `cursor` field. Used inside the
/// `impl PixelSampler` block, beside the sampler's own draws.
///
/// A macro, not a blanket impl: `PixelSampler` is the library's trait, so
/// the examples cannot implement it for every type that has a cursor.
macro_rules! cursor_position {
    () => {
        fn samples_per_pixel(&self) -> u32 {
            self.cursor.spp
        }

        fn start_pixel_sample(
            &mut self,
            pixel: [u32; 2],
            index: u32,
            dimension: u32,
        ) -> Result<(), bridson::Error> {
            self.cursor.start(pixel, index, dimension)
        }
    };
}
pub(crate) use cursor_position;

/// The current draw of a sampler: where it is (pixel, sample index,
/// dimension) and the hash of its seed.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cursor {
    /// The samples per pixel.
    pub(crate) spp: u32,
    /// The hash of the seed, the first word of every draw's hash.
    pub(crate) seed_hash: u64,
    /// The current pixel.
    pub(crate) pixel: [u32; 2],
    /// The current sample index, `< spp`.
    pub(crate) index: u32,
    /// The next dimension to draw.
    pub(crate) dimension: u32,
}

impl Cursor {
    /// A cursor at pixel `[0, 0]`, sample 0, dimension 0.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if `spp` is 0 or above `max`.
    pub(crate) fn new(spp: u32, seed: u64, max: u32) -> Result<Self, Error> {
        if !(1..=max).contains(&spp) {
            return Err(Error::InvalidSamplesPerPixel { spp, max });
        }
        Ok(Self {
            spp,
            seed_hash: mix(seed ^ 0xb7e1_5162_8aed_2a6b),
            pixel: [0, 0],
            index: 0,
            dimension: 0,
        })
    }

    /// Moves to sample `index` of `pixel` at `dimension`.
    ///
    /// # Errors
    /// [`Error::SampleIndexOutOfRange`] if `index >= spp`; the cursor then
    /// stays where it was.
    pub(crate) fn start(
        &mut self,
        pixel: [u32; 2],
        index: u32,
        dimension: u32,
    ) -> Result<(), Error> {
        if index >= self.spp {
            return Err(Error::SampleIndexOutOfRange {
                index,
                spp: self.spp,
            });
        }
        self.pixel = pixel;
        self.index = index;
        self.dimension = dimension;
        Ok(())
    }

    /// The dimension of the next draw of `count` values; moves the counter
    /// on by `count` (wrapping past `u32::MAX`).
    pub(crate) fn take(&mut self, count: u32) -> u32 {
        let dimension = self.dimension;
        self.dimension = dimension.wrapping_add(count);
        dimension
    }

    /// The key of a draw of kind `tag` at `dimension` in the current pixel:
    /// the same for every sample index of the pixel, so the pixel's samples
    /// of that dimension form one set.
    pub(crate) fn set_key(&self, tag: u64, dimension: u32) -> u64 {
        let [x, y] = self.pixel;
        hash(&[
            self.seed_hash,
            tag,
            u64::from(x) << 32 | u64::from(y),
            u64::from(dimension),
        ])
    }
}

/// Whether `points` (`2^m` of them, in `[0, 1)²`) hold exactly one point in
/// every elementary interval of area `2^-m` in base 2: a (0,m,2)-net.
pub(crate) fn is_net(points: &[[f64; 2]]) -> bool {
    let n = points.len();
    if !n.is_power_of_two() {
        return false;
    }
    let m = n.trailing_zeros();
    (0..=m).all(|a| {
        let mut seen = vec![false; n];
        points.iter().all(|p| {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "in [0, 2^m) for values in [0, 1)"
            )]
            let (cx, cy) = (
                ((p[0] * f64::from(1_u32 << a)) as usize).min((1 << a) - 1),
                ((p[1] * f64::from(1_u32 << (m - a))) as usize).min((1 << (m - a)) - 1),
            );
            let cell = (cx << (m - a)) | cy;
            !std::mem::replace(&mut seen[cell], true)
        })
    })
}
