//! Python bindings of the `bridson` crate, built with PyO3 and maturin into
//! the module `bridson_rs._native` (the Python package `bridson_rs`
//! re-exports it and adds the scipy drop-in, `bridson_rs.qmc`).
//!
//! Layout: the const-generic samplers (`PoissonDisk<N>`) are reached from
//! Python's run-time dimension `d` through [`with_dim!`], which matches
//! `d` in `1..=8` and calls a generic function with `N = d`. What a
//! Python object holds afterwards is a trait object ([`Sampler`],
//! [`Stream`]) with the dimension erased, so one Python class serves
//! every `N`.
//!
//! Arrays leave without a copy: the points are pushed into one `Vec<f64>`
//! (row-major, `d` values a point), which `PyArray1::from_vec` (that is,
//! `IntoPyArray::into_pyarray`) hands to NumPy as the array's own buffer:
//! the Vec's allocation is moved into a capsule that owns it, its data is
//! not copied. `reshape` of that contiguous array is a view of the same
//! buffer. The GIL is released while sampling, chunk by chunk ([`CHUNK`]
//! points), with Python's signal handlers run between chunks so that
//! Ctrl-C stops a long run; a Python callback (a mask or a radius given as
//! a function) takes the GIL back for its own call only.
//!
//! The field sampler (`bridson::Field`, 1 to 4 dimensions) is in
//! [`field`], in the same shape: a match on `d`, a trait object, arrays
//! without a copy, queries without the GIL.

use bridson::{
    CameraPixels as CoreCameraPixels, Candidates, DefaultRng, Domain, Error,
    NetPixelSampler as CoreNetPixelSampler, PixelSampler as _, Pixels as CorePixels,
    PoissonDisk as CorePoissonDisk, PoissonPixelSampler as CorePixelSampler, Region, Scheme,
    Tiled as CoreTiled, VaryingPoints,
};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
#[cfg(feature = "parallel")]
use std::num::NonZeroUsize;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

mod field;

/// Points made between two checks for Ctrl-C (and between two releases of
/// the GIL): large enough that the check costs nothing, small enough (a
/// few milliseconds in 2-D) that Ctrl-C answers at once.
const CHUNK: usize = 1 << 16;

/// The largest dimension the bindings compile a sampler for.
const MAX_DIM: usize = 8;

/// The crate's error as Python's `ValueError`, with the crate's message.
fn value_error(e: Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Calls `$f::<N>(args)` with `N = $d`, for `$d` in `1..=8`; any other
/// dimension is a `ValueError`.
macro_rules! with_dim {
    ($d:expr, $f:ident ( $($arg:expr),* )) => {
        match $d {
            1 => $f::<1>($($arg),*),
            2 => $f::<2>($($arg),*),
            3 => $f::<3>($($arg),*),
            4 => $f::<4>($($arg),*),
            5 => $f::<5>($($arg),*),
            6 => $f::<6>($($arg),*),
            7 => $f::<7>($($arg),*),
            8 => $f::<8>($($arg),*),
            d => Err(PyValueError::new_err(format!(
                "the dimension must be within 1..={MAX_DIM}, not {d}"
            ))),
        }
    };
}

/// `v` as `[T; N]`, or a `ValueError` naming `what`.
fn fixed<T: Copy, const N: usize>(v: &[T], what: &str) -> PyResult<[T; N]> {
    <[T; N]>::try_from(v)
        .map_err(|_| PyValueError::new_err(format!("{what} must have {N} values, not {}", v.len())))
}

/// A flat row-major buffer of `d`-dimensional points as a `(n, d)` array,
/// without copying (see the module docs).
fn to_array(py: Python<'_>, flat: Vec<f64>, d: usize) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let n = flat.len().checked_div(d).unwrap_or(0);
    // `from_vec` moves the Vec into NumPy (no copy); `reshape` of a
    // contiguous array is a view of the same buffer.
    PyArray1::from_vec(py, flat).reshape([n, d])
}

/// Where a failure inside a Python callback is kept until the sampling
/// loop, back under the GIL, raises it.
#[derive(Default)]
struct Failure {
    failed: AtomicBool,
    error: Mutex<Option<PyErr>>,
}

impl Failure {
    fn set(&self, e: PyErr) {
        if let Ok(mut slot) = self.error.lock() {
            slot.get_or_insert(e);
        }
        self.failed.store(true, Ordering::Relaxed);
    }

    fn failed(&self) -> bool {
        self.failed.load(Ordering::Relaxed)
    }

    fn take(&self) -> Option<PyErr> {
        self.failed.store(false, Ordering::Relaxed);
        self.error.lock().ok().and_then(|mut slot| slot.take())
    }
}

/// A `d`-dimensional array laid over the box: cell `i` of axis `a` covers
/// `lo[a] + extent[a]·i/m[a] .. lo[a] + extent[a]·(i+1)/m[a]`.
struct Raster<T> {
    lo: Vec<f64>,
    /// `m[a] / extent[a]`.
    scale: Vec<f64>,
    shape: Vec<usize>,
    /// Row-major strides, in elements.
    strides: Vec<usize>,
    data: Vec<T>,
}

impl<T: Copy + numpy::Element> Raster<T> {
    /// The array `values` (one axis per dimension) over the box `lo..hi`.
    fn new(lo: &[f64], hi: &[f64], values: &PyReadonlyArrayDyn<'_, T>) -> PyResult<Self> {
        let shape = values.shape().to_vec();
        if shape.len() != lo.len() || shape.contains(&0) {
            return Err(PyValueError::new_err(format!(
                "the array must have one axis per dimension ({}) and no empty axis, not shape {shape:?}",
                lo.len()
            )));
        }
        let mut strides = vec![1; shape.len()];
        for a in (0..shape.len().saturating_sub(1)).rev() {
            strides[a] = strides[a + 1] * shape[a + 1];
        }
        let scale = shape
            .iter()
            .zip(lo.iter().zip(hi))
            .map(|(&m, (&l, &h))| m as f64 / (h - l))
            .collect();
        // Row-major order whatever the array's layout (a transposed view
        // included).
        let data = values.as_array().iter().copied().collect();
        Ok(Self {
            lo: lo.to_vec(),
            scale,
            shape,
            strides,
            data,
        })
    }

    /// The value of the cell that `p` lies in.
    fn at(&self, p: &[f64]) -> T {
        let mut index = 0;
        for (a, &x) in p.iter().enumerate() {
            let cell = ((x - self.lo[a]) * self.scale[a]).floor();
            // A saturating cast: NaN and negatives go to 0, past the end
            // to the last cell.
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "saturating, then clamped to the axis"
            )]
            let cell = (cell.max(0.0) as usize).min(self.shape[a] - 1);
            index += cell * self.strides[a];
        }
        self.data[index]
    }
}

