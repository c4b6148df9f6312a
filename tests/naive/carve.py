"""Oracle of the two-picture lift's kernels (:mod:`growsim.kernels.carve`): the same
paths of least cost, each step's costs for every pair of states as full NumPy matrices,
the spans' pixel counts summed from the grids directly (no running counts)."""

from __future__ import annotations

import math

import numpy as np


def _count(row: np.ndarray, lo: float, hi: float, w: int) -> float:
    """Pixels set in ``row`` from ``floor(lo) - w`` to ``ceil(hi) + w``, the span's ends
    first clipped to the row, then widened and clipped again."""
    n = row.size
    a = max(min(max(math.floor(lo), 0), n - 1) - w, 0)
    b = min(min(max(math.ceil(hi), 0), n - 1) + w, n - 1)
    return float(row[a : b + 1].sum())


def _trace(values, backs, cost):
    """The values of the path ending in the state of least ``cost``, traced back."""
    k = int(np.argmin(cost))
    out = np.empty(len(values))
    for i in range(len(values) - 1, 0, -1):
        out[i] = values[i][k]
        k = int(backs[i - 1][k])
    out[0] = values[0][k]
    return out


def carve_depth(branch, z0, grid, cover, params):
    """The kernel's depth columns by the definition of its costs.

    Examples
    --------
    >>> ptr = np.array([0, 1, 2, 3]); cols = np.array([2, 2, 2])
    >>> sil = np.zeros((3, 6), bool); sil[:, 1:4] = True
    >>> side_r = np.zeros((3, 6)); side_r[:, 2] = 1.0
    >>> out = np.zeros((3, 7)); out[:, 1:] = np.cumsum(~sil, axis=1)
    >>> z = carve_depth((np.array([0, 1, 2]), np.zeros(3), np.ones(3), np.ones(3)), 0.0,
    ...                 (ptr, cols, out, side_r), np.zeros((3, 6), np.int32),
    ...                 np.array([0.1, 3.0, 1.0, 0.05, 0.3, 3.0, 48.0, 2.0]))
    >>> z.tolist()
    [0.0, 2.0, 2.0]
    """
    rows, guess, radius, step = branch
    ptr, cols, outside_cum, side_radius = grid
    slide, outside, reward, guess_w, thickness, off, max_c, steep = params
    outside_px = np.diff(outside_cum, axis=1)
    nrows = side_radius.shape[0]
    values = [np.array([float(z0)])]
    backs = []
    cost = np.zeros(1)
    for i in range(1, len(rows)):
        r = int(rows[i])
        lo_r, hi_r = max(r - 1, 0), min(r + 1, nrows - 1)
        cand = np.unique(cols[ptr[lo_r] : ptr[hi_r + 1]])
        if cand.size > max_c:
            d = np.abs(cand - guess[i])
            cand = np.sort(cand[np.argsort(d, kind="mergesort")[: int(max_c)]])
        unc = (side_radius[r] > 0) & (cover[r] == 0)
        w = round(max(radius[i] - 0.5, 0.0))
        dg = guess[i] - guess[i - 1]
        prev = values[-1]
        rs = side_radius[lo_r : hi_r + 1, cand].max(axis=0) if cand.size else np.zeros(0)
        total = np.empty((prev.size, 1 + cand.size))
        total[:, 0] = (
            cost
            + abs(dg)
            + off
            + outside
            * np.array(
                [_count(outside_px[r], min(pa, pa + dg), max(pa, pa + dg), w) for pa in prev]
            )
        )
        for a, pa in enumerate(prev):
            for j, c in enumerate(cand.astype(np.float64)):
                lo, hi = min(pa, c), max(pa, c)
                gap = _count(outside_px[r], lo, hi, w)
                got = _count(unc, lo, hi, 0)
                fixed = guess_w * abs(c - guess[i]) + thickness * abs(rs[j] - radius[i])
                dz = hi - lo
                t = cost[a] + slide * dz + steep * max(dz - step[i], 0.0) + outside * gap
                total[a, j + 1] = t - reward * got + fixed
        arg = np.argmin(total, axis=0)
        cost = total[arg, np.arange(total.shape[1])]
        values.append(np.r_[prev[arg[0]] + dg, cand.astype(np.float64)])
        backs.append(arg)
    return _trace(values, backs, cost)


def carve_across(branch, x0, grid, params):
    """The kernel's columns and kept count by the definition of its costs.

    Examples
    --------
    >>> sil = np.zeros((3, 8), bool); sil[:, 2:4] = True
    >>> r, c = np.nonzero(sil); ptr = np.r_[0, np.cumsum(np.bincount(r, minlength=3))]
    >>> out = np.zeros((3, 9)); out[:, 1:] = np.cumsum(~sil, axis=1)
    >>> x, kept = carve_across((np.array([0, 1, 2]), np.ones(3)), 2.0, (ptr, c, out),
    ...                        np.array([0.1, 3.0, 2.0]))
    >>> x.tolist(), kept
    ([2.0, 2.0, 2.0], 3)
    """
    rows, radius = branch
    ptr, cols, outside_cum = grid
    slide, outside, max_gap = params
    outside_px = np.diff(outside_cum, axis=1)
    values = [np.array([float(x0)])]
    backs = []
    cost = np.zeros(1)
    for i in range(1, len(rows)):
        r = int(rows[i])
        w = round(max(radius[i] - 0.5, 0.0))
        prev = values[-1]
        cand = cols[ptr[r] : ptr[r + 1]].astype(np.float64)
        if cand.size == 0:
            gaps = np.array([_count(outside_px[r], p, p, w) for p in prev])
            cost = cost + outside * gaps
            values.append(prev.copy())
            backs.append(np.arange(prev.size))
            continue
        total = np.empty((prev.size, cand.size))
        for a, pa in enumerate(prev):
            for j, c in enumerate(cand):
                lo, hi = min(pa, c), max(pa, c)
                total[a, j] = cost[a] + slide * (hi - lo) + outside * _count(outside_px[r], lo,
                                                                             hi, w)  # fmt: skip
        arg = np.argmin(total, axis=0)
        cost = total[arg, np.arange(cand.size)]
        values.append(cand)
        backs.append(arg)
    x = _trace(values, backs, cost)
    kept = len(rows)
    for i in range(1, len(rows)):
        w = round(max(radius[i] - 0.5, 0.0))
        lo, hi = min(x[i - 1], x[i]), max(x[i - 1], x[i])
        if _count(outside_px[int(rows[i])], lo, hi, w) > max_gap:
            kept = i
            break
    return x, kept
