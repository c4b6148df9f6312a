"""Oracle of the traced trunk's kernels (:mod:`growsim.kernels.trunk`): each state's score
from the pixels directly (the inside's mean by ``mean``, no running sums), and the path
by full NumPy matrices of every state to every state, moves beyond one column or one
width ruled out."""

from __future__ import annotations

import numpy as np

FORBIDDEN = -1.0e3


def edge_pair_scores(edge, lab, colour, widths, weights):
    """The kernel's scores by their definition, from the colours ``lab`` (``(rows,
    columns, 3)``) themselves.

    Examples
    --------
    >>> edge = np.zeros((1, 8)); edge[0, 2] = edge[0, 5] = 3.0
    >>> lab = np.zeros((1, 8, 3)); lab[0, 3:5, 0] = 50.0
    >>> s = edge_pair_scores(edge, lab, np.array([50.0, 0, 0, 5.0]), (2, 1, 1),
    ...                      (4.0, 1.0, 6.0, 3.0))
    >>> float(s[0, 4, 0])
    6.0
    """
    cap, alpha, d_cap, gate = weights
    wmin, nk, step = widths
    n, ncol = edge.shape
    centre = np.arange(ncol)
    planes = []
    for width in wmin + step * np.arange(nk):
        first = centre - width // 2  # each trunk's first column inside
        fits = (first >= 1) & (first + width <= ncol - 1)
        plane = np.full((n, ncol), FORBIDDEN)
        if fits.any():
            inside = np.stack([lab[:, x : x + width].mean(axis=1) for x in first[fits]], axis=1)
            d = np.linalg.norm(inside - colour[:3], axis=-1) / colour[3]
            e = np.minimum(np.minimum(edge[:, first[fits] - 1], edge[:, first[fits] + width]), cap)
            plane[:, fits] = np.where(d > gate, FORBIDDEN, 2.0 * e - alpha * np.minimum(d, d_cap))
        planes.append(plane)
    return np.stack(planes, axis=-1)


def trace_path(score, start, costs):
    """The kernel's path: every state's best predecessor from a matrix of all pairs.

    Examples
    --------
    >>> s = np.full((4, 5, 1), -1.0); s[:2, 2, 0] = 2.0; s[2:, 3, 0] = 0.5
    >>> end, cs, ks, gain = trace_path(s, (2, 0), (1.0, 0.0))
    >>> end, cs.tolist(), gain
    (1, [2, 2], 4.0)
    """
    n, nc, nk = score.shape
    c = np.repeat(np.arange(nc), nk)
    k = np.tile(np.arange(nk), nc)
    dc, dk = np.abs(c[:, None] - c[None, :]), np.abs(k[:, None] - k[None, :])
    step = np.where((dc <= 1) & (dk <= 1), -(costs[0] * dc + costs[1] * dk), -np.inf)
    acc = np.full(nc * nk, -np.inf)
    acc[start[0] * nk + start[1]] = 0.0
    backs, best = [], (0.0, -1, start[0] * nk + start[1])
    for r in range(n):
        cand = acc[None, :] + step  # [to, from]
        back = np.argmax(cand, axis=1)
        acc = cand[np.arange(nc * nk), back] + score[r].reshape(-1)
        backs.append(back)
        i = int(np.argmax(acc))
        if acc[i] > best[0]:
            best = (float(acc[i]), r, i)
    gain, end, i = best
    states = []
    for r in range(end, -1, -1):
        states.append(i)
        i = int(backs[r][i])
    states = np.array(states[::-1], dtype=np.int64)
    return end, states // nk, states % nk, gain
