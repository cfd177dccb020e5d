//! `best-candidate`: pbrt-v2's `BestCandidateSampler`, a 4096-sample
//! table of Mitchell's best-candidate points tiled over the image, with an
//! exact count per pixel.

use super::stratified::{cell_2d, grid_of, stratum_1d};
use super::{Cursor, TAG_1D, TAG_2D, cursor_position, hash, to_unit};
use bridson::{Error, PixelSampler};
use std::sync::{Arc, OnceLock};

/// The number of samples in the table, as in pbrt-v2.
pub(crate) const TABLE_SIZE: usize = 4096;

/// The seed the table is built from: the table is a constant of the
/// program, like pbrt-v2's precomputed `sampledata.out`.
const TABLE_SEED: u64 = 0x0bc5_a3d1_7e21_9f40;

/// The most candidates tried for one new sample. Mitchell tries a number
/// growing with the samples placed so far (pbrt-v2's offline tool: 500 per
/// sample placed); we try `i + 1` for the `i`-th, capped here, so that the
/// table builds in milliseconds. The cap still gives a minimum distance
/// several times that of random points (`tests/baselines.rs`).
const MAX_CANDIDATES: usize = 64;

/// How many of the unplaced time (or lens) values are tried for each
/// sample when they are redistributed against its image neighbours.
/// pbrt-v2 tries every unplaced value, `O(n²)` in all; a random window of
/// this many keeps the build fast.
const REDISTRIBUTION_WINDOW: usize = 64;

/// The cells per side of the grid that finds image-space neighbours.
const GRID: usize = 64;

/// How many cells around a point's own the best-candidate search reaches:
/// two cells are about two mean spacings of 4096 points.
const REACH: isize = 2;

/// The reach of the redistribution's neighbour search: one cell, the 3 × 3
/// block, about 9 image neighbours, of which about half are placed before.
const NEIGHBOUR_REACH: isize = 1;

/// The largest value below 1.
const ONE_BELOW: f64 = 1.0 - f64::EPSILON / 2.0;

/// The five-dimensional table: image position on the unit torus, time,
/// lens.
#[derive(Debug)]
pub(crate) struct Table {
    /// Image positions, in the order Mitchell's algorithm placed them (so
    /// every prefix is itself well spread).
    pub(crate) image: Vec<[f64; 2]>,
    /// Times: stratified values redistributed so that image neighbours
    /// have distant times.
    pub(crate) time: Vec<f64>,
    /// Lens positions: a best-candidate set redistributed so that image
    /// neighbours have distant lens positions.
    pub(crate) lens: Vec<[f64; 2]>,
}

/// A deterministic stream of uniform values for building the table.
struct Stream {
    key: u64,
    count: u64,
}

impl Stream {
    fn new(name: u64) -> Self {
        Self {
            key: hash(&[TABLE_SEED, name]),
            count: 0,
        }
    }

    fn next(&mut self) -> f64 {
        self.count += 1;
        to_unit(hash(&[self.key, self.count]))
    }

    /// A uniform index in `0..n` (a bias below `n / 2⁵³`).
    fn below(&mut self, n: usize) -> usize {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a value in [0, n) floored, n a usize"
        )]
        let i = (self.next() * n as f64) as usize;
        i.min(n - 1)
    }
}

/// The toroidal distance between two coordinates in `[0, 1)`.
fn wrapped(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

fn wrapped_squared(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (wrapped(a[0], b[0]), wrapped(a[1], b[1]));
    dx * dx + dy * dy
}

/// The grid cell of a coordinate in `[0, 1)`.
fn cell(u: f64) -> usize {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "u in [0, 1), so u * GRID in [0, GRID)"
    )]
    let c = (u * GRID as f64) as usize;
    c.min(GRID - 1)
}

/// A uniform grid over the unit torus holding point numbers.
struct Grid {
    cells: Vec<Vec<u16>>,
}

impl Grid {
    fn new() -> Self {
        Self {
            cells: vec![Vec::new(); GRID * GRID],
        }
    }

    fn insert(&mut self, p: [f64; 2], number: usize) {
        let number = u16::try_from(number).expect("the table has 4096 entries");
        self.cells[cell(p[1]) * GRID + cell(p[0])].push(number);
    }

