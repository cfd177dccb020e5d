//! [`NetPixelSampler`]: Poisson disk nets, sets that are stratified like a
//! (0,m,2)-net and spaced like a Poisson disk set at once, in every
//! dimension of every pixel.

use super::hash::mix;
use super::net_keys::{Shared, compose, tile, tile_key};
use super::net_table::{NETS, SHIFTED};
use super::{CameraSample, PixelSampler};
use crate::Error;
use std::sync::Arc;

/// The largest sample count per pixel [`NetPixelSampler`] accepts.
pub const NET_MAX_SAMPLES_PER_PIXEL: u32 = 4096;

/// Separates a draw's hash input by kind, as in the Poisson sampler.
const TAG_FILM: u64 = 0;
const TAG_1D: u64 = 1;
const TAG_2D: u64 = 2;

/// Salts the user's seed before it is mixed (not the Poisson sampler's
/// salt: the two samplers draw unrelated sets for the same seed).
const SEED_SALT: u64 = 0x4528_21e6_38d0_1377;

/// Separates a draw's second hash input from its first.
const SECOND: u64 = 0xbe54_66cf_34e9_0c6c;

/// Separates a lattice draw's shift hash from the move hash.
const THIRD: u64 = 0xc0ac_29b7_c97c_50dd;

/// Shared moves are kept for hash inputs `dimension << 2 | kind` below
/// this (dimensions below 32); others are hashed when drawn.
const SHARED_CACHED: u64 = 128;

/// A [`PixelSampler`] whose film offsets and every 2-D pair of every pixel
/// are a **Poisson disk net**: for `spp = 2^m` (up to 4096) a (0,m,2)-net (every
/// elementary interval of area `1/spp` holds exactly one sample) whose
/// points also keep a large toroidal minimum distance; for other counts a
/// set stratified in both 1-D projections (one sample in every column and
/// every row of the `spp × spp` grid), just as well spaced. Every 1-D
/// dimension (time, …) is a stratified set of evenly spaced values.
///
/// # How a set is made
/// Sets live on the `n × n` grid of cells (`n = spp`): one point per cell
/// it occupies, and every point at the same offset inside its cell, so the
/// set's distances are exactly those of its cells.
/// - `n = 2^m` up to 64: a bank of nets built offline by `examples/net_bank.rs`
///   (simulated annealing over swaps that keep the net property, with a
///   balance constraint; the table is `src/render/net_table.rs`).
/// - `n = 2^m` from 128 to 4096: a bank of *shift-invariant* nets from
///   the same generator, nets whose every cyclic shift of the columns is a
///   net too (Hammersley's net with its rows Owen-scrambled, the flips
///   annealed for spacing). A uniform column shift is then one of the
///   moves, and it alone makes every cell equally likely.
/// - Other `n`: the rank-1 lattice `(c, a·c mod n)` whose multiplier `a`
///   (coprime to `n`) gives the largest minimum distance, found in
///   [`new`](Self::new).
///
/// A draw at (pixel, dimension) takes moves that keep both the
/// stratification and every distance:
/// - the bank entry (nets);
/// - a shift of the columns by whole cells (nets from 128 samples);
/// - shifts by a half in x and y, reflections in x and y, and the x↔y swap
///   (nets: 32 moves); shifts by whole cells, both reflections and the swap
///   (lattices);
/// - the common offset inside the cells, uniform;
/// - which point is sample `index`: `(u·index + k) mod n`, `u` a unit
///   mod `n`, `k` uniform.
///
/// # Error as blue noise across pixels (`spp` a power of two up to 64)
/// The bank entry, the symmetry and the offset inside the cells are read
/// from a 32 × 32 toroidal tile of per-pixel keys (`src/render/net_tile.rs`,
/// made by `examples/net_tile.rs` by simulated annealing), at an offset
/// hashed from the seed and the dimension, and composed with moves shared
/// by the whole image for that seed and dimension (a uniform symmetry after
/// the tile's, a uniform offset added to the tile's mod one cell). The
/// tile is chosen so that when neighbouring pixels integrate the same
/// function their errors cancel: the error image has little power at low
/// frequencies (blue noise), which a blur, a denoiser or the eye removes.
/// Each bank entry fills the same number of tile pixels and the shared
/// moves are uniform group elements, so every pixel's moves keep exactly
/// the distribution below (guarantee 3). Which point is sample `index`
/// still comes from the pixel's own hash. Pixels 32 apart draw the same set
/// (in another order). Other counts hash every move from the pixel.
///
/// # Guarantees
/// 1. Exactly `spp` samples per pixel in every dimension; film offsets and
///    every 2-D pair are a (0,m,2)-net when `spp = 2^m`
///    ([`is_net`](Self::is_net)), and stratified in x and in y otherwise;
///    1-D values hold one value in every `[j/spp, (j+1)/spp)`.
/// 2. The toroidal minimum distance between a pixel's points in any 2-D
///    dimension is at least [`min_distance_2d`](Self::min_distance_2d);
///    1-D values are `1/spp` apart (to 2⁻³²).
/// 3. Balanced: over the bank entries and the moves, every sample index is
///    equally likely in every cell of the `spp × spp` grid (the tests
///    enumerate them), and the offset inside the cell is uniform, so each
///    value is uniform on the 2⁻³² grid and estimates are unbiased.
/// 4. Values are a pure function of (seed, pixel, sample index,
///    dimension), as the [`PixelSampler`] contract asks.
///
/// # Example: a (0,4,2)-net of film offsets in every pixel
/// ```
/// use bridson::{NetPixelSampler, PixelSampler};
/// let mut sampler = NetPixelSampler::new(16, 7)?.with_resolution([64, 48]);
/// let mut films = Vec::new();
/// for index in 0..16 {
///     sampler.start_pixel_sample([10, 20], index, 0)?;
///     films.push(sampler.camera_sample().film);
/// }
/// // Every elementary interval of area 1/16 holds exactly one offset.
/// for k in 0..=4 {
///     let (columns, rows) = (1u32 << k, 16u32 >> k);
///     let mut seen = [false; 16];
///     for [x, y] in &films {
///         let cell = (x * f64::from(columns)) as u32 * rows + (y * f64::from(rows)) as u32;
///         assert!(!std::mem::replace(&mut seen[cell as usize], true));
///     }
/// }
/// assert!(sampler.start_pixel_sample([0, 0], 16, 0).is_err());
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct NetPixelSampler {
    layout: Arc<Layout>,
    seed: u64,
    /// `mix(seed ^ SEED_SALT)`.
    seed_hash: u64,
    resolution: Option<[u32; 2]>,
    pixel: [u32; 2],
    /// `mix(seed_hash ^ pixel)`, for the current pixel.
    pixel_hash: u64,
    /// The shared moves of the first dimensions (tiled counts only).
    shared: Arc<[Shared]>,
    index: u32,
    dimension: u32,
}

