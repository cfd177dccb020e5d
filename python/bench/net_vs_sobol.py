"""Per-pixel film MSE of bridson's camera samplers against SciPy's scrambled
Sobol' of the same count (issue 51): the check that a pixel's film offsets
integrate as well as a scrambled (0,m,2)-net.

    python python/bench/net_vs_sobol.py                      # the full study
    python python/bench/net_vs_sobol.py --quick              # a smoke run
    python python/bench/net_vs_sobol.py --csv net16.csv      # the CLI's samples
    python python/bench/net_vs_sobol.py --diagnostics        # why, where it fails

Every family draws random integrands on the unit pixel square, each with an
exact integral:

- ``step-axis``: ``x < e`` or ``y < e``, the axis and ``e`` uniform;
- ``step-rotated``: a half-plane whose edge passes through a uniform point
  at a uniform angle (exact area by clipping the square);
- ``disk``: a disk of uniform centre in the square and radius 0.05..0.45,
  clipped to the square (exact area in closed form);
- ``bump``: ``exp(-|p - c|^2 / 2 s^2)``, centre uniform, ``s`` log-uniform
  in 0.05..0.5 (exact by erf; smooth, not periodic).

The diagnostics (``--diagnostics``) add ``linear`` (``a x + b y``, ``a``
and ``b`` normal), whose error isolates the first-order term;
``bump-torus``, the bump on the torus (periodic: no boundary term); and
``bump-wide``, ``s`` log-uniform in 0.25..1 (a smooth shading gradient
across the pixel, nearly linear).

For each family the same instances serve every sampler. The error of one
(instance, randomisation) is ``mean f(film) - exact``; a sampler's
randomisations are its pixels (``--pixels`` of them: bridson's samplers are
a pure function of (seed, pixel, index), so distinct pixels are
independent draws) and SciPy's are ``Sobol(d=2, scramble=True)`` engines,
one per seed. Each instance gets its own ``--per-instance`` randomisations
of every sampler, so instances are independent. The MSE averages over
instances and randomisations; the ratio ``sampler / sobol`` is a ratio of
sums over the same instances, and its standard error comes from the paired
per-instance MSEs (delta method).

SciPy's ``scramble=True`` is Matousek's linear matrix scrambling with a
digital shift, whose variance equals that of Owen's nested uniform
scrambling (Owen 2003), so on smooth integrands it converges as O(n^-3).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.special import erf
from scipy.stats import qmc

# --- integrands --------------------------------------------------------


@dataclass
class Family:
    """Instances of one integrand family: ``value(points)`` takes a
    ``(K, ..., 2)`` array and returns the ``(K, ...)`` values, row ``k``
    of instance ``k``; ``exact`` is ``(K,)``; ``params`` keeps the draws."""

    name: str
    value: Callable[[np.ndarray], np.ndarray]
    exact: np.ndarray
    params: dict


def clip_half_plane(normal: np.ndarray, offset: float) -> float:
    """Area of ``{p in [0,1]^2 : normal . p < offset}`` (Sutherland-Hodgman
    on the square, then the shoelace formula)."""
    square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
    out = []
    for i, p in enumerate(square):
        q = square[(i + 1) % 4]
        dp = normal[0] * p[0] + normal[1] * p[1] - offset
        dq = normal[0] * q[0] + normal[1] * q[1] - offset
        if dp < 0:
            out.append(p)
        if (dp < 0) != (dq < 0):
            t = dp / (dp - dq)
            out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
    if len(out) < 3:
        return 0.0
    xs = np.array([p[0] for p in out])
    ys = np.array([p[1] for p in out])
    return 0.5 * abs(np.dot(xs, np.roll(ys, -1)) - np.dot(ys, np.roll(xs, -1)))


def disk_in_square(cx: float, cy: float, r: float) -> float:
    """Exact area of the disk ``|p - c| < r`` inside ``[0,1]^2``: the
    integral over x of the clipped chord, piece by piece between the
    points where the chord meets ``y = 0`` or ``y = 1``, in closed form."""

    def half_chord_integral(a: float, b: float) -> float:
        # Integral of sqrt(r^2 - (x - cx)^2) from a to b.
        def prim(x: float) -> float:
            t = np.clip((x - cx) / r, -1.0, 1.0)
            return 0.5 * r * r * (t * np.sqrt(1.0 - t * t) + np.arcsin(t))

        return prim(b) - prim(a)

    lo, hi = max(0.0, cx - r), min(1.0, cx + r)
    if lo >= hi:
        return 0.0
    cuts = {lo, hi}
    for edge in (0.0, 1.0):
        d = edge - cy
        if abs(d) < r:
            w = np.sqrt(r * r - d * d)
            cuts.update(x for x in (cx - w, cx + w) if lo < x < hi)
    cuts = sorted(cuts)
    area = 0.0
    for a, b in zip(cuts[:-1], cuts[1:]):
        mid = 0.5 * (a + b)
        h = np.sqrt(max(r * r - (mid - cx) ** 2, 0.0))
        top_clipped = cy + h > 1.0
        bottom_clipped = cy - h < 0.0
        top = (1.0 * (b - a)) if top_clipped else (cy * (b - a) + half_chord_integral(a, b))
        bottom = 0.0 if bottom_clipped else (cy * (b - a) - half_chord_integral(a, b))
        area += max(top - bottom, 0.0)
    return area


def gauss_1d(c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Integral over [0, 1] of exp(-(x - c)^2 / 2 s^2)."""
    k = s * np.sqrt(2.0)
    return s * np.sqrt(np.pi / 2.0) * (erf((1.0 - c) / k) + erf(c / k))


