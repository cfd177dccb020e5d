"""Type stubs of the native module (Rust, PyO3). Every array returned is a
float64 NumPy array that owns the sampler's buffer (no copy)."""

from collections.abc import Callable, Iterator, Sequence
from typing import Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

MAX_DIM: int
DEFAULT_ATTEMPTS: int
MAX_ATTEMPTS: int
MAX_SAMPLES_PER_PIXEL: int
NET_MAX_SAMPLES_PER_PIXEL: int
MAX_FIELD_DIM: int

Seed = int
"""A seed: any int in ``0 .. 2**64``."""

FloatArray = npt.NDArray[np.float64]
Mask = Union[Callable[[FloatArray], npt.ArrayLike], npt.ArrayLike]
RadiusField = Union[Callable[[FloatArray], npt.ArrayLike], npt.ArrayLike]

class PoissonDisk:
    """Poisson disk sampling in a box of 1 to 8 dimensions: random points
    no two closer than ``radius``, every one in ``lo <= x < hi``.

    ``periodic`` is a bool for every axis or one per axis. ``attempts`` is
    Bridson's ``k``; ``candidates`` is ``"annulus"`` (Bridson's, in
    ``r .. 2r``) or ``"sphere"`` (on the sphere of radius ``r``, denser).
    ``max_points`` caps the stream (a blob around its first point: for
    about ``n`` points over the whole box use :meth:`about_points`);
    ``max_grid_bytes`` is the memory budget (default 1 GiB). Bad settings
    raise ``ValueError`` with the crate's message.
    """

    def __init__(
        self,
        lo: Sequence[float],
        hi: Sequence[float],
        radius: float,
        *,
        periodic: Union[bool, Sequence[bool], None] = None,
        attempts: int = 30,
        candidates: str = "annulus",
        max_points: Optional[int] = None,
        max_grid_bytes: Optional[int] = None,
    ) -> None: ...
    @staticmethod
    def about_points(
        lo: Sequence[float],
        hi: Sequence[float],
        n: int,
        *,
        periodic: Union[bool, Sequence[bool], None] = None,
        attempts: int = 30,
        candidates: str = "annulus",
        max_points: Optional[int] = None,
        max_grid_bytes: Optional[int] = None,
    ) -> "PoissonDisk":
        """Count mode: the radius that gives about ``n`` points spread over
        the whole box (within 2 % on average for ``n >= 1000`` in 2-D and
        3-D)."""
    @property
    def d(self) -> int:
        """The dimension."""
    @property
    def radius(self) -> float:
        """The minimum distance (in count mode, the one derived)."""
    @property
    def attempts(self) -> int:
        """Attempts ``k`` around each active point."""
    @property
    def lo(self) -> list[float]:
        """The box's lower corner."""
    @property
    def hi(self) -> list[float]:
        """The box's upper corner (excluded)."""
    @property
    def periodic(self) -> list[bool]:
        """Which axes wrap around."""
    @property
    def requested_count(self) -> Optional[int]:
        """In count mode, the number of points asked for."""
    @property
    def max_points(self) -> Optional[int]:
        """The point cap, if any."""
    @property
    def grid_bytes(self) -> int:
        """Bytes the grid allocates before the first point."""
    def generate(self, seed: Seed) -> FloatArray:
        """All points for ``seed``, ``(n, d)``. The same seed gives the same
        points on every run and platform. Releases the GIL; Ctrl-C stops
        it. ``ValueError`` if the run outgrew the memory budget."""
    def generate_parallel(self, seed: Seed, threads: int) -> FloatArray:
        """All points for ``seed``, made slab by slab on ``threads`` threads
        (a different set from ``generate``'s, with its statistics). Only in
        a build with the bindings crate's ``parallel`` feature (``pip
        install ./python --config-settings=maturin.build-args="--features
        parallel"``); without it the method is absent."""
    def iter(self, seed: Seed) -> "Points":
        """The lazy stream of points for ``seed``, in generation order."""
    def iter_with(
        self,
        seed: Seed,
        region: Optional[Mask] = None,
        fixed: Optional[npt.ArrayLike] = None,
    ) -> "Points":
        """The stream of points in ``region`` that keep their distance from
        the pre-placed points ``fixed`` (``(m, d)``, not yielded).

        ``region`` is a boolean array with one axis per dimension laid over
        the box (axis ``a`` of the array is coordinate ``a``: an image
        indexed ``[row, column]`` is ``image.T`` for ``(x, y)``; a point
        takes the value of the cell it lies in), sampled without the GIL;
        or a callable ``f(points) -> bools``, called with a ``(1, d)``
        array for every candidate, under the GIL (slower: prefer arrays).
        """
    def iter_varying(self, seed: Seed, r_min: float, field: RadiusField) -> "Points":
        """The stream of points whose spacing follows ``field``: no two
        points ``p``, ``q`` closer than ``max(r(p), r(q))``, with ``r`` the
        field clamped to ``r_min ..= radius`` (NaN counts as ``radius``).

        ``field`` is an array laid over the box as ``region`` is in
        :meth:`iter_with`, or a callable ``f(points) -> radii`` called with
        a ``(1, d)`` array under the GIL.
        """