/// A Python callable `f(points)`, called with a `(1, d)` array.
struct Callback {
    f: Py<PyAny>,
    failure: Arc<Failure>,
}

impl Callback {
    /// `read(f(p))` under the GIL, or `None` once any call has failed (the
    /// error is kept for the sampling loop to raise).
    fn call<T>(
        &self,
        p: &[f64],
        read: impl for<'py> FnOnce(&Bound<'py, PyAny>) -> PyResult<T>,
    ) -> Option<T> {
        if self.failure.failed() {
            return None;
        }
        // `attach` takes the GIL for this call only; the sampling around
        // it runs without.
        let result = Python::attach(|py| {
            let point = PyArray1::from_slice(py, p).reshape([1, p.len()])?;
            let value = self.f.bind(py).call1((point,))?;
            read(&value)
        });
        result.map_err(|e| self.failure.set(e)).ok()
    }
}

/// The first element of `value`, a number or an array, as `f64`.
fn first_f64(value: &Bound<'_, PyAny>) -> PyResult<f64> {
    if let Ok(x) = value.extract::<f64>() {
        return Ok(x);
    }
    let np = value.py().import("numpy")?;
    let flat = np.call_method1("ravel", (value,))?;
    flat.get_item(0)?.extract::<f64>()
}

/// A region where new points may go: everywhere, a boolean array over the
/// box, or a Python callable.
enum Mask {
    Everywhere,
    Array(Raster<bool>),
    Callable(Callback),
}

impl<const N: usize> Region<N> for Mask {
    fn admits(&self, p: &[f64; N]) -> bool {
        match self {
            Self::Everywhere => true,
            Self::Array(r) => r.at(p),
            Self::Callable(c) => c.call(p, |v| v.is_truthy()).unwrap_or(false),
        }
    }
}

/// A radius field: an array over the box, or a Python callable.
enum RadiusField {
    Array(Raster<f64>),
    Callable(Callback),
}

impl RadiusField {
    fn at(&self, p: &[f64]) -> f64 {
        match self {
            Self::Array(r) => r.at(p),
            // NaN means the sampler's radius, the largest: after a failure
            // the run ends as fast as it can.
            Self::Callable(c) => c.call(p, first_f64).unwrap_or(f64::NAN),
        }
    }
}

/// A point stream with its dimension erased.
trait Stream: Send {
    /// Appends the coordinates of up to `max` more points to `out`;
    /// returns how many points it appended (fewer: the stream has ended).
    fn fill(&mut self, max: usize, out: &mut Vec<f64>) -> usize;
    /// Why the stream ended early, if it did.
    fn error(&self) -> Option<Error>;
}

/// Appends up to `max` points of `it` to `out`, stopping early if
/// `failure` is set.
fn fill_from<const N: usize>(
    it: &mut impl Iterator<Item = [f64; N]>,
    max: usize,
    out: &mut Vec<f64>,
    failure: Option<&Failure>,
) -> usize {
    let mut made = 0;
    while made < max {
        if failure.is_some_and(Failure::failed) {
            break;
        }
        let Some(p) = it.next() else { break };
        out.extend_from_slice(&p);
        made += 1;
    }
    made
}

/// A fixed-radius stream, with the failure slot of its mask.
struct FixedStream<const N: usize> {
    points: bridson::Points<N, DefaultRng, Mask>,
    failure: Arc<Failure>,
}

impl<const N: usize> Stream for FixedStream<N> {
    fn fill(&mut self, max: usize, out: &mut Vec<f64>) -> usize {
        fill_from(&mut self.points, max, out, Some(&self.failure))
    }

    fn error(&self) -> Option<Error> {
        self.points.error()
    }
}