    /// Calls `f` with the number of every point in the cells within
    /// `reach` of `p`'s cell, wrapping around.
    fn near(&self, p: [f64; 2], reach: isize, mut f: impl FnMut(usize)) {
        let n = GRID.cast_signed();
        let (cx, cy) = (cell(p[0]).cast_signed(), cell(p[1]).cast_signed());
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let x = (cx + dx).rem_euclid(n).cast_unsigned();
                let y = (cy + dy).rem_euclid(n).cast_unsigned();
                for &k in &self.cells[y * GRID + x] {
                    f(usize::from(k));
                }
            }
        }
    }
}

/// Mitchell's best-candidate algorithm on the unit torus: each new point is
/// the candidate, of `min(i + 1, MAX_CANDIDATES)` uniform ones, farthest
/// from the points placed so far (as far as the grid's reach sees; a
/// candidate with no point in reach is the farthest possible).
fn best_candidate(stream: &mut Stream, grid: &mut Grid) -> Vec<[f64; 2]> {
    let mut points: Vec<[f64; 2]> = Vec::with_capacity(TABLE_SIZE);
    for i in 0..TABLE_SIZE {
        let mut best = [0.0; 2];
        let mut best_distance = -1.0;
        for _ in 0..(i + 1).min(MAX_CANDIDATES) {
            let candidate = [stream.next(), stream.next()];
            let mut nearest = f64::INFINITY;
            grid.near(candidate, REACH, |k| {
                nearest = nearest.min(wrapped_squared(candidate, points[k]));
            });
            if nearest > best_distance {
                best_distance = nearest;
                best = candidate;
            }
        }
        grid.insert(best, i);
        points.push(best);
    }
    points
}

/// Reorders `values` so that, sample by sample in table order, each takes
/// the value (among a random window of the unplaced ones) farthest from
/// the values of its image neighbours placed before it: pbrt-v2's
/// `Redistribute2D` (and its time loop), with a bounded window.
fn redistribute<T: Copy>(
    values: &mut [T],
    image: &[[f64; 2]],
    grid: &Grid,
    stream: &mut Stream,
    distance: impl Fn(T, T) -> f64,
) {
    // A random order first, so that a window holds unrelated values.
    for i in (1..values.len()).rev() {
        values.swap(i, stream.below(i + 1));
    }
    for (current, &at) in image.iter().enumerate().take(values.len()).skip(1) {
        let end = (current + REDISTRIBUTION_WINDOW).min(values.len());
        let mut best = current;
        let mut best_distance = -1.0;
        for candidate in current..end {
            let mut nearest = f64::INFINITY;
            grid.near(at, NEIGHBOUR_REACH, |k| {
                if k < current {
                    nearest = nearest.min(distance(values[k], values[candidate]));
                }
            });
            if nearest > best_distance {
                best_distance = nearest;
                best = candidate;
            }
        }
        values.swap(current, best);
    }
}

impl Table {
    fn build() -> Self {
        let mut image_grid = Grid::new();
        let image = best_candidate(&mut Stream::new(1), &mut image_grid);

        let mut stream = Stream::new(2);
        let mut time: Vec<f64> = (0..TABLE_SIZE)
            .map(|i| {
                let i = u32::try_from(i).expect("4096 fits");
                (f64::from(i) + stream.next()) / 4096.0
            })
            .collect();
        redistribute(&mut time, &image, &image_grid, &mut stream, wrapped);

        let mut lens = best_candidate(&mut Stream::new(3), &mut Grid::new());
        redistribute(&mut lens, &image, &image_grid, &mut stream, |a, b| {
            wrapped_squared(a, b)
        });
        Self { image, time, lens }
    }

    /// The table, built on first use and shared from then on.
    pub(crate) fn shared() -> Arc<Self> {
        static TABLE: OnceLock<Arc<Table>> = OnceLock::new();
        Arc::clone(TABLE.get_or_init(|| Arc::new(Self::build())))
    }
}

/// The table's samples dealt to the pixels of one tile, exactly `spp` to
/// each.
#[derive(Debug)]
pub(crate) struct Tiling {
    /// The tile's size in pixels, `[w, h]`, with `w * h * spp <= 4096`.
    pub(crate) size: [u32; 2],
    /// For local pixel `p = y * w + x`, entries `p * spp .. (p + 1) * spp`:
    /// a table index and the film offset in the pixel.
    pub(crate) entries: Vec<(u16, [f64; 2])>,
    /// How many samples were moved to a pixel other than the one they fell
    /// in, to make the counts exact.
    pub(crate) moved: usize,
}