class Points(Iterator[FloatArray]):
    """A lazy point stream. ``take(n)`` the next points, ``collect()`` the
    rest, or iterate point by point (slow: one array a point)."""

    @property
    def d(self) -> int:
        """The dimension."""
    @property
    def error(self) -> Optional[str]:
        """Why the stream ended early (the crate's message), or None."""
    def take(self, n: int) -> FloatArray:
        """The next ``n`` points (fewer if the stream ends), ``(m, d)``."""
    def collect(self) -> FloatArray:
        """Every remaining point, ``(m, d)``."""
    def __iter__(self) -> "Points": ...
    def __next__(self) -> FloatArray: ...

class Tiled:
    """A 2-D Poisson disk set streamed over a ``width x height`` raster pixel
    by pixel in scan order, its memory one row of pixels. Give ``radius``
    (in pixels) or ``per_pixel`` (points a pixel); ``exact=n`` gives exactly
    ``n`` points in every pixel. ``scheme`` is ``"sweep"`` (one process
    across the image, no trace of pixel borders) or ``"paper"``."""

    def __init__(
        self,
        width: int,
        height: int,
        *,
        radius: Optional[float] = None,
        per_pixel: Optional[float] = None,
        exact: Optional[int] = None,
        attempts: Optional[int] = None,
        candidates: str = "annulus",
        scheme: str = "sweep",
        max_window_bytes: Optional[int] = None,
    ) -> None: ...
    @property
    def radius(self) -> float:
        """The minimum distance used, in pixels."""
    @property
    def attempts(self) -> int: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def exact(self) -> Optional[int]: ...
    @property
    def window_bytes(self) -> int:
        """Bytes of the rolling window."""
    def pixels(self, seed: Seed) -> "Pixels":
        """The pixels in scan order for ``seed``."""

class Pixels(Iterator[Tuple[int, int, FloatArray]]):
    """The pixel stream: iterate for ``(x, y, points)`` (raster coordinates,
    ``(m, 2)``), or ``take(n)``."""

    @property
    def top_ups(self) -> int:
        """Exact mode: top-up points placed so far (closer than radius)."""
    def take(self, n: int) -> Tuple[npt.NDArray[np.uint32], FloatArray]:
        """The next ``n`` pixels: their counts ``(k,)`` and their points one
        pixel after the other, ``(sum(counts), 2)``."""
    def __iter__(self) -> "Pixels": ...
    def __next__(self) -> Tuple[int, int, FloatArray]: ...

