"""Issue 51's check on hidden integrands: the per-pixel film MSE of
``NetPixelSampler`` against SciPy's scrambled Sobol' of the same count, at
16 and 64 samples per pixel. The study with more integrands and its
diagnostics is ``python/bench/net_vs_sobol.py``; this is its small form,
a few seconds.

The bounds are the issue's (steps and disks at most 1.05x, smooth bumps at
most 2x), tested at two standard errors: a ratio passes when it is not
significantly above its bound. The issue's families are the study's
``step-axis``, ``step-rotated``, ``disk`` and ``bump`` (width 0.05..0.5);
``bump-wide`` (width 0.25..1, a smooth gradient across the pixel) is where
the sampler falls short, and that case is an ``xfail(strict=True)`` with
the reason: it turns into a failure the day the sampler meets the bound,
so that the mark is removed. (At 16 spp the study reads ``bump-wide``
2.2-2.4x, too close to 2 for this test's precision: left out.)
"""

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scipy")

import bridson_rs as b

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "bench"))
import net_vs_sobol as study  # noqa: E402

INSTANCES = 600
PER_INSTANCE = 2
BOUNDS = {"step-axis": 1.05, "step-rotated": 1.05, "disk": 1.05, "bump": 2.0, "bump-wide": 2.0}
CASES = [(f, n) for n in (16, 64) for f in BOUNDS if (f, n) != ("bump-wide", 16)]

# Measured by the study (docs/rendering.md, "Film error against scrambled
# Sobol'").
KNOWN_SHORT = {
    ("bump-wide", 64): "every point of a set sits at the same offset in its cell of the "
    "spp x spp grid, so the first-order error does not cancel: about n x Sobol' on "
    "a linear integrand, 5.7-6.0x on wide bumps at 64 spp",
}


def _rows(spp):
    samplers = {
        "net": lambda n, c, s: study.pixel_films(b.NetPixelSampler, n, c, s),
        "poisson": lambda n, c, s: study.pixel_films(b.PoissonPixelSampler, n, c, s),
    }
    rows = study.measure(spp, INSTANCES, PER_INSTANCE, 7, samplers, list(BOUNDS))
    return {(r["family"], r["sampler"]): r for r in rows}


_cache: dict = {}


def rows(spp):
    if spp not in _cache:
        _cache[spp] = _rows(spp)
    return _cache[spp]


def test_exact_integrals_match_a_fine_grid():
    g = (np.arange(500) + 0.5) / 500
    grid = np.stack(np.meshgrid(g, g), axis=-1).reshape(1, 1, -1, 2)
    for k, name in enumerate(study.FAMILIES + study.DIAGNOSTICS):
        family = study.make_family(name, 12, np.random.default_rng([3, k]))
        points = np.broadcast_to(grid, (12,) + grid.shape[1:])
        midpoint = family.value(points).mean(axis=-1)[:, 0]
        # The midpoint rule on 500 x 500 cells: an edge costs at most
        # about its length x the cell size, 2e-3 x 4.
        assert np.abs(midpoint - family.exact).max() < 5e-3, name


def test_net_films_are_nets():
    films = study.pixel_films(b.NetPixelSampler, 16, 8, 1)
    for film in films:
        for k in range(5):
            cells = (film[:, 0] * 2**k).astype(int) * 2 ** (4 - k) + (film[:, 1] * 2 ** (4 - k)).astype(int)
            assert len(set(cells)) == 16


@pytest.mark.parametrize("family,spp", CASES)
def test_net_against_scrambled_sobol(family, spp, request):
    if (family, spp) in KNOWN_SHORT:
        request.applymarker(pytest.mark.xfail(strict=True, reason=KNOWN_SHORT[(family, spp)]))
    row = rows(spp)[(family, "net")]
    assert row["ratio"] - 2 * row["se"] <= BOUNDS[family], row


@pytest.mark.parametrize("spp", [16, 64])
def test_net_beats_poisson_on_steps(spp):
    # Today's default sampler reads about 2x on steps; the nets must do
    # clearly better.
    for family in ("step-axis", "step-rotated"):
        net, poisson = rows(spp)[(family, "net")], rows(spp)[(family, "poisson")]
        assert net["ratio"] + 2 * net["se"] < poisson["ratio"] - 2 * poisson["se"], (net, poisson)