/// What one sample count's sets are made of.
#[derive(Debug)]
pub(crate) struct Layout {
    /// Samples per pixel, `n`.
    n: u32,
    /// `Some(m)` when `n = 2^m` (the net bank), else `None` (the lattice).
    m: Option<u32>,
    /// Nets: the bank, `sets` nets of `n` rows (row of column `c`).
    rows: &'static [u16],
    sets: u32,
    /// Nets: every cyclic shift of a bank entry's columns is a net too, and
    /// the moves shift them by a uniform whole number of cells.
    shifted: bool,
    /// Lattices: the multiplier.
    a: u32,
    /// The units mod `n` that map sample indices to points.
    units: Vec<u32>,
    /// The smallest toroidal minimum distance of any set, in cells².
    min_d2_cells: Option<u64>,
    /// Nets: the tile of per-pixel keys, when there is one for `n`.
    tile: Option<&'static [u32]>,
}

/// A draw's moves, all of them chosen by hash: which set, the symmetry,
/// the cell shift, which point is sample `index`, the offset in the cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Moves {
    /// The bank entry (nets; 0 for lattices).
    pub(crate) set: u32,
    /// Bits 0-1: x flip class (nets: none, half shift, reflection, both;
    /// lattices: bit 0 reflects x), bits 2-3 the same for y, bit 4 the swap.
    pub(crate) symmetry: u32,
    /// The shift in cells, x and y (lattices; shifted nets use x only).
    pub(crate) shift: [u32; 2],
    /// Sample `index` takes point `(unit · index + key) mod n`.
    pub(crate) unit: u32,
    pub(crate) key: u32,
}

impl Layout {
    fn build(n: u32) -> Self {
        let units: Vec<u32> = (1..n.max(2)).filter(|&u| gcd(u, n) == 1).collect();
        let units = if units.is_empty() { vec![1] } else { units };
        let bank = NETS
            .get(n.trailing_zeros() as usize)
            .filter(|_| n.is_power_of_two());
        if let Some(&rows) = bank {
            let m = n.trailing_zeros();
            let sets = u32::try_from(rows.len() / n as usize).unwrap_or(1).max(1);
            let mut layout = Self {
                n,
                m: Some(m),
                rows,
                sets,
                shifted: SHIFTED.get(m as usize).copied().unwrap_or(false),
                a: 1,
                units,
                min_d2_cells: None,
                tile: tile(m),
            };
            layout.min_d2_cells = (0..sets).filter_map(|s| layout.set_min_d2(s)).min();
            layout
        } else {
            // The multiplier with the largest minimum distance; ties go to
            // the smallest.
            let mut best = (0, 1);
            for &a in &units {
                let d2 = lattice_min_d2(n, a);
                if d2 > best.0 {
                    best = (d2, a);
                }
            }
            Self {
                n,
                m: None,
                rows: &[],
                sets: 1,
                shifted: false,
                a: best.1,
                units,
                min_d2_cells: (n > 1).then_some(best.0),
                tile: None,
            }
        }
    }

