"""A drop-in for ``scipy.stats.qmc.PoissonDisk``, on the Rust sampler.

``from bridson_rs.qmc import PoissonDisk`` in place of
``from scipy.stats.qmc import PoissonDisk``: the same constructor
(``d``, ``radius``, ``hypersphere``, ``ncandidates``, ``optimization``,
``rng``/``seed``, ``l_bounds``, ``u_bounds``), the same methods (``random``,
``fill_space``, ``reset``, ``integers``, ``fast_forward``) and the same
``ValueError`` messages for bad bounds and options. It subclasses
``scipy.stats.qmc.QMCEngine``, so it needs SciPy (the native API in
``bridson_rs`` does not).

What differs, on purpose:

- No two points are ever closer than ``radius``, in every dimension.
  SciPy checks only the grid cells within two cells (of side
  ``radius / sqrt(d)``) of a candidate, so from 5-D up it accepts pairs
  closer than ``radius``; and it compares with its grid's points rounded
  to float32, so it accepts pairs a hair closer in any dimension.
- Every point lies in ``l_bounds < x < u_bounds``.
- ``d`` is 0 (empty samples) or 1 to 8; a larger ``d`` is a ``ValueError``.
- A ``radius`` the sampler cannot use (not finite, ``<= 0``, outside
  ``1e-150 ..= 1e150``, or a box wider than 2**40 radii) and an
  ``ncandidates`` outside ``1 ..= 65536`` are a ``ValueError`` with the
  crate's message.
- The points themselves differ from SciPy's for the same ``rng``: the first
  call to ``random`` (or ``fill_space``) draws one 64-bit seed from the
  engine's Generator, which consumes its state, and the Rust sampler runs
  from that seed. The same ``rng`` gives the same points, and ``reset()``
  gives them again.
- Once the space is full, ``random`` returns empty samples (SciPy starts a
  new, unchecked point).

As in SciPy, ``random(n)`` returns the next ``n`` points of one growing
set (fewer when the space is full), so a short sample is a compact blob
around the first point, and ``fill_space()`` returns all the remaining
points. The optimizers (``optimization="random-cd"`` or ``"lloyd"``)
move the points after sampling: their output no longer keeps the minimum
distance.
"""

from __future__ import annotations

import numpy as np
from scipy.stats.qmc import QMCEngine

from . import _native

try:  # SciPy's own handling of the old ``seed=`` keyword (SPEC 7).
    from scipy._lib._util import _transition_to_rng
except ImportError:  # pragma: no cover - a SciPy without it
    import functools

    def _transition_to_rng(old_name, **_kwargs):
        def decorator(fun):
            @functools.wraps(fun)
            def wrapper(*args, **kwargs):
                if old_name in kwargs:
                    if "rng" in kwargs:
                        raise TypeError(
                            f"{fun.__name__}() got multiple values for "
                            f"argument now known as `rng`"
                        )
                    kwargs["rng"] = kwargs.pop(old_name)
                return fun(*args, **kwargs)

            return wrapper

        return decorator


__all__ = ["PoissonDisk"]


def _validate_bounds(l_bounds, u_bounds, d):
    """SciPy's bounds check, with its messages."""
    try:
        lower = np.broadcast_to(l_bounds, d)
        upper = np.broadcast_to(u_bounds, d)
    except ValueError as exc:
        msg = (
            "'l_bounds' and 'u_bounds' must be broadcastable and respect"
            " the sample dimension"
        )
        raise ValueError(msg) from exc

    if not np.all(lower < upper):
        raise ValueError("Bounds are not consistent 'l_bounds' < 'u_bounds'")

    return lower, upper


def _draw_seed(rng) -> int:
    """One 64-bit seed from a NumPy Generator (or RandomState), consuming
    its state."""
    if hasattr(rng, "integers"):
        return int(rng.integers(0, 2**64, dtype=np.uint64))
    return int(rng.randint(0, 2**64, dtype=np.uint64))


