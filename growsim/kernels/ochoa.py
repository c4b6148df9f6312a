"""Numba kernels of the Ochoa terms (:mod:`growsim.objectives.ochoa`) on a plant's 2D view.

A view is a ``(S0, S1)`` raster (non-zero = plant), rows downwards, as
:mod:`growsim.kernels.views` draws them.

- :func:`shadow_bins`: how much of the light crossing the raster the plant intercepts: the
  foreground pixel centres projected on the axis perpendicular to the light, counted in
  one-pixel bins (the 2D analogue of :func:`growsim.env.light.projected_area`: the length
  of the plant's shadow);
- :func:`prune`: a skeleton's spurs removed (end pixels peeled ``iterations`` times);
- :func:`junctions`: the branching points of a skeleton and the branches at each.

Skeletons are one pixel wide, 8-connected (``skimage.morphology.skeletonize``). A pixel's
*degree* is its number of skeleton neighbours (8-neighbourhood). Pixels of degree >= 3
are junction pixels; 8-connected junction pixels form one branching point (a junction
is often 2-4 pixels in a thin skeleton); its *branches* are the 8-connected groups of the
non-junction skeleton pixels that touch it (the branch it grows from counts: a fork has
3).
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = ["junctions", "junctions_kernel", "prune", "prune_kernel", "shadow_bins",
           "shadow_bins_kernel"]  # fmt: skip


@njit
def shadow_bins_kernel(img, ux, uy, mark):
    """Number of one-pixel bins, across the light ``(ux, uy)`` (unit, y up), that hold a
    foreground pixel centre of ``img``. ``mark`` is scratch of at least
    ``ceil(S1 |uy| + S0 |ux|) + 2`` entries (zeroed here).

    Pixel ``(i, j)``'s centre is ``x = j + 0.5``, ``y = S0 - i - 0.5`` (y up); its
    coordinate across the light is ``s = -uy x + ux y``; bins are ``floor(s - s0)``, ``s0``
    the smallest ``s`` of the raster's corners.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((3, 4), np.uint8); img[0, 1] = img[2, 1] = img[1, 3] = 1
    >>> shadow_bins_kernel(img, 0.0, -1.0, np.empty(8, np.uint8))  # columns 1 and 3
    2
    """
    S0, S1 = img.shape
    for q in range(mark.shape[0]):
        mark[q] = 0
    s0 = min(0.0, -uy * S1) + min(0.0, ux * S0)
    n = 0
    for i in range(S0):
        y = S0 - i - 0.5
        for j in range(S1):
            if img[i, j]:
                s = -uy * (j + 0.5) + ux * y
                b = math.floor(s - s0)
                if b < 0:
                    b = 0
                if b >= mark.shape[0]:
                    b = mark.shape[0] - 1
                if mark[b] == 0:
                    mark[b] = 1
                    n += 1
    return n


@njit
def _degree(skel, i, j):
    S0, S1 = skel.shape
    n = 0
    for di in range(-1, 2):
        for dj in range(-1, 2):
            if di == 0 and dj == 0:
                continue
            ii = i + di
            jj = j + dj
            if ii >= 0 and jj >= 0 and ii < S0 and jj < S1 and skel[ii, jj]:
                n += 1
    return n


@njit
def prune_kernel(skel, iterations):
    """Peel the end pixels (degree <= 1) of skeleton ``skel`` (uint8, in place),
    ``iterations`` times, all ends of one pass at once; returns the pixels removed.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((1, 5), np.uint8); s[0, :] = 1
    >>> prune_kernel(s, 1), s.tolist()
    (2, [[0, 1, 1, 1, 0]])
    """
    S0, S1 = skel.shape
    ends = np.empty((S0 * S1, 2), np.int64)
    removed = 0
    for _ in range(iterations):
        m = 0
        for i in range(S0):
            for j in range(S1):
                if skel[i, j] and _degree(skel, i, j) <= 1:
                    ends[m, 0] = i
                    ends[m, 1] = j
                    m += 1
        if m == 0:
            break
        for q in range(m):
            skel[ends[q, 0], ends[q, 1]] = 0
        removed += m
    return removed


@njit
def junctions_kernel(skel, many):
    """``(branching points, those with >= many branches)`` of skeleton ``skel``.

    See the module docstring for the definitions. A group of junction pixels touching
    fewer than 3 branches (a small loop) is not a branching point.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((5, 5), np.uint8); s[2, :] = 1; s[:, 2] = 1  # a cross: 4 branches
    >>> junctions_kernel(s, 4)
    (1, 1)
    >>> s[3:, 2] = 0  # a T: 3 branches
    >>> junctions_kernel(s, 4)
    (1, 0)
    """
    S0, S1 = skel.shape
    deg = np.zeros((S0, S1), np.int64)
    for i in range(S0):
        for j in range(S1):
            if skel[i, j]:
                deg[i, j] = _degree(skel, i, j)
    # label[i, j]: junction cluster id + 1 (0: none); exit[i, j]: exit group id + 1
    label = np.zeros((S0, S1), np.int64)
    stamp = np.zeros((S0, S1), np.int64)  # last cluster (id + 1) that visited an exit
    stack = np.empty((S0 * S1, 2), np.int64)
    exits = np.empty((S0 * S1, 2), np.int64)
    n_points = 0
    n_many = 0
    cluster = 0
    for i0 in range(S0):
        for j0 in range(S1):
            if deg[i0, j0] < 3 or label[i0, j0] != 0:
                continue
            cluster += 1
            # flood fill the junction pixels of this cluster; collect its exits
            top = 0
            stack[0, 0] = i0
            stack[0, 1] = j0
            label[i0, j0] = cluster
            top = 1
            m = 0
            while top > 0:
                top -= 1
                i = stack[top, 0]
                j = stack[top, 1]
                for di in range(-1, 2):
                    for dj in range(-1, 2):
                        ii = i + di
                        jj = j + dj
                        if (di == 0 and dj == 0) or ii < 0 or jj < 0 or ii >= S0 or jj >= S1:
                            continue
                        if not skel[ii, jj]:
                            continue
                        if deg[ii, jj] >= 3:
                            if label[ii, jj] == 0:
                                label[ii, jj] = cluster
                                stack[top, 0] = ii
                                stack[top, 1] = jj
                                top += 1
                        elif stamp[ii, jj] != cluster:
                            stamp[ii, jj] = cluster
                            exits[m, 0] = ii
                            exits[m, 1] = jj
                            m += 1
            # branches: 8-connected groups among the exits (union-find)
            parent = np.arange(m)
            for a in range(m):
                for b in range(a + 1, m):
                    if abs(exits[a, 0] - exits[b, 0]) <= 1 and abs(exits[a, 1] - exits[b, 1]) <= 1:
                        ra = a
                        while parent[ra] != ra:
                            ra = parent[ra]
                        rb = b
                        while parent[rb] != rb:
                            rb = parent[rb]
                        if ra != rb:
                            parent[rb] = ra
            branches = 0
            for a in range(m):
                if parent[a] == a:
                    branches += 1
            if branches >= 3:
                n_points += 1
                if branches >= many:
                    n_many += 1
    return n_points, n_many


def _check_img(img, what: str) -> np.ndarray:
    img = np.asarray(img)
    if img.ndim != 2:
        raise ValueError(f"{what}: expected a (S0, S1) raster, got shape {img.shape}")
    return np.ascontiguousarray(img != 0, dtype=np.uint8)


def shadow_bins(img, direction=(0.0, -1.0)) -> tuple[int, float]:
    """``(bins, frame)``: the plant's shadow across the light ``direction`` (2D, y up; any
    length > 0) in one-pixel bins (:func:`shadow_bins_kernel`), and the raster's own
    shadow length ``S1 |uy| + S0 |ux|``: their ratio is the share of the light crossing the
    raster that the plant intercepts.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((4, 4), np.uint8); img[1, :2] = 1
    >>> shadow_bins(img)  # light from above: 2 of 4 columns
    (2, 4.0)
    """
    img = _check_img(img, "shadow_bins")
    d = np.asarray(direction, dtype=np.float64).reshape(-1)
    norm = float(np.hypot(d[0], d[1])) if d.size == 2 else 0.0
    if d.size != 2 or not np.isfinite(d).all() or norm == 0.0:
        raise ValueError(f"shadow_bins: direction must be a non-zero 2-vector, got {direction!r}")
    ux, uy = float(d[0] / norm), float(d[1] / norm)
    S0, S1 = img.shape
    frame = S1 * abs(uy) + S0 * abs(ux)
    mark = np.empty(math.ceil(frame) + 2, np.uint8)
    return int(shadow_bins_kernel(img, ux, uy, mark)), float(frame)


def prune(skel, iterations: int) -> np.ndarray:
    """A copy of skeleton ``skel`` with its end pixels peeled ``iterations`` times
    (:func:`prune_kernel`): spurs shorter than ``iterations`` pixels vanish, and every
    tip shortens by as much.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((4, 7), np.uint8); s[3, :] = 1; s[:3, 3] = 1  # a T, upright 3 long
    >>> prune(s, 2).sum(axis=1).tolist()  # the bar 2 shorter each side, the upright 2
    [0, 0, 1, 3]
    """
    out = _check_img(skel, "prune").copy()
    prune_kernel(out, int(iterations))
    return out


def junctions(skel, many: int = 4) -> tuple[int, int]:
    """``(branching points, those with at least many branches)`` of skeleton ``skel``
    (:func:`junctions_kernel`).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.eye(7, dtype=np.uint8); s[3, :] = 1  # two lines crossing: 4 branches
    >>> junctions(s, 4)
    (1, 1)
    """
    return tuple(int(v) for v in junctions_kernel(_check_img(skel, "junctions"), int(many)))