    /// The unmoved cell of point `slot` of set `set`.
    #[inline(always)]
    fn cell(&self, set: u32, slot: u32) -> [u32; 2] {
        if self.m.is_some() {
            let at = set as usize * self.n as usize + slot as usize;
            [slot, u32::from(self.rows.get(at).copied().unwrap_or(0))]
        } else {
            let y = u64::from(slot) * u64::from(self.a) % u64::from(self.n);
            #[expect(clippy::cast_possible_truncation, reason = "below n, a u32")]
            let y = y as u32;
            [slot, y]
        }
    }

    /// The cell of sample `index` under `moves`.
    #[cfg(test)]
    pub(crate) fn place(&self, moves: Moves, index: u32) -> [u32; 2] {
        self.place_offsets(moves, index, [0, 0]).0
    }

    /// The cell of sample `index` under `moves`, and its offsets inside the
    /// cell (32-bit fractions) given the unmoved ones: for nets the moves
    /// act on the torus as the symmetries they are, so a reflection
    /// reflects the offset too (to within 2⁻³² of a cell) and the swap
    /// swaps them. Lattices leave the offsets alone.
    #[inline(always)]
    pub(crate) fn place_offsets(
        &self,
        moves: Moves,
        index: u32,
        [mut ox, mut oy]: [u32; 2],
    ) -> ([u32; 2], [u32; 2]) {
        let n = self.n;
        let slot = self.slot(moves, index);
        let [mut x, mut y] = self.cell(moves.set, slot);
        if self.m.is_some() {
            // A whole-cell shift of the columns (0 unless `shifted`).
            x = (x + moves.shift[0]) & (n - 1);
            // Bit 0: a half shift; bit 1: a reflection (all bits flipped).
            let flip = |bits: u32| ((n >> 1) * (bits & 1)) ^ ((n - 1) * (bits >> 1 & 1));
            x ^= flip(moves.symmetry);
            y ^= flip(moves.symmetry >> 2);
            if moves.symmetry & 2 == 2 {
                ox = !ox;
            }
            if moves.symmetry & 8 == 8 {
                oy = !oy;
            }
        } else {
            x = add_mod(x, moves.shift[0], n);
            y = add_mod(y, moves.shift[1], n);
            if moves.symmetry & 1 == 1 {
                x = n - 1 - x;
            }
            if moves.symmetry & 4 == 4 {
                y = n - 1 - y;
            }
        }
        if moves.symmetry & 16 == 16 {
            ([y, x], [oy, ox])
        } else {
            ([x, y], [ox, oy])
        }
    }

    /// The point of sample `index`: `(unit · index + key) mod n`.
    #[inline(always)]
    pub(crate) fn slot(&self, moves: Moves, index: u32) -> u32 {
        let v = u64::from(moves.unit) * u64::from(index) + u64::from(moves.key);
        let v = match self.m {
            Some(m) => v & ((1 << m) - 1),
            None => v % u64::from(self.n),
        };
        #[expect(clippy::cast_possible_truncation, reason = "below n, a u32")]
        let v = v as u32;
        v
    }

    /// The moves a hash chooses. Nets: bits 0-4 the symmetry, the next
    /// `log2(sets)` the bank entry, bits 12-43 the unit, the top `m` the
    /// key, so that entry, symmetry and key are exactly uniform and
    /// independent; shifted nets take the unit from bits 12-31 and the
    /// column shift from bits 32 to `31 + m` (`m <= 12`). Lattices: bits 0-4 the symmetry, 5-31 the unit, 32-63
    /// the key, and a second hash the shifts (uniform to within `n/2³²`).
    #[inline(always)]
    fn moves(&self, h: u64) -> Moves {
        let n = self.n;
        let len = u32::try_from(self.units.len()).unwrap_or(u32::MAX);
        #[expect(clippy::cast_possible_truncation, reason = "bit fields of the hash")]
        match self.m {
            Some(m) if self.shifted => Moves {
                set: (h >> 5) as u32 & (self.sets - 1),
                symmetry: h as u32 & 31,
                shift: [(h >> 32) as u32 & (n - 1), 0],
                unit: self.unit(below_u32(((h >> 12) as u32) << 12, len)),
                key: (h >> (64 - m)) as u32,
            },
            Some(m) => Moves {
                set: (h >> 5) as u32 & (self.sets - 1),
                symmetry: h as u32 & 31,
                shift: [0, 0],
                unit: self.unit(below_u32((h >> 12) as u32, len)),
                key: if m == 0 { 0 } else { (h >> (64 - m)) as u32 },
            },
            None => {
                let shifts = mix(h ^ THIRD);
                Moves {
                    set: 0,
                    symmetry: h as u32 & 31,
                    shift: [
                        below_u32((shifts >> 32) as u32, n),
                        below_u32(shifts as u32, n),
                    ],
                    unit: self.unit(below_u32((h as u32) & !31, len)),
                    key: below_u32((h >> 32) as u32, n),
                }
            }
        }
    }