def gauss_torus_1d(c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """The same of the torus distance, |x - c| taken mod 1 (at most 1/2):
    over a full period it is the integral over [-1/2, 1/2]."""
    k = s * np.sqrt(2.0)
    return s * np.sqrt(2.0 * np.pi) * erf(0.5 / k)


def make_family(name: str, count: int, rng: np.random.Generator) -> Family:
    """``count`` instances of family ``name``."""
    if name == "step-axis":
        axis = rng.integers(0, 2, count)
        edge = rng.random(count)

        def value(p, axis=axis, edge=edge):
            shape = (-1,) + (1,) * (p.ndim - 2)
            x, y = p[..., 0], p[..., 1]
            coord = np.where(axis.reshape(shape) == 1, y, x)
            return (coord < edge.reshape(shape)).astype(float)

        return Family(name, value, edge.copy(), {"axis": axis, "edge": edge})
    if name == "step-rotated":
        theta = rng.uniform(0.0, 2.0 * np.pi, count)
        through = rng.random((count, 2))
        normal = np.stack([np.cos(theta), np.sin(theta)], axis=1)
        offset = (normal * through).sum(axis=1)
        exact = np.array([clip_half_plane(n, o) for n, o in zip(normal, offset)])

        def value(p, normal=normal, offset=offset):
            shape = (-1,) + (1,) * (p.ndim - 2)
            d = normal[:, 0].reshape(shape) * p[..., 0] + normal[:, 1].reshape(shape) * p[..., 1]
            return (d < offset.reshape(shape)).astype(float)

        return Family(name, value, exact, {"theta": theta, "through": through})
    if name == "disk":
        centre = rng.random((count, 2))
        radius = rng.uniform(0.05, 0.45, count)
        exact = np.array([disk_in_square(c[0], c[1], r) for c, r in zip(centre, radius)])

        def value(p, centre=centre, radius=radius):
            shape = (-1,) + (1,) * (p.ndim - 2)
            dx = p[..., 0] - centre[:, 0].reshape(shape)
            dy = p[..., 1] - centre[:, 1].reshape(shape)
            return (dx * dx + dy * dy < (radius * radius).reshape(shape)).astype(float)

        return Family(name, value, exact, {"centre": centre, "radius": radius})
    if name in ("bump", "bump-torus", "bump-wide"):
        centre = rng.random((count, 2))
        low, high = (0.25, 1.0) if name == "bump-wide" else (0.05, 0.5)
        width = np.exp(rng.uniform(np.log(low), np.log(high), count))
        torus = name == "bump-torus"
        one_d = gauss_torus_1d if torus else gauss_1d
        exact = one_d(centre[:, 0], width) * one_d(centre[:, 1], width)

        def value(p, centre=centre, width=width, torus=torus):
            shape = (-1,) + (1,) * (p.ndim - 2)
            dx = np.abs(p[..., 0] - centre[:, 0].reshape(shape))
            dy = np.abs(p[..., 1] - centre[:, 1].reshape(shape))
            if torus:
                dx, dy = np.minimum(dx, 1.0 - dx), np.minimum(dy, 1.0 - dy)
            return np.exp(-(dx * dx + dy * dy) / (2.0 * (width * width).reshape(shape)))

        return Family(name, value, exact, {"centre": centre, "width": width})
    if name == "linear":
        coef = rng.normal(size=(count, 2))
        exact = 0.5 * coef.sum(axis=1)

        def value(p, coef=coef):
            shape = (-1,) + (1,) * (p.ndim - 2)
            return coef[:, 0].reshape(shape) * p[..., 0] + coef[:, 1].reshape(shape) * p[..., 1]

        return Family(name, value, exact, {"coef": coef})
    raise ValueError(f"unknown family {name!r}")


FAMILIES = ["step-axis", "step-rotated", "disk", "bump"]
DIAGNOSTICS = ["linear", "bump-torus", "bump-wide"]

# --- samples -------------------------------------------------------------


def pixel_films(sampler_class, spp: int, pixels: int, seed: int) -> np.ndarray:
    """``(pixels, spp, 2)`` film offsets of a bridson sampler (pixels of a
    256-wide raster, row by row)."""
    sampler = sampler_class(spp, seed)
    out = np.empty((pixels, spp, 2))
    for k in range(pixels):
        film, _, _ = sampler.camera_samples((k % 256, k // 256))
        out[k] = film
    return out


def sobol_films(spp: int, count: int, seed: int) -> np.ndarray:
    """``(count, spp, 2)``: the first ``spp`` points of ``count`` scrambled
    Sobol' engines, seeded from one generator."""
    rng = np.random.default_rng(seed)
    out = np.empty((count, spp, 2))
    for k in range(count):
        out[k] = qmc.Sobol(d=2, scramble=True, rng=rng).random(spp)
    return out


def csv_films(path: str) -> tuple[int, np.ndarray]:
    """The film offsets of ``points --pixels WxH --camera --spp N`` output:
    ``(N, (pixels, N, 2))``, offsets inside the pixel (the CSV has raster
    coordinates)."""
    data = np.loadtxt(path, delimiter=",", skiprows=1, usecols=(0, 1, 2, 3, 4))
    index = data[:, 2].astype(int)
    spp = int(index.max()) + 1
    if len(data) % spp or not np.array_equal(index, np.tile(np.arange(spp), len(data) // spp)):
        raise ValueError(f"{path}: not {spp} samples per pixel in order")
    film = data[:, 3:5] - data[:, 0:2]
    return spp, film.reshape(-1, spp, 2)


def rejitter(films: np.ndarray, common_bits: int, seed: int) -> np.ndarray:
    """A prototype of another randomisation of the net sampler's sets (not
    the library's): keep each point's cell of the ``spp x spp`` grid and
    the top ``common_bits`` bits of the sampler's in-cell offset (common to
    all points of a set), and draw the bits below independently for every
    point. ``common_bits = 0`` is Owen scrambling of every digit finer than
    the cell (each point uniform in its own cell); the net is kept (it
    depends on the cells only) and the spacing loses up to ``2^-bits``
    cells in each axis. Values stay uniform, so the estimate stays
    unbiased."""
    n = films.shape[1]
    cell = np.floor(films * n)
    offset = films * n - cell
    scale = 2.0**common_bits
    top = np.floor(offset * scale)
    fresh = np.random.default_rng(seed).random(films.shape)
    return (cell + (top + fresh) / scale) / n


def antithetic(films: np.ndarray, bit: int = 0) -> np.ndarray:
    """Another prototype (not the library's): keep the cells and the common
    in-cell offset ``u``, but reflect it, ``1 - u``, in every odd column
    (for x) and odd row (for y) of the ``spp x spp`` grid. Each column and
    row holds one point, so half the points take ``u`` and half ``1 - u``
    on each axis: the mean offset is exactly 1/2, and neighbouring columns
    cancel each other's first-order error. Offsets stay uniform and the
    net is kept; points of columns of different parity move by ``1 - 2u``
    cells against each other. ``bit = k`` reflects where bit ``k`` of the
    column (row) is set instead: blocks of ``2^k`` columns alternate."""
    n = films.shape[1]
    cell = np.floor(films * n)
    offset = films * n - cell
    odd = (cell.astype(np.int64) >> bit) % 2 == 1
    return (cell + np.where(odd, 1.0 - offset, offset)) / n


def median_rho(films: np.ndarray) -> float:
    """Median over sets of the toroidal minimum distance over that of the
    hexagonal packing of as many points, ``sqrt(2 / (sqrt(3) n))``."""
    n = films.shape[1]
    d = np.abs(films[:, :, None, :] - films[:, None, :, :])
    d = np.minimum(d, 1.0 - d)
    d2 = (d * d).sum(axis=-1)
    d2[:, np.arange(n), np.arange(n)] = np.inf
    return float(np.median(np.sqrt(d2.min(axis=(1, 2)))) / np.sqrt(2.0 / (np.sqrt(3.0) * n)))


def uniform_films(spp: int, count: int, seed: int) -> np.ndarray:
    """Plain Monte Carlo, for context."""
    return np.random.default_rng(seed).random((count, spp, 2))


# --- the measurement -------------------------------------------------------


def per_instance_mse(family: Family, films: np.ndarray) -> np.ndarray:
    """``(K,)``: each instance's squared error averaged over its own
    randomisations, ``films[k]`` (``(K, R, spp, 2)``)."""
    estimate = family.value(films).mean(axis=-1)  # (K, R)
    return ((estimate - family.exact[:, None]) ** 2).mean(axis=1)


def ratio(num: np.ndarray, den: np.ndarray) -> tuple[float, float]:
    """``sum(num) / sum(den)`` over paired per-instance values, and its
    standard error by the delta method."""
    r = num.sum() / den.sum()
    k = len(num)
    resid = num - r * den
    se = np.sqrt(resid.var(ddof=1) / k) / den.mean()
    return float(r), float(se)


def measure(
    spp: int,
    instances: int,
    per_instance: int,
    seed: int,
    samplers: dict,
    families: list[str],
    diagnostics: bool = False,
) -> list[dict]:
    """For each family and sampler, the MSE, SciPy's, and the ratio with
    its standard error. ``samplers`` maps a name to a function
    ``(spp, count, seed) -> (count, spp, 2)`` film offsets; instance ``k``
    of a family gets randomisations ``k R .. (k + 1) R - 1`` of every
    sampler (``R = per_instance``), so instances are independent."""
    count = instances * per_instance
    sobol = sobol_films(spp, count, seed)
    runs = [(name, make(spp, count, seed)) for name, make in samplers.items()]
    if diagnostics:
        nets = [films for name, films in runs if name == "net" or name.startswith("csv:")]
        for bits in (0, 1, 2) if nets else ():
            runs.append((f"net-rejitter{bits}", rejitter(nets[0], bits, seed)))
        if nets:
            runs.append(("net-antithetic", antithetic(nets[0])))
    rows = []
    shape = (instances, per_instance, spp, 2)
    for fam_index, fam_name in enumerate(families):
        family = make_family(fam_name, instances, np.random.default_rng([seed, fam_index]))
        base = per_instance_mse(family, sobol.reshape(shape))
        for name, films in runs:
            mse = per_instance_mse(family, films.reshape(shape))
            r, se = ratio(mse, base)
            rows.append(
                {
                    "family": fam_name,
                    "spp": spp,
                    "sampler": name,
                    "mse": float(mse.mean()),
                    "sobol_mse": float(base.mean()),
                    "ratio": r,
                    "se": se,
                    "rho": median_rho(films[:512]) if fam_index == 0 else None,
                }
            )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--spp", default="16,64", help="comma-separated counts")
    parser.add_argument("--instances", type=int, default=2000, help="integrands a family")
    parser.add_argument("--per-instance", type=int, default=4, help="randomisations (pixels, Sobol' seeds) an integrand")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--samplers", default="net,poisson", help="net, poisson, uniform")
    parser.add_argument("--csv", action="append", default=[], help="film offsets from the CLI, as sampler csv:PATH")
    parser.add_argument("--diagnostics", action="store_true", help="linear and torus-bump families, rejittered nets")
    parser.add_argument("--quick", action="store_true", help="400 instances, 2 randomisations each")
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    if args.quick:
        args.instances, args.per_instance = 400, 2

    import bridson_rs

    classes = {"poisson": bridson_rs.PoissonPixelSampler}
    if hasattr(bridson_rs, "NetPixelSampler"):
        classes["net"] = bridson_rs.NetPixelSampler
    families = FAMILIES + (DIAGNOSTICS if args.diagnostics else [])
    csvs: dict = {}
    for path in args.csv:
        spp, films = csv_films(path)
        csvs.setdefault(spp, {})[f"csv:{path}"] = films
    counts = sorted({int(s) for s in args.spp.split(",")} | set(csvs))
    print(
        f"{args.instances} integrands a family, {args.per_instance} randomisations each, seed {args.seed}"
    )
    print("| family | spp | sampler | MSE | sobol MSE | ratio ± se | median rho |")
    print("|---|---:|---|---:|---:|---:|---:|")
    rows = []
    for spp in counts:
        start = time.perf_counter()
        makers = {}
        for name in args.samplers.split(","):
            if name == "uniform":
                makers[name] = uniform_films
            elif name in classes:
                makers[name] = lambda n, c, s, cls=classes[name]: pixel_films(cls, n, c, s)
            else:
                print(f"(no sampler {name!r} in this bridson_rs)")
        for name, films in csvs.get(spp, {}).items():
            if len(films) < args.instances * args.per_instance:
                raise SystemExit(f"{name}: {len(films)} pixels, fewer than instances x per-instance")
            makers[name] = lambda n, c, s, f=films: f[:c]
        for row in measure(spp, args.instances, args.per_instance, args.seed, makers, families, args.diagnostics):
            rows.append(row)
            rho = "" if row["rho"] is None else f"{row['rho']:.3f}"
            print(
                f"| {row['family']} | {spp} | {row['sampler']} | {row['mse']:.3e} | {row['sobol_mse']:.3e} "
                f"| {row['ratio']:.3f} ± {row['se']:.3f} | {rho} |"
            )
        print(f"(spp {spp}: {time.perf_counter() - start:.1f} s; Sobol' median rho {median_rho(sobol_films(spp, 512, args.seed)):.3f})")
    if args.json:
        import json

        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