class PoissonDisk(QMCEngine):
    """Poisson disk sampling, exact in every dimension: a drop-in for
    ``scipy.stats.qmc.PoissonDisk``.

    Parameters
    ----------
    d : int
        Dimension of the parameter space (0, or 1 to 8).
    radius : float
        Minimal distance to keep between points, in the units of the
        bounds. Default 0.05.
    hypersphere : {"volume", "surface"}, optional
        Where candidates are drawn around a point: ``"volume"`` in the
        annulus ``radius .. 2 radius`` (Bridson's algorithm), ``"surface"``
        on the sphere of radius ``radius`` (denser packing). Default
        ``"volume"``.
    ncandidates : int
        Candidates drawn around each point before it retires (Bridson's
        ``k``). Default 30.
    optimization : {None, "random-cd", "lloyd"}, optional
        A post-processing step from SciPy. It moves the points, so the
        minimum distance no longer holds after it. Default None.
    rng : `numpy.random.Generator`, optional
        Source of the seed, as in SciPy (``seed=`` is accepted too).
    l_bounds, u_bounds : array_like, optional
        Bounds of the box, default the unit hypercube.

    Notes
    -----
    ``random(n)`` gives the next ``n`` points of one growing set, in
    generation order; ``fill_space()`` the rest of it. See the module
    docstring for what differs from SciPy.
    """

    @_transition_to_rng("seed", replace_doc=False)
    def __init__(
        self,
        d,
        *,
        radius=0.05,
        hypersphere="volume",
        ncandidates=30,
        optimization=None,
        rng=None,
        l_bounds=None,
        u_bounds=None,
    ) -> None:
        # Used by `scipy.integrate.qmc_quad`.
        self._init_quad = {
            "d": d,
            "radius": radius,
            "hypersphere": hypersphere,
            "ncandidates": ncandidates,
            "optimization": optimization,
        }
        super()._initialize(d=d, optimization=optimization, rng=rng)

        # The same dict as SciPy's, so that the message lists the names
        # in the same order.
        hypersphere_sample = {"volume": "annulus", "surface": "sphere"}
        try:
            candidates = hypersphere_sample[hypersphere]
        except KeyError as exc:
            message = (
                f"{hypersphere!r} is not a valid hypersphere sampling"
                f" method. It must be one of {set(hypersphere_sample)!r}"
            )
            raise ValueError(message) from exc
        self.hypersphere = hypersphere

        self.radius_factor = 2 if hypersphere == "volume" else 1.001
        self.radius = radius
        self.radius_squared = self.radius**2
        self.ncandidates = ncandidates

        if u_bounds is None:
            u_bounds = np.ones(d)
        if l_bounds is None:
            l_bounds = np.zeros(d)
        self.l_bounds, self.u_bounds = _validate_bounds(
            l_bounds=l_bounds, u_bounds=u_bounds, d=int(d)
        )

        self._sampler = None
        if self.d > 0:
            self._sampler = _native.PoissonDisk(
                [float(x) for x in self.l_bounds],
                [float(x) for x in self.u_bounds],
                float(radius),
                attempts=int(ncandidates),
                candidates=candidates,
            )
        self._points = None

    def _random(self, n=1, *, workers=1) -> np.ndarray:
        """The next ``n`` points of the set (fewer once it is full)."""
        full = n == np.inf
        if self.d == 0 or self._sampler is None:
            return np.empty((0 if full else n, self.d))
        if n == 0:
            return np.empty((0, self.d))
        if self._points is None:
            self._points = self._sampler.iter(_draw_seed(self.rng))
        sample = self._points.collect() if full else self._points.take(int(n))
        # The crate's box is half-open, lo <= x < hi; SciPy's tests ask for
        # lo < x. A coordinate exactly on lo (a uniform draw of exactly 0)
        # is all but impossible, but drop it if it comes.
        inside = np.all(sample > self.l_bounds, axis=1)
        if not inside.all():
            sample = sample[inside]
        return sample

    def fill_space(self) -> np.ndarray:
        """Draw points until the space is full: every remaining point of
        the set, as an ``(n, d)`` array."""
        return self.random(np.inf)

    def reset(self) -> "PoissonDisk":
        """Reset the engine to its base state: the next ``random`` call
        draws the same seed again, so gives the same points."""
        super().reset()
        self._points = None
        return self
