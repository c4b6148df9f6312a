"""Numba kernels of the trunk traced below the cut (:func:`growsim.pictures.foot.traced_trunk`):
a trunk's two edges followed down, row by row, as a path of most gain (Viterbi).

- :func:`edge_pair_scores`: each row's score of a trunk centred on a column with a width:
  the weaker of its two edges, less the distance of its inside's mean colour from the
  trunk's; a state whose inside is not of the trunk's colours is forbidden;
- :func:`trace_path`: from a start state, the path of most gain down the rows, moving by
  at most one column and one width a row (each move paid for), ending where it gains most.

Grids are ``(rows, columns)``; widths are ``wmin + k * step`` for ``k`` in
``0 .. nk - 1``; a trunk of width ``w`` centred on column ``c`` holds columns
``c - w // 2`` to ``c - w // 2 + w - 1``, its edges the columns just outside.
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.config import njit

__all__ = ["edge_pair_scores", "trace_path"]

#: a forbidden state's score
FORBIDDEN = -1.0e3


@njit
def edge_pair_scores(edge, cum, colour, widths, weights):
    """``score[row, c, k]`` of a trunk of width ``wmin + k * step`` centred on column ``c``:
    ``2 * min(left edge, right edge, cap) - alpha * min(d, d_cap)``, where the edges are
    ``edge`` (``(rows, columns)``) just outside it and ``d`` the distance of its inside's
    mean colour (from ``cum``, each row's running sum of the three colour channels,
    ``(rows, columns + 1, 3)``) from ``colour[:3]`` in units of ``colour[3]``;
    :data:`FORBIDDEN` where ``d > gate`` or the trunk and its edges do not fit in the
    row. ``widths`` ``(wmin, nk, step)``; ``weights`` ``(cap, alpha, d_cap, gate)``.

    Examples
    --------
    >>> edge = np.zeros((1, 8)); edge[0, 2] = edge[0, 5] = 3.0      # edges at 2 and 5
    >>> lab = np.zeros((1, 8, 3)); lab[0, 3:5, 0] = 50.0             # the trunk: 3, 4
    >>> cum = np.zeros((1, 9, 3)); cum[:, 1:] = np.cumsum(lab, axis=1)
    >>> s = edge_pair_scores(edge, cum, np.array([50.0, 0, 0, 5.0]), (2, 1, 1),
    ...                      (4.0, 1.0, 6.0, 3.0))
    >>> float(s[0, 4, 0]), float(s[0, 5, 0])                        # on it, one off
    (6.0, -1000.0)
    """
    cap, alpha, d_cap, gate = weights
    wmin, nk, step = widths
    n, ncol = edge.shape
    out = np.full((n, ncol, nk), FORBIDDEN)
    for k in range(nk):
        w = wmin + k * step
        for c in range(ncol):
            a = c - w // 2
            b = a + w
            if a < 1 or b > ncol - 1:
                continue
            for r in range(n):
                d2 = 0.0
                for ch in range(3):
                    m = (cum[r, b, ch] - cum[r, a, ch]) / w - colour[ch]
                    d2 += m * m
                d = np.sqrt(d2) / colour[3]
                if d > gate:
                    continue
                e = min(edge[r, a - 1], edge[r, b], cap)
                out[r, c, k] = 2.0 * e - alpha * min(d, d_cap)
    return out


@njit
def trace_path(score, start, costs):
    """The path of most gain through ``score`` (``(rows, columns, widths)``) from state
    ``start`` ``(c, k)`` before row 0, moving by at most one column and one width a row at
    ``costs`` ``(per column, per width)`` a step; it may end after any row (or before the
    first: nothing). Returns ``(last row, columns, widths, gain)``: the last row is -1
    when no path gains.

    Examples
    --------
    >>> s = np.full((4, 5, 1), -1.0); s[:2, 2, 0] = 2.0; s[2:, 3, 0] = 0.5
    >>> end, cs, ks, gain = trace_path(s, (2, 0), (1.0, 0.0))
    >>> int(end), cs.tolist(), float(gain)        # two rows down column 2; no more
    (1, [2, 2], 4.0)
    """
    n, nc, nk = score.shape
    low = -1.0e18
    acc = np.full((nc, nk), low)
    acc[start[0], start[1]] = 0.0
    back = np.zeros((n, nc, nk), dtype=np.int8)  # the move from above: 3 (dc + 1) + dk + 1
    best, best_r, best_c, best_k = 0.0, -1, start[0], start[1]
    new = np.empty((nc, nk))
    for r in range(n):
        for c in range(nc):
            for k in range(nk):
                v, move = low, 0
                for dc in range(-1, 2):
                    cc = c + dc
                    if cc < 0 or cc >= nc:
                        continue
                    for dk in range(-1, 2):
                        kk = k + dk
                        if kk < 0 or kk >= nk or acc[cc, kk] <= low:
                            continue
                        u = acc[cc, kk] - costs[0] * abs(dc) - costs[1] * abs(dk)
                        if u > v:
                            v, move = u, 3 * (dc + 1) + dk + 1
                if v <= low:
                    new[c, k] = low
                    continue
                new[c, k] = v + score[r, c, k]
                back[r, c, k] = move
                if new[c, k] > best:
                    best, best_r, best_c, best_k = new[c, k], r, c, k
        acc[:, :] = new
    cs = np.zeros(best_r + 1, dtype=np.int64)
    ks = np.zeros(best_r + 1, dtype=np.int64)
    c, k = best_c, best_k
    for r in range(best_r, -1, -1):
        cs[r] = c
        ks[r] = k
        move = back[r, c, k]
        c, k = c + move // 3 - 1, k + move % 3 - 1
    return best_r, cs, ks, best
