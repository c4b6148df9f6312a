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
``docs/environment.md``). Each capsule is walked line by line along its shorter extent
(rows, or columns for a segment taller than wide) over exactly the pixels of the line's
chord of the capsule, computed in closed form.

The map is read only where it is queried: each plant's query points (segment samples or
given points) are listed per pixel first, and a capsule's pixel is judged only when it
holds queries, so a plant costs its segments' walks and its queries, not a whole map's
writes. The answers are those of the whole map at the pixels read (tested against a
pixel-by-pixel z-buffer, ``tests/naive/light.py``'s ``render_depth``,
:func:`map_depth_kernel` read at every pixel centre).

Hard shadows (:func:`segment_exposure_kernel`, :func:`point_exposure_kernel`): the map
keeps each pixel's nearest depth and segment (the first drawn on a tie, as a z-buffer). A
point at depth ``z`` in pixel ``(i, j)`` is lit (exposure 1) when the pixel is empty, when
its nearest segment is the point's own segment, or when ``z - depth[i, j] <= bias``
(``bias = bias_pixels * pix``); else 0. Points outside the frame are lit.

Soft shadows (:func:`soft_segment_exposure_kernel`, :func:`soft_point_exposure_kernel`):
the deep map (every segment covering a pixel, at its depth there). A point's exposure is
the product of the transmissions ``trans[s]`` of the other segments ``s`` lying in front
of it at its pixel by more than the bias: ``exp(-sum k_s)``, ``k_s = -ln trans[s]``. With
every ``trans -> 0`` it is 0 when anything else lies in front: the binary map, except
that a steep segment whose own nearest depth at the pixel is in front of an occluder does
not shield its point here.