/// A varying-radius stream, with the failure slot of its field.
struct VaryingStream<const N: usize, F> {
    points: VaryingPoints<N, F, DefaultRng>,
    failure: Arc<Failure>,
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64 + Send> Stream for VaryingStream<N, F> {
    fn fill(&mut self, max: usize, out: &mut Vec<f64>) -> usize {
        fill_from(&mut self.points, max, out, Some(&self.failure))
    }

    fn error(&self) -> Option<Error> {
        self.points.error()
    }
}

/// What a Python `PoissonDisk` needs of the sampler, its dimension erased.
trait Sampler: Send + Sync {
    fn radius(&self) -> f64;
    fn attempts(&self) -> u32;
    fn lo(&self) -> Vec<f64>;
    fn hi(&self) -> Vec<f64>;
    fn periodic(&self) -> Vec<bool>;
    fn requested_count(&self) -> Option<u64>;
    fn max_points(&self) -> Option<u64>;
    fn grid_bytes(&self) -> u64;
    fn iter_with(
        &self,
        seed: u64,
        mask: Mask,
        fixed: &[f64],
        failure: Arc<Failure>,
    ) -> PyResult<Box<dyn Stream>>;
    fn iter_varying(
        &self,
        seed: u64,
        r_min: f64,
        field: RadiusField,
        failure: Arc<Failure>,
    ) -> PyResult<Box<dyn Stream>>;
    #[cfg(feature = "parallel")]
    fn generate_parallel(&self, seed: u64, threads: NonZeroUsize) -> Result<Vec<f64>, Error>;
}

impl<const N: usize> Sampler for CorePoissonDisk<N> {
    fn radius(&self) -> f64 {
        CorePoissonDisk::radius(self)
    }
    fn attempts(&self) -> u32 {
        CorePoissonDisk::attempts(self)
    }
    fn lo(&self) -> Vec<f64> {
        self.domain().lo().to_vec()
    }
    fn hi(&self) -> Vec<f64> {
        self.domain().hi().to_vec()
    }
    fn periodic(&self) -> Vec<bool> {
        self.domain().periodic().to_vec()
    }
    fn requested_count(&self) -> Option<u64> {
        CorePoissonDisk::requested_count(self)
    }
    fn max_points(&self) -> Option<u64> {
        CorePoissonDisk::max_points(self)
    }
    fn grid_bytes(&self) -> u64 {
        CorePoissonDisk::grid_bytes(self)
    }
    fn iter_with(
        &self,
        seed: u64,
        mask: Mask,
        fixed: &[f64],
        failure: Arc<Failure>,
    ) -> PyResult<Box<dyn Stream>> {
        let fixed: Vec<[f64; N]> = fixed.chunks_exact(N).map(fixed_point::<N>).collect();
        let points = self
            .iter_with_seeded(seed, mask, &fixed)
            .map_err(value_error)?;
        Ok(Box::new(FixedStream { points, failure }))
    }
    fn iter_varying(
        &self,
        seed: u64,
        r_min: f64,
        field: RadiusField,
        failure: Arc<Failure>,
    ) -> PyResult<Box<dyn Stream>> {
        let points = self
            .iter_varying_seeded(seed, r_min, move |p: &[f64; N]| field.at(p))
            .map_err(value_error)?;
        Ok(Box::new(VaryingStream { points, failure }))
    }
    #[cfg(feature = "parallel")]
    fn generate_parallel(&self, seed: u64, threads: NonZeroUsize) -> Result<Vec<f64>, Error> {
        self.generate_parallel_seeded(seed, threads)
            .map(Vec::into_flattened)
            .map_err(Error::from)
    }
}

/// A chunk of exactly `N` values as a point (`chunks_exact` guarantees
/// the length).
fn fixed_point<const N: usize>(c: &[f64]) -> [f64; N] {
    let mut p = [0.0; N];
    p.copy_from_slice(c);
    p
}

/// The settings every way of building a native `PoissonDisk` shares.
struct Settings<'a> {
    lo: &'a [f64],
    hi: &'a [f64],
    periodic: &'a [bool],
    radius: Option<f64>,
    about_points: Option<u64>,
    attempts: u32,
    candidates: Candidates,
    max_points: Option<u64>,
    max_grid_bytes: Option<u64>,
}

/// Builds the sampler for `N = settings.lo.len()`.
fn build<const N: usize>(s: &Settings<'_>) -> PyResult<Arc<dyn Sampler>> {
    let lo = fixed::<f64, N>(s.lo, "lo")?;
    let hi = fixed::<f64, N>(s.hi, "hi")?;
    let periodic = fixed::<bool, N>(s.periodic, "periodic")?;
    let domain = Domain::new(lo, hi)
        .map_err(value_error)?
        .with_periodic(periodic);
    let mut builder = match s.about_points {
        Some(n) => CorePoissonDisk::about_points_builder(domain, n),
        None => CorePoissonDisk::builder(domain, s.radius.unwrap_or(f64::NAN)),
    }
    .attempts(s.attempts)
    .candidates(s.candidates);
    if let Some(cap) = s.max_points {
        builder = builder.max_points(cap);
    }
    if let Some(bytes) = s.max_grid_bytes {
        builder = builder.max_grid_bytes(bytes);
    }
    Ok(Arc::new(builder.build().map_err(value_error)?))
}

/// `"annulus"` or `"sphere"`.
fn candidates(name: &str) -> PyResult<Candidates> {
    match name {
        "annulus" => Ok(Candidates::Annulus),
        "sphere" => Ok(Candidates::Sphere),
        _ => Err(PyValueError::new_err(format!(
            "candidates must be 'annulus' or 'sphere', not {name:?}"
        ))),
    }
}

/// `periodic` as one flag per axis: a bool for every axis, or a sequence.
fn periodic_flags(periodic: Option<&Bound<'_, PyAny>>, d: usize) -> PyResult<Vec<bool>> {
    let Some(periodic) = periodic else {
        return Ok(vec![false; d]);
    };
    if let Ok(all) = periodic.extract::<bool>() {
        return Ok(vec![all; d]);
    }
    periodic.extract::<Vec<bool>>()
}

