//! The field sampler (`bridson::Field`) for Python: a maximal Poisson disk
//! set that is a pure function of (seed, radius, domain, position), asked
//! for box by box.
//!
//! As for `PoissonDisk`, Python's run-time dimension reaches the
//! const-generic `Field<N>` through a match ([`with_field_dim!`], 1 to 4:
//! the field's cost grows as `5^N` and the crate calls it practical to
//! about 4-D), and the class holds a [`FieldSampler`] trait object with
//! the dimension erased. Queries run without the GIL; the chunked form
//! checks for Ctrl-C between batches of chunks. Points leave as `(n, d)`
//! float64 arrays that own the crate's buffer (no copy).

use crate::{fixed, periodic_flags, seed_u64, to_array, value_error};
use bridson::{Domain, Error, Field as CoreField, chunk_boxes, field_order};
use numpy::{PyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::cmp::Ordering;
use std::sync::Arc;

/// The largest dimension the bindings compile a field for.
pub(crate) const MAX_FIELD_DIM: usize = 4;

/// Chunks one thread makes between two checks for Ctrl-C in
/// `points_in_parallel`: at the default chunk of `64 r` (about 4 000
/// points in 2-D) a batch takes a few tens of milliseconds.
const CHUNKS_PER_THREAD_AND_BATCH: usize = 16;

/// Calls `$f::<N>(args)` with `N = $d`, for `$d` in `1..=4`; any other
/// dimension is a `ValueError`.
macro_rules! with_field_dim {
    ($d:expr, $f:ident ( $($arg:expr),* )) => {
        match $d {
            1 => $f::<1>($($arg),*),
            2 => $f::<2>($($arg),*),
            3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*),
            d => Err(PyValueError::new_err(format!(
                "a Field's dimension must be within 1..={MAX_FIELD_DIM}, not {d}"
            ))),
        }
    };
}

/// What a Python `Field` needs of the crate's, its dimension erased.
trait FieldSampler: Send + Sync {
    /// The points in `[lo, hi)`, flat, in the canonical order.
    fn points_in(&self, py: Python<'_>, lo: &[f64], hi: &[f64]) -> PyResult<Vec<f64>>;
    /// The same points made chunk by chunk on `threads` threads.
    fn points_in_parallel(
        &self,
        py: Python<'_>,
        lo: &[f64],
        hi: &[f64],
        chunk: f64,
        threads: usize,
    ) -> PyResult<Vec<f64>>;
}

impl<const N: usize> FieldSampler for CoreField<N> {
    fn points_in(&self, py: Python<'_>, lo: &[f64], hi: &[f64]) -> PyResult<Vec<f64>> {
        let lo = fixed::<f64, N>(lo, "lo")?;
        let hi = fixed::<f64, N>(hi, "hi")?;
        py.detach(|| CoreField::points_in(self, lo, hi))
            .map(Vec::into_flattened)
            .map_err(value_error)
    }

    fn points_in_parallel(
        &self,
        py: Python<'_>,
        lo: &[f64],
        hi: &[f64],
        chunk: f64,
        threads: usize,
    ) -> PyResult<Vec<f64>> {
        let lo = fixed::<f64, N>(lo, "lo")?;
        let hi = fixed::<f64, N>(hi, "hi")?;
        let boxes = chunk_boxes(lo, hi, chunk).map_err(value_error)?;
        let mut all: Vec<[f64; N]> = Vec::new();
        for batch in boxes.chunks(threads.max(1) * CHUNKS_PER_THREAD_AND_BATCH) {
            py.detach(|| {
                let parts = self.points_in_boxes(batch, threads)?;
                all.extend(parts.into_iter().flatten());
                Ok::<(), Error>(())
            })
            .map_err(value_error)?;
            py.check_signals()?;
        }
        py.detach(|| all.sort_unstable_by(field_order));
        Ok(all.into_flattened())
    }
}

/// The settings of a native `Field`: enough to build it again (they are
/// what pickling sends).
#[derive(Clone, Debug)]
struct Params {
    d: usize,
    /// The box, or `None` for all of space.
    bounds: Option<(Vec<f64>, Vec<f64>)>,
    periodic: Vec<bool>,
    radius: f64,
    seed: u64,
    max_window_bytes: u64,
}

/// [`Params`] as Python sees them: `(d, lo, hi, periodic, radius, seed,
/// max_window_bytes)`.
type ParamsTuple = (
    usize,
    Option<Vec<f64>>,
    Option<Vec<f64>>,
    Vec<bool>,
    f64,
    u64,
    u64,
);

/// Builds the field for `N = params.d`.
fn build<const N: usize>(p: &Params) -> PyResult<Arc<dyn FieldSampler>> {
    let field = match &p.bounds {
        Some((lo, hi)) => {
            let lo = fixed::<f64, N>(lo, "lo")?;
            let hi = fixed::<f64, N>(hi, "hi")?;
            let periodic = fixed::<bool, N>(&p.periodic, "periodic")?;
            let domain = Domain::new(lo, hi)
                .map_err(value_error)?
                .with_periodic(periodic);
            CoreField::<N>::new(domain, p.radius, p.seed)
        }
        None => CoreField::<N>::unbounded(p.radius, p.seed),
    }
    .map_err(value_error)?
    .with_max_window_bytes(p.max_window_bytes);
    Ok(Arc::new(field))
}

/// A maximal Poisson disk set that is a pure function of (seed, radius,
/// domain, position): `points_in(lo, hi)` returns exactly the whole set's
/// points in that box, bit for bit, whatever the order of the queries,
/// their size, the threads or the machine.
///
/// `Field(lo, hi, radius, seed, *, periodic=False, max_window_bytes=2**30)`
/// on a box of 1 to 4 dimensions (each axis bounded or periodic), or
/// `Field.unbounded(d, radius, seed)` on all of space.
#[pyclass(name = "Field", module = "bridson_rs._native", frozen)]
pub(crate) struct PyField {
    inner: Arc<dyn FieldSampler>,
    params: Params,
}

impl PyField {
    fn make(params: Params) -> PyResult<Self> {
        let inner = with_field_dim!(params.d, build(&params))?;
        Ok(Self { inner, params })
    }

