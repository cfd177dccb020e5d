"""The field sampler (`bridson_rs.Field`): a pure function of place."""

import _thread
import pickle
import signal
import threading

import numpy as np
import pytest

import bridson_rs as b
from test_native import pairs_closer


def bits(points):
    """The points' bits, for comparing bit for bit (-0.0 differs from 0.0)."""
    return np.ascontiguousarray(points).view(np.uint64)


def same(a, b_):
    return a.shape == b_.shape and np.array_equal(bits(a), bits(b_))


@pytest.mark.parametrize("d", range(1, 5))
def test_every_dimension_exact_in_box_and_chunk_free(d):
    # 4-D is slow (the field's cost grows as 5**d): a few hundred points
    # take seconds, so it gets a coarse radius and two halves, not chunks.
    radius = [0.01, 0.04, 0.12, 0.6][d - 1]
    lo, hi = [-1.0] * d, [0.5] * d
    field = b.Field(lo, hi, radius, seed=d)
    points = field.points()
    assert points.shape[1] == d and points.dtype == np.float64
    assert len(points) > 20
    assert np.all(points >= -1.0) and np.all(points < 0.5)
    assert pairs_closer(points, radius) == 0
    # Canonical order, and the same bits from other boxes.
    assert same(points, b.field_sort(points))
    if d < 4:
        chunk = 0.37 if d < 3 else 0.8  # 3-D: 8 chunks, each a whole window
        assert same(points, field.points_in_parallel(chunk=chunk, threads=2))
    else:
        mid = lo[:-1] + [-0.3]
        halves = [field.points_in(lo, hi[:-1] + [-0.3]), field.points_in(mid, hi)]
        assert same(points, np.concatenate(halves))


def test_arrays_are_not_copied():
    points = b.Field([0, 0], [1, 1], 0.05, 7).points_in([0, 0], [1, 1])
    assert points.flags["C_CONTIGUOUS"] and points.shape[1] == 2
    assert points.base is not None and not points.flags["OWNDATA"]
    assert type(points.base.base).__name__ == "PySliceContainer"


def test_a_box_is_the_whole_sets_points_in_it():
    field = b.Field([0, 0], [4, 3], 0.05, seed=11)
    whole = field.points()
    lo, hi = np.array([1.1, 0.3]), np.array([2.7, 2.05])
    inside = whole[np.all((whole >= lo) & (whole < hi), axis=1)]
    assert same(field.points_in(lo.tolist(), hi.tolist()), inside)


def test_unbounded_two_orders_one_world():
    world = b.Field.unbounded(2, 1.0, seed=7)
    a = world.points_in([0, 0], [20, 10])
    parts = [world.points_in([10, 0], [20, 10]), world.points_in([0, 0], [10, 10])]
    assert same(a, b.field_sort(np.concatenate(parts)))
    assert b.field_digest(a) == (b.field_digest(parts[0]) + b.field_digest(parts[1])) % 2**64
    assert world.lo is None and world.hi is None
    with pytest.raises(ValueError, match="unbounded field has no box"):
        world.points()


def test_periodic_keeps_its_distance_across_the_seam():
    field = b.Field([0, 0], [1, 1], 0.05, seed=3, periodic=True)
    points = field.points()
    assert field.periodic == [True, True]
    assert pairs_closer(points, 0.05, periods=np.array([1.0, 1.0])) == 0
    assert not same(points, b.Field([0, 0], [1, 1], 0.05, seed=3).points())


def test_seed_and_params():
    f = b.Field([0, 0, 0], [1, 2, 1], 0.1, seed=2**64 - 1, periodic=[True, False, True])
    assert f.seed == 2**64 - 1 and f.d == 3
    assert f.params == (3, [0, 0, 0], [1, 2, 1], [True, False, True], 0.1, 2**64 - 1, 2**30)
    g = b.Field.from_params(f.params)
    assert g == f and pickle.loads(pickle.dumps(f)) == f
    assert same(g.points(), f.points())
    u = b.Field.unbounded(2, 0.5, seed=1)
    assert pickle.loads(pickle.dumps(u)) == u
    assert not same(b.Field([0, 0], [1, 1], 0.05, 1).points(), b.Field([0, 0], [1, 1], 0.05, 2).points())