/// A seed as the crate's `u64`: any Python int in `0 .. 2**64`.
fn seed_u64(seed: &Bound<'_, PyAny>) -> PyResult<u64> {
    seed.extract::<u64>()
        .map_err(|_| PyValueError::new_err("seed must be an int in 0 .. 2**64"))
}

/// Poisson disk sampling in a box of 1 to 8 dimensions: random points no
/// two closer than `radius`, every one in `lo <= x < hi`.
///
/// `PoissonDisk(lo, hi, radius, *, periodic=False, attempts=30,
/// candidates="annulus", max_points=None, max_grid_bytes=None)`; or
/// `PoissonDisk.about_points(lo, hi, n, ...)` for about `n` points spread
/// over the box (the radius follows). Bad settings raise `ValueError` with
/// the crate's message.
#[pyclass(module = "bridson_rs._native", frozen)]
struct PoissonDisk {
    inner: Arc<dyn Sampler>,
    d: usize,
}

impl PoissonDisk {
    #[expect(clippy::too_many_arguments, reason = "Python's keyword arguments")]
    fn make(
        lo: Vec<f64>,
        hi: Vec<f64>,
        radius: Option<f64>,
        about_points: Option<u64>,
        periodic: Option<&Bound<'_, PyAny>>,
        attempts: u32,
        candidates_name: &str,
        max_points: Option<u64>,
        max_grid_bytes: Option<u64>,
    ) -> PyResult<Self> {
        let d = lo.len();
        if hi.len() != d {
            return Err(PyValueError::new_err(format!(
                "lo and hi must have the same length, not {d} and {}",
                hi.len()
            )));
        }
        let periodic = periodic_flags(periodic, d)?;
        let settings = Settings {
            lo: &lo,
            hi: &hi,
            periodic: &periodic,
            radius,
            about_points,
            attempts,
            candidates: candidates(candidates_name)?,
            max_points,
            max_grid_bytes,
        };
        let inner = with_dim!(d, build(&settings))?;
        Ok(Self { inner, d })
    }

    /// Runs `stream` to its end (or `limit` points), chunk by chunk without
    /// the GIL, checking for Ctrl-C between chunks.
    fn drain(
        py: Python<'_>,
        stream: &mut dyn Stream,
        failure: &Failure,
        limit: usize,
        out: &mut Vec<f64>,
    ) -> PyResult<usize> {
        let mut made = 0;
        while made < limit {
            let want = CHUNK.min(limit - made);
            let got = py.detach(|| stream.fill(want, out));
            made += got;
            if let Some(e) = failure.take() {
                return Err(e);
            }
            py.check_signals()?;
            if got < want {
                break;
            }
        }
        Ok(made)
    }
}

/// `obj` as a contiguous float64 NumPy array (converted only if it is not
/// one already).
fn float_array<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let np = obj.py().import("numpy")?;
    np.call_method1("ascontiguousarray", (obj, np.getattr("float64")?))
}

/// A mask from Python: `None`, a callable, or a boolean array.
fn mask(
    region: Option<&Bound<'_, PyAny>>,
    lo: &[f64],
    hi: &[f64],
    failure: &Arc<Failure>,
) -> PyResult<Mask> {
    let Some(region) = region else {
        return Ok(Mask::Everywhere);
    };
    if region.is_callable() {
        return Ok(Mask::Callable(Callback {
            f: region.clone().unbind(),
            failure: Arc::clone(failure),
        }));
    }
    let np = region.py().import("numpy")?;
    let array = np.call_method1("asarray", (region, np.getattr("bool_")?))?;
    let array: PyReadonlyArrayDyn<'_, bool> = array.extract()?;
    Ok(Mask::Array(Raster::new(lo, hi, &array)?))
}

/// A radius field from Python: a callable or an array.
fn field(
    radius: &Bound<'_, PyAny>,
    lo: &[f64],
    hi: &[f64],
    failure: &Arc<Failure>,
) -> PyResult<RadiusField> {
    if radius.is_callable() {
        return Ok(RadiusField::Callable(Callback {
            f: radius.clone().unbind(),
            failure: Arc::clone(failure),
        }));
    }
    let array: PyReadonlyArrayDyn<'_, f64> = float_array(radius)?.extract()?;
    Ok(RadiusField::Array(Raster::new(lo, hi, &array)?))
}

#[pymethods]
impl PoissonDisk {
    /// A sampler of points at least `radius` apart in the box `lo <= x < hi`
    /// (`len(lo)` dimensions, 1 to 8).
    #[new]
    #[pyo3(signature = (lo, hi, radius, *, periodic=None, attempts=30, candidates="annulus", max_points=None, max_grid_bytes=None))]
    #[expect(clippy::too_many_arguments, reason = "Python's keyword arguments")]
    fn new(
        lo: Vec<f64>,
        hi: Vec<f64>,
        radius: f64,
        periodic: Option<&Bound<'_, PyAny>>,
        attempts: u32,
        candidates: &str,
        max_points: Option<u64>,
        max_grid_bytes: Option<u64>,
    ) -> PyResult<Self> {
        Self::make(
            lo,
            hi,
            Some(radius),
            None,
            periodic,
            attempts,
            candidates,
            max_points,
            max_grid_bytes,
        )
    }