/// The offset, in `[0, 1)`, of coordinate `x` (on a torus of length
/// `len`) in the pixel starting at `start`: as is if inside; reflected
/// across the pixel's nearer edge if outside (a sample just outside lands
/// just inside).
fn offset_in(x: f64, start: f64, len: f64) -> f64 {
    let d = (x - start - 0.5).rem_euclid(len);
    let d = if d >= len / 2.0 { d - len } else { d };
    let offset = if d >= 0.5 {
        1.0 - (d - 0.5)
    } else if d < -0.5 {
        -0.5 - d
    } else {
        d + 0.5
    };
    offset.clamp(0.0, ONE_BELOW)
}

/// The distance from `x` to the pixel starting at `start`, on a torus of
/// length `len` (0 inside).
fn outside(x: f64, start: f64, len: f64) -> f64 {
    let d = (x - start - 0.5).rem_euclid(len);
    let d = d.min(len - d);
    (d - 0.5).max(0.0)
}

impl Tiling {
    /// Deals the first `w * h * spp` table samples to a `w × h` tile, `w =
    /// ⌊√(4096 / spp)⌋`, `h = ⌊4096 / (spp w)⌋` (a square of side
    /// `√(4096 / spp)` when that is whole, e.g. 16 × 16 pixels at 16 spp).
    /// Best-candidate order makes any prefix of the table well spread.
    ///
    /// A sample goes to the pixel its scaled position falls in; then each
    /// pixel short of `spp` takes, one at a time, the sample nearest to it
    /// (toroidally in the tile) among those of pixels over `spp`, and that
    /// sample's film offset is its position reflected into the pixel
    /// across the nearer edge.
    fn build(table: &Table, spp: u32) -> Self {
        let per_tile = u32::try_from(TABLE_SIZE).expect("4096 fits") / spp;
        let w = (1..=per_tile)
            .take_while(|w| w * w <= per_tile)
            .last()
            .unwrap_or(1);
        let h = per_tile / w;
        let (wf, hf) = (f64::from(w), f64::from(h));
        let pixels = usize::try_from(w * h).expect("at most 4096");
        let spp_usize = usize::try_from(spp).expect("at most 4096");
        let n = pixels * spp_usize;

        let position = |k: usize| {
            let [x, y] = table.image[k];
            [(x * wf).min(wf * ONE_BELOW), (y * hf).min(hf * ONE_BELOW)]
        };
        let pixel_of = |p: [f64; 2]| {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "p is in [0, w) × [0, h)"
            )]
            let (x, y) = (p[0] as usize, p[1] as usize);
            y * usize::try_from(w).expect("at most 4096") + x
        };
        let mut owner: Vec<usize> = (0..n).map(|k| pixel_of(position(k))).collect();
        let mut count = vec![0_usize; pixels];
        for &p in &owner {
            count[p] += 1;
        }
        let mut moved = 0;
        let width = usize::try_from(w).expect("at most 4096");
        let mut offsets: Vec<Option<[f64; 2]>> = vec![None; n];
        for q in 0..pixels {
            let corner = [
                f64::from(u32::try_from(q % width).expect("small")),
                f64::from(u32::try_from(q / width).expect("small")),
            ];
            while count[q] < spp_usize {
                let mut best = None;
                let mut best_distance = f64::INFINITY;
                for k in 0..n {
                    if count[owner[k]] > spp_usize {
                        let p = position(k);
                        let dx = outside(p[0], corner[0], wf);
                        let dy = outside(p[1], corner[1], hf);
                        let d = dx * dx + dy * dy;
                        if d < best_distance {
                            best_distance = d;
                            best = Some(k);
                        }
                    }
                }
                let k = best.expect("counts sum to w h spp, so a pixel short means one over");
                count[owner[k]] -= 1;
                owner[k] = q;
                count[q] += 1;
                let p = position(k);
                offsets[k] = Some([
                    offset_in(p[0], corner[0], wf),
                    offset_in(p[1], corner[1], hf),
                ]);
                moved += 1;
            }
        }
        let mut entries = vec![(0_u16, [0.0; 2]); n];
        let mut filled = vec![0_usize; pixels];
        for k in 0..n {
            let q = owner[k];
            let p = position(k);
            let film = offsets[k].unwrap_or_else(|| {
                let x = f64::from(u32::try_from(q % width).expect("small"));
                let y = f64::from(u32::try_from(q / width).expect("small"));
                [
                    (p[0] - x).clamp(0.0, ONE_BELOW),
                    (p[1] - y).clamp(0.0, ONE_BELOW),
                ]
            });
            entries[q * spp_usize + filled[q]] = (u16::try_from(k).expect("< 4096"), film);
            filled[q] += 1;
        }
        Self {
            size: [w, h],
            entries,
            moved,
        }
    }
}