    /// `lo` and `hi` of a query, checked for length.
    fn corners(&self, lo: &[f64], hi: &[f64]) -> PyResult<()> {
        let d = self.params.d;
        if lo.len() != d || hi.len() != d {
            return Err(PyValueError::new_err(format!(
                "lo and hi must have {d} values each, not {} and {}",
                lo.len(),
                hi.len()
            )));
        }
        Ok(())
    }

    /// The box of a bounded field, or a `ValueError` for an unbounded one.
    fn bounds(&self, what: &str) -> PyResult<(Vec<f64>, Vec<f64>)> {
        self.params.bounds.clone().ok_or_else(|| {
            PyValueError::new_err(format!(
                "an unbounded field has no box: give {what} the box to fill"
            ))
        })
    }
}

#[pymethods]
impl PyField {
    /// The field on the box `lo <= x < hi` (`len(lo)` dimensions, 1 to 4),
    /// with minimum distance `radius` and the given seed; `periodic` is a
    /// bool for every axis or one per axis.
    #[new]
    #[pyo3(signature = (lo, hi, radius, seed, *, periodic=None, max_window_bytes=bridson::DEFAULT_MAX_WINDOW_CELLS_BYTES))]
    fn new(
        lo: Vec<f64>,
        hi: Vec<f64>,
        radius: f64,
        seed: &Bound<'_, PyAny>,
        periodic: Option<&Bound<'_, PyAny>>,
        max_window_bytes: u64,
    ) -> PyResult<Self> {
        let d = lo.len();
        if hi.len() != d {
            return Err(PyValueError::new_err(format!(
                "lo and hi must have the same length, not {d} and {}",
                hi.len()
            )));
        }
        let periodic = periodic_flags(periodic, d)?;
        Self::make(Params {
            d,
            bounds: Some((lo, hi)),
            periodic,
            radius,
            seed: seed_u64(seed)?,
            max_window_bytes,
        })
    }

    /// The field on all of `d`-dimensional space (an endless world): its
    /// lattice is anchored at the origin, so every box of any size or place
    /// sees the same points.
    #[staticmethod]
    #[pyo3(signature = (d, radius, seed, *, max_window_bytes=bridson::DEFAULT_MAX_WINDOW_CELLS_BYTES))]
    fn unbounded(
        d: usize,
        radius: f64,
        seed: &Bound<'_, PyAny>,
        max_window_bytes: u64,
    ) -> PyResult<Self> {
        Self::make(Params {
            d,
            bounds: None,
            periodic: vec![false; d],
            radius,
            seed: seed_u64(seed)?,
            max_window_bytes,
        })
    }

    /// The dimension.
    #[getter]
    fn d(&self) -> usize {
        self.params.d
    }

    /// The minimum distance `r`.
    #[getter]
    fn radius(&self) -> f64 {
        self.params.radius
    }

    /// The seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.params.seed
    }

    /// The box's lower corner, or `None` when unbounded.
    #[getter]
    fn lo(&self) -> Option<Vec<f64>> {
        self.params.bounds.as_ref().map(|(lo, _)| lo.clone())
    }

    /// The box's upper corner (excluded), or `None` when unbounded.
    #[getter]
    fn hi(&self) -> Option<Vec<f64>> {
        self.params.bounds.as_ref().map(|(_, hi)| hi.clone())
    }

