"""A plant among copies of itself in a periodic stand, lit through its own shadow map
(:func:`growsim.kernels.light.point_light_into` with ``shifts``).

Copy ``j`` of a plant, moved by ``shifts[j]``, shades a point ``q`` exactly as the plant
shades ``q - shifts[j]``, so the copies are never drawn: the plant's own map (its frame
and pixel size, as alone) is read at each point and at each point moved back by a shift,
and the point is lit when every reading is (soft shadows: the product of the readings).
Hard shadows: :func:`copies_hard` fills the map whole over the box those readings fall
in and reads it once per point and copy, so the cost is one plant's raster plus a lookup
per copy, not a raster per copy. Soft shadows: :func:`among_copies` lists the moved
points as queries for :func:`growsim.kernels.light.judge_queries`. The readings agree
with a map of the plant and its copies drawn together wherever the point lies more than
a pixel from a shadow's edge (the two maps' pixels lie differently).
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.capsule import project_segment, walk_capsule
from growsim.kernels.config import njit
from growsim.kernels.raster import ifloor

__all__ = ["among_copies", "copies_hard"]


@njit
def copies_hard(segments, frames, plane, shadow, targets, shifts, scratch, expo):
    """Hard exposures (1 or 0) of ``targets`` ``(points, point_offsets)`` along one light
    (``plane`` ``(u, v, d)``, ``frames`` and ``segments`` as
    :func:`growsim.kernels.light.judge_queries` takes them) among each plant's copies
    moved by ``shifts`` ``(k, 3)``, into ``expo`` (returned). Each plant's map is drawn
    whole over the box its points, moved back by every shift, can fall in (every pixel of
    the box set in ``occ`` of the ``scratch``, so :func:`walk_capsule` fills the nearest
    depths and segments it fills for queries there), then read once per point and copy:
    point ``q`` at ``x - su_j``, ``y - sv_j``, depth ``z - sd_j`` (``x, y, z`` its pixel
    coordinates and depth, ``su_j, sv_j, sd_j`` the shift's), lit by copy ``j`` when that
    pixel is outside the frame, empty or its nearest depth is within the bias. The
    ``scratch`` (:func:`growsim.kernels.light.shadow_scratch`) is left as given.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.kernels.light import plant_frames, shadow_scratch
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]]); r = np.array([0.2])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> off = np.array([0, 1]); frames = plant_frames(s, e, r, off, u, v, 64)
    >>> pts = np.array([[0.5, 0, 0], [5.5, 0, 0]])  # under the plant; 5 m to its right
    >>> copies_hard((s, e, r, off), frames, (u, v, d), (64, 0.1), (pts, np.array([0, 2])),
    ...             np.array([[5.0, 0, 0]]), shadow_scratch(64), np.empty(2)).tolist()
    [0.0, 0.0]
    """
    start, end, radius, offsets = segments
    points, point_offsets = targets
    u, v, d = plane
    res, bias_pixels = shadow[0], shadow[1]
    occ, near_z, near_id = scratch[1], scratch[2], scratch[3]
    W = (res + 63) // 64
    k = shifts.shape[0]
    move = np.zeros((k + 1, 3))  # (su, sv, sd) of each copy, the plant's own first
    for j in range(k):
        move[j + 1] = _dot(shifts, j, u), _dot(shifts, j, v), _dot(shifts, j, d)
    none = np.empty(0, np.int64)
    unused = (none, np.empty(0), none, np.empty(0))  # hard shadows read no query list
    for p in range(offsets.shape[0] - 1):
        a, b = point_offsets[p], point_offsets[p + 1]
        expo[a:b] = 1.0
        if b <= a or offsets[p + 1] <= offsets[p]:
            continue
        ox, oy, inv = frames[p, 0], frames[p, 1], 1.0 / frames[p, 2]
        bias = bias_pixels * frames[p, 2]
        xyz = np.empty((b - a, 3))
        for i in range(a, b):
            xyz[i - a] = _dot(points, i, u), _dot(points, i, v), _dot(points, i, d)
        lo_x = max(0, ifloor((xyz[:, 0].min() - move[:, 0].max() - ox) * inv, res))
        hi_x = min(res - 1, ifloor((xyz[:, 0].max() - move[:, 0].min() - ox) * inv, res))
        lo_y = max(0, ifloor((xyz[:, 1].min() - move[:, 1].max() - oy) * inv, res))
        hi_y = min(res - 1, ifloor((xyz[:, 1].max() - move[:, 1].min() - oy) * inv, res))
        if lo_x > hi_x or lo_y > hi_y:
            continue
        for yi in range(lo_y, hi_y + 1):
            near_z[yi * res + lo_x : yi * res + hi_x + 1] = np.inf
            near_id[yi * res + lo_x : yi * res + hi_x + 1] = -1
        _box_bits(occ, (lo_x, hi_x, lo_y, hi_y), res, W, True)
        for s in range(offsets[p], offsets[p + 1]):
            ends = project_segment(start, end, s, u, v, d, ox, oy, inv)
            walk_capsule(s, ends, radius[s] * inv, res, scratch, unused, bias, False, 1.0)
        _box_bits(occ, (lo_x, hi_x, lo_y, hi_y), res, W, False)
        for i in range(b - a):
            for j in range(k + 1):
                x = (xyz[i, 0] - move[j, 0] - ox) * inv
                y = (xyz[i, 1] - move[j, 1] - oy) * inv
                if x >= 0.0 and y >= 0.0 and x < res and y < res:
                    at = int(y) * res + int(x)
                    if near_id[at] >= 0 and xyz[i, 2] - move[j, 2] - near_z[at] > bias:
                        expo[a + i] = 0.0
                        break
    return expo


@njit(inline="always")
def _dot(rows, i, axis):
    """``rows[i] . axis`` (3-vectors)."""
    return rows[i, 0] * axis[0] + rows[i, 1] * axis[1] + rows[i, 2] * axis[2]


@njit(inline="always")
def _box_bits(occ, box, res, W, on):
    """Set (``on``) or clear the occupancy bits of the pixels of ``box`` ``(lo_x, hi_x,
    lo_y, hi_y)``, by rows and by columns (:func:`growsim.kernels.light.shadow_scratch`)."""
    lo_x, hi_x, lo_y, hi_y = box
    for yi in range(lo_y, hi_y + 1):
        for xi in range(lo_x, hi_x + 1):
            if on:
                occ[yi * W + (xi >> 6)] |= np.uint64(1) << np.uint64(xi & 63)
                occ[(res + xi) * W + (yi >> 6)] |= np.uint64(1) << np.uint64(yi & 63)
            else:
                occ[yi * W + (xi >> 6)] = 0
                occ[(res + xi) * W + (yi >> 6)] = 0


@njit
def among_copies(points, point_offsets, frames, grid, shifts):
    """The queries that judge ``points`` ``(c, 3)`` (plant ``p`` owning
    ``point_offsets[p]:point_offsets[p + 1]``) among each plant's copies moved by
    ``shifts`` ``(k, 3)``: each point itself, then ``point - shifts[j]`` for each copy
    whose moved point falls in the plant's frame (``frames``, ``grid`` ``(u, v, res)``;
    with a pixel of margin: a point outside is in the open). Returns ``(queries (c', 3),
    query_offsets (P + 1,), src (c',))``, ``src`` the point each query judges.

    Examples
    --------
    >>> import numpy as np
    >>> u, v = np.array([1.0, 0, 0]), np.array([0.0, 0, -1])
    >>> frames = np.array([[0.0, -1.0, 1 / 32]])  # a frame 2 m across, 64 pixels
    >>> q, q_off, src = among_copies(np.array([[0.5, 0, 0]]), np.array([0, 1]), frames,
    ...                              (u, v, 64), np.array([[0.25, 0, 0], [5.0, 0, 0]]))
    >>> q.tolist(), q_off.tolist(), src.tolist()  # the copy 5 m away is out of the frame
    ([[0.5, 0.0, 0.0], [0.25, 0.0, 0.0]], [0, 2], [0, 0])
    """
    u, v, res = grid
    c, k = points.shape[0], shifts.shape[0]
    P = point_offsets.shape[0] - 1
    su = np.empty(k)
    sv = np.empty(k)
    for j in range(k):
        su[j], sv[j] = _dot(shifts, j, u), _dot(shifts, j, v)
    queries = np.empty((c * (k + 1), 3))
    src = np.empty(c * (k + 1), np.int64)
    offsets = np.empty(P + 1, np.int64)
    n = 0
    for p in range(P):
        offsets[p] = n
        ox, oy, inv = frames[p, 0], frames[p, 1], 1.0 / frames[p, 2]
        for i in range(point_offsets[p], point_offsets[p + 1]):
            x, y = _dot(points, i, u), _dot(points, i, v)
            for j in range(k + 1):
                if j > 0:
                    xj = (x - su[j - 1] - ox) * inv
                    yj = (y - sv[j - 1] - oy) * inv
                    if xj < -1.0 or yj < -1.0 or xj > res + 1.0 or yj > res + 1.0:
                        continue
                for a in range(3):
                    queries[n, a] = points[i, a] - (shifts[j - 1, a] if j > 0 else 0.0)
                src[n] = i
                n += 1
    offsets[P] = n
    return queries[:n], offsets, src[:n]
