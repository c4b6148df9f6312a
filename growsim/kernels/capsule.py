"""Walking a capsule over the pixels of a shadow map that hold queries
(:mod:`growsim.kernels.light`).

A segment seen along the light is a capsule in the map's pixel coordinates: its axis
``a-b`` and radius ``r``; it covers the pixels whose centre lies within ``r`` of the axis,
at the depth of the axis at the point nearest the centre. The map only keeps the pixels
that hold queries: a bit per such pixel in words of 64 by rows, then by columns
(``occ``), and per pixel the head of its list of queries (``head``, ``nxt``) and, for hard
shadows, its nearest depth and segment so far (``near_z``, ``near_id``).
:func:`project_segment` puts a segment in a map's pixels; :func:`walk_capsule` visits
exactly the occupied pixels its capsule covers.
"""

from __future__ import annotations

import math

import numpy as np
from numba.cpython.unsafe.numbers import trailing_zeros

from growsim.kernels.config import njit
from growsim.kernels.raster import iceil, ifloor

__all__ = ["project_segment", "walk_capsule"]

#: a capsule is judged over its bounding box (not line by line) when the box holds at most
#: this many pixels, or at most ``_BOX_RATIO`` times the capsule's area
_BOX_PIXELS = 64
_BOX_RATIO = 3.0


@njit(inline="always")
def project_segment(start, end, k, u, v, d, ox, oy, inv):
    """Segment ``k`` in a plant's frame: its ends in pixel coordinates ``(ax, ay, bx, by)``
    (``x = (p . u - ox) * inv``, ``inv = 1 / pix``) and their depths ``(za, zb)``.

    Examples
    --------
    >>> import numpy as np
    >>> e = np.eye(3)
    >>> project_segment(np.zeros((1, 3)), np.ones((1, 3)), 0, e[0], e[2], e[1], 0.0, 0.0, 2.0)
    (0.0, 0.0, 2.0, 2.0, 0.0, 1.0)
    """
    ax = (start[k, 0] * u[0] + start[k, 1] * u[1] + start[k, 2] * u[2] - ox) * inv
    ay = (start[k, 0] * v[0] + start[k, 1] * v[1] + start[k, 2] * v[2] - oy) * inv
    bx = (end[k, 0] * u[0] + end[k, 1] * u[1] + end[k, 2] * u[2] - ox) * inv
    by = (end[k, 0] * v[0] + end[k, 1] * v[1] + end[k, 2] * v[2] - oy) * inv
    za = start[k, 0] * d[0] + start[k, 1] * d[1] + start[k, 2] * d[2]
    zb = end[k, 0] * d[0] + end[k, 1] * d[1] + end[k, 2] * d[2]
    return ax, ay, bx, by, za, zb


@njit(inline="always")
def _setup(ax, ay, bx, by, rr, res):
    """The walk of a capsule (axis ``a-b`` in pixels, radius ``rr``) along its shorter
    extent (fewer lines, each a longer chord): ``tr`` (walk columns: x and y are swapped,
    and so are the pixel's indices),
    the swapped ends, the radius, the first and last line, ``dx, dy, 1 / L2`` and the
    body's chord per line (see :func:`_span`)."""
    tr = abs(by - ay) > abs(bx - ax)
    if tr:
        ax, ay = ay, ax
        bx, by = by, bx
    r = rr
    i0 = max(0, iceil(min(ay, by) - r - 0.5, res))
    i1 = min(res - 1, ifloor(max(ay, by) + r - 0.5, res))
    dx = bx - ax
    dy = by - ay
    L2 = dx * dx + dy * dy
    inv_L2 = 1.0 / L2 if L2 > 0.0 else 0.0
    # along the shorter extent |dy| <= |dx|: dy = 0 for a level segment or a point
    slope = dx / dy if dy != 0.0 else 0.0
    half = r * math.sqrt(L2) / abs(dy) if dy != 0.0 else -1.0
    # 0 <= t <= 1 on the line e = yc - ay: e dy in [-(x - ax) dx, L2 - (x - ax) dx]
    cap = -dy / dx if dx != 0.0 else 0.0
    cap_w = L2 / dx if dx != 0.0 else 0.0
    return tr, ax, ay, bx, by, r, i0, i1, dx, dy, L2, inv_L2, slope, half, cap, cap_w