    #[inline(always)]
    fn unit(&self, at: u32) -> u32 {
        self.units.get(at as usize).copied().unwrap_or(1)
    }

    /// A cell coordinate and a 32-bit offset as a value in `[0, 1)`:
    /// `(c + offset / 2³²) / n`, rounded down to the 2⁻³² grid.
    #[inline(always)]
    fn value(&self, c: u32, offset: u32) -> f64 {
        let v = u64::from(c) << 32 | u64::from(offset);
        let q = match self.m {
            Some(m) => v >> m,
            None => v / u64::from(self.n),
        };
        #[expect(clippy::cast_precision_loss, reason = "q < 2^32 is exact in f64")]
        let q = q as f64;
        q * (1.0 / 4_294_967_296.0)
    }

    /// The smallest toroidal distance², in cells², between two points of
    /// bank entry `set`: columns `dc` apart are compared only while `dc²`
    /// is below the best so far, so it costs about `n·d_min` steps.
    fn set_min_d2(&self, set: u32) -> Option<u64> {
        let n = self.n;
        let mut best: Option<u64> = None;
        for dc in 1..=n / 2 {
            if best.is_some_and(|b| u64::from(dc) * u64::from(dc) >= b) {
                break;
            }
            for a in 0..n {
                let b = (a + dc) & (n - 1);
                let [ax, ay] = self.cell(set, a);
                let [bx, by] = self.cell(set, b);
                let d2 = torus_d2(ax, bx, n) + torus_d2(ay, by, n);
                best = Some(best.map_or(d2, |x| x.min(d2)));
            }
        }
        best
    }
}

#[inline(always)]
fn add_mod(a: u32, b: u32, n: u32) -> u32 {
    let s = u64::from(a) + u64::from(b);
    let n = u64::from(n);
    #[expect(clippy::cast_possible_truncation, reason = "below n, a u32")]
    let r = (if s >= n { s - n } else { s }) as u32;
    r
}

/// A uniform index in `0..n` from 32 hash bits (multiply-high).
#[inline(always)]
fn below_u32(h: u32, n: u32) -> u32 {
    ((u64::from(h) * u64::from(n)) >> 32) as u32
}

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Squared toroidal distance along one axis of `n` cells.
fn torus_d2(a: u32, b: u32, n: u32) -> u64 {
    let d = a.abs_diff(b);
    let d = u64::from(d.min(n - d));
    d * d
}

/// The smallest squared toroidal distance, in cells², of the lattice
/// `(c, a·c mod n)`: that of its shortest nonzero vector.
fn lattice_min_d2(n: u32, a: u32) -> u64 {
    (1..n)
        .map(|c| {
            #[expect(clippy::cast_possible_truncation, reason = "below n, a u32")]
            let y = (u64::from(c) * u64::from(a) % u64::from(n)) as u32;
            torus_d2(0, c, n) + torus_d2(0, y, n)
        })
        .min()
        .unwrap_or(0)
}

