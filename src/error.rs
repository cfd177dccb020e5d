//! The one error type of the crate.

use core::fmt;

/// Why a sampler could not be built.
///
/// Every constructor validates its inputs up front and returns one of these
/// instead of panicking, aborting or running out of memory.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error {
    /// Occurs when the dimension `N` is zero.
    ZeroDimension,
    /// Occurs when the radius is NaN, infinite, zero or negative, or so small
    /// or large that its square is not a normal `f64` (outside about
    /// `1e-150 ..= 1e150`), where squared distances can no longer be compared.
    InvalidRadius,
    /// Occurs when a bound of the box is NaN or infinite.
    NonFiniteBound {
        /// The first axis with a bad bound.
        axis: usize,
    },
    /// Occurs when `lo >= hi` on some axis: the half-open box is empty.
    EmptyBox {
        /// The first empty axis.
        axis: usize,
    },
    /// Occurs when `hi - lo` overflows to infinity on some axis
    /// (for example `-1e308 .. 1e308`).
    ExtentOverflow {
        /// The first axis whose extent overflows.
        axis: usize,
    },
    /// Occurs when the number of attempts `k` is zero.
    ZeroAttempts,
    /// Occurs when the number of attempts `k` is above
    /// [`MAX_ATTEMPTS`](crate::MAX_ATTEMPTS) (65 536). A run costs about
    /// `2·n·k` candidate throws for `n` points, so a larger `k` only makes a
    /// run take minutes for no visible gain in packing.
    TooManyAttempts {
        /// The largest `k` accepted.
        max: u32,
    },
    /// Occurs when count mode ([`PoissonDiskBuilder::about_points`](crate::PoissonDiskBuilder::about_points))
    /// in 2-D or 3-D is asked for with `k` outside the range its density
    /// tables cover: below 3 growth dies out at random, so no radius gives
    /// a count; above 1000 the density, still creeping up, is not measured.
    CountAttemptsOutOfRange {
        /// The smallest `k` count mode takes.
        min: u32,
        /// The largest.
        max: u32,
    },
    /// Occurs when count mode
    /// ([`PoissonDiskBuilder::about_points`](crate::PoissonDiskBuilder::about_points))
    /// asks for 0 points.
    InvalidPointCount,
    /// Occurs when a pre-placed point given to
    /// [`PoissonDisk::iter_with`](crate::PoissonDisk::iter_with) is not
    /// finite, lies outside the domain, or lies closer than `r` to an
    /// earlier pre-placed point.
    InvalidFixedPoint {
        /// The index of the first bad point.
        index: usize,
    },
    /// Occurs when the box spans more than 2⁴⁰ radii on some axis. Cell
    /// indices that large lose the precision the exact search relies on, so
    /// neither a point cap nor a larger budget helps: grow the radius or
    /// shrink the box.
    BoxTooWide {
        /// The first axis that is too wide.
        axis: usize,
    },
    /// Occurs, from `build()`, when what the background grid must allocate
    /// before its first point (the dense layout's cells and search
    /// stencils, or one point's worth of the sparse layout) is already over
    /// the budget. Only certain failures are reported up front: a job whose
    /// points may fit is started, and stops with
    /// [`MemoryBudgetExceeded`](Self::MemoryBudgetExceeded) if they do not.
    GridTooLarge {
        /// The bytes the smallest feasible layout needs up front, saturated
        /// at `u64::MAX`; always more than `budget`, or `u64::MAX`. `u64::MAX`
        /// also stands for a grid that no budget makes possible, such as a
        /// dense grid that would hold 2³² points or more.
        needed: u64,
        /// The budget in force.
        budget: u64,
    },
    /// Occurs when a streaming raster ([`Tiled`](crate::Tiled)) has no
    /// pixel: its width (axis 0) or height (axis 1) is 0.
    EmptyRaster {
        /// The first empty axis: 0 for the width, 1 for the height.
        axis: usize,
    },
    /// Occurs when the points per pixel asked of a streaming raster are not
    /// a positive finite number ([`TiledBuilder::per_pixel`](crate::TiledBuilder::per_pixel)),
    /// or exact mode asks for 0 ([`TiledBuilder::exact`](crate::TiledBuilder::exact)).
    InvalidPerPixel,
    /// Occurs when a streaming raster's rolling window would need more
    /// memory than its budget ([`TiledBuilder::max_window_bytes`](crate::TiledBuilder::max_window_bytes)).
    WindowTooLarge {
        /// The bytes the window needs, saturated at `u64::MAX`; `u64::MAX`
        /// also stands for a window no budget makes possible (more than
        /// 65 536 cells per pixel, or a radius of more than about `1.25e8`
        /// pixels).
        needed: u64,
        /// The budget in force.
        budget: u64,
    },
    /// Occurs when a run stops because storing its next point would take
    /// the memory in use (the grid, its points and the active list) past
    /// the budget. Reported by [`Points::error`](crate::Points::error) and by
    /// [`PoissonDisk::generate`](crate::PoissonDisk::generate). The points
    /// already yielded are a valid set (every guarantee holds for them);
    /// it is just not complete. Raise the budget, cap the number of points
    /// or grow the radius.
    MemoryBudgetExceeded {
        /// How many points had been made when the run stopped.
        points: u64,
        /// The budget in force.
        budget: u64,
    },
    /// Occurs at the start of a run over the whole box (no region) whose
    /// expected size is clearly over the memory budget: even stored at the
    /// bare 8 bytes a coordinate, the points the density model expects
    /// need more than twice the budget. The run makes no point. Reported as
    /// [`MemoryBudgetExceeded`](Self::MemoryBudgetExceeded) is, at once
    /// instead of after minutes. Raise the budget, cap the number of points
    /// or grow the radius.
    RunTooLarge {
        /// The points the run is expected to make (the density model's
        /// mean, or the point cap if lower), saturated at `u64::MAX`.
        expected_points: u64,
        /// The bytes those points need at the least, saturated at
        /// `u64::MAX`.
        needed: u64,
        /// The budget in force.
        budget: u64,
    },
    /// Occurs when a run in a region
    /// ([`PoissonDisk::iter_with`](crate::PoissonDisk::iter_with)) with no
    /// pre-placed points finds no first point: none of its uniform tries
    /// over the box landed in the region. The region is empty, or too small
    /// a part of the box to hit: pre-place a point in it, or sample a
    /// smaller box around it.
    RegionMissed {
        /// The tries made (`64·k`).
        tries: u64,
    },
    /// Occurs when `f32` points cannot keep the radius
    /// ([`PoissonDisk::for_f32`](crate::PoissonDisk::for_f32),
    /// [`PoissonDisk::f32_radius`](crate::PoissonDisk::f32_radius)): `r` is
    /// within a few `f32` ulps of the box's largest coordinate magnitude
    /// (the padding that rounding needs would be over a quarter of `r`), or
    /// squares of distances across the box overflow `f32`. Grow the radius,
    /// or move the box nearer the origin (coordinates relative to a corner).
    F32TooCoarse {
        /// The radius in `f32` ulps of the largest coordinate magnitude,
        /// rounded down (saturating).
        ulps: u64,
    },
    /// Occurs when a sampler with a point cap
    /// ([`PoissonDiskBuilder::max_points`](crate::PoissonDiskBuilder::max_points)) is asked for a
    /// parallel run ([`PoissonDisk::generate_parallel`](crate::PoissonDisk::generate_parallel)):
    /// a cap keeps a prefix of one run's stream, and a parallel run has no
    /// single stream. Bound its memory with the budget instead.
    PointCapInParallel,
    /// Occurs when a pixel sampler is asked for 0 samples per pixel, or for
    /// more than it supports.
    InvalidSamplesPerPixel {
        /// The count asked for.
        spp: u32,
        /// The largest count the sampler supports.
        max: u32,
    },
    /// Occurs when a pixel sampler is moved to a sample index at or past its
    /// samples per pixel.
    SampleIndexOutOfRange {
        /// The index asked for.
        index: u32,
        /// The samples per pixel: valid indices are `0..spp`.
        spp: u32,
    },
    /// Occurs when a pixel sampler that knows the image size is moved to a
    /// pixel outside it.
    PixelOutOfImage {
        /// The pixel asked for, `[x, y]`.
        pixel: [u32; 2],
        /// The image size, `[width, height]`.
        resolution: [u32; 2],
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Self::ZeroDimension => f.write_str("the dimension N must be at least 1"),
            Self::InvalidRadius => f.write_str(
                "the radius must be finite, > 0 and have a normal f64 square (about 1e-150..=1e150)",
            ),
            Self::NonFiniteBound { axis } => {
                write!(f, "the box bounds on axis {axis} must be finite")
            }
            Self::EmptyBox { axis } => {
                write!(f, "the box is empty on axis {axis}: lo must be < hi")
            }
            Self::ExtentOverflow { axis } => {
                write!(f, "the box extent hi - lo on axis {axis} overflows f64")
            }
            Self::ZeroAttempts => f.write_str("the number of attempts k must be at least 1"),
            Self::TooManyAttempts { max } => {
                write!(f, "the number of attempts k must be at most {max}")
            }
            Self::InvalidFixedPoint { index } => write!(
                f,
                "pre-placed point {index} is not finite, lies outside the domain, or lies closer \
                 than r to an earlier one"
            ),
            Self::InvalidPointCount => f.write_str("a point count must be at least 1"),
            Self::CountAttemptsOutOfRange { min, max } => write!(
                f,
                "a point count needs the number of attempts k within {min}..={max} (2-D and 3-D)"
            ),
            Self::BoxTooWide { axis } => write!(
                f,
                "the box spans more than 2^40 radii on axis {axis}: grow the radius or shrink the box"
            ),
            Self::GridTooLarge { needed: u64::MAX, budget } => write!(
                f,
                "the background grid would need more than 2^64 bytes, over the budget of {budget} bytes"
            ),
            Self::GridTooLarge { needed, budget } => write!(
                f,
                "the background grid needs {needed} bytes, over the budget of {budget} bytes"
            ),
            Self::EmptyRaster { axis: 0 } => f.write_str("the raster has width 0"),
            Self::EmptyRaster { .. } => f.write_str("the raster has height 0"),
            Self::InvalidPerPixel => f.write_str(
                "the points per pixel must be a positive finite number (exact mode: at least 1)",
            ),
            Self::WindowTooLarge {
                needed: u64::MAX,
                budget,
            } => write!(
                f,
                "no streaming window can hold this raster at this radius (budget {budget} bytes)"
            ),
            Self::WindowTooLarge { needed, budget } => write!(
                f,
                "the streaming window needs {needed} bytes, over the budget of {budget} bytes"
            ),
            Self::MemoryBudgetExceeded { points, budget } => write!(
                f,
                "the run stopped after {points} points: the next one would take its memory past \
                 the budget of {budget} bytes (the points made are valid, but not complete)"
            ),
            Self::RunTooLarge {
                expected_points,
                needed,
                budget,
            } => {
                if expected_points == u64::MAX {
                    f.write_str("the run is expected to make more than 1.8e19 points")?;
                } else {
                    write!(f, "the run is expected to make about {expected_points} points")?;
                }
                if needed == u64::MAX {
                    f.write_str(", which need more than 1.8e19 bytes")?;
                } else {
                    write!(f, ", which need at least {needed} bytes")?;
                }
                write!(
                    f,
                    ", over the memory budget of {budget} bytes: raise the budget, cap the \
                     points or use a larger radius"
                )
            }
            Self::RegionMissed { tries } => write!(
                f,
                "no first point landed in the region in {tries} uniform tries over the box: \
                 the region is empty or too small a part of the box (pre-place a point in it, \
                 or sample a smaller box around it)"
            ),
            Self::F32TooCoarse { ulps } => write!(
                f,
                "f32 points cannot keep this radius: it spans only {ulps} f32 ulps of the box's \
                 largest coordinate (or squared distances overflow f32); grow the radius or \
                 move the box nearer the origin"
            ),
            Self::PointCapInParallel => f.write_str(
                "a parallel run takes no point cap (a cap keeps a prefix of one run's stream)",
            ),
            Self::InvalidSamplesPerPixel { spp, max } => write!(
                f,
                "the samples per pixel must be in 1..={max}, not {spp}"
            ),
            Self::SampleIndexOutOfRange { index, spp } => write!(
                f,
                "the sample index {index} is past the {spp} samples per pixel"
            ),
            Self::PixelOutOfImage {
                pixel: [x, y],
                resolution: [w, h],
            } => write!(f, "the pixel ({x}, {y}) lies outside the {w}x{h} image"),
        }
    }
}

impl core::error::Error for Error {}
