"""Numba kernels of the OpenGL shadow-map backend's CPU side (:mod:`growsim.env.shadow_gl`):
the capsules' vertices, the samples' texels and the final depth test.

The GPU renders every plant's hard shadow map into one tile of an atlas (``cols`` tiles a
row, ``res`` x ``res`` texels each, the atlas ``width`` texels wide): plant ``p`` of a
batch starting at plant ``p0`` has tile ``p - p0``, its origin at texel ``((tile % cols)
res, (tile // cols) res)``. The frames are :func:`growsim.kernels.light.plant_frames`'
and the arithmetic of a point's pixel is the numba kernels' (every sample picks the same
pixel as there). The map stores each plant's depths normalised to ``[0, 1/2]`` over the
plant's own depth range (:func:`depth_ranges`), so that the cleared value 1 means empty.

State is passed as tuples: ``segments`` ``(start, end, radius, offsets)`` and ``plane``
``(u, v, d)`` as in :mod:`growsim.kernels.light`; ``batch`` ``(p0, p1, c0, c1)``: the
plants ``p0:p1`` of the batch and the items (segments or points) ``c0:c1`` of the call;
``atlas`` ``(cols, res, width)``. The oracle is ``tests/naive/shadow_gl.py``.
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.capsule import project_segment
from growsim.kernels.config import njit

__all__ = [
    "VERTEX_FLOATS",
    "depth_ranges",
    "point_queries",
    "resolve_exposure",
    "segment_queries",
    "texel",
    "tile_vertices",
]

#: vertex layout: ax, ay, bx, by, za, zb (normalised depths), R, tile x, tile y, id
VERTEX_FLOATS = 10


@njit
def depth_ranges(start, end, offsets, d, p0, p1, zinfo):
    """``zinfo[p] = (zmin, 2 (zmax - zmin))`` over plant ``p``'s segment ends (``p0 <= p <
    p1``), their depths along ``d``: the map stores ``(z - zmin) / zinfo[p, 1]``, in
    ``[0, 1/2]`` (``(0, 0)`` for a plant of no segments, ``zinfo[p, 1] = 0`` for one of no
    depth). Returns ``zinfo``.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0, 3, 0]]); e = np.zeros((2, 3))
    >>> depth_ranges(s, e, np.array([0, 2]), np.array([0.0, -1, 0]), 0, 1,
    ...              np.empty((1, 2))).tolist()
    [[-3.0, 6.0]]
    """
    for p in range(p0, p1):
        lo = np.inf
        hi = -np.inf
        for s in range(offsets[p], offsets[p + 1]):
            za = start[s, 0] * d[0] + start[s, 1] * d[1] + start[s, 2] * d[2]
            zb = end[s, 0] * d[0] + end[s, 1] * d[1] + end[s, 2] * d[2]
            lo = min(lo, za, zb)
            hi = max(hi, za, zb)
        zinfo[p, 0] = lo if lo < np.inf else 0.0
        zinfo[p, 1] = 2.0 * (hi - lo) if hi > lo else 0.0
    return zinfo


@njit
def tile_vertices(segments, frames, plane, batch, atlas, zinfo, out, out_id):
    """The 4 vertices of each segment ``c0 <= k < c1`` (of plants ``p0:p1``, ``batch``
    ``(p0, p1, c0, c1)``): rows ``4 (k - c0) + corner`` of ``out`` (float32,
    :data:`VERTEX_FLOATS` columns, all four alike; ``out_id`` the same memory as int32):
    ``ax, ay, bx, by`` (pixels in the tile), ``za, zb`` (depths normalised by ``zinfo``,
    :func:`depth_ranges`), ``R`` (the radius in pixels), the tile's origin in the atlas
    (``atlas`` ``(cols, res, width)``) and ``k`` (in ``out_id``).

    Examples
    --------
    >>> import numpy as np
    >>> s, e, r = np.zeros((1, 3)), np.array([[2.0, 0, 0]]), np.array([0.5])
    >>> plane = (np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0]))
    >>> frames, zinfo = np.array([[-1.0, -1.0, 0.5]]), np.array([[0.0, 0.0]])
    >>> out = np.empty((4, VERTEX_FLOATS), np.float32)
    >>> tile_vertices((s, e, r, np.array([0, 1])), frames, plane, (0, 1, 0, 1), (1, 8, 8),
    ...               zinfo, out, out.view(np.int32))
    >>> out[0, :7].tolist(), int(out.view(np.int32)[3, 9])
    ([2.0, 2.0, 6.0, 2.0, 0.0, 0.0, 1.0], 0)
    """
    start, end, radius, offsets = segments
    u, v, d = plane
    p0, p1, c0, c1 = batch
    cols, res = atlas[0], atlas[1]
    for p in range(p0, p1):
        k0 = max(offsets[p], c0)
        k1 = min(offsets[p + 1], c1)
        if k1 <= k0:
            continue
        ox, oy, inv = frames[p, 0], frames[p, 1], 1.0 / frames[p, 2]
        zmin = zinfo[p, 0]
        scale = 1.0 / zinfo[p, 1] if zinfo[p, 1] > 0.0 else 0.0
        tile = p - p0
        tx = float((tile % cols) * res)
        ty = float((tile // cols) * res)
        for k in range(k0, k1):
            ax, ay, bx, by, za, zb = project_segment(start, end, k, u, v, d, ox, oy, inv)
            rr = radius[k] * inv
            for c in range(4 * (k - c0), 4 * (k - c0) + 4):
                out[c, 0] = ax
                out[c, 1] = ay
                out[c, 2] = bx
                out[c, 3] = by
                out[c, 4] = (za - zmin) * scale
                out[c, 5] = (zb - zmin) * scale
                out[c, 6] = rr
                out[c, 7] = tx
                out[c, 8] = ty
                out_id[c, 9] = k


@njit
def texel(pu, pv, frame, res, tx, ty, width):
    """Atlas texel (``y * width + x``) of a point given in image-plane coordinates ``(pu,
    pv)``, in the tile at ``(tx, ty)`` of a plant's ``frame`` ``(ox, oy, pix)``; -1
    outside the frame (the same arithmetic as the numba kernels' pixel).

    Examples
    --------
    >>> import numpy as np
    >>> frame = np.array([-1.0, -1.0, 0.5])
    >>> texel(0.2, 0.9, frame, 8, 8, 0, 16), texel(5.0, 0.0, frame, 8, 8, 0, 16)
    (58, -1)
    """
    inv = 1.0 / frame[2]
    x = (pu - frame[0]) * inv
    y = (pv - frame[1]) * inv
    if not (x >= 0.0 and y >= 0.0 and x < res and y < res):
        return -1
    return (ty + int(y)) * width + tx + int(x)


@njit(inline="always")
def _tile_origin(tile, cols, res):
    """The texel origin ``(tx, ty)`` of a batch's ``tile``-th map in an atlas of ``cols``
    columns of ``res x res`` maps."""
    return (tile % cols) * res, (tile // cols) * res


@njit
def segment_queries(segments, frames, plane, batch, atlas, samples, q, z):
    """The samples of segments ``c0 <= s < c1`` (of plants ``p0:p1``), ``samples`` per
    segment at ``t = (k + 0.5) / samples`` of its axis: row ``i = (s - c0) samples + k``
    holds ``q[i] = (texel, s)`` (:func:`texel`) and the sample's depth ``z[i]``.

    Examples
    --------
    >>> import numpy as np
    >>> s, e, r = np.zeros((1, 3)), np.array([[2.0, 0, 0]]), np.array([0.5])
    >>> plane = (np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0]))
    >>> q, z = np.empty((2, 2), np.int32), np.empty(2)
    >>> segment_queries((s, e, r, np.array([0, 1])), np.array([[-1.0, -1.0, 0.5]]), plane,
    ...                 (0, 1, 0, 1), (1, 8, 8), 2, q, z)
    >>> q.tolist(), z.tolist()
    ([[19, 0], [21, 0]], [0.0, 0.0])
    """
    start, end, _, offsets = segments
    u, v, d = plane
    p0, p1, c0, c1 = batch
    cols, res, width = atlas
    for p in range(p0, p1):
        s0, s1 = max(offsets[p], c0), min(offsets[p + 1], c1)
        if s1 <= s0:
            continue
        frame = frames[p]
        tx, ty = _tile_origin(p - p0, cols, res)
        for s in range(s0, s1):
            for k in range(samples):
                t = (k + 0.5) / samples
                qx = start[s, 0] + t * (end[s, 0] - start[s, 0])
                qy = start[s, 1] + t * (end[s, 1] - start[s, 1])
                qz = start[s, 2] + t * (end[s, 2] - start[s, 2])
                pu = qx * u[0] + qy * u[1] + qz * u[2]
                pv = qx * v[0] + qy * v[1] + qz * v[2]
                i = (s - c0) * samples + k
                q[i, 0] = texel(pu, pv, frame, res, tx, ty, width)
                q[i, 1] = s
                z[i] = qx * d[0] + qy * d[1] + qz * d[2]


@njit
def point_queries(points, point_offsets, frames, plane, batch, atlas, q, z):
    """The points ``c0 <= m < c1`` (of plants ``p0:p1``; plant ``p`` owns
    ``point_offsets[p]:point_offsets[p + 1]``): row ``m - c0`` holds ``q = (texel, -1)``
    (:func:`texel`) and the point's depth ``z``.

    Examples
    --------
    >>> import numpy as np
    >>> plane = (np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0]))
    >>> q, z = np.empty((2, 2), np.int32), np.empty(2)
    >>> point_queries(np.array([[0.5, 1, 0], [9, 0, 0]]), np.array([0, 2]),
    ...               np.array([[-1.0, -1.0, 0.5]]), plane, (0, 1, 0, 2), (1, 8, 8), q, z)
    >>> q.tolist(), z.tolist()
    ([[19, -1], [-1, -1]], [-1.0, 0.0])
    """
    u, v, d = plane
    p0, p1, c0, c1 = batch
    cols, res, width = atlas
    for p in range(p0, p1):
        m0, m1 = max(point_offsets[p], c0), min(point_offsets[p + 1], c1)
        if m1 <= m0:
            continue
        frame = frames[p]
        tx, ty = _tile_origin(p - p0, cols, res)
        for m in range(m0, m1):
            pu = points[m, 0] * u[0] + points[m, 1] * u[1] + points[m, 2] * u[2]
            pv = points[m, 0] * v[0] + points[m, 1] * v[1] + points[m, 2] * v[2]
            q[m - c0, 0] = texel(pu, pv, frame, res, tx, ty, width)
            q[m - c0, 1] = -1
            z[m - c0] = points[m, 0] * d[0] + points[m, 1] * d[1] + points[m, 2] * d[2]


@njit
def resolve_exposure(val, z, offsets, frames, zinfo, bias_pixels, batch, per, out):
    """Exposures ``out[s]`` of the items ``c0 <= s < c1`` (of plants ``p0:p1``; segments
    with ``per`` samples each, or points, ``per = 1``; ``offsets`` the items' offsets by
    plant) from the query pass's values ``val`` (2: lit, else the pixel's normalised
    depth) and the samples' depths ``z``: a sample is lit when ``z - depth <= bias_pixels
    pix``, ``depth`` back in world units (``zmin + val zinfo[p, 1]``); an item's exposure
    is the share of its samples lit.

    Examples
    --------
    >>> import numpy as np
    >>> val, z = np.array([2.0, 0.25]), np.array([0.0, 5.0])
    >>> out = np.empty(2)
    >>> resolve_exposure(val, z, np.array([0, 2]), np.array([[0.0, 0.0, 1.0]]),
    ...                  np.array([[0.0, 4.0]]), 0.5, (0, 1, 0, 2), 1, out)
    >>> out.tolist()
    [1.0, 0.0]
    """
    p0, p1, c0, c1 = batch
    for p in range(p0, p1):
        s0 = max(offsets[p], c0)
        s1 = min(offsets[p + 1], c1)
        zmin = zinfo[p, 0]
        span = zinfo[p, 1]
        bias = bias_pixels * frames[p, 2]
        for s in range(s0, s1):
            e = 0.0
            for k in range(per):
                i = (s - c0) * per + k
                w = val[i]
                if w > 1.5 or z[i] - (zmin + w * span) <= bias:
                    e += 1.0
            out[s] = e / per