    /// Count mode: a sampler whose radius gives about `n` points spread
    /// over the whole box.
    #[staticmethod]
    #[pyo3(signature = (lo, hi, n, *, periodic=None, attempts=30, candidates="annulus", max_points=None, max_grid_bytes=None))]
    #[expect(clippy::too_many_arguments, reason = "Python's keyword arguments")]
    fn about_points(
        lo: Vec<f64>,
        hi: Vec<f64>,
        n: u64,
        periodic: Option<&Bound<'_, PyAny>>,
        attempts: u32,
        candidates: &str,
        max_points: Option<u64>,
        max_grid_bytes: Option<u64>,
    ) -> PyResult<Self> {
        Self::make(
            lo,
            hi,
            None,
            Some(n),
            periodic,
            attempts,
            candidates,
            max_points,
            max_grid_bytes,
        )
    }

    /// The dimension.
    #[getter]
    fn d(&self) -> usize {
        self.d
    }

    /// The minimum distance (in count mode, the one derived).
    #[getter]
    fn radius(&self) -> f64 {
        self.inner.radius()
    }

    /// The attempts `k` around each active point.
    #[getter]
    fn attempts(&self) -> u32 {
        self.inner.attempts()
    }

    /// The box's lower corner.
    #[getter]
    fn lo(&self) -> Vec<f64> {
        self.inner.lo()
    }

    /// The box's upper corner (excluded).
    #[getter]
    fn hi(&self) -> Vec<f64> {
        self.inner.hi()
    }

    /// Which axes wrap around.
    #[getter]
    fn periodic(&self) -> Vec<bool> {
        self.inner.periodic()
    }

    /// In count mode, the number of points asked for.
    #[getter]
    fn requested_count(&self) -> Option<u64> {
        self.inner.requested_count()
    }

    /// The point cap, if any.
    #[getter]
    fn max_points(&self) -> Option<u64> {
        self.inner.max_points()
    }

    /// What the grid allocates before the first point, in bytes.
    #[getter]
    fn grid_bytes(&self) -> u64 {
        self.inner.grid_bytes()
    }

    /// The lazy stream of points for `seed`, in generation order.
    fn iter(&self, seed: &Bound<'_, PyAny>) -> PyResult<Points> {
        self.iter_with(seed, None, None)
    }

    /// The lazy stream of points for `seed` that lie in `region` (a
    /// callable `f(points) -> bools` called with a `(1, d)` array, or a
    /// boolean array with one axis per dimension laid over the box) and
    /// keep their distance from the pre-placed points `fixed` (`(m, d)`).
    #[pyo3(signature = (seed, region=None, fixed=None))]
    fn iter_with(
        &self,
        seed: &Bound<'_, PyAny>,
        region: Option<&Bound<'_, PyAny>>,
        fixed: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Points> {
        let seed = seed_u64(seed)?;
        let failure = Arc::new(Failure::default());
        let (lo, hi) = (self.inner.lo(), self.inner.hi());
        let mask = mask(region, &lo, &hi, &failure)?;
        let fixed: Vec<f64> = match fixed {
            None => Vec::new(),
            Some(f) => {
                let array: numpy::PyReadonlyArray2<'_, f64> =
                    float_array(f)?.extract().map_err(|_| {
                        PyValueError::new_err(format!("fixed must be an (m, {}) array", self.d))
                    })?;
                if array.shape()[1] != self.d {
                    return Err(PyValueError::new_err(format!(
                        "fixed must be an (m, {}) array, not {:?}",
                        self.d,
                        array.shape()
                    )));
                }
                array.as_array().iter().copied().collect()
            }
        };
        // The first point is drawn here (the mask is called): a callback
        // that raised is the error to report, not the region it "missed".
        let stream = self
            .inner
            .iter_with(seed, mask, &fixed, Arc::clone(&failure))
            .map_err(|e| failure.take().unwrap_or(e))?;
        Ok(Points::new(stream, failure, self.d))
    }

    /// The lazy stream of points for `seed` whose spacing follows the
    /// radius field `field` (a callable `f(points) -> radii` called with a
    /// `(1, d)` array, or an array with one axis per dimension laid over
    /// the box), clamped to `r_min ..= radius`.
    fn iter_varying(
        &self,
        seed: &Bound<'_, PyAny>,
        r_min: f64,
        field: &Bound<'_, PyAny>,
    ) -> PyResult<Points> {
        let seed = seed_u64(seed)?;
        let failure = Arc::new(Failure::default());
        let (lo, hi) = (self.inner.lo(), self.inner.hi());
        let field = self::field(field, &lo, &hi, &failure)?;
        let stream = self
            .inner
            .iter_varying(seed, r_min, field, Arc::clone(&failure))?;
        Ok(Points::new(stream, failure, self.d))
    }

    /// All points for `seed`, as an `(n, d)` float64 array.
    fn generate<'py>(
        &self,
        py: Python<'py>,
        seed: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut points = self.iter(seed)?;
        let all = points.collect(py)?;
        match points.stream.get_mut().map_or(None, |s| s.error()) {
            Some(e) => Err(value_error(e)),
            None => Ok(all),
        }
    }