@njit(inline="always")
def _span(i, walk, res):
    """Columns ``j0..j1`` of line ``i`` whose centres lie within ``r`` of the axis (the
    line's chord of the capsule: the union of the two end discs and the body, an interval
    because the capsule is convex; ``j0 > j1`` when the line misses it). With
    ``e = yc - ay`` the body is ``|perpendicular| <= r``: ``x in ax + e dx / dy +- r L /
    |dy|``, and ``0 <= t <= 1``: ``x`` between ``ax - e dy / dx`` and that plus
    ``L2 / dx`` (for ``dx = 0``: ``0 <= e dy <= L2``). ``walk`` is :func:`_setup`'s
    tuple."""
    _, ax, ay, bx, by, r, _, _, dx, dy, L2, _, slope, half, cap, cap_w = walk
    yc = i + 0.5
    r2 = r * r
    lo = np.inf
    hi = -np.inf
    e = yc - ay
    if e * e <= r2:
        w = math.sqrt(r2 - e * e)
        lo = ax - w
        hi = ax + w
    f = yc - by
    if f * f <= r2:
        w = math.sqrt(r2 - f * f)
        lo = min(lo, bx - w)
        hi = max(hi, bx + w)
    if half >= 0.0:
        c = ax + e * slope
        plo = c - half
        phi = c + half
        if dx != 0.0:
            x0 = ax + e * cap
            x1 = x0 + cap_w
            plo = max(plo, min(x0, x1))
            phi = min(phi, max(x0, x1))
        elif not (0.0 <= e * dy <= L2):
            plo = np.inf
        if plo <= phi:
            lo = min(lo, plo)
            hi = max(hi, phi)
    elif L2 > 0.0 and e * e <= r2:  # a level segment: its body spans ax..bx
        lo = min(lo, ax, bx)
        hi = max(hi, ax, bx)
    if not lo <= hi:
        return 1, 0
    return max(0, iceil(lo - 0.5, res)), min(res - 1, ifloor(hi - 0.5, res))


@njit(inline="always")
def _bits(lo, hi):
    """The bits ``lo..hi`` (``0 <= lo <= hi <= 63``) of a 64-bit word."""
    n = hi - lo + 1
    m = np.uint64(0xFFFFFFFFFFFFFFFF) if n == 64 else (np.uint64(1) << np.uint64(n)) - np.uint64(1)
    return m << np.uint64(lo)


@njit(inline="always")
def _meet(px, k, z, scratch, queries, bias, soft, trans_k):
    """Segment ``k``, at depth ``z`` over pixel ``px`` (which holds queries): hard shadows
    keep the pixel's nearest depth and segment in ``near_z``/``near_id`` (the first drawn
    wins a tie, as in a z-buffer); soft ones multiply the ``expo`` of each of the pixel's
    queries (a list from ``head[px]`` on, through ``nxt``) that belongs to another segment
    and lies more than ``bias`` behind ``z`` by ``trans_k`` (``scratch`` and ``queries``
    as :func:`walk_capsule`)."""
    head, _, near_z, near_id = scratch
    nxt, qz, qown, expo = queries
    if soft:
        q = head[px]
        while q >= 0:
            if qown[q] != k and z < qz[q] - bias:
                expo[q] *= trans_k
            q = nxt[q]
    elif z < near_z[px]:
        near_z[px] = z
        near_id[px] = k