/// pbrt-v2's best-candidate sampler, with exactly `spp` samples in every
/// pixel.
///
/// # The table
/// Built once per program (deterministically, from a fixed seed) and
/// shared: 4096 samples whose image positions are Mitchell's
/// best-candidate points on the unit torus, whose times are 4096 stratified
/// values and whose lens positions a second best-candidate set, both
/// redistributed so that each sample's time (lens position) is far from
/// those of its image-space neighbours: pbrt-v2's `samplepat` tool, with
/// the candidate counts bounded (see [`MAX_CANDIDATES`] and
/// [`REDISTRIBUTION_WINDOW`]).
///
/// # Tiling
/// The table covers a tile of `w × h` pixels, `w h spp <= 4096` (see
/// [`Tiling`]: 16 × 16 pixels at 16 spp), repeated over the image as in
/// pbrt-v2. Unlike pbrt-v2, whose pixels get however many table samples
/// fall in them, each pixel gets exactly `spp`: samples are moved from
/// over-full to short pixels nearby. Each tile shifts the times and lens
/// positions by its own hashed offset (pbrt-v2's per-tile
/// `sampleOffsets`), so tiles repeat the film pattern only.
///
/// # Dimensions
/// The table serves the camera sample as [`PixelSampler::camera_sample`]
/// draws it: the film offset, time (the 1-D draw at dimension 0) and lens
/// (the 2-D draw at dimension 1). Every other draw falls back to padded
/// jittered strata, as the `stratified` sampler makes them (pbrt-v2 used
/// its scrambled low-discrepancy sets there).
///
/// At most 4096 samples per pixel.
#[derive(Clone, Debug)]
pub(crate) struct BestCandidateSampler {
    cursor: Cursor,
    table: Arc<Table>,
    tiling: Arc<Tiling>,
    grid: [u32; 2],
}

impl BestCandidateSampler {
    /// A sampler of `spp` samples per pixel for `seed`.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if `spp` is 0 or above 4096.
    pub(crate) fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        let cursor = Cursor::new(spp, seed, u32::try_from(TABLE_SIZE).expect("4096 fits"))?;
        let table = Table::shared();
        let tiling = Arc::new(Tiling::build(&table, spp));
        Ok(Self {
            cursor,
            table,
            tiling,
            grid: grid_of(spp),
        })
    }

    /// The shared table.
    pub(crate) fn table(&self) -> &Table {
        &self.table
    }

    /// How the table is dealt to the pixels of a tile.
    pub(crate) fn tiling(&self) -> &Tiling {
        &self.tiling
    }

    /// The table entry of the current sample, and its tile's key.
    fn entry(&self) -> ((u16, [f64; 2]), u64) {
        let [w, h] = self.tiling.size;
        let [px, py] = self.cursor.pixel;
        let local = (py % h) * w + px % w;
        let at = usize::try_from(local * self.cursor.spp + self.cursor.index).expect("below 4096");
        let tile = u64::from(px / w) << 32 | u64::from(py / h);
        let key = hash(&[self.cursor.seed_hash, 0x7469_6c65, tile]);
        (self.tiling.entries[at], key)
    }
}

/// `a + b` wrapped into `[0, 1)`, for `a`, `b` in `[0, 1)`.
fn shift(a: f64, b: f64) -> f64 {
    let s = a + b;
    (if s >= 1.0 { s - 1.0 } else { s }).min(ONE_BELOW)
}

impl PixelSampler for BestCandidateSampler {
    cursor_position!();

    fn get_1d(&mut self) -> f64 {
        let d = self.cursor.take(1);
        if d == 0 {
            let ((k, _), key) = self.entry();
            shift(self.table.time[usize::from(k)], to_unit(hash(&[key, 0])))
        } else {
            stratum_1d(
                self.cursor.set_key(TAG_1D, d),
                self.cursor.index,
                self.cursor.spp,
            )
        }
    }

    fn get_2d(&mut self) -> [f64; 2] {
        let d = self.cursor.take(2);
        if d == 1 {
            let ((k, _), key) = self.entry();
            let [u, v] = self.table.lens[usize::from(k)];
            [
                shift(u, to_unit(hash(&[key, 1]))),
                shift(v, to_unit(hash(&[key, 2]))),
            ]
        } else {
            cell_2d(self.cursor.set_key(TAG_2D, d), self.cursor.index, self.grid)
        }
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        self.entry().0.1
    }
}
