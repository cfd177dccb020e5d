"""Combines runs of the convergence study (``examples/convergence.rs``), one
per ``--seed``, into one compact record and a table of MSE slopes.

    for s in 1 2 3 4 5 6 7 8; do
        cargo run --release --example convergence -- --seed $s \\
            --samplers net,zsobol,pmj02bn,sobol-owen,poisson-pixel --json target/conv-$s.json
    done
    python3 python/bench/convergence_seeds.py target/conv-*.json --out docs/records/convergence-nets.json

Stdlib only. For each (integrand, sampler) it prints the slope of ln MSE on
ln N over N >= 16 (the study's own fit) for the MSE pooled over the seeds
(each seed is 1000 fresh integrands and pixels), and the mean and standard
error of the per-seed slopes; also the pooled MSE at N = 16 and 64. The
record keeps, per seed, sampler and integrand, the N grid and the MSEs.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
from collections import defaultdict


def slope(points: list[tuple[int, float]], start: int = 16) -> float:
    used = [(math.log(n), math.log(m)) for n, m in points if n >= start and m > 0]
    mx = sum(p[0] for p in used) / len(used)
    my = sum(p[1] for p in used) / len(used)
    sxx = sum((p[0] - mx) ** 2 for p in used)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in used)
    return sxy / sxx


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="--json files of the study, one per seed")
    parser.add_argument("--out", help="write the combined record here")
    parser.add_argument("--seeds", help="the seeds of the runs, in order (default 1, 2, ...)")
    parser.add_argument("--command", default="", help="the command, for the record")
    args = parser.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")] if args.seeds else list(range(1, len(args.runs) + 1))
    # curves[(integrand, sampler)][seed] = [(n, mse), ...]
    curves: dict = defaultdict(dict)
    trials = None
    for seed, path in zip(seeds, args.runs):
        with open(path) as f:
            for row in json.load(f)["results"]:
                curves[(row["integrand"], row["sampler"])].setdefault(seed, []).append((row["n"], row["mse"]))
                trials = row["trials"]
    print(f"{len(seeds)} seeds x {trials} trials")
    print("| integrand | sampler | MSE N=16 | MSE N=64 | slope pooled | slope per seed (mean ± se) |")
    print("|---|---|---:|---:|---:|---:|")
    for (integrand, sampler), by_seed in curves.items():
        grid = [n for n, _ in next(iter(by_seed.values()))]
        pooled = [(n, statistics.fmean(dict(c)[n] for c in by_seed.values())) for n in grid]
        per_seed = [slope(c) for c in by_seed.values()]
        se = statistics.stdev(per_seed) / math.sqrt(len(per_seed)) if len(per_seed) > 1 else float("nan")
        at = dict(pooled)
        print(
            f"| {integrand} | {sampler} | {at.get(16, float('nan')):.3e} | {at.get(64, float('nan')):.3e} "
            f"| {slope(pooled):.3f} | {statistics.fmean(per_seed):.3f} ± {se:.3f} |"
        )
    if args.out:
        record = {
            "command": args.command,
            "trials_per_seed": trials,
            "seeds": seeds,
            "curves": [
                {
                    "integrand": integrand,
                    "sampler": sampler,
                    "seed": seed,
                    "n": [n for n, _ in pts],
                    "mse": [float(f"{m:.6e}") for _, m in pts],
                }
                for (integrand, sampler), by_seed in curves.items()
                for seed, pts in by_seed.items()
            ],
        }
        with open(args.out, "w") as f:
            json.dump(record, f, separators=(",", ":"))
            f.write("\n")


if __name__ == "__main__":
    main()
