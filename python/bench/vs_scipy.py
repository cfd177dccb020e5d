"""bridson_rs against scipy.stats.qmc.PoissonDisk: fill_space() in the unit
cube, points per second, the whole call including the constructor.

    python python/bench/vs_scipy.py            # the sizes of issue 52
    python python/bench/vs_scipy.py --quick    # smaller, for a smoke run

Needs bridson_rs (pip install ./python) and scipy. For each case it runs
SciPy's PoissonDisk once (about a minute in 2-D), then the drop-in
(bridson_rs.qmc.PoissonDisk, the same call) and the native API
(bridson_rs.PoissonDisk(...).generate) --repeat times, keeping the median;
same radius, same box, same ncandidates (30). It also counts, with a
KD-tree, the pairs closer than the radius in each set and the closest
pair: SciPy keeps its grid's points in float32, so it accepts pairs a
little closer than r (by about 1e-5 r at r = 0.00248), and it checks
only two grid cells of side r/sqrt(d) around a candidate, which from 5-D
up misses neighbours outright.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time

import numpy as np
import scipy
from scipy.spatial import cKDTree
from scipy.stats import qmc

import bridson_rs
from bridson_rs.qmc import PoissonDisk as DropIn

# (dimension, radius): about 100 k points in 2-D (issue 52), about 9 k in
# 3-D and 3.5 k in 5-D (SciPy takes some ten seconds on each).
CASES = [(2, 0.00248), (3, 0.04), (5, 0.18)]
QUICK = [(2, 0.01), (3, 0.08), (5, 0.25)]


def close_pairs(points: np.ndarray, radius: float) -> tuple[int, float]:
    """How many pairs lie strictly closer than `radius`, and the closest
    pair's distance over `radius`."""
    tree = cKDTree(points)
    count = len(tree.query_pairs(np.nextafter(radius, 0.0)))
    nearest, _ = tree.query(points, k=2)
    return count, float(nearest[:, 1].min()) / radius


def timed(make) -> tuple[float, np.ndarray]:
    start = time.perf_counter()
    points = make()
    return time.perf_counter() - start, points


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="smaller sets")
    parser.add_argument("--repeat", type=int, default=5, help="runs of ours (median)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    print(
        f"python {platform.python_version()}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}, {platform.machine()}, one thread\n"
    )
    header = (
        "| d | radius | points (scipy / ours) | scipy pts/s | drop-in pts/s | "
        "native pts/s | drop-in / scipy | pairs < r (scipy / ours) | "
        "closest pair / r (scipy / ours) |"
    )
    print(header)
    print("|" + "---|" * 9)
    for d, radius in QUICK if args.quick else CASES:

        def scipy_run():
            engine = qmc.PoissonDisk(d, radius=radius, rng=np.random.default_rng(args.seed))
            return engine.fill_space()

        def dropin_run():
            engine = DropIn(d, radius=radius, rng=np.random.default_rng(args.seed))
            return engine.fill_space()

        def native_run():
            return bridson_rs.PoissonDisk([0.0] * d, [1.0] * d, radius).generate(seed=args.seed)

        t_scipy, p_scipy = timed(scipy_run)
        runs = [timed(dropin_run) for _ in range(args.repeat)]
        t_drop, p_drop = statistics.median(t for t, _ in runs), runs[0][1]
        runs = [timed(native_run) for _ in range(args.repeat)]
        t_native, p_native = statistics.median(t for t, _ in runs), runs[0][1]
        rate_scipy = len(p_scipy) / t_scipy
        rate_drop = len(p_drop) / t_drop
        rate_native = len(p_native) / t_native
        pairs_scipy, near_scipy = close_pairs(p_scipy, radius)
        pairs_ours, near_ours = close_pairs(p_drop, radius)
        print(
            f"| {d} | {radius} | {len(p_scipy)} / {len(p_drop)} | {rate_scipy:,.0f} | "
            f"{rate_drop:,.0f} | {rate_native:,.0f} | {rate_drop / rate_scipy:,.0f}x | "
            f"{pairs_scipy} / {pairs_ours} | {near_scipy:.7f} / {near_ours:.7f} |",
            flush=True,
        )
        print(
            f"<!-- d={d}: scipy {t_scipy:.3f} s, drop-in {t_drop:.4f} s, "
            f"native {t_native:.4f} s (medians of {args.repeat}) -->",
            flush=True,
        )


if __name__ == "__main__":
    main()