    /// Which axes wrap around (all `False` when unbounded).
    #[getter]
    fn periodic(&self) -> Vec<bool> {
        self.params.periodic.clone()
    }

    /// The memory budget of one query's window, in bytes.
    #[getter]
    fn max_window_bytes(&self) -> u64 {
        self.params.max_window_bytes
    }

    /// The points in the half-open box `lo <= x < hi`, as an `(n, d)`
    /// float64 array in the canonical order (see `field_sort`): exactly
    /// the whole set's points there. One query, without the GIL; a box
    /// whose window is over `max_window_bytes` is a `ValueError` (ask in
    /// chunks: `points_in_parallel`).
    fn points_in<'py>(
        &self,
        py: Python<'py>,
        lo: Vec<f64>,
        hi: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.corners(&lo, &hi)?;
        let flat = self.inner.points_in(py, &lo, &hi)?;
        to_array(py, flat, self.params.d)
    }

    /// Every point of a bounded or periodic field (`points_in` of its box).
    fn points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (lo, hi) = self.bounds("points_in")?;
        self.points_in(py, lo, hi)
    }

    /// The points in `lo <= x < hi` made chunk by chunk (chunks of `chunk`
    /// on a side, default `64 * radius`) on `threads` threads (default:
    /// every core), in the canonical order: the same array, bit for bit,
    /// as `points_in`, for every `chunk` and `threads`, and with no limit
    /// on the box but memory for its points. Ctrl-C stops it between
    /// batches of chunks. `lo` and `hi` default to a bounded field's box.
    #[pyo3(signature = (lo=None, hi=None, *, chunk=None, threads=None))]
    fn points_in_parallel<'py>(
        &self,
        py: Python<'py>,
        lo: Option<Vec<f64>>,
        hi: Option<Vec<f64>>,
        chunk: Option<f64>,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (lo, hi) = match (lo, hi) {
            (Some(lo), Some(hi)) => (lo, hi),
            (None, None) => self.bounds("points_in_parallel")?,
            _ => return Err(PyValueError::new_err("give both lo and hi, or neither")),
        };
        self.corners(&lo, &hi)?;
        let chunk = chunk.unwrap_or(64.0 * self.params.radius);
        let threads = match threads {
            Some(0) => return Err(PyValueError::new_err("threads must be at least 1")),
            Some(t) => t,
            None => std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
        };
        let flat = self
            .inner
            .points_in_parallel(py, &lo, &hi, chunk, threads)?;
        to_array(py, flat, self.params.d)
    }

    /// The settings as a plain tuple `(d, lo, hi, periodic, radius, seed,
    /// max_window_bytes)` (`lo` and `hi` `None` when unbounded):
    /// `Field.from_params(f.params)` is the same field. For sending a field
    /// to other processes (pickling uses it).
    #[getter]
    fn params(&self) -> ParamsTuple {
        let p = &self.params;
        (
            p.d,
            self.lo(),
            self.hi(),
            p.periodic.clone(),
            p.radius,
            p.seed,
            p.max_window_bytes,
        )
    }

    /// The field whose `params` are `params`.
    #[staticmethod]
    fn from_params(params: ParamsTuple) -> PyResult<Self> {
        let (d, lo, hi, periodic, radius, seed, max_window_bytes) = params;
        let bounds = match (lo, hi) {
            (Some(lo), Some(hi)) => Some((lo, hi)),
            (None, None) => None,
            _ => return Err(PyValueError::new_err("give both lo and hi, or neither")),
        };
        if periodic.len() != d {
            return Err(PyValueError::new_err(format!(
                "periodic must have {d} values, not {}",
                periodic.len()
            )));
        }
        Self::make(Params {
            d,
            bounds,
            periodic,
            radius,
            seed,
            max_window_bytes,
        })
    }

    /// Pickling: the field is rebuilt from its `params`.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let from_params = slf.get_type().getattr("from_params")?;
        let params = slf.getattr("params")?;
        let args = pyo3::types::PyTuple::new(slf.py(), [params])?.into_any();
        Ok((from_params, args))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<Self>().is_ok_and(|o| {
            let (a, b) = (&self.params, &o.get().params);
            a.d == b.d
                && a.bounds == b.bounds
                && a.periodic == b.periodic
                && a.radius.to_bits() == b.radius.to_bits()
                && a.seed == b.seed
                && a.max_window_bytes == b.max_window_bytes
        })
    }

    fn __repr__(&self) -> String {
        let p = &self.params;
        let flags: Vec<&str> = p
            .periodic
            .iter()
            .map(|&x| if x { "True" } else { "False" })
            .collect();
        match &p.bounds {
            Some((lo, hi)) => format!(
                "Field(lo={lo:?}, hi={hi:?}, radius={:?}, seed={}, periodic=[{}])",
                p.radius,
                p.seed,
                flags.join(", ")
            ),
            None => format!(
                "Field.unbounded(d={}, radius={:?}, seed={})",
                p.d, p.radius, p.seed
            ),
        }
    }
}

