"""The native API: NumPy arrays out, the crate's guarantees, its errors."""

import _thread
import signal
import threading

import numpy as np
import pytest

import bridson_rs as b


def pairs_closer(points, radius, periods=None):
    """Pairs closer than `radius` (toroidal on axes with a period): by a
    KD-tree where SciPy is installed, else by brute force."""
    try:
        from scipy.spatial import cKDTree
    except ImportError:
        cKDTree = None
    if cKDTree is not None and periods is None:
        return len(cKDTree(points).query_pairs(radius * (1 - 1e-12)))
    diff = np.abs(points[:, None, :] - points[None, :, :])
    if periods is not None:
        diff = np.minimum(diff, periods - diff)
    d2 = (diff**2).sum(axis=2)
    np.fill_diagonal(d2, np.inf)
    return int((d2 < radius * radius).sum() // 2)


@pytest.mark.parametrize("d", range(1, 9))
def test_every_dimension_exact_and_in_box(d):
    radius = [0.02, 0.05, 0.12, 0.2, 0.3, 0.4, 0.5, 0.6][d - 1]
    lo, hi = [-1.0] * d, [0.5] * d
    points = b.PoissonDisk(lo, hi, radius).generate(seed=d)
    assert points.shape[1] == d and points.dtype == np.float64
    assert len(points) > 20
    assert np.all(points >= -1.0) and np.all(points < 0.5)
    assert pairs_closer(points, radius) == 0


def test_arrays_are_not_copied():
    points = b.PoissonDisk([0, 0], [1, 1], 0.05).generate(seed=1)
    assert points.flags["C_CONTIGUOUS"]
    # A view of the 1-D array that owns the Rust buffer (no NumPy copy).
    assert points.base is not None and not points.flags["OWNDATA"]
    assert not points.base.flags["OWNDATA"]
    assert type(points.base.base).__name__ == "PySliceContainer"


def test_seed_reproducible_and_u64():
    s = b.PoissonDisk([0, 0], [1, 1], 0.05)
    assert np.array_equal(s.generate(seed=7), s.generate(seed=7))
    assert not np.array_equal(s.generate(seed=7), s.generate(seed=8))
    assert len(s.generate(seed=2**64 - 1)) > 0
    for bad in (-1, 2**64):
        with pytest.raises(ValueError, match="seed"):
            s.generate(seed=bad)


def test_stream_take_collect_iterate():
    s = b.PoissonDisk([0, 0], [1, 1], 0.05)
    whole = s.generate(seed=3)
    it = s.iter(seed=3)
    head = it.take(5)
    one = next(it)
    rest = it.collect()
    assert np.array_equal(np.concatenate([head, one[None], rest]), whole)
    assert it.take(3).shape == (0, 2)
    assert list(it) == [] and it.error is None


def test_periodic():
    s = b.PoissonDisk([0, 0], [1, 2], 0.1, periodic=[True, True])
    points = s.generate(seed=4)
    assert s.periodic == [True, True]
    assert pairs_closer(points, 0.1, periods=np.array([1.0, 2.0])) == 0
    assert b.PoissonDisk([0] * 3, [1] * 3, 0.2, periodic=True).periodic == [True] * 3


def test_about_points():
    s = b.PoissonDisk.about_points([0, 0], [2, 1], 5000)
    assert s.requested_count == 5000
    n = len(s.generate(seed=1))
    assert abs(n / 5000 - 1) < 0.03


def test_mask_array_and_fixed_points():
    s = b.PoissonDisk([0, 0], [1, 1], 0.05)
    mask = np.zeros((4, 4), dtype=bool)
    mask[:2, :] = True  # axis 0 is x: x < 0.5
    fixed = np.array([[0.25, 0.5], [0.35, 0.5]])
    points = s.iter_with(seed=5, region=mask, fixed=fixed).collect()
    assert len(points) > 50 and np.all(points[:, 0] < 0.5)
    assert pairs_closer(np.concatenate([fixed, points]), 0.05) == 0


def test_mask_callable():
    s = b.PoissonDisk([0, 0], [1, 1], 0.05)

    def disc(p):
        return ((p - 0.5) ** 2).sum(axis=1) < 0.16

    points = s.iter_with(seed=5, region=disc).collect()
    assert len(points) > 100 and disc(points).all()


def test_callback_error_propagates():
    s = b.PoissonDisk([0, 0], [1, 1], 0.05)

    def boom(p):
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError, match="boom"):
        s.iter_with(seed=1, region=boom).collect()
    with pytest.raises(RuntimeError, match="boom"):
        s.iter_varying(1, 0.02, boom).collect()


def test_varying_radius_array_and_callable():
    s = b.PoissonDisk([0, 0], [1, 1], 0.08)

    def field(p):
        return 0.02 + 0.06 * p[:, 0]

    for f in (field, np.repeat(np.linspace(0.02, 0.08, 64)[:, None], 64, axis=1)):
        points = s.iter_varying(3, 0.02, f).collect()
        r = np.clip(field(points), 0.02, 0.08) if callable(f) else None
        assert len(points) > 200
        left = (points[:, 0] < 0.5).sum()
        assert left > 2 * (len(points) - left)
        if r is not None:
            diff = points[:, None, :] - points[None, :, :]
            d2 = (diff**2).sum(axis=2)
            need = np.maximum(r[:, None], r[None, :]) ** 2
            np.fill_diagonal(d2, np.inf)
            assert np.all(d2 >= need)


