"""Numba kernels of the two-picture lift (:mod:`growsim.reconstruction.lift`): paths of
least cost through one picture's pixels, row by row (Viterbi).

- :func:`carve_depth`: a front branch's depth at each of its points, a side-skeleton
  column of the point's row (or the guess kept), paying for depth change, for pixels
  drawn outside the side silhouette and for a thickness unlike the side branch's, and
  rewarded for side-skeleton pixels no branch covers yet;
- :func:`carve_across`: a side branch hidden in the front picture, its column in the
  front picture at each point, inside the front silhouette where it can be; the path is
  cut where it must leave the silhouette.

Grids are ``(rows, columns)`` of pixels; a row's pixels of interest are listed in CSR form
(``ptr`` of ``rows + 1`` offsets into ``cols``, each row's columns ascending); an
``outside_cum`` grid is each row's running count of pixels outside the silhouette
(``(rows, columns + 1)``, first column 0).
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = ["carve_across", "carve_depth"]


@njit
def _row_candidates(ptr, cols, r0, r1):
    """The distinct columns listed in rows ``r0 .. r1`` (ascending)."""
    n = 0
    for r in range(r0, r1 + 1):
        n += ptr[r + 1] - ptr[r]
    out = np.empty(n, np.int64)
    k = 0
    for r in range(r0, r1 + 1):
        for j in range(ptr[r], ptr[r + 1]):
            out[k] = cols[j]
            k += 1
    return np.unique(out)


@njit
def _span(cum, r, lo, hi, w, ncols):
    """Pixels counted by ``cum`` in row ``r`` from ``floor(lo) - w`` to ``ceil(hi) + w``
    (clipped to the grid)."""
    a = min(max(math.floor(lo), 0), ncols - 1) - w
    b = min(max(math.ceil(hi), 0), ncols - 1) + w
    a = max(a, 0)
    b = min(b, ncols - 1)
    return cum[r, b + 1] - cum[r, a]


@njit
def _trellis(k, width, start):
    """The Viterbi trellis of a path of ``k`` points with at most ``width`` states each:
    ``(value, back, count, cost, new_cost)``, its first point's one state at ``start``
    (cost 0)."""
    value = np.empty((k, width))
    back = np.zeros((k, width), np.int64)
    count = np.zeros(k, np.int64)
    value[0, 0] = start
    count[0] = 1
    return value, back, count, np.zeros(width), np.empty(width)


@njit
def _path(value, back, cost):
    """The path of least ``cost`` (the last point's states' costs; the first on equal
    costs) traced back through ``back`` (each state's best previous state): its values."""
    k = value.shape[0]
    best = 0
    for a in range(cost.shape[0]):
        if cost[a] < cost[best]:
            best = a
    out = np.empty(k)
    for i in range(k - 1, -1, -1):
        out[i] = value[i, best]
        best = back[i, best]
    return out


@njit
def carve_depth(branch, z0, grid, cover, params):
    """A branch's depth columns on the side picture's grid.

    Parameters
    ----------
    branch : ``(rows, guess, radius, step)``: the branch's points' rows (int64, clipped to
        the grid), their guessed columns, their radii and the length of the step to each
        from the one before in the front picture (float64, pixels).
    z0 : float, the first point's column (the parent's end).
    grid : ``(ptr, cols, outside_cum, side_radius)``: the side skeleton's columns by row
        (CSR), the running count of pixels outside the side silhouette, and the side
        skeleton's radius at its pixels (0 elsewhere), ``(rows, columns)``.
    cover : ``(rows, columns)`` int32, how many branches cover each side-skeleton pixel.
    params : float64 ``(slide, outside, reward, guess, thickness, off, max_candidates,
        steep)``: a step's change of depth costs ``slide`` a pixel, and ``steep`` more a
        pixel beyond the step's length in the front picture.

    Returns
    -------
    ``(k,)`` float64 columns: the path of least total cost from ``z0``.

    Examples
    --------
    >>> ptr = np.array([0, 1, 2, 3]); cols = np.array([2, 2, 2])   # a side branch at x = 2
    >>> sil = np.zeros((3, 6), bool); sil[:, 1:4] = True
    >>> side_r = np.zeros((3, 6)); side_r[:, 2] = 1.0
    >>> out = np.zeros((3, 7)); out[:, 1:] = np.cumsum(~sil, axis=1)
    >>> carve_depth((np.array([0, 1, 2]), np.zeros(3), np.ones(3), np.ones(3)), 0.0,
    ...             (ptr, cols, out, side_r), np.zeros((3, 6), np.int32),
    ...             np.array([0.1, 3.0, 1.0, 0.05, 0.3, 3.0, 48.0, 2.0])).tolist()
    [0.0, 2.0, 2.0]
    """
    rows, guess, radius, step = branch
    ptr, cols, outside_cum, side_radius = grid
    slide, outside, reward, guess_w, thickness, off, steep = (
        params[0], params[1], params[2], params[3], params[4], params[5], params[7])  # fmt: skip
    max_c = int(params[6])
    k = rows.shape[0]
    nrows, ncols = side_radius.shape
    width = max_c + 1
    value, back, count, cost, new_cost = _trellis(k, width, z0)
    unc = np.zeros(ncols + 1)
    for i in range(1, k):
        r = rows[i]
        cand = _row_candidates(ptr, cols, max(r - 1, 0), min(r + 1, nrows - 1))
        if cand.size > max_c:
            d = np.abs(cand.astype(np.float64) - guess[i])
            cand = np.sort(cand[np.argsort(d, kind="mergesort")[:max_c]])
        nc = cand.size
        # the row's side-skeleton pixels no branch covers yet, counted cumulatively
        unc[0] = 0.0
        for c in range(ncols):
            hit = side_radius[r, c] > 0.0 and cover[r, c] == 0
            unc[c + 1] = unc[c] + (1.0 if hit else 0.0)
        w = round(max(radius[i] - 0.5, 0.0))
        dg = guess[i] - guess[i - 1]
        n_prev = count[i - 1]
        # state 0: off the side skeleton, the guess's step from a previous state (its
        # pixels outside the side silhouette paid as any step's)
        best = 0
        b_val = np.inf
        for a in range(n_prev):
            pa = value[i - 1, a]
            t = cost[a] + abs(dg) + off + outside * _span(outside_cum, r, min(pa, pa + dg),
                                                          max(pa, pa + dg), w, ncols)  # fmt: skip
            if t < b_val:
                b_val = t
                best = a
        new_cost[0] = b_val
        back[i, 0] = best
        value[i, 0] = value[i - 1, best] + dg
        for j in range(nc):
            c = float(cand[j])
            rs = 0.0
            for rr in range(max(r - 1, 0), min(r + 1, nrows - 1) + 1):
                rs = max(rs, side_radius[rr, cand[j]])
            fixed = guess_w * abs(c - guess[i]) + thickness * abs(rs - radius[i])
            b_arg = 0
            b_val = np.inf
            for a in range(n_prev):
                pa = value[i - 1, a]
                lo = min(pa, c)
                hi = max(pa, c)
                gap = _span(outside_cum, r, lo, hi, w, ncols)
                ua = min(max(math.floor(lo), 0), ncols - 1)
                ub = min(max(math.ceil(hi), 0), ncols - 1)
                got = unc[ub + 1] - unc[ua]
                dz = hi - lo
                t = cost[a] + slide * dz + steep * max(dz - step[i], 0.0) + outside * gap
                t = t - reward * got + fixed
                if t < b_val:
                    b_val = t
                    b_arg = a
            new_cost[j + 1] = b_val
            back[i, j + 1] = b_arg
            value[i, j + 1] = c
        count[i] = nc + 1
        for j in range(nc + 1):
            cost[j] = new_cost[j]
    return _path(value, back, cost[: count[k - 1]])


@njit
def carve_across(branch, x0, grid, params):
    """A hidden branch's columns in the front picture, and how many of its points to keep.

    Parameters
    ----------
    branch : ``(rows, radius)``: its points' rows (int64, clipped to the grid) and radii
        (float64, pixels).
    x0 : float, the first point's column (where it leaves the tree).
    grid : ``(ptr, cols, outside_cum)``: the front silhouette's pixels by row (CSR) and
        the running count of pixels outside it.
    params : float64 ``(slide, outside, max_gap)``.

    Returns
    -------
    ``(x, kept)``: ``(k,)`` float64 columns of least cost (change of column ``slide`` a
    pixel, pixels drawn outside ``outside`` each), and the points kept: up to the first
    step that draws more than ``max_gap`` pixels outside.

    Examples
    --------
    >>> sil = np.zeros((3, 8), bool); sil[:, 2:4] = True          # the front silhouette
    >>> r, c = np.nonzero(sil); ptr = np.r_[0, np.cumsum(np.bincount(r, minlength=3))]
    >>> out = np.zeros((3, 9)); out[:, 1:] = np.cumsum(~sil, axis=1)
    >>> x, kept = carve_across((np.array([0, 1, 2]), np.ones(3)), 2.0, (ptr, c, out),
    ...                        np.array([0.1, 3.0, 2.0]))
    >>> x.tolist(), int(kept)
    ([2.0, 2.0, 2.0], 3)
    """
    rows, radius = branch
    ptr, cols, outside_cum = grid
    slide, outside, max_gap = params[0], params[1], params[2]
    k = rows.shape[0]
    ncols = outside_cum.shape[1] - 1
    widest = 1
    for r in range(outside_cum.shape[0]):
        widest = max(widest, ptr[r + 1] - ptr[r])
    value, back, count, cost, new_cost = _trellis(k, widest, x0)
    for i in range(1, k):
        r = rows[i]
        n_prev = count[i - 1]
        nc = ptr[r + 1] - ptr[r]
        w = round(max(radius[i] - 0.5, 0.0))
        if nc == 0:  # no silhouette in this row: the columns carried on
            for j in range(n_prev):
                value[i, j] = value[i - 1, j]
                back[i, j] = j
                new_cost[j] = cost[j] + outside * _span(outside_cum, r, value[i, j],
                                                        value[i, j], w, ncols)  # fmt: skip
            count[i] = n_prev
        else:
            for j in range(nc):
                c = float(cols[ptr[r] + j])
                b_arg = 0
                b_val = np.inf
                for a in range(n_prev):
                    pa = value[i - 1, a]
                    lo = min(pa, c)
                    hi = max(pa, c)
                    t = cost[a] + slide * (hi - lo) + outside * _span(outside_cum, r, lo, hi,
                                                                      w, ncols)  # fmt: skip
                    if t < b_val:
                        b_val = t
                        b_arg = a
                new_cost[j] = b_val
                back[i, j] = b_arg
                value[i, j] = c
            count[i] = nc
        for j in range(count[i]):
            cost[j] = new_cost[j]
    x = _path(value, back, cost[: count[k - 1]])
    kept = k
    for i in range(1, k):
        w = round(max(radius[i] - 0.5, 0.0))
        lo = min(x[i - 1], x[i])
        hi = max(x[i - 1], x[i])
        if _span(outside_cum, rows[i], lo, hi, w, ncols) > max_gap:
            kept = i
            break
    return x, kept
