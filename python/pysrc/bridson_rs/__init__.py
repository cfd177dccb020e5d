"""Poisson disk sampling in any dimension, exact and fast: Python bindings
of the Rust crate ``bridson``.

Native API (NumPy in, NumPy out, no SciPy needed):

- :class:`PoissonDisk` -- points at least ``radius`` apart in a box of 1 to 8
  dimensions, each axis bounded or periodic; :meth:`PoissonDisk.about_points`
  asks for about ``n`` points instead. ``generate(seed)`` returns an
  ``(n, d)`` float64 array; ``iter``, ``iter_with`` (a region mask and
  pre-placed points) and ``iter_varying`` (a radius that varies with
  position) return lazy :class:`Points` streams.
- :class:`Tiled` -- a 2-D set streamed over a raster pixel by pixel
  (:class:`Pixels`).
- :class:`PoissonPixelSampler`, :class:`NetPixelSampler` (Poisson disk
  nets) and :class:`CameraPixels` -- camera samples for a renderer.
- :class:`Field` -- a maximal set that is a pure function of (seed, radius,
  domain, position), asked for box by box (``points_in``), 1 to 4
  dimensions, bounded, periodic or unbounded; :func:`chunk_boxes`,
  :func:`field_sort` (the canonical order) and :func:`field_digest` (an
  order-independent digest). :mod:`bridson_rs.dask` makes Dask collections
  of its points chunk by chunk (it needs Dask).

The drop-in for ``scipy.stats.qmc.PoissonDisk`` is
:class:`bridson_rs.qmc.PoissonDisk` (it needs SciPy).
"""

from ._native import (
    DEFAULT_ATTEMPTS,
    MAX_ATTEMPTS,
    MAX_DIM,
    MAX_FIELD_DIM,
    MAX_SAMPLES_PER_PIXEL,
    NET_MAX_SAMPLES_PER_PIXEL,
    CameraPixels,
    NetPixelSampler,
    Field,
    Pixels,
    Points,
    PoissonDisk,
    PoissonPixelSampler,
    Tiled,
    chunk_boxes,
    field_digest,
    field_sort,
)

__all__ = [
    "DEFAULT_ATTEMPTS",
    "MAX_ATTEMPTS",
    "MAX_DIM",
    "MAX_FIELD_DIM",
    "MAX_SAMPLES_PER_PIXEL",
    "NET_MAX_SAMPLES_PER_PIXEL",
    "CameraPixels",
    "NetPixelSampler",
    "Field",
    "Pixels",
    "Points",
    "PoissonDisk",
    "PoissonPixelSampler",
    "Tiled",
    "chunk_boxes",
    "field_digest",
    "field_sort",
]
