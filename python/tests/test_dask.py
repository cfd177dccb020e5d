"""The field's points through Dask (issue 52, item 4): a LocalCluster of 2
worker processes writes them to Parquet chunk by chunk, and the result is
the single-process field's points in the same box, sorted, bit for bit.

Every test here has ``dask`` in its name (``pytest python -k dask``).
The default size runs in CI (about 240 000 points in 2-D); with
``BRIDSON_DASK_BIG=1`` the same test also runs at 10**8 points and prints
its wall time and each worker's peak memory.
"""

import math
import os
import resource
import time

import numpy as np
import pytest

import bridson_rs as b

dask = pytest.importorskip("dask")
pytest.importorskip("dask.dataframe")
distributed = pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

from bridson_rs.dask import field_chunks, to_dask_array, to_dask_dataframe  # noqa: E402

BIG = os.environ.get("BRIDSON_DASK_BIG") == "1"

#: Points times r**2 per unit area of the 2-D field: 1 134 532 points in
#: the unit square at r = 0.000784 (docs/field.md).
POINTS_R2 = 1_134_532 * 0.000784**2


def radius_for(n_points):
    """The radius that gives about `n_points` in the unit square."""
    return math.sqrt(POINTS_R2 / n_points)


def bits(points):
    return np.ascontiguousarray(points).view(np.uint64)


def peak_rss_mib():
    """This process's peak resident memory in MiB (Linux: ru_maxrss in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def parquet_points(path):
    """The points of a Parquet folder as an (n, 2) float64 array."""
    import pyarrow.parquet as pq

    table = pq.read_table(path, columns=["x", "y"])
    points = np.empty((table.num_rows, 2))
    for axis, name in enumerate(["x", "y"]):
        points[:, axis] = table.column(name).to_numpy()
    return points


def count_and_digest(frame):
    """Count and order-independent digest of one partition, in its task."""
    points = frame[["x", "y"]].to_numpy()
    return len(points), b.field_digest(points)


@pytest.fixture
def cluster_client():
    """A fresh LocalCluster of 2 worker processes, 1 thread each."""
    with distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        memory_limit=None,
    ) as cluster, distributed.Client(cluster) as client:
        yield client


@pytest.mark.parametrize(
    "n_points, chunk_a, chunk_b",
    [
        pytest.param(240_000, 0.125, 0.3, id="small"),
        pytest.param(
            10**8,
            0.05,
            0.07,
            id="1e8",
            marks=pytest.mark.skipif(not BIG, reason="set BRIDSON_DASK_BIG=1"),
        ),
    ],
)
def test_dask_parquet_equals_single_process(cluster_client, tmp_path, n_points, chunk_a, chunk_b):
    client = cluster_client
    field = b.Field([0.0, 0.0], [1.0, 1.0], radius_for(n_points), seed=52)
    path = tmp_path / "points"

    # Chunking A, written by the workers, one Parquet file per chunk.
    frame = to_dask_dataframe(field, chunk=chunk_a)
    assert frame.npartitions == len(field_chunks(field, chunk=chunk_a))
    started = time.perf_counter()
    frame.to_parquet(path, write_index=False)
    wall = time.perf_counter() - started
    worker_peaks = client.run(peak_rss_mib)

    # Chunking B, each partition reduced to its count and digest in its task.
    parts = to_dask_dataframe(field, chunk=chunk_b).to_delayed()
    per_chunk = dask.compute(*[dask.delayed(count_and_digest)(p) for p in parts])
    count_b = sum(n for n, _ in per_chunk)
    digest_b = sum(h for _, h in per_chunk) % 2**64

    # The single process: the whole box in chunks of yet another side on
    # this process's threads (points_in itself for the small box).
    started = time.perf_counter()
    if n_points <= 10**6:
        reference = field.points()
    else:
        reference = field.points_in_parallel(chunk=0.0625, threads=2)
    single_wall = time.perf_counter() - started

    written = b.field_sort(parquet_points(path))
    assert len(reference) == len(written)
    assert np.array_equal(bits(reference), bits(written))
    assert count_b == len(reference) and digest_b == b.field_digest(reference)
    if n_points <= 10**6:
        other = b.field_sort(sums_frame_points(field, chunk_b))
        assert np.array_equal(bits(reference), bits(other))

    print(
        f"\n[dask] {len(reference)} points, r = {field.radius:.6g}, "
        f"{frame.npartitions} chunks of {chunk_a}: to_parquet {wall:.1f} s on 2 workers; "
        f"single process ({'points' if n_points <= 10**6 else 'points_in_parallel, 2 threads'}) "
        f"{single_wall:.1f} s; peak RSS per worker (MiB): "
        + ", ".join(f"{v:.0f}" for v in worker_peaks.values())
        + f"; this process {peak_rss_mib():.0f} MiB"
    )
    if n_points >= 10**8:
        # Bounded by the chunks: each worker held far less than the set
        # (1.6 GB of points).
        assert all(v < 1024 for v in worker_peaks.values())


def sums_frame_points(field, chunk):
    """The points of the chunking `chunk`, computed on the cluster."""
    return to_dask_dataframe(field, chunk=chunk).compute()[["x", "y"]].to_numpy()


def test_dask_array_and_unbounded_field_agree_with_points_in(cluster_client):
    world = b.Field.unbounded(2, 1.0, seed=9)
    lo, hi = [-30.0, 5.0], [40.0, 60.0]
    array = to_dask_array(world, lo, hi, chunk=17.0)
    assert array.shape[1] == 2 and math.isnan(array.shape[0])
    points = array.compute()
    assert np.array_equal(bits(b.field_sort(points)), bits(world.points_in(lo, hi)))


def test_dask_graph_is_a_pure_function_of_its_inputs():
    field = b.Field([0, 0], [1, 1], 0.01, seed=1)
    one = to_dask_dataframe(field, chunk=0.5)
    assert one._name == to_dask_dataframe(b.Field([0, 0], [1, 1], 0.01, seed=1), chunk=0.5)._name
    assert one._name != to_dask_dataframe(b.Field([0, 0], [1, 1], 0.01, seed=2), chunk=0.5)._name
    # Computed without a cluster, by the threaded scheduler, in any order.
    parts = [one.get_partition(i).compute(scheduler="threads") for i in range(one.npartitions)[::-1]]
    got = b.field_sort(np.concatenate([p.to_numpy() for p in parts]))
    assert np.array_equal(bits(got), bits(field.points()))
    with pytest.raises(ValueError, match="3 names"):
        to_dask_dataframe(b.Field([0, 0, 0], [1, 1, 1], 0.1, 1), columns=["a"])