impl NetPixelSampler {
    /// A sampler of `spp` samples per pixel for `seed`, accepting any
    /// pixel. It starts at pixel `[0, 0]`, sample 0, dimension 0.
    ///
    /// Cheap: the nets come from a table; a count that is not a power of
    /// two searches its lattice multiplier, `O(spp²)`.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if `spp` is 0 or above
    /// [`NET_MAX_SAMPLES_PER_PIXEL`].
    pub fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        if !(1..=NET_MAX_SAMPLES_PER_PIXEL).contains(&spp) {
            return Err(Error::InvalidSamplesPerPixel {
                spp,
                max: NET_MAX_SAMPLES_PER_PIXEL,
            });
        }
        Ok(Self::from_layout(Arc::new(Layout::build(spp)), seed))
    }

    fn from_layout(layout: Arc<Layout>, seed: u64) -> Self {
        let seed_hash = mix(seed ^ SEED_SALT);
        let cached = if layout.tile.is_some() {
            SHARED_CACHED
        } else {
            0
        };
        let shared = (0..cached)
            .map(|input| Shared::new(seed_hash ^ input, layout.n))
            .collect();
        Self {
            layout,
            seed,
            seed_hash,
            resolution: None,
            pixel: [0, 0],
            pixel_hash: pixel_hash(seed_hash, [0, 0]),
            shared,
            index: 0,
            dimension: 0,
        }
    }

    /// The same sampler for another seed, sharing its tables, at pixel
    /// `[0, 0]`, sample 0, dimension 0, with the same resolution.
    #[must_use]
    pub fn with_seed(&self, seed: u64) -> Self {
        Self {
            resolution: self.resolution,
            ..Self::from_layout(Arc::clone(&self.layout), seed)
        }
    }

    /// The same sampler, told the image size `[width, height]`: from now on
    /// a pixel with `x >= width` or `y >= height` is an error in
    /// [`start_pixel_sample`](PixelSampler::start_pixel_sample).
    #[must_use]
    pub fn with_resolution(mut self, resolution: [u32; 2]) -> Self {
        self.resolution = Some(resolution);
        self
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The image size, if the sampler was told it.
    pub fn resolution(&self) -> Option<[u32; 2]> {
        self.resolution
    }

    /// The current pixel.
    pub fn pixel(&self) -> [u32; 2] {
        self.pixel
    }

    /// The current sample index.
    pub fn sample_index(&self) -> u32 {
        self.index
    }

    /// The dimension the next [`get_1d`](PixelSampler::get_1d) or
    /// [`get_2d`](PixelSampler::get_2d) draws.
    pub fn dimension(&self) -> u32 {
        self.dimension
    }

    /// Whether every pixel's film offsets and 2-D pairs are (0,m,2)-nets:
    /// `spp` is a power of two (the bank holds every one the sampler
    /// accepts).
    pub fn is_net(&self) -> bool {
        self.layout.m.is_some()
    }

    /// A lower bound on the toroidal minimum distance between the points of
    /// one pixel in any 2-D dimension (film, lens, …), on the unit torus:
    /// the smallest over the sets the sampler draws from (less 2⁻³¹ when
    /// `spp` is not a power of two, for rounding). `None` for one sample
    /// per pixel.
    pub fn min_distance_2d(&self) -> Option<f64> {
        let d2 = self.layout.min_d2_cells?;
        #[expect(clippy::cast_precision_loss, reason = "small integers")]
        let (d2, n) = (d2 as f64, f64::from(self.layout.n));
        // Net values are exact multiples of the cell size apart; lattice
        // values are rounded down to the 2⁻³² grid one by one, which can
        // bring two of them up to √2 · 2⁻³² closer.
        let rounding = if self.layout.m.is_some() {
            0.0
        } else {
            2.0 / 4_294_967_296.0
        };
        Some(d2.sqrt() / n - rounding)
    }

    /// The moves of a draw and the offsets inside the cells, before the
    /// moves act on them. Tiled counts: the bank entry, the symmetry and
    /// the offsets from the tile composed with the shared moves, and the
    /// rest (which point is sample `index`) from the pixel's hash; other
    /// counts: all from the pixel's hashes.
    #[inline(always)]
    fn draw(&self, tag: u64, dimension: u32) -> (Moves, [u32; 2]) {
        let kind = u64::from(dimension) << 2 | tag;
        let input = self.pixel_hash ^ kind;
        let layout = &*self.layout;
        let mut moves = layout.moves(mix(input));
        if let Some(tile) = layout.tile {
            let computed;
            let shared = match usize::try_from(kind).ok().and_then(|k| self.shared.get(k)) {
                Some(s) => s,
                None => {
                    computed = Shared::new(self.seed_hash ^ kind, layout.n);
                    &computed
                }
            };
            let (set, symmetry, [ox, oy]) = tile_key(tile, self.pixel, shared);
            moves.set = set;
            moves.symmetry = compose(shared.symmetry, symmetry);
            if layout.shifted {
                moves.shift = [shared.shift, 0];
            }
            let offsets = [
                (ox << 24).wrapping_add(shared.offset[0]),
                (oy << 24).wrapping_add(shared.offset[1]),
            ];
            (moves, offsets)
        } else {
            let offsets = mix(input ^ SECOND);
            #[expect(clippy::cast_possible_truncation, reason = "the low word")]
            let offsets = [(offsets >> 32) as u32, offsets as u32];
            (moves, offsets)
        }
    }

    #[inline(always)]
    fn plane(&self, tag: u64, dimension: u32) -> [f64; 2] {
        let (moves, offsets) = self.draw(tag, dimension);
        let layout = &*self.layout;
        let ([x, y], [ox, oy]) = layout.place_offsets(moves, self.index, offsets);
        [layout.value(x, ox), layout.value(y, oy)]
    }

    #[inline(always)]
    fn line(&self, dimension: u32) -> f64 {
        let (moves, [offset, _]) = self.draw(TAG_1D, dimension);
        let layout = &*self.layout;
        let slot = layout.slot(moves, self.index);
        layout.value(slot, offset)
    }
}