@njit(inline="always")
def walk_capsule(k, ends, rr, res, scratch, queries, bias, soft, trans_k):
    """Rasterise segment ``k`` (``ends`` ``(ax, ay, bx, by, za, zb)``: its ends ``a``,
    ``b`` in pixel coordinates and their depths, as
    :func:`project_segment` gives them; radius ``rr`` pixels) and let
    it meet (:func:`_meet`) the queries of the pixels it covers: those whose centre lies
    within the radius of the axis. Only pixels holding queries are visited: ``scratch``
    ``(head, occ, near_z, near_id)`` (:func:`growsim.kernels.light.shadow_scratch`):
    ``occ`` holds a bit per such pixel, by rows (``W = (res + 63) // 64`` words per row)
    then by columns, ``head[pixel]`` the pixel's first query and, for hard shadows,
    ``near_z``, ``near_id`` its nearest depth and segment so far; ``queries`` ``(nxt, qz,
    qown, expo)``: per query the next one in its pixel (-1: no more), its depth, its own
    segment (-1: none) and its exposure (soft shadows: multiplied by ``trans_k`` for each
    segment more than ``bias`` in front). A small capsule tests the pixels of its bounding
    box that hold queries (row by row, or column by column when the box is taller than
    wide: fewer lines, the same pixels); a larger one is walked line by line along its
    shorter extent over exactly the columns of each line's chord (closed form,
    :func:`_span`).

    Examples
    --------
    >>> import numpy as np
    >>> head, occ = np.empty(64, np.int64), np.zeros(16, np.uint64)  # an 8-pixel map
    >>> near_z, near_id = np.empty(64), np.empty(64, np.int64)
    >>> px = 4 * 8 + 3  # one query, at row 4, column 3
    >>> head[px], near_z[px], near_id[px] = 0, np.inf, -1
    >>> occ[4] |= np.uint64(1 << 3); occ[8 + 3] |= np.uint64(1 << 4)  # its row's, column's bit
    >>> queries = (np.array([-1]), np.zeros(1), np.array([-1]), np.ones(1))
    >>> walk_capsule(7, (0.5, 4.5, 7.5, 4.5, 1.0, 2.0), 0.6, 8, (head, occ, near_z, near_id),
    ...              queries, 0.0, False, 1.0)
    >>> int(near_id[px]), round(float(near_z[px]), 3)  # segment 7, its depth there
    (7, 1.429)
    """
    ax, ay, bx, by, za, zb = ends
    occ = scratch[1]
    W = (res + 63) // 64
    r = rr
    dx = bx - ax
    dy = by - ay
    L2 = dx * dx + dy * dy
    inv_L2 = 1.0 / L2 if L2 > 0.0 else 0.0
    i0 = max(0, iceil(min(ay, by) - r - 0.5, res))
    i1 = min(res - 1, ifloor(max(ay, by) + r - 0.5, res))
    j0 = max(0, iceil(min(ax, bx) - r - 0.5, res))
    j1 = min(res - 1, ifloor(max(ax, bx) + r - 0.5, res))
    if i0 > i1 or j0 > j1:
        return
    box = (i1 - i0 + 1) * (j1 - j0 + 1)
    if box <= _BOX_PIXELS or box <= _BOX_RATIO * (2.0 * r * math.sqrt(L2) + math.pi * r * r):
        r2 = r * r
        if i1 - i0 > j1 - j0:  # taller than wide: by columns (fewer lines, same pixels)
            for j in range(j0, j1 + 1):
                xc = j + 0.5
                for w in range(i0 >> 6, (i1 >> 6) + 1):
                    bits = occ[(res + j) * W + w] & _bits(
                        max(i0, w * 64) - w * 64, min(i1, w * 64 + 63) - w * 64
                    )
                    while bits != 0:
                        i = w * 64 + trailing_zeros(bits)
                        bits &= bits - np.uint64(1)
                        yc = i + 0.5
                        t = ((xc - ax) * dx + (yc - ay) * dy) * inv_L2
                        t = min(1.0, max(0.0, t))
                        px = ax + t * dx - xc
                        py = ay + t * dy - yc
                        if px * px + py * py <= r2:
                            _meet(i * res + j, k, za + t * (zb - za), scratch, queries, bias,
                                  soft, trans_k)  # fmt: skip
            return
        for i in range(i0, i1 + 1):
            yc = i + 0.5
            e = (yc - ay) * dy
            for w in range(j0 >> 6, (j1 >> 6) + 1):
                bits = occ[i * W + w] & _bits(
                    max(j0, w * 64) - w * 64, min(j1, w * 64 + 63) - w * 64
                )
                while bits != 0:
                    j = w * 64 + trailing_zeros(bits)
                    bits &= bits - np.uint64(1)
                    xc = j + 0.5
                    t = ((xc - ax) * dx + e) * inv_L2
                    t = min(1.0, max(0.0, t))
                    px = ax + t * dx - xc
                    py = ay + t * dy - yc
                    if px * px + py * py <= r2:
                        _meet(i * res + j, k, za + t * (zb - za), scratch, queries, bias, soft,
                              trans_k)  # fmt: skip
        return
    walk = _setup(ax, ay, bx, by, rr, res)
    tr, ax, ay, bx, by, r, i0, i1, dx, dy, L2, inv_L2, slope, half, _, _ = walk
    # lines whose band chord lies within the body's length (0 <= t <= 1 at both its ends):
    # their chord is the band's, ax + e dx / dy +- half (the end discs lie inside the band)
    inv_dy = 1.0 / dy if dy != 0.0 else 0.0
    slack = abs(half * dx * inv_L2)
    line = 1 if tr else res  # pixel (i, j) of the walk is i * line + j * step
    step = res if tr else 1
    lines = res * W if tr else 0  # the line's occupancy words: by columns or by rows
    for i in range(i0, i1 + 1):
        te = (i + 0.5 - ay) * inv_dy
        if dy != 0.0 and slack <= te <= 1.0 - slack:
            c = ax + (i + 0.5 - ay) * slope
            j0 = max(0, math.ceil(c - half - 0.5))
            j1 = min(res - 1, math.floor(c + half - 0.5))
        else:
            j0, j1 = _span(i, walk, res)
        if j0 > j1:
            continue
        e = (i + 0.5 - ay) * dy
        for w in range(j0 >> 6, (j1 >> 6) + 1):
            bits = occ[lines + i * W + w] & _bits(
                max(j0, w * 64) - w * 64, min(j1, w * 64 + 63) - w * 64
            )
            while bits != 0:
                j = w * 64 + trailing_zeros(bits)
                bits &= bits - np.uint64(1)
                t = ((j + 0.5 - ax) * dx + e) * inv_L2
                t = min(1.0, max(0.0, t))
                _meet(i * line + j * step, k, za + t * (zb - za), scratch, queries, bias, soft,
                      trans_k)  # fmt: skip