/// Lower and upper corners of boxes, `(k, d)` each.
type Corners<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>);

/// The chunk boxes over the half-open box `[lo, hi)`: `(los, his)`, two
/// `(k, d)` float64 arrays, box `i` being `los[i] <= x < his[i]`, cut at
/// `lo + j * side` on every axis, the last axis slowest. Neighbouring boxes
/// share their border bit for bit, so every point of the box is in exactly
/// one. The boxes the field's chunked queries use (and the Dask
/// partitions).
#[pyfunction(name = "chunk_boxes")]
pub(crate) fn chunk_boxes_of<'py>(
    py: Python<'py>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    side: f64,
) -> PyResult<Corners<'py>> {
    let d = lo.len();
    if hi.len() != d {
        return Err(PyValueError::new_err(format!(
            "lo and hi must have the same length, not {d} and {}",
            hi.len()
        )));
    }
    let (los, his) = with_field_dim!(d, boxes_flat(&lo, &hi, side))?;
    Ok((to_array(py, los, d)?, to_array(py, his, d)?))
}

/// [`chunk_boxes`] for `N = lo.len()`, the corners flattened.
fn boxes_flat<const N: usize>(lo: &[f64], hi: &[f64], side: f64) -> PyResult<(Vec<f64>, Vec<f64>)> {
    let lo = fixed::<f64, N>(lo, "lo")?;
    let hi = fixed::<f64, N>(hi, "hi")?;
    let boxes = chunk_boxes(lo, hi, side).map_err(value_error)?;
    let (los, his): (Vec<[f64; N]>, Vec<[f64; N]>) = boxes.into_iter().unzip();
    Ok((los.into_flattened(), his.into_flattened()))
}

/// `points`, an `(n, d)` array, as contiguous, aligned float64 rows
/// (copied only if it is not that already: arrays unpickled from another
/// process can be unaligned).
fn rows<'py>(points: &Bound<'py, PyAny>) -> PyResult<numpy::PyReadonlyArray2<'py, f64>> {
    let np = points.py().import("numpy")?;
    np.call_method1("require", (points, np.getattr("float64")?, ["C", "A"]))?
        .extract()
        .map_err(|_| PyValueError::new_err("points must be an (n, d) array"))
}

/// The canonical order of two points: by coordinate, the last axis first,
/// each compared with `total_cmp` (the crate's `field_order`).
fn order(a: &[f64], b: &[f64]) -> Ordering {
    a.iter()
        .rev()
        .zip(b.iter().rev())
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        .unwrap_or(Ordering::Equal)
}

/// A copy of `points` (`(n, d)`) in the field's canonical order:
/// lexicographic by coordinate, the last axis first (every query returns
/// its points so). Two sets of points are the same set exactly when their
/// sorted arrays are equal bit for bit.
#[pyfunction]
pub(crate) fn field_sort<'py>(
    py: Python<'py>,
    points: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let points = rows(points)?;
    let d = points.shape()[1];
    let flat = points.as_slice()?;
    let sorted = py.detach(|| {
        if d == 0 {
            return Vec::new();
        }
        let mut index: Vec<&[f64]> = flat.chunks_exact(d).collect();
        index.sort_unstable_by(|a, b| order(a, b));
        index.concat()
    });
    to_array(py, sorted, d)
}

/// The hash of one point: its coordinates' bits through SplitMix64's
/// finaliser, as the `points` CLI's `--format none` digest.
fn point_hash(p: &[f64]) -> u64 {
    let mut h: u64 = 0x243f_6a88_85a3_08d3;
    for x in p {
        let mut z = h ^ x.to_bits();
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h = z ^ (z >> 31);
    }
    h
}

/// An order-independent digest of `points` (`(n, d)`): the wrapping sum of
/// a 64-bit hash of each point's bits, the digest the `points` CLI prints
/// with `--field --format none` (as hex). Digests of parts add up (mod
/// 2**64) to the digest of their union, so sets made in different pieces
/// can be compared without gathering them.
#[pyfunction]
pub(crate) fn field_digest(py: Python<'_>, points: &Bound<'_, PyAny>) -> PyResult<u64> {
    let points = rows(points)?;
    let d = points.shape()[1];
    let flat = points.as_slice()?;
    Ok(py.detach(|| {
        if d == 0 {
            return 0;
        }
        flat.chunks_exact(d)
            .fold(0u64, |sum, p| sum.wrapping_add(point_hash(p)))
    }))
}