Plants never shade each other: each has its own map (one buffer of list heads, reset
after each plant at its queries' pixels only).
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.raster import _iceil, _ifloor

__all__ = [
    "map_depth_kernel",
    "plant_frames",
    "point_exposure_kernel",
    "point_light_into",
    "point_light_kernel",
    "project_segment",
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
    i0 = max(0, _iceil(min(ay, by) - r - 0.5, res))
    i1 = min(res - 1, _ifloor(max(ay, by) + r - 0.5, res))
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
    elif L2 > 0.0 and e * e <= r2:  # a level segment: its body spans ax..bx
        lo = min(lo, ax, bx)
        hi = max(hi, ax, bx)
    if not lo <= hi:
        return 1, 0
    return max(0, _iceil(lo - 0.5, res)), min(res - 1, _ifloor(hi - 0.5, res))


@njit(inline="always")
def _walk(k, ax, ay, bx, by, za, zb, rr, res, head, nxt, qz, qown, bias, soft, trans_k,
          best_z, best_id, expo):  # fmt: skip
    """Rasterise segment ``k`` (pixel coordinates ``a``, ``b``, depths ``za``, ``zb``,
    radius ``rr`` pixels) and judge the queries of the pixels it covers: every pixel whose
    centre lies within the radius of the axis, walked line by line along the segment's
    shorter extent over exactly the columns it covers. ``head[pixel]`` is the pixel's first
    query (-1: none), ``nxt[q]`` the next one. Hard shadows: the nearest depth (and its
    segment) over the pixel goes into ``best_z``/``best_id`` of each of its queries (the
    first drawn wins a tie, as in a z-buffer). Soft: a query ``q`` of another segment
    lying more than ``bias`` behind the segment's depth there has its ``expo`` multiplied
    by ``trans_k``."""
    tr, ax, ay, bx, by, r, i0, i1, dx, dy, L2, inv_L2, slope, half, cap, cap_w = _setup(
        ax, ay, bx, by, rr, res
    )
    # lines whose band chord lies within the body's length (0 <= t <= 1 at both its ends):
    # their chord is the band's, ax + e dx / dy +- half (the end discs lie inside the band)
    inv_dy = 1.0 / dy if dy != 0.0 else 0.0
    slack = abs(half * dx * inv_L2)
    line = 1 if tr else res  # pixel (i, j) of the walk is i * line + j * step
    step = res if tr else 1
    for i in range(i0, i1 + 1):
        te = (i + 0.5 - ay) * inv_dy
        if dy != 0.0 and slack <= te <= 1.0 - slack:
            c = ax + (i + 0.5 - ay) * slope
            j0 = max(0, math.ceil(c - half - 0.5))
            j1 = min(res - 1, math.floor(c + half - 0.5))
        else:
            j0, j1 = _span(i, ax, ay, bx, by, r, dx, dy, L2, slope, half, cap, cap_w, res)
        e = (i + 0.5 - ay) * dy
        for j in range(j0, j1 + 1):
            q = head[i * line + j * step]
            if q < 0:
                continue
            t = ((j + 0.5 - ax) * dx + e) * inv_L2
            t = min(1.0, max(0.0, t))
            z = za + t * (zb - za)
            while q >= 0:
                if soft:
                    if qown[q] != k and z < qz[q] - bias:
                        expo[q] *= trans_k
                elif z < best_z[q]:
                    best_z[q] = z
                    best_id[q] = k
                q = nxt[q]


@njit
def _judge(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, query,
           query_offsets, own, trans, soft, expo, head):  # fmt: skip
    """Exposure of every query point (``query`` ``(m, 3)``; plant ``p`` owns queries
    ``query_offsets[p]:query_offsets[p + 1]``; ``own[q]`` the segment a query belongs to,
    or -1) into ``expo`` ``(m,)``: the plant's shadow map read at the queries' pixels only
    (a pixel holding no query is never written: the same answers as a whole z-buffer or
    deep map, for the pixels read). Also returns, for hard shadows, the map's depth and
    segment at each query's pixel (``inf`` and -1 where empty)."""
    m = query.shape[0]
    head = np.full(res * res, -1, np.int64)
    nxt = np.empty(m, np.int64)
    pix = np.empty(m, np.int64)
    qz = np.empty(m)
    best_z = np.empty(m)
    best_id = np.empty(m, np.int64)
    for p in range(offsets.shape[0] - 1):
        q0 = query_offsets[p]
        q1 = query_offsets[p + 1]
        if q1 <= q0:
            continue
        ox, oy, inv = frames[p, 0], frames[p, 1], 1.0 / frames[p, 2]
        bias = bias_pixels * frames[p, 2]
        # the queries' pixels, as lists per pixel
        for q in range(q0, q1):
            x = (query[q, 0] * u[0] + query[q, 1] * u[1] + query[q, 2] * u[2] - ox) * inv
            y = (query[q, 0] * v[0] + query[q, 1] * v[1] + query[q, 2] * v[2] - oy) * inv
            qz[q] = query[q, 0] * d[0] + query[q, 1] * d[1] + query[q, 2] * d[2]
            best_z[q] = np.inf
            best_id[q] = -1
            expo[q] = 1.0
            if x >= 0.0 and y >= 0.0 and x < res and y < res:
                pix[q] = int(y) * res + int(x)
                nxt[q] = head[pix[q]]
                head[pix[q]] = q
            else:
                pix[q] = -1  # outside the frame: in the open
        for k in range(offsets[p], offsets[p + 1]):
            ax, ay, bx, by, za, zb = project_segment(start, end, k, u, v, d, ox, oy, inv)
            _walk(k, ax, ay, bx, by, za, zb, radius[k] * inv, res, head, nxt, qz, own, bias,
                  soft, trans[k] if soft else 1.0, best_z, best_id, expo)  # fmt: skip
        for q in range(q0, q1):
            if pix[q] >= 0:
                head[pix[q]] = -1
            if not soft:
                k = best_id[q]
                lit = k < 0 or k == own[q] or qz[q] - best_z[q] <= bias
                expo[q] = 1.0 if lit else 0.0
    return expo, best_z, best_id


@njit
def _samples(start, end, offsets, samples):
    """The segments' sample points (``samples`` per segment, at ``t = (i + 0.5) /
    samples`` of the axis), their plants' offsets and their segments."""
    n = start.shape[0]
    query = np.empty((n * samples, 3))
    own = np.empty(n * samples, np.int64)
    for s in range(n):
        for i in range(samples):
            t = (i + 0.5) / samples
            for c in range(3):
                query[s * samples + i, c] = start[s, c] + t * (end[s, c] - start[s, c])
            own[s * samples + i] = s
    return query, offsets * samples, own


@njit
def _segment_exposure(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, samples,
                      trans, soft, out):  # fmt: skip
    query, qoff, own = _samples(start, end, offsets, samples)
    expo = _judge(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, query, qoff,
                  own, trans, soft, np.empty(query.shape[0]), _heads(res))[0]  # fmt: skip
    for s in range(start.shape[0]):
        acc = 0.0
        for i in range(samples):
            acc += expo[s * samples + i]
        out[s] = acc / samples
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
    return _segment_exposure(start, end, radius, offsets, frames, u, v, d, res, bias_pixels,
                             samples, np.empty(0), False, out)  # fmt: skip


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
    return _segment_exposure(start, end, radius, offsets, frames, u, v, d, res, bias_pixels,
                             samples, trans, True, out)  # fmt: skip


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
    own = np.full(points.shape[0], -1, np.int64)
    return _judge(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, points,
                  point_offsets, own, np.empty(0), False, out, _heads(res))[0]  # fmt: skip


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
    own = np.full(points.shape[0], -1, np.int64)
    return _judge(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, points,
                  point_offsets, own, trans, True, out, _heads(res))[0]  # fmt: skip


@njit
def point_light_kernel(start, end, radius, offsets, points, point_offsets, normals, dirs, us,
                       vs, weights, res, bias_pixels, soft, trans, out):  # fmt: skip
    """Light at points from several parallel lights: ``out[m] = sum_k weights[k] x
    exposure_k[m] x max(0, -normals[m] . dirs[k])``, each direction ``k`` (unit ``dirs[k]``,
    image plane ``us[k], vs[k]``) with its own shadow maps (hard, or soft with the
    per-segment ``trans`` when ``soft``); a direction of weight 0 is skipped. ``normals``
    unit ``(m, 3)``; other arguments as :func:`point_exposure_kernel`. ``out`` ``(m,)`` is
    overwritten and returned. One call for a sun and its sky
    (:meth:`growsim.env.Light.point_light`).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]]); r = np.array([0.2])
    >>> d = np.array([[0.0, -1, 0], [-1.0, 0, 0]])  # from above, from the right
    >>> u = np.array([[1.0, 0, 0], [0.0, 0, -1]]); v = np.array([[0.0, 0, -1], [0.0, 1, 0]])
    >>> pts, nrm = np.array([[0.5, 0, 0]]), np.array([[0.6, 0.8, 0]])
    >>> point_light_kernel(s, e, r, np.array([0, 1]), pts, np.array([0, 1]), nrm, d, u, v,
    ...     np.array([1.0, 0.5]), 64, 0.1, False, np.empty(0), np.empty(1)).round(3).tolist()
    [0.3]
    """
    return point_light_into(start, end, radius, offsets, points, point_offsets, normals, dirs,
                            us, vs, weights, res, bias_pixels, soft, trans, _heads(res),
                            out)  # fmt: skip


@njit
def point_light_into(start, end, radius, offsets, points, point_offsets, normals, dirs, us,
                     vs, weights, res, bias_pixels, soft, trans, head, out):  # fmt: skip
    """:func:`point_light_kernel` with the map's list heads ``head`` ``(res * res,)``
    int64, all -1, given (and left all -1): a caller that lights a plant at every step
    (:func:`growsim.kernels.hormone.grow_step`) fills them once, not at every call.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]]); r = np.array([0.2])
    >>> d = np.array([[0.0, -1, 0]]); u = np.array([[1.0, 0, 0]]); v = np.array([[0.0, 0, -1]])
    >>> head = np.full(64 * 64, -1, np.int64)
    >>> point_light_into(s, e, r, np.array([0, 1]), np.array([[0.5, 0, 0]]), np.array([0, 1]),
    ...     np.array([[0.0, 1, 0]]), d, u, v, np.ones(1), 64, 0.1, False, np.empty(0), head,
    ...     np.empty(1)).tolist(), bool((head == -1).all())
    ([0.0], True)
    """
    m = points.shape[0]
    out[:] = 0.0
    own = np.full(m, -1, np.int64)
    expo = np.empty(m)
    for k in range(dirs.shape[0]):
        w = weights[k]
        if w == 0.0:
            continue
        d, u, v = dirs[k], us[k], vs[k]
        frames = plant_frames(start, end, radius, offsets, u, v, res)
        _judge(start, end, radius, offsets, frames, u, v, d, res, bias_pixels, points,
               point_offsets, own, trans, soft, expo, head)  # fmt: skip
        for q in range(m):
            cos = -(normals[q, 0] * d[0] + normals[q, 1] * d[1] + normals[q, 2] * d[2])
            out[q] += expo[q] * max(0.0, cos) * w
    return out


@njit
def _heads(res):
    """A fresh map of list heads, all -1 (no query in any pixel)."""
    return np.full(res * res, -1, np.int64)


@njit
def map_depth_kernel(start, end, radius, offsets, frames, points, point_offsets, u, v, d, res):
    """The hard shadow map read at points: ``(depth, segment)`` ``(m,)`` of the nearest
    capsule at each point's pixel of its plant's map (``inf`` and -1 where the pixel is
    empty or the point lies outside the frame).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 2, 0], [0, 1, 0]]); e = s + np.array([1.0, 0, 0])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> r, off = np.full(2, 0.2), np.array([0, 2]); f = plant_frames(s, e, r, off, u, v, 64)
    >>> z, k = map_depth_kernel(s, e, r, off, f, np.array([[0.5, 0, 0], [3, 0, 0]]),
    ...                         np.array([0, 2]), u, v, d, 64)
    >>> z.tolist(), k.tolist()
    ([-2.0, inf], [0, -1])
    """
    m = points.shape[0]
    _, depth, seg = _judge(start, end, radius, offsets, frames, u, v, d, res, 0.0, points,
                           point_offsets, np.full(m, -1, np.int64), np.empty(0), False,
                           np.empty(m), _heads(res))  # fmt: skip
    return depth, seg


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
