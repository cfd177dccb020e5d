"""A prototype for issue 51 (not the library's generator): can a (0,m,2)-net
keep its spacing when its in-cell offsets are antithetic?

``NetPixelSampler`` puts every point of a set at one common offset ``u``
inside its cell of the ``n x n`` grid; ``net_vs_sobol.py`` shows that this
costs it about ``n`` times the error of scrambled Sobol' on smooth, non-periodic
integrands, and that offset ``u`` in even columns (rows) and ``1 - u`` in
odd ones removes the first-order error, at a loss of spacing with today's
bank (median rho 0.624 at 16 spp). This anneals one net for the spacing
under that move: the score is the median, over a grid of ``(u_x, u_y)``,
of the toroidal minimum distance over the hexagonal packing's, plus a
tenth of its minimum. Moves are Owen flips (digit ``j`` of x or of y,
for the points whose top ``j`` digits of that axis share a prefix), which
keep the net property; it is checked anyway.

    python python/bench/net_antithetic_anneal.py --m 4 --steps 15000 --seed 1

Prints the annealed net's median and minimum rho under antithetic offsets
and its median under one common offset (today's sampler), and its rows.
Numpy only; about a minute for m = 4.
"""

from __future__ import annotations

import argparse

import numpy as np


def is_net(rows: np.ndarray, m: int) -> bool:
    """Point ``c`` is the cell ``(c, rows[c])``: a (0,m,2)-net when every
    elementary interval of ``k`` x digits and ``m - k`` y digits holds one."""
    n = 1 << m
    cols = np.arange(n)
    for k in range(m + 1):
        keys = (cols >> (m - k)) * (1 << (m - k)) + (rows >> k)
        if len(np.unique(keys)) != n:
            return False
    return True


def rho_grid(rows: np.ndarray, m: int, grid: int, antithetic: bool) -> np.ndarray:
    """rho of the set for each ``(u_x, u_y)`` of a ``grid x grid`` lattice of
    offsets."""
    n = 1 << m
    cols = np.arange(n)
    us = (np.arange(grid) + 0.5) / grid
    upper = np.triu_indices(n, 1)
    d_hex = np.sqrt(2.0 / (np.sqrt(3.0) * n))
    out = []
    for ux in us:
        for uy in us:
            ox = np.where(antithetic & (cols % 2 == 1), 1.0 - ux, ux)
            oy = np.where(antithetic & (rows % 2 == 1), 1.0 - uy, uy)
            x, y = (cols + ox) / n, (rows + oy) / n
            dx = np.abs(x[:, None] - x[None])
            dy = np.abs(y[:, None] - y[None])
            dx, dy = np.minimum(dx, 1.0 - dx), np.minimum(dy, 1.0 - dy)
            out.append(np.sqrt((dx * dx + dy * dy)[upper].min()) / d_hex)
    return np.array(out)


def anneal(m: int, steps: int, seed: int, grid: int = 6) -> np.ndarray:
    n = 1 << m
    rng = np.random.default_rng(seed)
    cols = np.arange(n)

    def score(rows):
        r = rho_grid(rows, m, grid, True)
        return np.median(r) + 0.1 * r.min()

    # Start from Hammersley's net: rows are the bit-reversed columns.
    rows = np.array([int(format(c, f"0{m}b")[::-1], 2) for c in range(n)])
    current = score(rows)
    best = (current, rows.copy())
    for step in range(steps):
        temperature = 0.05 * (1.0 - step / steps) + 1e-4
        j = int(rng.integers(0, m))
        prefix = int(rng.integers(0, 1 << j))
        if rng.random() < 0.5:
            new = rows.copy()
            new[(rows >> (m - j)) == prefix] ^= 1 << (m - 1 - j)
        else:
            moved = cols.copy()
            moved[(cols >> (m - j)) == prefix] ^= 1 << (m - 1 - j)
            new = np.empty_like(rows)
            new[moved] = rows
        if not is_net(new, m):
            continue
        s = score(new)
        if s > current or rng.random() < np.exp((s - current) / temperature):
            rows, current = new, s
            if s > best[0]:
                best = (s, rows.copy())
    return best[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--m", type=int, default=4, help="the net has 2^m points")
    parser.add_argument("--steps", type=int, default=15000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rows = anneal(args.m, args.steps, args.seed)
    assert is_net(rows, args.m)
    anti = rho_grid(rows, args.m, 6, True)
    common = rho_grid(rows, args.m, 6, False)
    print(
        f"n = {1 << args.m}: antithetic offsets median rho {np.median(anti):.3f}, min {anti.min():.3f}; "
        f"one common offset median {np.median(common):.3f}; rows {rows.tolist()}"
    )


if __name__ == "__main__":
    main()
