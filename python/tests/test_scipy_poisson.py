"""SciPy's own PoissonDisk tests, run against the drop-in.

``TestPoisson`` in ``scipy/stats/tests/test_qmc.py`` (shipped in the SciPy
wheel) picks its engine from the class attribute ``qmce``: the subclass
below swaps ours in and inherits every test, SciPy's skips included.
"""

import numpy as np
import pytest

scipy_tests = pytest.importorskip("scipy.stats.tests.test_qmc")

from bridson_rs.qmc import PoissonDisk  # noqa: E402


class TestPoissonBridson(scipy_tests.TestPoisson):
    qmce = PoissonDisk

    def test_raises(self):
        # SciPy's version builds `qmc.PoissonDisk` by name; the same check
        # on ours.
        super().test_raises()
        message = r"'toto' is not a valid hypersphere sampling"
        with pytest.raises(ValueError, match=message):
            PoissonDisk(1, hypersphere="toto")


def test_swapped_in():
    """The inherited tests really build ours."""
    engine = TestPoissonBridson().engine(d=2, scramble=False)
    assert isinstance(engine, PoissonDisk)


def test_errors_match_scipy():
    """Bad bounds and options give SciPy's exception and message."""
    from scipy.stats import qmc

    cases = [
        dict(d=3, l_bounds=[3, 2, 1], u_bounds=[-1, -2, -1]),
        dict(d=3, l_bounds=[3, 2], u_bounds=[-1, -2]),
        dict(d=2, hypersphere="toto"),
        dict(d=2, optimization="toto"),
        dict(d=-1),
        dict(d=1.5),
    ]
    for kwargs in cases:
        with pytest.raises(ValueError) as theirs:
            qmc.PoissonDisk(**kwargs)
        with pytest.raises(ValueError) as ours:
            PoissonDisk(**kwargs)
        assert str(ours.value) == str(theirs.value), kwargs


def test_signature_matches_scipy():
    import inspect

    from scipy.stats import qmc

    theirs = inspect.signature(qmc.PoissonDisk.__init__)
    ours = inspect.signature(PoissonDisk.__init__)
    assert list(ours.parameters) == list(theirs.parameters)
    for name, p in theirs.parameters.items():
        assert ours.parameters[name].default == p.default, name
        assert ours.parameters[name].kind == p.kind, name
    for method in ["random", "fill_space", "reset", "integers", "fast_forward"]:
        assert callable(getattr(PoissonDisk, method))


@pytest.mark.parametrize("d", [1, 2, 3, 4, 5, 6, 7, 8])
def test_exact_in_every_dimension(d):
    """No pair closer than the radius (SciPy's own misses some from 5-D)."""
    from scipy.spatial import cKDTree

    radius = {1: 0.01, 2: 0.03, 3: 0.1, 4: 0.2, 5: 0.3, 6: 0.4, 7: 0.5, 8: 0.6}[d]
    sample = PoissonDisk(d, radius=radius, rng=np.random.default_rng(d)).fill_space()
    assert len(sample) > 10
    assert cKDTree(sample).query_pairs(radius * (1 - 1e-12)) == set()
    assert np.all(sample > 0) and np.all(sample < 1)


def test_reproducible_and_consumes_rng():
    rng = np.random.default_rng(5)
    a = PoissonDisk(2, radius=0.1, rng=rng).fill_space()
    b = PoissonDisk(2, radius=0.1, rng=rng).fill_space()
    assert not np.array_equal(a, b)
    c = PoissonDisk(2, radius=0.1, rng=np.random.default_rng(5)).fill_space()
    assert np.array_equal(a, c)


def test_random_then_fill_space_continue_one_set():
    engine = PoissonDisk(2, radius=0.05, seed=3)
    head = engine.random(10)
    rest = engine.fill_space()
    whole = np.concatenate([head, rest])
    engine.reset()
    assert np.array_equal(engine.fill_space(), whole)
    # Full: nothing more.
    assert engine.random(5).shape == (0, 2)


def test_too_many_dimensions_is_a_value_error():
    with pytest.raises(ValueError, match="dimension"):
        PoissonDisk(9, radius=0.5)


class TestPoissonBridsonExtra:
    """Two of SciPy's generic engine tests that its PoissonDisk skips
    ("not applicable") pass here exactly: `random(n)` takes the next `n`
    points of one seeded stream, so fast-forwarding and continuing give
    the same points as one long call."""

    engine = scipy_tests.TestPoisson.engine
    can_scramble = False
    qmce = PoissonDisk

    def test_fast_forward(self):
        scipy_tests.QMCEngineTests.test_fast_forward(self, scramble=False)

    def test_continuing(self):
        scipy_tests.QMCEngineTests.test_continuing(self, scramble=False)