@pytest.mark.skipif(
    not hasattr(b.PoissonDisk, "generate_parallel"),
    reason="built without the bindings crate's `parallel` feature",
)
def test_generate_parallel():
    s = b.PoissonDisk([0, 0], [2, 1], 0.02)
    points = s.generate_parallel(seed=5, threads=2)
    assert abs(len(points) / len(s.generate(seed=5)) - 1) < 0.03
    with pytest.raises(ValueError):
        s.generate_parallel(seed=5, threads=0)


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: b.PoissonDisk([0, 0], [1, 1], -1.0), "radius"),
        (lambda: b.PoissonDisk([0, 0], [1, 1], float("nan")), "radius"),
        (lambda: b.PoissonDisk([0, 0], [0, 1], 0.1), "empty on axis 0"),
        (lambda: b.PoissonDisk([0, float("inf")], [1, 1], 0.1), "finite"),
        (lambda: b.PoissonDisk([0, 0], [1, 1, 1], 0.1), "same length"),
        (lambda: b.PoissonDisk([0] * 9, [1] * 9, 0.5), "dimension"),
        (lambda: b.PoissonDisk([], [], 0.5), "dimension"),
        (lambda: b.PoissonDisk([0, 0], [1, 1], 0.1, attempts=0), "attempts"),
        (lambda: b.PoissonDisk([0, 0], [1, 1], 0.1, candidates="x"), "candidates"),
        (lambda: b.PoissonDisk([0, 0], [1, 1], 1e-13), r"2\^40"),
        (lambda: b.PoissonDisk.about_points([0, 0], [1, 1], 0), "count"),
        (lambda: b.Tiled(0, 4, radius=1.0), "width"),
        (lambda: b.Tiled(4, 4), "radius"),
        (lambda: b.PoissonPixelSampler(0, 1), "samples"),
        (
            lambda: b.PoissonDisk([0, 0], [1, 1], 0.1).iter_with(
                1, fixed=[[0.5, 0.5], [0.5, 0.52]]
            ),
            "pre-placed point 1",
        ),
    ],
)
def test_bad_input_is_a_value_error(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_memory_budget_error():
    s = b.PoissonDisk([0, 0], [1, 1], 0.001, max_grid_bytes=200_000, candidates="annulus")
    with pytest.raises(ValueError):
        s.generate(seed=1)


def test_ctrl_c_stops_a_long_run():
    s = b.PoissonDisk([0, 0], [2000, 2000], 0.5)
    # Python's SIGINT handler, even in a process started in the
    # background (which ignores SIGINT, so interrupt_main does nothing).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.05, _thread.interrupt_main)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            s.generate(seed=1)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


def test_sampling_runs_without_the_gil():
    """Two threads sampling at once both finish, and a Python thread keeps
    running meanwhile."""
    s = b.PoissonDisk([0, 0], [300, 300], 0.5)
    results = []
    threads = [
        threading.Thread(target=lambda i=i: results.append(len(s.generate(seed=i))))
        for i in range(2)
    ]
    for t in threads:
        t.start()
    ticks = 0
    while any(t.is_alive() for t in threads):
        ticks += 1
    for t in threads:
        t.join()
    assert len(results) == 2 and ticks > 1000


def test_tiled_pixels():
    t = b.Tiled(16, 8, per_pixel=4.0)
    pixels = t.pixels(seed=3)
    x, y, first = next(pixels)
    assert (x, y) == (0, 0)
    assert np.all((first >= 0) & (first < 1))
    counts, points = pixels.take(10_000)
    assert len(counts) == 16 * 8 - 1 and counts.sum() == len(points)
    assert abs((counts.sum() + len(first)) / 128 - 4) < 0.5
    exact = b.Tiled(8, 6, exact=3).pixels(seed=1)
    counts, _ = exact.take(48)
    assert np.all(counts == 3)


def test_camera_samples():
    s = b.PoissonPixelSampler(16, 7, resolution=(64, 64))
    s.start_pixel_sample((3, 5), 9)
    film, time, lens = s.camera_sample()
    assert 0 <= time < 1 and all(0 <= v < 1 for v in film + lens)
    films, times, lenses = s.camera_samples((3, 5))
    assert films.shape == (16, 2) and times.shape == (16,) and lenses.shape == (16, 2)
    assert tuple(films[9]) == film
    with pytest.raises(ValueError):
        s.start_pixel_sample((64, 0), 0)
    with pytest.raises(ValueError):
        s.start_pixel_sample((0, 0), 16)
    stream = b.CameraPixels(b.Tiled(8, 6, exact=4), 7, extra_dims=2)
    x, y, film, time, lens, extra = next(stream)
    assert (x, y) == (0, 0)
    assert film.shape == (4, 2) and time.shape == (4,) and extra.shape == (4, 2)
    assert sum(1 for _ in stream) == 47
