"""A :class:`~bridson_rs.Field`'s points as Dask collections, chunk by chunk.

Each partition is one chunk box of :func:`bridson_rs.chunk_boxes`, and its
task builds the field again from :attr:`Field.params` (plain numbers) and
asks it for that box with :meth:`Field.points_in`. A chunk's points are a
pure function of (seed, radius, domain, box), so the collection holds the
same points, bit for bit, whatever the number of workers, the chunk side
or the schedule; only the partitioning differs. A worker holds one chunk
and its halo per running task, never the whole set.

Partitions come in the order of :func:`~bridson_rs.chunk_boxes` (the last
axis slowest), each in the field's canonical order; the collection as a
whole is not sorted (:func:`~bridson_rs.field_sort` sorts an array,
:func:`~bridson_rs.field_digest` compares sets without sorting).

Dask is imported when a function here is called, so ``bridson_rs`` works
without it. Install ``dask[dataframe]`` (and ``pyarrow`` for Parquet).

Example::

    import bridson_rs as b
    from bridson_rs.dask import to_dask_dataframe

    field = b.Field([0, 0], [1, 1], 0.001, seed=7)
    df = to_dask_dataframe(field, chunk=0.25)   # 16 partitions, columns x, y
    df.to_parquet("points/")                     # each task writes its chunk
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Optional

import numpy as np

from ._native import Field, chunk_boxes

__all__ = ["field_chunks", "to_dask_array", "to_dask_dataframe"]

#: Column names of the dataframe for 1 to 4 dimensions.
DEFAULT_COLUMNS = ("x", "y", "z", "w")

#: A chunk box: its lower and upper corners.
Box = tuple[tuple[float, ...], tuple[float, ...]]


def default_chunk(field: Field) -> float:
    """The default chunk side: ``radius * 2**(18 / d)``, about ``2**18``
    cubes of side ``r`` a chunk (``512 r`` in 2-D: about 180 000 points,
    3 MB of points)."""
    return field.radius * 2.0 ** (18.0 / field.d)


def field_chunks(
    field: Field,
    lo: Optional[Sequence[float]] = None,
    hi: Optional[Sequence[float]] = None,
    chunk: Optional[float] = None,
) -> list[Box]:
    """The chunk boxes the collections here are made of: the box
    ``lo <= x < hi`` (default: a bounded field's box) cut into chunks of
    ``chunk`` on a side (default :func:`default_chunk`), the last axis
    slowest."""
    if lo is None and hi is None:
        if field.lo is None:
            raise ValueError("an unbounded field has no box: give lo and hi")
        lo, hi = field.lo, field.hi
    elif lo is None or hi is None:
        raise ValueError("give both lo and hi, or neither")
    los, his = chunk_boxes(list(lo), list(hi), default_chunk(field) if chunk is None else chunk)
    return [(tuple(a), tuple(b)) for a, b in zip(los.tolist(), his.tolist())]


def _chunk_points(params: tuple, box: Box) -> np.ndarray:
    """One partition's points: the field rebuilt from ``params``, asked for
    ``box``. Everything it reads is in its arguments."""
    return Field.from_params(params).points_in(list(box[0]), list(box[1]))


def _chunk_frame(box: Box, params: tuple, names: tuple[str, ...]) -> Any:
    """One partition as a pandas DataFrame (the array is not copied)."""
    import pandas as pd

    return pd.DataFrame(_chunk_points(params, box), columns=list(names), copy=False)


def _columns(field: Field, columns: Optional[Sequence[str]]) -> tuple[str, ...]:
    if columns is None:
        if field.d > len(DEFAULT_COLUMNS):
            raise ValueError(f"give columns for {field.d} dimensions")
        return DEFAULT_COLUMNS[: field.d]
    names = tuple(columns)
    if len(names) != field.d:
        raise ValueError(f"columns must have {field.d} names, not {len(names)}")
    return names


def to_dask_dataframe(
    field: Field,
    lo: Optional[Sequence[float]] = None,
    hi: Optional[Sequence[float]] = None,
    *,
    chunk: Optional[float] = None,
    columns: Optional[Sequence[str]] = None,
) -> Any:
    """A Dask DataFrame of the field's points in ``lo <= x < hi`` (default:
    a bounded field's box), one partition a chunk of :func:`field_chunks`,
    float64 columns ``x, y, z, w`` (as many as dimensions) or ``columns``.

    Each partition's index is its own ``0 .. n``; the divisions are
    unknown. Nothing runs until the collection is computed or written
    (``to_parquet``), each task on its own chunk.
    """
    import dask.dataframe as dd
    import pandas as pd

    names = _columns(field, columns)
    boxes = field_chunks(field, lo, hi, chunk)
    params = field.params
    meta = pd.DataFrame({name: np.empty(0, np.float64) for name in names})
    return dd.from_map(
        _chunk_frame,
        boxes,
        args=(params, names),
        meta=meta,
        label="bridson-field",
        enforce_metadata=False,
    )


def to_dask_array(
    field: Field,
    lo: Optional[Sequence[float]] = None,
    hi: Optional[Sequence[float]] = None,
    *,
    chunk: Optional[float] = None,
) -> Any:
    """A Dask array ``(n, d)`` float64 of the field's points in
    ``lo <= x < hi`` (default: a bounded field's box), one block a chunk of
    :func:`field_chunks`. The blocks' lengths are unknown (``nan``) until
    computed (``compute_chunk_sizes()`` finds them)."""
    import dask
    import dask.array as da

    params = field.params
    make = dask.delayed(_chunk_points, pure=True)
    blocks = [
        da.from_delayed(make(params, box), shape=(np.nan, field.d), dtype=np.float64)
        for box in field_chunks(field, lo, hi, chunk)
    ]
    return da.concatenate(blocks, axis=0)
