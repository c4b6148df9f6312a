"""Oracles of the 2D IFS kernels (:mod:`growsim.kernels.ifs2d`): plain Python and NumPy.

- :func:`all_maps`: the deterministic renderer: every composition of the maps to depth
  ``k`` applied to a start point (``N^k`` points, no randomness), the attractor the chaos
  game samples;
- :func:`chaos_game`: the chaos game one point at a time with Python integers for the
  SplitMix64 draws (so it replays the kernel's stream bit for bit);
- :func:`points_raster`: ``np.add.at`` on the pixel indices.
"""

from __future__ import annotations

import numpy as np

MASK = (1 << 64) - 1


def splitmix64(state: int) -> tuple[int, int]:
    """One SplitMix64 step on Python ints: ``(new_state, output)``.

    Examples
    --------
    >>> hex(splitmix64(0)[1])
    '0xe220a8397b1dcdaf'
    """
    state = (state + 0x9E3779B97F4A7C15) & MASK
    z = state
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
    return state, z ^ (z >> 31)


def cumulative(p) -> np.ndarray:
    """Cumulative normalised probabilities, the last exactly 1 (all zero: equal)."""
    p = np.asarray(p, dtype=float)
    if p.sum() == 0:
        p = np.ones_like(p)
    c = np.cumsum(p / p.sum())
    c[-1] = 1.0
    return c


def chaos_game(maps, p, n, *, seed=0, burn_in=100, start=(0.0, 0.0)) -> np.ndarray:
    """``(n, 2)`` chaos-game points, one at a time (see the module docstring).

    Examples
    --------
    >>> chaos_game([[0.5, 0, 0, 0.5, 0, 0]], [1.0], 2, burn_in=0, start=(1.0, 2.0)).tolist()
    [[0.5, 1.0], [0.25, 0.5]]
    """
    maps = [[float(v) for v in row] for row in np.asarray(maps, dtype=float)]
    cum = cumulative(p)
    s = int(seed) % (1 << 64)
    x, y = (float(v) for v in start)
    out = []
    for t in range(burn_in + n):
        s, z = splitmix64(s)
        u = (z >> 11) * (1.0 / 9007199254740992.0)
        k = 0
        while k < len(maps) - 1 and u >= cum[k]:
            k += 1
        a, b, c, d, e, f = maps[k]
        x, y = a * x + b * y + e, c * x + d * y + f
        if t >= burn_in:
            out.append((x, y))
    return np.array(out, dtype=float).reshape(-1, 2)


def all_maps(maps, depth: int, start=(0.0, 0.0)) -> np.ndarray:
    """``(N^depth, 2)``: every composition ``W_j1 ... W_jdepth`` of the maps applied to
    ``start`` (the deterministic IFS renderer).

    Examples
    --------
    >>> all_maps([[0.5, 0, 0, 0.5, 0, 0], [0.5, 0, 0, 0.5, 1, 0]], 2, (0.0, 0.0)).tolist()
    [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [1.5, 0.0]]
    """
    maps = np.asarray(maps, dtype=float).reshape(-1, 6)
    pts = np.array([start], dtype=float)
    for _ in range(depth):
        pts = np.concatenate(
            [np.column_stack([m[0] * pts[:, 0] + m[1] * pts[:, 1] + m[4],
                              m[2] * pts[:, 0] + m[3] * pts[:, 1] + m[5]]) for m in maps]
        )  # fmt: skip
    return pts


def points_raster(col, row, shape, count=False) -> np.ndarray:
    """Raster of points at pixel coordinates (``np.add.at``; outside points skipped)."""
    col = np.asarray(col, dtype=float)
    row = np.asarray(row, dtype=float)
    img = np.zeros(shape, dtype=np.int64)
    ok = (col >= 0) & (row >= 0) & (col < shape[1]) & (row < shape[0])
    np.add.at(img, (row[ok].astype(int), col[ok].astype(int)), 1)
    return img if count else (img > 0).astype(np.uint8)