/// The hash of a pixel under a seed.
#[inline(always)]
fn pixel_hash(seed_hash: u64, [x, y]: [u32; 2]) -> u64 {
    mix(seed_hash ^ (u64::from(x) | u64::from(y) << 32))
}

impl PixelSampler for NetPixelSampler {
    fn samples_per_pixel(&self) -> u32 {
        self.layout.n
    }

    fn start_pixel_sample(
        &mut self,
        pixel: [u32; 2],
        index: u32,
        dimension: u32,
    ) -> Result<(), Error> {
        let spp = self.layout.n;
        if index >= spp {
            return Err(Error::SampleIndexOutOfRange { index, spp });
        }
        if let Some(resolution) = self.resolution
            && (pixel[0] >= resolution[0] || pixel[1] >= resolution[1])
        {
            return Err(Error::PixelOutOfImage { pixel, resolution });
        }
        if pixel != self.pixel {
            self.pixel = pixel;
            self.pixel_hash = pixel_hash(self.seed_hash, pixel);
        }
        self.index = index;
        self.dimension = dimension;
        Ok(())
    }

    #[inline]
    fn get_1d(&mut self) -> f64 {
        let v = self.line(self.dimension);
        self.dimension = self.dimension.wrapping_add(1);
        v
    }

    #[inline]
    fn get_2d(&mut self) -> [f64; 2] {
        let v = self.plane(TAG_2D, self.dimension);
        self.dimension = self.dimension.wrapping_add(2);
        v
    }

    #[inline]
    fn get_pixel_2d(&mut self) -> [f64; 2] {
        self.plane(TAG_FILM, 0)
    }