    /// All points for `seed`, made slab by slab on `threads` threads (a
    /// different set from `generate`'s, with its statistics). Only in a
    /// build with the `parallel` feature: its code for eight dimensions
    /// took 40 % of the wheel's build time.
    #[cfg(feature = "parallel")]
    fn generate_parallel<'py>(
        &self,
        py: Python<'py>,
        seed: &Bound<'py, PyAny>,
        threads: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let seed = seed_u64(seed)?;
        let threads = NonZeroUsize::new(threads)
            .ok_or_else(|| PyValueError::new_err("threads must be at least 1"))?;
        let inner = Arc::clone(&self.inner);
        let flat = py
            .detach(move || inner.generate_parallel(seed, threads))
            .map_err(value_error)?;
        to_array(py, flat, self.d)
    }

    fn __repr__(&self) -> String {
        let periodic: Vec<&str> = self
            .inner
            .periodic()
            .iter()
            .map(|&p| if p { "True" } else { "False" })
            .collect();
        format!(
            "PoissonDisk(lo={:?}, hi={:?}, radius={:?}, periodic=[{}], attempts={})",
            self.inner.lo(),
            self.inner.hi(),
            self.inner.radius(),
            periodic.join(", "),
            self.inner.attempts()
        )
    }
}

/// A lazy point stream (from `PoissonDisk.iter`, `iter_with` or
/// `iter_varying`): `take(n)` the next points, `collect()` the rest, or
/// iterate point by point. `error` tells why it ended early, if it did.
#[pyclass(module = "bridson_rs._native")]
struct Points {
    stream: Mutex<Box<dyn Stream>>,
    failure: Arc<Failure>,
    d: usize,
}

impl Points {
    fn new(stream: Box<dyn Stream>, failure: Arc<Failure>, d: usize) -> Self {
        Self {
            stream: Mutex::new(stream),
            failure,
            d,
        }
    }

    fn next_points<'py>(
        &mut self,
        py: Python<'py>,
        limit: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut out = Vec::new();
        let stream = self
            .stream
            .get_mut()
            .map_err(|_| PyValueError::new_err("the stream failed earlier"))?;
        PoissonDisk::drain(py, stream.as_mut(), &self.failure, limit, &mut out)?;
        to_array(py, out, self.d)
    }
}

#[pymethods]
impl Points {
    /// The next `n` points (fewer if the stream ends), as `(m, d)`.
    fn take<'py>(&mut self, py: Python<'py>, n: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.next_points(py, n)
    }

    /// Every remaining point, as `(m, d)`.
    fn collect<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.next_points(py, usize::MAX)
    }

    /// Why the stream ended early (the crate's message), or `None`.
    #[getter]
    fn error(&mut self) -> Option<String> {
        self.stream
            .get_mut()
            .ok()
            .and_then(|s| s.error())
            .map(|e| e.to_string())
    }

    /// The dimension.
    #[getter]
    fn d(&self) -> usize {
        self.d
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&mut self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let one = self.next_points(py, 1)?;
        if one.shape()[0] == 0 {
            return Ok(None);
        }
        Ok(Some(one.reshape([self.d])?))
    }
}

/// `"sweep"` or `"paper"`.
fn scheme(name: &str) -> PyResult<Scheme> {
    match name {
        "sweep" => Ok(Scheme::Sweep),
        "paper" => Ok(Scheme::Paper),
        _ => Err(PyValueError::new_err(format!(
            "scheme must be 'sweep' or 'paper', not {name:?}"
        ))),
    }
}

/// A 2-D Poisson disk set streamed over a `width × height` raster pixel by
/// pixel, in scan order, its memory one row of pixels. Give the spacing as
/// `radius` (in pixels) or `per_pixel` (points a pixel); `exact=n` gives
/// exactly `n` points in every pixel.
#[pyclass(module = "bridson_rs._native", frozen)]
struct Tiled {
    inner: CoreTiled,
}

#[pymethods]
impl Tiled {
    #[new]
    #[pyo3(signature = (width, height, *, radius=None, per_pixel=None, exact=None, attempts=None, candidates="annulus", scheme="sweep", max_window_bytes=None))]
    #[expect(clippy::too_many_arguments, reason = "Python's keyword arguments")]
    fn new(
        width: u32,
        height: u32,
        radius: Option<f64>,
        per_pixel: Option<f64>,
        exact: Option<u32>,
        attempts: Option<u32>,
        candidates: &str,
        scheme: &str,
        max_window_bytes: Option<u64>,
    ) -> PyResult<Self> {
        let mut b = CoreTiled::builder(width, height)
            .candidates(self::candidates(candidates)?)
            .scheme(self::scheme(scheme)?);
        if let Some(r) = radius {
            b = b.radius(r);
        }
        if let Some(n) = per_pixel {
            b = b.per_pixel(n);
        }
        if let Some(n) = exact {
            b = b.exact(n);
        }
        if let Some(k) = attempts {
            b = b.attempts(k);
        }
        if let Some(bytes) = max_window_bytes {
            b = b.max_window_bytes(bytes);
        }
        Ok(Self {
            inner: b.build().map_err(value_error)?,
        })
    }

    /// The minimum distance used, in pixels.
    #[getter]
    fn radius(&self) -> f64 {
        self.inner.radius()
    }

    /// The attempts `k` of the sweep.
    #[getter]
    fn attempts(&self) -> u32 {
        self.inner.attempts()
    }

    /// Raster width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.inner.width()
    }

    /// Raster height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.inner.height()
    }

    /// In exact mode, the points every pixel holds.
    #[getter]
    fn exact(&self) -> Option<u32> {
        self.inner.exact()
    }

    /// Bytes of the rolling window.
    #[getter]
    fn window_bytes(&self) -> u64 {
        self.inner.window_bytes()
    }

    /// The pixels in scan order for `seed`.
    fn pixels(&self, seed: &Bound<'_, PyAny>) -> PyResult<Pixels> {
        Ok(Pixels {
            inner: Mutex::new(self.inner.pixels_seeded(seed_u64(seed)?)),
        })
    }
}