class PoissonPixelSampler:
    """Camera samples in the shape of pbrt-v4's sampler: exactly ``spp``
    samples in every dimension of every pixel, each dimension a periodic
    Poisson disk set, a pure function of (seed, pixel, index, dimension)."""

    def __init__(
        self, spp: int, seed: Seed, *, resolution: Optional[Tuple[int, int]] = None
    ) -> None: ...
    @property
    def samples_per_pixel(self) -> int: ...
    @property
    def seed(self) -> int: ...
    def start_pixel_sample(
        self, pixel: Tuple[int, int], index: int, dimension: int = 0
    ) -> None:
        """Moves to sample ``index`` of ``pixel``; ``ValueError`` if
        ``index >= spp`` or the pixel lies outside ``resolution``."""
    def get_1d(self) -> float: ...
    def get_2d(self) -> Tuple[float, float]: ...
    def get_pixel_2d(self) -> Tuple[float, float]: ...
    def camera_sample(
        self,
    ) -> Tuple[Tuple[float, float], float, Tuple[float, float]]:
        """``(film, time, lens)`` of the current sample."""
    def camera_samples(
        self, pixel: Tuple[int, int]
    ) -> Tuple[FloatArray, FloatArray, FloatArray]:
        """Every sample of ``pixel``: film ``(spp, 2)``, time ``(spp,)``,
        lens ``(spp, 2)``."""

class NetPixelSampler:
    """Camera samples whose film offsets and 2-D pairs are Poisson disk
    nets: for ``spp = 2^m`` a (0,m,2)-net in every pixel and dimension pair,
    also well spaced; stratified in both axes for other counts (1 to
    ``NET_MAX_SAMPLES_PER_PIXEL``). The methods of
    :class:`PoissonPixelSampler`."""

    def __init__(
        self, spp: int, seed: Seed, *, resolution: Optional[Tuple[int, int]] = None
    ) -> None: ...
    @property
    def samples_per_pixel(self) -> int: ...
    @property
    def seed(self) -> int: ...
    def start_pixel_sample(
        self, pixel: Tuple[int, int], index: int, dimension: int = 0
    ) -> None:
        """Moves to sample ``index`` of ``pixel``; ``ValueError`` if
        ``index >= spp`` or the pixel lies outside ``resolution``."""
    def get_1d(self) -> float: ...
    def get_2d(self) -> Tuple[float, float]: ...
    def get_pixel_2d(self) -> Tuple[float, float]: ...
    def camera_sample(
        self,
    ) -> Tuple[Tuple[float, float], float, Tuple[float, float]]:
        """``(film, time, lens)`` of the current sample."""
    def camera_samples(
        self, pixel: Tuple[int, int]
    ) -> Tuple[FloatArray, FloatArray, FloatArray]:
        """Every sample of ``pixel``: film ``(spp, 2)``, time ``(spp,)``,
        lens ``(spp, 2)``."""

class CameraPixels(
    Iterator[Tuple[int, int, FloatArray, FloatArray, FloatArray, FloatArray]]
):
    """Camera samples pixel by pixel in scan order: ``(x, y, film, time,
    lens, extra)``, the film points from a :class:`Tiled` stream."""

    def __init__(self, tiled: Tiled, seed: Seed, extra_dims: int = 0) -> None: ...
    @property
    def top_ups(self) -> int: ...
    def __iter__(self) -> "CameraPixels": ...
    def __next__(
        self,
    ) -> Tuple[int, int, FloatArray, FloatArray, FloatArray, FloatArray]: ...

FieldParams = Tuple[
    int, Optional[list[float]], Optional[list[float]], list[bool], float, int, int
]
"""``(d, lo, hi, periodic, radius, seed, max_window_bytes)``; ``lo`` and
``hi`` are ``None`` for an unbounded field."""