def test_chunk_boxes_tile_the_box():
    los, his = b.chunk_boxes([0, 0], [1, 0.5], 0.3)
    assert los.shape == his.shape == (4 * 2, 2)
    assert np.all(los < his)
    assert his[:, 0].max() == 1 and his[:, 1].max() == 0.5
    # The last axis slowest.
    assert list(los[:4, 1]) == [0.0] * 4 and list(los[:4, 0]) == [0.0, 0.3, 0.6, 0.8999999999999999]


def test_digest_matches_the_cli_formula():
    # The hash of the point (0.5, 0.25) as examples/points/field.rs makes it.
    def point_hash(p):
        mask = 2**64 - 1
        h = 0x243F6A8885A308D3
        for x in p:
            z = h ^ int(np.float64(x).view(np.uint64))
            z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
            z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
            h = z ^ (z >> 31)
        return h

    pts = np.array([[0.5, 0.25], [-3.0, 1e-300]])
    assert b.field_digest(pts) == (point_hash(pts[0]) + point_hash(pts[1])) % 2**64
    assert b.field_digest(pts[::-1]) == b.field_digest(pts)


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: b.Field([0, 0], [1, 1], -1.0, 1), "radius"),
        (lambda: b.Field([0, 0], [0, 1], 0.1, 1), "empty"),
        (lambda: b.Field([0] * 5, [1] * 5, 0.1, 1), "dimension must be within 1..=4"),
        (lambda: b.Field([0, 0], [1], 0.1, 1), "same length"),
        (lambda: b.Field([0, 0], [1, 1], 0.1, -1), "seed"),
        (lambda: b.Field([0, 0], [1, 1], 0.1, 1).points_in([0, 0], [0, 1]), "empty"),
        (lambda: b.Field([0, 0], [1, 1], 0.1, 1).points_in([0, 0], [np.inf, 1]), "finite"),
        (lambda: b.Field([0, 0], [1, 1], 0.1, 1).points_in([0, 0, 0], [1, 1, 1]), "2 values"),
        (lambda: b.Field([0, 0], [1, 1], 0.1, 1).points_in_parallel(chunk=0.0), "radius"),
        (lambda: b.Field([0, 0], [1, 1], 0.1, 1).points_in_parallel(threads=0), "threads"),
        (lambda: b.Field.unbounded(0, 0.1, 1), "dimension"),
        (lambda: b.chunk_boxes([0, 0], [1, 1], float("nan")), "radius"),
    ],
)
def test_bad_input_is_a_value_error(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_window_budget_is_a_value_error_and_chunks_get_round_it():
    field = b.Field([0, 0], [1, 1], 0.01, seed=5, max_window_bytes=1 << 20)
    with pytest.raises(ValueError, match="budget"):
        field.points_in([0, 0], [1, 1])
    chunked = field.points_in_parallel(chunk=0.1, threads=1)
    assert same(chunked, b.Field([0, 0], [1, 1], 0.01, seed=5).points())


def test_ctrl_c_stops_a_long_chunked_run():
    # About 1.8 million points, seconds of work: the interrupt at 50 ms
    # must stop it. Python's own SIGINT handler is installed for the test,
    # since a process started in the background (`cmd &` in a script)
    # ignores SIGINT, and then interrupt_main does nothing.
    field = b.Field.unbounded(2, 0.5, seed=1)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.05, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            field.points_in_parallel([0, 0], [600, 600], chunk=32.0, threads=1)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_queries_run_without_the_gil():
    field = b.Field([0, 0], [150, 150], 0.5, seed=9)
    results = []
    threads = [
        threading.Thread(target=lambda: results.append(len(field.points_in([0, 0], [150, 150]))))
        for _ in range(2)
    ]
    for t in threads:
        t.start()
    ticks = 0
    while any(t.is_alive() for t in threads):
        ticks += 1
    for t in threads:
        t.join()
    assert len(results) == 2 and results[0] == results[1] and ticks > 1000