    #[inline]
    fn camera_sample(&mut self) -> CameraSample {
        let d = self.dimension;
        let film = self.plane(TAG_FILM, 0);
        let time = self.line(d);
        let lens = self.plane(TAG_2D, d.wrapping_add(1));
        self.dimension = d.wrapping_add(3);
        CameraSample { film, time, lens }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Calls `f` with every move of a layout: bank entry, symmetry, shifts
    /// and key (the unit is fixed: any unit gives the same counts, as `key`
    /// is added after it). Shifts: both axes for lattices, the columns for
    /// shifted nets, none for other nets.
    fn for_every_move(layout: &Layout, mut f: impl FnMut(Moves)) {
        let n = layout.n;
        let (xs, ys) = match (layout.m, layout.shifted) {
            (None, _) => (n, n),
            (Some(_), true) => (n, 1),
            (Some(_), false) => (1, 1),
        };
        let unit = layout.units[layout.units.len() / 2];
        for set in 0..layout.sets {
            for symmetry in 0..32 {
                for sx in 0..xs {
                    for sy in 0..ys {
                        for key in 0..n {
                            f(Moves {
                                set,
                                symmetry,
                                shift: [sx, sy],
                                unit,
                                key,
                            });
                        }
                    }
                }
            }
        }
    }

    /// Every cell of the `n × n` grid counted sample `index` equally often.
    fn assert_uniform(counts: &[u32], n: u32, index: u32) {
        let first = counts[0];
        assert!(
            counts.iter().all(|&c| c == first),
            "n {n}, index {index}: counts from {} to {}",
            counts.iter().min().unwrap(),
            counts.iter().max().unwrap()
        );
    }

    /// Over every move, sample `index` falls equally often in every cell
    /// of the `n × n` grid.
    fn assert_balanced_at(layout: &Layout, index: u32) {
        let n = layout.n;
        let mut counts = vec![0u32; (n * n) as usize];
        for_every_move(layout, |mv| {
            let [x, y] = layout.place(mv, index);
            counts[(x * n + y) as usize] += 1;
        });
        assert_uniform(&counts, n, index);
    }

    /// [`assert_balanced_at`] for every index up to 64 samples; at 128,
    /// for the first, second, middle and last; above, for one (an index
    /// enters the moves only through `(unit · index + key) mod n`, which
    /// takes every value once as the key does, so the counts are the same
    /// for every index).
    fn assert_balanced(n: u32) {
        let layout = Layout::build(n);
        let indices: Vec<u32> = match n {
            0..=64 => (0..n).collect(),
            65..=128 => vec![0, 1, n / 2, n - 1],
            _ => vec![n / 3],
        };
        for index in indices {
            assert_balanced_at(&layout, index);
        }
    }

    #[test]
    fn every_index_is_equally_likely_in_every_cell_for_nets() {
        // Up to 512 samples: 32 · 512² moves for the last.
        for m in 0..NETS.len().min(10) {
            assert_balanced(1 << m);
        }
    }

    #[test]
    #[ignore = "7·10^8 moves, 13 s in release: cargo test --release -- --ignored"]
    fn every_index_is_equally_likely_in_every_cell_for_big_nets() {
        for m in 10..NETS.len() {
            assert_balanced(1 << m);
        }
    }

    /// Over every tile offset, shared symmetry, shared column shift (for
    /// shift-invariant banks) and key, through the sampler's own path
    /// ([`tile_key`], [`compose`], [`Layout::place`]), sample `index` falls
    /// equally often in every cell: the tiled draw is balanced as it is,
    /// not only because the moves it makes are uniform.
    fn assert_tiled_balanced_at(layout: &Layout, index: u32) {
        use super::super::net_tile::TILE_SIDE;
        let n = layout.n;
        let tile = layout.tile.expect("a tiled count");
        let shifts = if layout.shifted { n } else { 1 };
        let unit = layout.units[layout.units.len() / 2];
        let mut counts = vec![0u32; (n * n) as usize];
        for ty in 0..TILE_SIDE {
            for tx in 0..TILE_SIDE {
                for g in 0..32 {
                    for shift in 0..shifts {
                        let shared = Shared {
                            tile: [tx, ty],
                            symmetry: g,
                            shift,
                            offset: [0, 0],
                        };
                        let (set, symmetry, _) = tile_key(tile, [5, 9], &shared);
                        for key in 0..n {
                            let mv = Moves {
                                set,
                                symmetry: compose(g, symmetry),
                                shift: [shift, 0],
                                unit,
                                key,
                            };
                            let [x, y] = layout.place(mv, index);
                            counts[(x * n + y) as usize] += 1;
                        }
                    }
                }
            }
        }
        assert_uniform(&counts, n, index);
    }

    #[test]
    fn tiled_draws_are_balanced() {
        let mut tiled = 0;
        for m in 0..NETS.len() {
            let n = 1u32 << m;
            let layout = Layout::build(n);
            if layout.tile.is_none() {
                continue;
            }
            tiled += 1;
            let indices: Vec<u32> = if n <= 16 {
                (0..n).collect()
            } else {
                vec![0, n / 2 + 1, n - 1]
            };
            for index in indices {
                assert_tiled_balanced_at(&layout, index);
            }
        }
        assert!(tiled >= 7, "tiles for 1 to 64 samples");
    }

    #[test]
    fn every_index_is_equally_likely_in_every_cell_for_lattices() {
        for n in [3, 5, 6, 7, 12, 24, 33] {
            assert_balanced(n);
        }
    }

    #[test]
    fn every_bank_entry_is_a_net_with_its_spacing() {
        // The generated table itself: every entry of every count is a
        // (0,m,2)-net on the grid of cells, and the bank's smallest
        // distance is what min_distance_2d reports.
        for m in 0..u32::try_from(NETS.len()).unwrap() {
            let n = 1u32 << m;
            let layout = Layout::build(n);
            assert_eq!(layout.m, Some(m), "n {n} is not read as a net");
            assert_eq!(
                NETS[m as usize].len() % n as usize,
                0,
                "n {n}: ragged table"
            );
            for set in 0..layout.sets {
                for k in 0..=m {
                    let mut seen = vec![false; n as usize];
                    for c in 0..n {
                        let [x, y] = layout.cell(set, c);
                        assert!(y < n, "n {n}, set {set}: row {y}");
                        let cell = (x >> (m - k)) << (m - k) | y >> k;
                        assert!(
                            !std::mem::replace(&mut seen[cell as usize], true),
                            "n {n}, set {set}: not a net at k = {k}"
                        );
                    }
                }
            }
            if n >= 4 {
                let d2 = layout.min_d2_cells.unwrap();
                assert!(d2 >= 2, "n {n}: cells {d2} apart");
                let smallest = (0..layout.sets).filter_map(|s| layout.set_min_d2(s)).min();
                assert_eq!(smallest, Some(d2), "n {n}: min_d2_cells");
            }
        }
    }

    /// Whether every cyclic shift of bank entry `set`'s columns is a net.
    fn every_shift_is_a_net(layout: &Layout, set: u32) -> bool {
        let (n, m) = (layout.n, layout.m.unwrap());
        (0..n).all(|t| {
            (0..=m).all(|k| {
                let mut seen = vec![false; n as usize];
                (0..n).all(|c| {
                    let [_, y] = layout.cell(set, (c + t) & (n - 1));
                    let cell = (c >> (m - k)) << (m - k) | y >> k;
                    !std::mem::replace(&mut seen[cell as usize], true)
                })
            })
        })
    }

    /// Whether the top `j` bits of bank entry `set`'s rows depend on the
    /// column `c` only through `c mod 2^j`, one to one, for every `j`: then
    /// any `2^j` consecutive columns (every residue once) meet each block of
    /// `n/2^j` rows once, which is every shifted elementary interval of
    /// width `2^j/n` holding one point, so every shift is a net.
    fn rows_follow_the_low_bits(layout: &Layout, set: u32) -> bool {
        let (n, m) = (layout.n, layout.m.unwrap());
        (1..=m).all(|j| {
            let mut top = vec![u32::MAX; 1 << j];
            let consistent = (0..n).all(|c| {
                let [_, y] = layout.cell(set, c);
                let slot = &mut top[(c & ((1 << j) - 1)) as usize];
                let bits = y >> (m - j);
                if *slot == u32::MAX {
                    *slot = bits;
                }
                *slot == bits
            });
            let mut seen = vec![false; 1 << j];
            consistent
                && top
                    .iter()
                    .all(|&b| !std::mem::replace(&mut seen[b as usize], true))
        })
    }

    /// Every shifted bank entry, with every column shift checked one by
    /// one up to `max_n` points and by [`rows_follow_the_low_bits`] above.
    fn assert_shifts_are_nets(max_n: u32) {
        let mut seen = 0;
        for m in 0..u32::try_from(NETS.len()).unwrap() {
            let layout = Layout::build(1 << m);
            if !layout.shifted {
                continue;
            }
            seen += 1;
            for set in 0..layout.sets {
                let n = layout.n;
                assert!(
                    rows_follow_the_low_bits(&layout, set),
                    "n {n}, set {set}: rows do not follow the low bits"
                );
                if n <= max_n {
                    assert!(
                        every_shift_is_a_net(&layout, set),
                        "n {n}, set {set}: a shift is not a net"
                    );
                }
            }
        }
        assert!(seen > 0, "no shifted bank");
    }

    #[test]
    fn shifted_bank_entries_stay_nets_under_every_column_shift() {
        // What makes a shifted bank balanced (every column shift is one
        // of its moves) without a balanced bank: each shift is a net.
        assert_shifts_are_nets(512);
        // The structural check can fail: a balanced bank's nets are not
        // shift-invariant.
        let balanced = Layout::build(64);
        assert!(!balanced.shifted);
        assert!(!rows_follow_the_low_bits(&balanced, 0), "64, entry 0");
        assert!(!every_shift_is_a_net(&balanced, 0), "64, entry 0");
    }

    #[test]
    #[ignore = "every shift of 1024 to 4096 points one by one: 14 s in debug"]
    fn every_column_shift_of_big_banks_is_a_net() {
        assert_shifts_are_nets(u32::MAX);
    }

    #[test]
    fn every_bank_entry_keeps_the_spacing_floor() {
        // Not only the median over pixels: the smallest ρ of every entry,
        // so that no weak net can hide in a bank (one of 32 at 128 once
        // read ρ 0.116).
        const FLOOR: f64 = 0.65;
        for m in 1..u32::try_from(NETS.len()).unwrap() {
            let n = 1u32 << m;
            let layout = Layout::build(n);
            let d_hex = (2.0 / (3f64.sqrt() * f64::from(n))).sqrt();
            for set in 0..layout.sets {
                let d2 = layout.set_min_d2(set).unwrap();
                #[expect(clippy::cast_precision_loss, reason = "small integers")]
                let rho = (d2 as f64).sqrt() / f64::from(n) / d_hex;
                assert!(rho >= FLOOR, "n {n}, set {set}: ρ {rho:.3} < {FLOOR}");
            }
        }
    }

    #[test]
    fn hashed_moves_stay_in_range() {
        for n in [1, 2, 3, 16, 100, 256] {
            let layout = Layout::build(n);
            for k in 0..200u64 {
                let mv = layout.moves(mix(k));
                assert!(mv.set < layout.sets, "n {n}: set {}", mv.set);
                assert!(mv.key < n.max(1), "n {n}: key {}", mv.key);
                assert!(mv.shift.iter().all(|&s| s < n), "n {n}: shift");
                assert!(gcd(mv.unit, n) == 1 || n == 1, "n {n}: unit {}", mv.unit);
            }
        }
    }

    #[test]
    fn values_stay_below_one() {
        for n in [1, 3, 16, 255] {
            let layout = Layout::build(n);
            let v = layout.value(n - 1, u32::MAX);
            assert!(v < 1.0, "n {n}: {v}");
            assert_eq!(layout.value(0, 0), 0.0, "n {n}");
        }
    }
}