class Field:
    """A maximal Poisson disk set that is a pure function of (seed, radius,
    domain, position): :meth:`points_in` returns exactly the whole set's
    points in a box, bit for bit, whatever the order of the queries, their
    size, the threads or the machine. Every point of the domain is within
    ``radius`` of a point (maximal).

    ``Field(lo, hi, radius, seed)`` is the set on the box ``lo <= x < hi``
    (1 to 4 dimensions), each axis bounded or periodic (``periodic``: a
    bool for every axis or one per axis); :meth:`unbounded` is the set on
    all of space. ``max_window_bytes`` is the memory budget of one query
    (default 1 GiB). Bad settings raise ``ValueError`` with the crate's
    message. Fields pickle (as their :attr:`params`) and compare equal when
    their settings are equal.
    """

    def __init__(
        self,
        lo: Sequence[float],
        hi: Sequence[float],
        radius: float,
        seed: Seed,
        *,
        periodic: Union[bool, Sequence[bool], None] = None,
        max_window_bytes: int = 2**30,
    ) -> None: ...
    @staticmethod
    def unbounded(d: int, radius: float, seed: Seed, *, max_window_bytes: int = 2**30) -> "Field":
        """The set on all of ``d``-dimensional space (an endless world): the
        lattice is anchored at the origin, so every box sees the same
        points."""
    @staticmethod
    def from_params(params: FieldParams) -> "Field":
        """The field whose :attr:`params` are ``params``."""
    @property
    def params(self) -> FieldParams:
        """The settings as plain values (what a Dask task receives)."""
    @property
    def d(self) -> int:
        """The dimension."""
    @property
    def radius(self) -> float:
        """The minimum distance ``r``."""
    @property
    def seed(self) -> int:
        """The seed."""
    @property
    def lo(self) -> Optional[list[float]]:
        """The box's lower corner, ``None`` when unbounded."""
    @property
    def hi(self) -> Optional[list[float]]:
        """The box's upper corner (excluded), ``None`` when unbounded."""
    @property
    def periodic(self) -> list[bool]:
        """Which axes wrap around."""
    @property
    def max_window_bytes(self) -> int:
        """The memory budget of one query's window."""
    def points_in(self, lo: Sequence[float], hi: Sequence[float]) -> FloatArray:
        """The points in the half-open box ``lo <= x < hi``, ``(n, d)``, in
        the canonical order (:func:`field_sort`). One query without the GIL;
        over ``max_window_bytes`` it is a ``ValueError``: ask in chunks
        with :meth:`points_in_parallel`."""
    def points(self) -> FloatArray:
        """Every point of a bounded field (``ValueError`` when unbounded)."""
    def points_in_parallel(
        self,
        lo: Optional[Sequence[float]] = None,
        hi: Optional[Sequence[float]] = None,
        *,
        chunk: Optional[float] = None,
        threads: Optional[int] = None,
    ) -> FloatArray:
        """The points in ``lo <= x < hi`` (default: the field's box) made in
        chunks of ``chunk`` on a side (default ``64 * radius``) on
        ``threads`` threads (default: every core), in the canonical order:
        the same array as :meth:`points_in`, bit for bit, for every chunk
        and thread count. Ctrl-C stops it between batches of chunks."""
    def __eq__(self, other: object) -> bool: ...

def chunk_boxes(
    lo: Sequence[float], hi: Sequence[float], side: float
) -> Tuple[FloatArray, FloatArray]:
    """The chunks of ``side`` over ``lo <= x < hi``: ``(los, his)``, two
    ``(k, d)`` arrays, box ``i`` being ``los[i] <= x < his[i]``, the last
    axis slowest. Every point of the box is in exactly one chunk."""

def field_sort(points: npt.ArrayLike) -> FloatArray:
    """A copy of ``points`` ``(n, d)`` in the field's canonical order:
    lexicographic, the last axis first, by the bits' total order. Two sets
    are equal exactly when their sorted arrays are equal bit for bit."""

def field_digest(points: npt.ArrayLike) -> int:
    """An order-independent 64-bit digest of ``points`` ``(n, d)``: the
    wrapping sum of a hash of each point's bits, as printed (in hex) by
    ``points --field --format none``. Digests of disjoint parts add up
    (mod ``2**64``) to the digest of their union."""
