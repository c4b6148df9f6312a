"""Numba kernels of the shadow-map light (:mod:`growsim.env.light`).

Framing
-------
Each plant (segments ``offsets[k]:offsets[k + 1]``) gets its own square raster across the
light's direction ``d`` (unit), on the image plane ``(u, v)``: :func:`plant_frames` gives
``(ox, oy, pix)`` per plant, and a point ``p`` falls at pixel coordinates
``x = (p . u - ox) / pix``, ``y = (p . v - oy) / pix`` (pixel ``(i, j) = (floor(y),
floor(x))``), at depth ``z = p . d`` (nearer to the light = smaller). The frame is the
plant's projected bounding box grown by its largest radius, ``resolution`` pixels across
with one pixel of margin each side, as :func:`growsim.env.light.projected_area` frames a
shadow. Every backend (this one, :mod:`growsim.env.shadow_gl`) uses these frames.

Coverage and depth
------------------
Every segment is a capsule of its radius (in pixels ``r = radius / pix``): it covers the
pixels whose centre lies within ``r`` of its projected axis, and the depth it gives a
pixel is the depth of its axis at the point nearest the pixel centre. Sampling pixel
centres at the true radius estimates each shadow's area without bias (a segment thinner
than a pixel covers some pixels or none, in proportion to its width); a minimum width of
a pixel, as silhouettes use, would darken plants of thin twigs (measured in
``docs/environment.md``). Each capsule is walked line by line along its longer extent
(rows, or columns for a segment wider than tall) over exactly the pixels of the line's
chord of the capsule, computed in closed form, so a plant costs the pixels its segments
cover. Oracle: ``tests/naive/light.py``'s ``render_depth``, pixel by pixel.

Hard shadows (:func:`segment_exposure_kernel`, :func:`point_exposure_kernel`): a z-buffer
keeps each pixel's nearest depth and segment. A point at depth ``z`` in pixel ``(i, j)``
is lit (exposure 1) when the pixel is empty, when its nearest segment is the point's own
segment, or when ``z - depth[i, j] <= bias`` (``bias = bias_pixels * pix``); else 0.

Soft shadows (:func:`soft_segment_exposure_kernel`, :func:`soft_point_exposure_kernel`):
a deep shadow map keeps, per pixel, every segment covering it and its depth there (a
linked list of fragments). A point's exposure is the product of the transmissions
``trans[s]`` of the other segments ``s`` lying in front of it at its pixel by more than
the bias: ``exp(-sum k_s)``, ``k_s = -ln trans[s]``. With every ``trans -> 0`` it is 0
when anything else lies in front: the binary map, except that a steep segment whose own
nearest depth at the pixel is in front of an occluder does not shield its point here.

Maps are never cleared between plants (a z-buffer pixel whose segment id is below the
plant's first segment is empty; the deep map stamps its pixels with the plant's number),
so a population costs what its segments cover, not ``resolution`` squared per plant.
Plants never shade each other.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.raster import _iceil, _ifloor

__all__ = [
    "plant_frames",
    "point_exposure_kernel",
    "segment_cosines",
    "segment_exposure_kernel",
    "soft_point_exposure_kernel",
    "soft_segment_exposure_kernel",
]


@njit
def plant_frames(start, end, radius, offsets, u, v, res):
    """``(k, 3)`` float64: each plant's raster frame ``(ox, oy, pix)`` (see the module).

    A plant with no segments gets ``(0, 0, 1)``; one whose shadow is a single point (no
    width, seen end on) gets pixel size 1.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((1, 3)); e = np.array([[4.0, 0, 0]])
    >>> u, v = np.array([1.0, 0, 0]), np.array([0.0, 0, -1])
    >>> plant_frames(s, e, np.array([0.5]), np.array([0, 1]), u, v, 12).tolist()
    [[-1.0, -1.0, 0.5]]
    """
    k = offsets.shape[0] - 1
    out = np.empty((k, 3))
    for p in range(k):
        s0 = offsets[p]
        s1 = offsets[p + 1]
        if s1 <= s0:
            out[p, 0] = 0.0
            out[p, 1] = 0.0
            out[p, 2] = 1.0
            continue
        lox = np.inf
        loy = np.inf
        hix = -np.inf
        hiy = -np.inf
        rmax = 0.0
        for s in range(s0, s1):
            for q in range(2):
                pt = start if q == 0 else end
                x = pt[s, 0] * u[0] + pt[s, 1] * u[1] + pt[s, 2] * u[2]
                y = pt[s, 0] * v[0] + pt[s, 1] * v[1] + pt[s, 2] * v[2]
                lox = min(lox, x)
                hix = max(hix, x)
                loy = min(loy, y)
                hiy = max(hiy, y)
            rmax = max(rmax, radius[s])
        size = max(hix - lox, hiy - loy) + 2.0 * rmax
        pix = size / (res - 2) if size > 0.0 else 1.0
        out[p, 0] = lox - rmax - pix
        out[p, 1] = loy - rmax - pix
        out[p, 2] = pix
    return out


@njit(inline="always")
def _setup(ax, ay, bx, by, rr, res):
    """The walk of a capsule (axis ``a-b`` in pixels, radius ``rr``) along its longer
    extent: ``tr`` (walk columns: x and y are swapped, and so are the pixel's indices),
    the swapped ends, the radius, the first and last line, ``dx, dy, 1 / L2`` and the
    body's chord per line (see :func:`_span`)."""
    tr = abs(bx - ax) > abs(by - ay)
    if tr:
        ax, ay = ay, ax
        bx, by = by, bx
    r = rr
    i0 = max(0, _iceil(min(ay, by) - r - 0.5, res))
    i1 = min(res - 1, _ifloor(max(ay, by) + r - 0.5, res))
    dx = bx - ax
    dy = by - ay
    L2 = dx * dx + dy * dy
    inv_L2 = 1.0 / L2 if L2 > 0.0 else 0.0
    # along the longer extent |dy| >= |dx|, and dy = 0 only for a point (no body)
    slope = dx / dy if dy != 0.0 else 0.0
    half = r * math.sqrt(L2) / abs(dy) if dy != 0.0 else -1.0
    # 0 <= t <= 1 on the line e = yc - ay: e dy in [-(x - ax) dx, L2 - (x - ax) dx]
    cap = -dy / dx if dx != 0.0 else 0.0
    cap_w = L2 / dx if dx != 0.0 else 0.0
    return tr, ax, ay, bx, by, r, i0, i1, dx, dy, L2, inv_L2, slope, half, cap, cap_w


@njit(inline="always")
def _span(i, ax, ay, bx, by, r, dx, dy, L2, slope, half, cap, cap_w, res):
    """Columns ``j0..j1`` of line ``i`` whose centres lie within ``r`` of the axis (the
    line's chord of the capsule: the union of the two end discs and the body, an interval
    because the capsule is convex; ``j0 > j1`` when the line misses it). With
    ``e = yc - ay`` the body is ``|perpendicular| <= r``: ``x in ax + e dx / dy +- r L /
    |dy|``, and ``0 <= t <= 1``: ``x`` between ``ax - e dy / dx`` and that plus
    ``L2 / dx`` (for ``dx = 0``: ``0 <= e dy <= L2``)."""
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
    if not lo <= hi:
        return 1, 0
    return max(0, _iceil(lo - 0.5, res)), min(res - 1, _ifloor(hi - 0.5, res))


@njit
def _zbuffer_walk(k, ax, ay, bx, by, za, zb, rr, res, depth, ids, first):
    """Rasterise segment ``k`` (pixel coordinates ``a``, ``b``, depths ``za``, ``zb``,
    radius ``rr`` pixels) into the z-buffer ``depth``/``ids``: every pixel whose centre
    lies within the radius of the axis, walked line
    by line along the segment's longer extent over exactly the columns it covers; a pixel
    whose id is below ``first`` (the plant's first segment) is empty."""
    tr, ax, ay, bx, by, r, i0, i1, dx, dy, L2, inv_L2, slope, half, cap, cap_w = _setup(
        ax, ay, bx, by, rr, res
    )
    for i in range(i0, i1 + 1):
        j0, j1 = _span(i, ax, ay, bx, by, r, dx, dy, L2, slope, half, cap, cap_w, res)
        e = (i + 0.5 - ay) * dy
        for j in range(j0, j1 + 1):
            t = ((j + 0.5 - ax) * dx + e) * inv_L2
            t = min(1.0, max(0.0, t))
            z = za + t * (zb - za)
            pi = j if tr else i
            pj = i if tr else j
            if ids[pi, pj] < first or z < depth[pi, pj]:
                depth[pi, pj] = z
                ids[pi, pj] = k


@njit
def _deep_walk(k, ax, ay, bx, by, za, zb, rr, res, head, stamp, cur, frag):
    """Rasterise segment ``k`` as :func:`_zbuffer_walk` does, appending a fragment per
    pixel to the deep map (list heads ``head``, pixels stamped ``cur``: see
    :func:`_deep_put`). Returns the fragment buffers."""
    tr, ax, ay, bx, by, r, i0, i1, dx, dy, L2, inv_L2, slope, half, cap, cap_w = _setup(
        ax, ay, bx, by, rr, res
    )
    for i in range(i0, i1 + 1):
        j0, j1 = _span(i, ax, ay, bx, by, r, dx, dy, L2, slope, half, cap, cap_w, res)
        e = (i + 0.5 - ay) * dy
        for j in range(j0, j1 + 1):
            t = ((j + 0.5 - ax) * dx + e) * inv_L2
            t = min(1.0, max(0.0, t))
            z = za + t * (zb - za)
            frag = _deep_put(frag, j if tr else i, i if tr else j, z, k, head, stamp, cur)
    return frag


@njit(inline="always")
def _deep_put(frag, i, j, z, k, head, stamp, cur):
    """Append the fragment ``(z, k)`` to pixel ``(i, j)``'s list: ``head[i, j]`` is the
    pixel's last fragment (valid where ``stamp == cur``), ``frag = (fz, fk, fnext, count)``
    the fragment arrays (grown by doubling)."""
    fz, fk, fnext, count = frag
    if count[0] == fz.shape[0]:
        m = 2 * fz.shape[0]
        gz = np.empty(m)
        gk = np.empty(m, np.int64)
        gn = np.empty(m, np.int64)
        gz[: count[0]] = fz[: count[0]]
        gk[: count[0]] = fk[: count[0]]
        gn[: count[0]] = fnext[: count[0]]
        fz, fk, fnext = gz, gk, gn
    c = count[0]
    fz[c] = z
    fk[c] = k
    fnext[c] = head[i, j] if stamp[i, j] == cur else -1
    stamp[i, j] = cur
    head[i, j] = c
    count[0] = c + 1
    return fz, fk, fnext, count


@njit
def _empty_frags():
    return np.empty(1024), np.empty(1024, np.int64), np.empty(1024, np.int64), np.zeros(1, np.int64)


@njit
def _render(start, end, radius, s0, s1, u, v, d, frame, res, depth, ids, stamp, cur, deep,
            frag):  # fmt: skip
    """Render segments ``s0:s1`` in the plant's ``frame``: into the z-buffer
    ``depth``/``ids`` (pixels whose id is below ``s0`` are empty), or (``deep``) into the
    deep map (``ids`` holds the lists' heads, pixels stamped ``cur``, see
    :func:`_deep_put`). Returns the fragment buffers."""
    ox, oy, inv = frame[0], frame[1], 1.0 / frame[2]
    for k in range(s0, s1):
        ax = (start[k, 0] * u[0] + start[k, 1] * u[1] + start[k, 2] * u[2] - ox) * inv
        ay = (start[k, 0] * v[0] + start[k, 1] * v[1] + start[k, 2] * v[2] - oy) * inv
        bx = (end[k, 0] * u[0] + end[k, 1] * u[1] + end[k, 2] * u[2] - ox) * inv
        by = (end[k, 0] * v[0] + end[k, 1] * v[1] + end[k, 2] * v[2] - oy) * inv
        za = start[k, 0] * d[0] + start[k, 1] * d[1] + start[k, 2] * d[2]
        zb = end[k, 0] * d[0] + end[k, 1] * d[1] + end[k, 2] * d[2]
        if deep:
            frag = _deep_walk(k, ax, ay, bx, by, za, zb, radius[k] * inv, res, ids, stamp, cur,
                              frag)  # fmt: skip
        else:
            _zbuffer_walk(k, ax, ay, bx, by, za, zb, radius[k] * inv, res, depth, ids, s0)
    return frag


@njit
def _pixel(px, py, pz, frame, res):
    """Pixel ``(i, j)`` of a point given in image-plane coordinates; ``(-1, -1)`` outside
    the frame."""
    inv = 1.0 / frame[2]
    x = (px - frame[0]) * inv
    y = (py - frame[1]) * inv
    if not (x >= 0.0 and y >= 0.0 and x < res and y < res):
        return -1, -1
    return int(y), int(x)


@njit
def _hard(i, j, pz, own, bias, depth, ids, first):
    """Hard-shadow exposure (0 or 1) of a point at depth ``pz`` in pixel ``(i, j)`` of the
    z-buffer of the plant whose first segment is ``first``."""
    if i < 0 or ids[i, j] < first or ids[i, j] == own:
        return 1.0
    return 1.0 if pz - depth[i, j] <= bias else 0.0


@njit
def _soft(i, j, pz, own, bias, head, stamp, cur, frag, trans):
    """Soft-shadow exposure of a point: the product of the transmissions of the other
    segments in front of it by more than ``bias`` at pixel ``(i, j)``."""
    if i < 0 or stamp[i, j] != cur:
        return 1.0
    fz, fk, fnext, _ = frag
    e = 1.0
    f = head[i, j]
    while f >= 0:
        if fk[f] != own and fz[f] < pz - bias:
            e *= trans[fk[f]]
        f = fnext[f]
    return e


@njit
def _buffers(res):
    """The maps' buffers: depth, segment ids (or the deep map's list heads; -1: empty) and
    the stamp of the plant that last wrote each pixel of the deep map. They are never
    cleared between plants: a z-buffer pixel whose id is below the plant's first segment,
    or a deep-map pixel stamped by another plant, is empty."""
    depth = np.empty((res, res), np.float64)
    ids = np.full((res, res), -1, np.int64)
    stamp = np.full((res, res), -1, np.int64)
    return depth, ids, stamp


@njit
def _segments(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, samples,
              trans, deep, out):  # fmt: skip
    depth, ids, stamp = _buffers(res)
    frag = _empty_frags()
    head = ids  # the deep map's list heads live in the ids buffer
    for p in range(offsets.shape[0] - 1):
        s0 = offsets[p]
        s1 = offsets[p + 1]
        frame = frames[p]
        if deep:
            frag[3][0] = 0
        frag = _render(start, end, radius, s0, s1, u, v, d, frame, res, depth, ids, stamp, p,
                       deep, frag)  # fmt: skip
        bias = bias_pixels * frame[2]
        for s in range(s0, s1):
            e = 0.0
            for q in range(samples):
                t = (q + 0.5) / samples
                qx = start[s, 0] + t * (end[s, 0] - start[s, 0])
                qy = start[s, 1] + t * (end[s, 1] - start[s, 1])
                qz = start[s, 2] + t * (end[s, 2] - start[s, 2])
                pu = qx * u[0] + qy * u[1] + qz * u[2]
                pv = qx * v[0] + qy * v[1] + qz * v[2]
                pz = qx * d[0] + qy * d[1] + qz * d[2]
                i, j = _pixel(pu, pv, pz, frame, res)
                if deep:
                    e += _soft(i, j, pz, s, bias, head, stamp, p, frag, trans)
                else:
                    e += _hard(i, j, pz, s, bias, depth, ids, s0)
            out[s] = e / samples
    return out


@njit
def _points(start, end, radius, offsets, frames, points, point_offsets, u, v, d, res,
            bias_pixels, trans, deep, out):  # fmt: skip
    depth, ids, stamp = _buffers(res)
    frag = _empty_frags()
    head = ids
    for p in range(offsets.shape[0] - 1):
        frame = frames[p]
        if deep:
            frag[3][0] = 0
        frag = _render(start, end, radius, offsets[p], offsets[p + 1], u, v, d, frame, res,
                       depth, ids, stamp, p, deep, frag)  # fmt: skip
        bias = bias_pixels * frame[2]
        for m in range(point_offsets[p], point_offsets[p + 1]):
            pu = points[m, 0] * u[0] + points[m, 1] * u[1] + points[m, 2] * u[2]
            pv = points[m, 0] * v[0] + points[m, 1] * v[1] + points[m, 2] * v[2]
            pz = points[m, 0] * d[0] + points[m, 1] * d[1] + points[m, 2] * d[2]
            i, j = _pixel(pu, pv, pz, frame, res)
            if deep:
                out[m] = _soft(i, j, pz, -1, bias, head, stamp, p, frag, trans)
            else:
                out[m] = _hard(i, j, pz, -1, bias, depth, ids, offsets[p])
    return out


@njit
def segment_exposure_kernel(start, end, radius, offsets, frames, u, v, d, res, bias_pixels,
                            samples, out):  # fmt: skip
    """Hard shadows: each segment's share of its ``samples`` points (at ``t = (q + 0.5) /
    samples`` of its axis) that are lit, one z-buffer per plant.

    ``start, end`` ``(n, 3)``, ``radius`` ``(n,)`` float64; ``offsets`` ``(k + 1,)`` int64;
    ``frames`` ``(k, 3)`` from :func:`plant_frames`; ``u, v, d`` ``(3,)`` the image plane
    and the unit direction the light travels; ``res`` pixels across; ``bias_pixels`` the
    depth bias in pixels; ``out`` ``(n,)`` float64, overwritten and returned.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0, 0, 0]]); e = np.array([[1.0, 1, 0], [1, 0, 0]])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> r, off = np.full(2, 0.2), np.array([0, 2])
    >>> f = plant_frames(s, e, r, off, u, v, 64)
    >>> segment_exposure_kernel(s, e, r, off, f, u, v, d, 64, 1.5, 1, np.empty(2)).tolist()
    [1.0, 0.0]
    """
    return _segments(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, samples,
                     np.empty(0), False, out)  # fmt: skip


@njit
def soft_segment_exposure_kernel(start, end, radius, offsets, frames, u, v, d, res,
                                 bias_pixels, samples, trans, out):  # fmt: skip
    """Soft shadows: each segment's mean, over its samples, of the product of the
    transmissions ``trans`` ``(n,)`` of the other segments in front of the sample (a deep
    shadow map per plant). Other arguments as :func:`segment_exposure_kernel`.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 2, 0], [0, 1, 0], [0, 0, 0]])
    >>> e = s + np.array([1.0, 0, 0])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> r, off = np.full(3, 0.2), np.array([0, 3])
    >>> f = plant_frames(s, e, r, off, u, v, 64)
    >>> soft_segment_exposure_kernel(s, e, r, off, f, u, v, d, 64, 1.5, 1, np.full(3, 0.5),
    ...                              np.empty(3)).tolist()
    [1.0, 0.5, 0.25]
    """
    return _segments(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, samples,
                     trans, True, out)  # fmt: skip


@njit
def point_exposure_kernel(start, end, radius, offsets, frames, points, point_offsets, u, v, d,
                          res, bias_pixels, out):  # fmt: skip
    """Hard shadows at points: ``out[m]`` is 1 when point ``m`` (of plant ``p``:
    ``point_offsets[p] <= m < point_offsets[p + 1]``) is lit in plant ``p``'s map, else 0
    (outside the frame or on an empty pixel: lit).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]]); r = np.array([0.2])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> off = np.array([0, 1]); f = plant_frames(s, e, r, off, u, v, 64)
    >>> pts = np.array([[0.5, 0, 0], [0.5, 2, 0], [3, 0, 0]])
    >>> point_exposure_kernel(s, e, r, off, f, pts, np.array([0, 3]), u, v, d, 64, 1.5,
    ...                       np.empty(3)).tolist()
    [0.0, 1.0, 1.0]
    """
    return _points(start, end, radius, offsets, frames, points, point_offsets, u, v, d, res,
                   bias_pixels, np.empty(0), False, out)  # fmt: skip


@njit
def soft_point_exposure_kernel(start, end, radius, offsets, frames, points, point_offsets, u,
                               v, d, res, bias_pixels, trans, out):  # fmt: skip
    """Soft shadows at points: the product of the transmissions of the segments in front
    of each point (see :func:`soft_segment_exposure_kernel`).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 2, 0], [0, 1, 0]]); e = s + np.array([1.0, 0, 0])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> r, off = np.full(2, 0.2), np.array([0, 2]); f = plant_frames(s, e, r, off, u, v, 64)
    >>> soft_point_exposure_kernel(s, e, r, off, f, np.array([[0.5, 0, 0]]), np.array([0, 1]),
    ...     u, v, d, 64, 1.5, np.full(2, 0.1), np.empty(1)).round(6).tolist()
    [0.01]
    """
    return _points(start, end, radius, offsets, frames, points, point_offsets, u, v, d, res,
                   bias_pixels, trans, True, out)  # fmt: skip


@njit
def segment_cosines(start, end, normal, use_normal, d, out):
    """Lambert's cosine per segment for the light travelling along unit ``d``:
    ``|normal . d|`` where ``use_normal`` (a blade with a unit ``normal``, two-sided), else
    the side of a cylinder, ``sqrt(1 - (axis . d)^2)`` (1 for a segment of no length).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((2, 3)); e = np.array([[1.0, 0, 0], [0, 1, 0]])
    >>> segment_cosines(s, e, np.zeros((2, 3)), np.zeros(2, np.bool_), np.array([0.0, -1, 0]),
    ...                 np.empty(2)).tolist()
    [1.0, 0.0]
    """
    for s in range(start.shape[0]):
        if use_normal[s]:
            out[s] = abs(normal[s, 0] * d[0] + normal[s, 1] * d[1] + normal[s, 2] * d[2])
            continue
        ex = end[s, 0] - start[s, 0]
        ey = end[s, 1] - start[s, 1]
        ez = end[s, 2] - start[s, 2]
        L = math.sqrt(ex * ex + ey * ey + ez * ez)
        if L > 0.0:
            ad = (ex * d[0] + ey * d[1] + ez * d[2]) / L
            out[s] = math.sqrt(max(0.0, 1.0 - ad * ad))
        else:
            out[s] = 1.0
    return out