/// The pixel stream of a `Tiled` sampler: iterate for `(x, y, points)`
/// (points in raster coordinates, `(m, 2)`), or `take(n)` the next `n`
/// pixels at once as `(counts, points)`.
#[pyclass(module = "bridson_rs._native")]
struct Pixels {
    inner: Mutex<CorePixels<DefaultRng>>,
}

/// One pixel: `(x, y, points)`.
type PixelPoints<'py> = (u32, u32, Bound<'py, PyArray2<f64>>);

/// Pixel counts and their points.
type PixelRun<'py> = (Bound<'py, PyArray1<u32>>, Bound<'py, PyArray2<f64>>);

#[pymethods]
impl Pixels {
    /// The next `n` pixels (fewer at the end of the image): their point
    /// counts, `(k,)` uint32, and their points one pixel after the other,
    /// `(sum(counts), 2)`.
    fn take<'py>(&mut self, py: Python<'py>, n: usize) -> PyResult<PixelRun<'py>> {
        let inner = self
            .inner
            .get_mut()
            .map_err(|_| PyValueError::new_err("the stream failed earlier"))?;
        let mut counts: Vec<u32> = Vec::new();
        let mut flat: Vec<f64> = Vec::new();
        let mut pixel = Vec::new();
        while counts.len() < n {
            let want = (n - counts.len()).min(4096);
            let ended = py.detach(|| {
                for _ in 0..want {
                    if inner.next_into(&mut pixel).is_none() {
                        return true;
                    }
                    counts.push(u32::try_from(pixel.len()).unwrap_or(u32::MAX));
                    flat.extend(pixel.iter().flatten());
                }
                false
            });
            py.check_signals()?;
            if ended {
                break;
            }
        }
        Ok((PyArray1::from_vec(py, counts), to_array(py, flat, 2)?))
    }

    /// Exact mode: top-up points placed so far.
    #[getter]
    fn top_ups(&mut self) -> u64 {
        self.inner.get_mut().map_or(0, |p| p.top_ups())
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&mut self, py: Python<'py>) -> PyResult<Option<PixelPoints<'py>>> {
        let inner = self
            .inner
            .get_mut()
            .map_err(|_| PyValueError::new_err("the stream failed earlier"))?;
        let mut points = Vec::new();
        let Some((x, y)) = inner.next_into(&mut points) else {
            return Ok(None);
        };
        Ok(Some((x, y, to_array(py, points.into_flattened(), 2)?)))
    }
}

/// One camera sample: `(film, time, lens)`, film and lens `(u, v)` pairs.
type Camera = ((f64, f64), f64, (f64, f64));

/// A pixel's camera samples as arrays: film `(spp, 2)`, time `(spp,)`,
/// lens `(spp, 2)`.
type CameraArrays<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
);

/// The Python class of one of the crate's pixel samplers: the same
/// constructor (`spp`, `seed`, `resolution=`) and methods for every one.
macro_rules! pixel_sampler_class {
    ($(#[doc = $doc:expr])* $name:ident, $core:ty) => {
        $(#[doc = $doc])*
        #[pyclass(module = "bridson_rs._native")]
        struct $name {
            inner: Mutex<$core>,
        }

        impl $name {
            fn get(&mut self) -> PyResult<&mut $core> {
                self.inner
                    .get_mut()
                    .map_err(|_| PyValueError::new_err("the sampler failed earlier"))
            }
        }

        #[pymethods]
        impl $name {
            #[new]
            #[pyo3(signature = (spp, seed, *, resolution=None))]
            fn new(spp: u32, seed: &Bound<'_, PyAny>, resolution: Option<(u32, u32)>) -> PyResult<Self> {
                let mut inner = <$core>::new(spp, seed_u64(seed)?).map_err(value_error)?;
                if let Some((w, h)) = resolution {
                    inner = inner.with_resolution([w, h]);
                }
                Ok(Self {
                    inner: Mutex::new(inner),
                })
            }

            /// Samples per pixel.
            #[getter]
            fn samples_per_pixel(&mut self) -> PyResult<u32> {
                Ok(self.get()?.samples_per_pixel())
            }

            /// The seed.
            #[getter]
            fn seed(&mut self) -> PyResult<u64> {
                Ok(self.get()?.seed())
            }

            /// Moves to sample `index` of `pixel` (`(x, y)`), dimension `dimension`.
            #[pyo3(signature = (pixel, index, dimension=0))]
            fn start_pixel_sample(
                &mut self,
                pixel: (u32, u32),
                index: u32,
                dimension: u32,
            ) -> PyResult<()> {
                self.get()?
                    .start_pixel_sample([pixel.0, pixel.1], index, dimension)
                    .map_err(value_error)
            }

            /// The next value in `[0, 1)`.
            fn get_1d(&mut self) -> PyResult<f64> {
                Ok(self.get()?.get_1d())
            }

            /// The next pair in `[0, 1)²`.
            fn get_2d(&mut self) -> PyResult<(f64, f64)> {
                let [u, v] = self.get()?.get_2d();
                Ok((u, v))
            }

            /// The film offset of the current sample inside its pixel.
            fn get_pixel_2d(&mut self) -> PyResult<(f64, f64)> {
                let [u, v] = self.get()?.get_pixel_2d();
                Ok((u, v))
            }

            /// The camera's values for the current sample: `(film, time, lens)`.
            fn camera_sample(&mut self) -> PyResult<Camera> {
                let c = self.get()?.camera_sample();
                Ok(((c.film[0], c.film[1]), c.time, (c.lens[0], c.lens[1])))
            }

            /// Every sample of `pixel` at once: `(film, time, lens)` as `(spp, 2)`,
            /// `(spp,)` and `(spp, 2)` arrays (each sample from dimension 0).
            fn camera_samples<'py>(
                &mut self,
                py: Python<'py>,
                pixel: (u32, u32),
            ) -> PyResult<CameraArrays<'py>> {
                let s = self.get()?;
                let spp = s.samples_per_pixel();
                let (mut film, mut time, mut lens) = (Vec::new(), Vec::new(), Vec::new());
                for index in 0..spp {
                    s.start_pixel_sample([pixel.0, pixel.1], index, 0)
                        .map_err(value_error)?;
                    let c = s.camera_sample();
                    film.extend(c.film);
                    time.push(c.time);
                    lens.extend(c.lens);
                }
                Ok((
                    to_array(py, film, 2)?,
                    PyArray1::from_vec(py, time),
                    to_array(py, lens, 2)?,
                ))
            }
        }
    };
}

pixel_sampler_class!(
    /// Camera samples for a renderer, in the shape of pbrt-v4's sampler:
    /// exactly `spp` samples in every dimension of every pixel, each dimension
    /// a periodic Poisson disk set, the values a pure function of (seed,
    /// pixel, sample index, dimension).
    PoissonPixelSampler,
    CorePixelSampler
);

pixel_sampler_class!(
    /// Camera samples whose film offsets and 2-D pairs are Poisson disk nets:
    /// for `spp = 2^m` a (0,m,2)-net in every pixel and dimension pair, also
    /// well spaced; stratified in both axes for other counts (1 to 4096).
    /// The same methods as `PoissonPixelSampler`.
    NetPixelSampler,
    CoreNetPixelSampler
);

/// One pixel of a `CameraPixels` stream: `(x, y, film, time, lens,
/// extra)`, arrays of `(m, 2)`, `(m,)`, `(m, 2)` and `(m, extra_dims)`.
type CameraRow<'py> = (
    u32,
    u32,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
);

/// Camera samples pixel by pixel in scan order, the film points from a
/// `Tiled` stream (one Poisson set across pixel borders), the time, lens
/// and `extra_dims` further values from sets of as many points.
#[pyclass(module = "bridson_rs._native")]
struct CameraPixels {
    inner: Mutex<CoreCameraPixels>,
    extra_dims: usize,
}

#[pymethods]
impl CameraPixels {
    #[new]
    #[pyo3(signature = (tiled, seed, extra_dims=0))]
    fn new(tiled: &Tiled, seed: &Bound<'_, PyAny>, extra_dims: u32) -> PyResult<Self> {
        let inner = CoreCameraPixels::new(&tiled.inner, seed_u64(seed)?, extra_dims)
            .map_err(value_error)?;
        Ok(Self {
            inner: Mutex::new(inner),
            extra_dims: extra_dims as usize,
        })
    }

    /// Exact mode: top-up points placed so far.
    #[getter]
    fn top_ups(&mut self) -> u64 {
        self.inner.get_mut().map_or(0, |p| p.top_ups())
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__<'py>(&mut self, py: Python<'py>) -> PyResult<Option<CameraRow<'py>>> {
        let inner = self
            .inner
            .get_mut()
            .map_err(|_| PyValueError::new_err("the stream failed earlier"))?;
        let Some(pixel) = inner.next() else {
            return Ok(None);
        };
        let film: Vec<f64> = pixel.samples.iter().flat_map(|s| s.film).collect();
        let time: Vec<f64> = pixel.samples.iter().map(|s| s.time).collect();
        let lens: Vec<f64> = pixel.samples.iter().flat_map(|s| s.lens).collect();
        let m = pixel.samples.len();
        let extra = PyArray1::from_vec(py, pixel.extra).reshape([m, self.extra_dims])?;
        Ok(Some((
            pixel.x,
            pixel.y,
            to_array(py, film, 2)?,
            PyArray1::from_vec(py, time),
            to_array(py, lens, 2)?,
            extra,
        )))
    }
}

/// The native module: the samplers, their streams, and the limits.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PoissonDisk>()?;
    m.add_class::<Points>()?;
    m.add_class::<Tiled>()?;
    m.add_class::<Pixels>()?;
    m.add_class::<PoissonPixelSampler>()?;
    m.add_class::<NetPixelSampler>()?;
    m.add_class::<CameraPixels>()?;
    m.add_class::<field::PyField>()?;
    m.add_function(wrap_pyfunction!(field::chunk_boxes_of, m)?)?;
    m.add_function(wrap_pyfunction!(field::field_sort, m)?)?;
    m.add_function(wrap_pyfunction!(field::field_digest, m)?)?;
    m.add("MAX_FIELD_DIM", field::MAX_FIELD_DIM)?;
    m.add("MAX_DIM", MAX_DIM)?;
    m.add("DEFAULT_ATTEMPTS", bridson::DEFAULT_ATTEMPTS)?;
    m.add("MAX_ATTEMPTS", bridson::MAX_ATTEMPTS)?;
    m.add("MAX_SAMPLES_PER_PIXEL", bridson::MAX_SAMPLES_PER_PIXEL)?;
    m.add(
        "NET_MAX_SAMPLES_PER_PIXEL",
        bridson::NET_MAX_SAMPLES_PER_PIXEL,
    )?;
    Ok(())
}
