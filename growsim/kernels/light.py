"""Numba kernels of the shadow-map light (:mod:`growsim.env.light`), hard-shadow mode.

For each plant (segments ``offsets[k]:offsets[k + 1]``) the kernel renders one orthographic
depth image (a z-buffer) from the light: every segment is a capsule of its radius projected
on the plane ``(u, v)`` across the light's direction ``d`` (unit), its depth the distance
along ``d`` (``p . d``: nearer to the light = smaller), and each pixel keeps the nearest
depth and the segment that gave it. Coverage and depth follow the shared rasteriser
(:func:`growsim.kernels.raster.draw_segments_depth`: the thin line's supercover plus the
pixels whose centre lies within the radius; a segment's depth at a pixel is the depth of its
axis at the point nearest to the pixel centre), pixel for pixel, but each capsule is
walked row by row over the columns its axis can reach (tested against the shared kernel
in ``tests/test_light.py``). The raster frames the plant's shadow as
:func:`growsim.env.light.projected_area` does: a square of ``resolution`` pixels over the
projected bounding box grown by the largest radius, one pixel of margin each side.

A sample point ``p`` at depth ``z = p . d`` in pixel ``(i, j)`` is lit when the pixel is
empty, when its nearest segment is the sample's own segment, or when
``z - depth[i, j] <= bias`` with ``bias = bias_pixels * pixel size``. Plants never shade
each other. The depth buffer is not cleared between plants: a per-pixel stamp (the plant's
number) marks which pixels the current plant has written, so a population costs what its
segments cover, not ``resolution`` squared per plant.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.raster import _iceil, _ifloor, _seg_dist2_t, _thin_line

__all__ = ["point_light_kernel", "segment_light_kernel"]


@njit
def _render(start, end, radius, s0, s1, u, v, d, res, depth, ids, stamp, cur, mask):
    """Render segments ``s0:s1`` into the z-buffer (pixels stamped ``cur``); return the
    frame ``(ox, oy, pix)``: pixel coordinates are ``((p . u - ox) / pix, (p . v - oy) /
    pix)``."""
    lox = np.inf
    loy = np.inf
    hix = -np.inf
    hiy = -np.inf
    rmax = 0.0
    for s in range(s0, s1):
        for q in (start[s], end[s]):
            x = q[0] * u[0] + q[1] * u[1] + q[2] * u[2]
            y = q[0] * v[0] + q[1] * v[1] + q[2] * v[2]
            lox = min(lox, x)
            hix = max(hix, x)
            loy = min(loy, y)
            hiy = max(hiy, y)
        rmax = max(rmax, radius[s])
    size = max(hix - lox, hiy - loy) + 2.0 * rmax
    if s1 <= s0:
        return 0.0, 0.0, 1.0
    # a plant whose shadow is a single point (no width, seen end on): any pixel size will do
    pix = size / (res - 2) if size > 0.0 else 1.0
    ox = lox - rmax - pix
    oy = loy - rmax - pix
    H = res
    W = res
    for k in range(s0, s1):
        ax = (start[k, 0] * u[0] + start[k, 1] * u[1] + start[k, 2] * u[2] - ox) / pix
        ay = (start[k, 0] * v[0] + start[k, 1] * v[1] + start[k, 2] * v[2] - oy) / pix
        bx = (end[k, 0] * u[0] + end[k, 1] * u[1] + end[k, 2] * u[2] - ox) / pix
        by = (end[k, 0] * v[0] + end[k, 1] * v[1] + end[k, 2] * v[2] - oy) / pix
        za = start[k, 0] * d[0] + start[k, 1] * d[1] + start[k, 2] * d[2]
        zb = end[k, 0] * d[0] + end[k, 1] * d[1] + end[k, 2] * d[2]
        r = radius[k] / pix if radius[k] / pix > 0.5 else 0.0
        i0 = max(0, _ifloor(min(ay, by) - r - 0.5, H))
        i1 = min(H - 1, _iceil(max(ay, by) + r, H))
        # the thin line matters only where the capsule does not hold every pixel the axis
        # touches (a pixel's centre is at most sqrt(1/2) from any point of its square)
        thin = r * r < 0.5
        if thin:
            _thin_line(mask, ax, ay, bx, by)
        r2 = r * r
        dy = by - ay
        h = max(r, 0.5) + 1e-9
        for i in range(i0, i1 + 1):
            # the part of the axis within h of the row's centre line: the columns to visit
            y0 = i + 0.5 - h
            y1 = i + 0.5 + h
            if dy == 0.0:
                if ay < y0 or ay > y1:
                    continue
                xlo = min(ax, bx)
                xhi = max(ax, bx)
            else:
                t0 = (y0 - ay) / dy
                t1 = (y1 - ay) / dy
                if t0 > t1:
                    t0, t1 = t1, t0
                t0 = max(t0, 0.0)
                t1 = min(t1, 1.0)
                if t0 > t1:
                    continue
                x0 = ax + t0 * (bx - ax)
                x1 = ax + t1 * (bx - ax)
                xlo = min(x0, x1)
                xhi = max(x0, x1)
            j0 = max(0, _ifloor(xlo - r - 0.5, W))
            j1 = min(W - 1, _iceil(xhi + r, W))
            for j in range(j0, j1 + 1):
                if thin and mask[i, j]:
                    mask[i, j] = 0
                    _, t = _seg_dist2_t(j + 0.5, i + 0.5, ax, ay, bx, by)
                elif r > 0.0:
                    d2, t = _seg_dist2_t(j + 0.5, i + 0.5, ax, ay, bx, by)
                    if d2 > r2:
                        continue
                else:
                    continue
                z = za + t * (zb - za)
                if stamp[i, j] != cur or z < depth[i, j]:
                    stamp[i, j] = cur
                    depth[i, j] = z
                    ids[i, j] = k
    return ox, oy, pix


@njit
def _lit(px, py, pz, own, ox, oy, pix, bias, depth, ids, stamp, cur):
    """Whether the point ``(px, py, pz)`` (image-plane coordinates and depth) is lit."""
    x = (px - ox) / pix
    y = (py - oy) / pix
    res = depth.shape[0]
    if not (x >= 0.0 and y >= 0.0 and x < res and y < res):
        return True
    j = int(x)
    i = int(y)
    if stamp[i, j] != cur or ids[i, j] == own:
        return True
    return pz - depth[i, j] <= bias


@njit
def _map_buffers(res):
    """The shadow map's buffers: depth, segment ids, the stamp of the plant that last wrote
    each pixel (so the map is never cleared between plants) and a scratch mask."""
    depth = np.empty((res, res), np.float64)
    ids = np.empty((res, res), np.int64)
    stamp = np.full((res, res), -1, np.int64)
    mask = np.zeros((res, res), np.uint8)
    return depth, ids, stamp, mask


@njit
def segment_light_kernel(
    start, end, radius, offsets, normal, use_normal, u, v, d, intensity, res, bias_pixels,
    samples, out,
):  # fmt: skip
    """Light on every segment, one shadow map per plant.

    Parameters
    ----------
    start, end : ``(n, 3)`` float64; radius ``(n,)`` float64.
    offsets : ``(k + 1,)`` int64, plant ``p`` is segments ``offsets[p]:offsets[p + 1]``.
    normal : ``(n, 3)`` float64 unit normals, read where ``use_normal[s]`` (``(n,)`` bool).
    u, v, d : ``(3,)`` float64, the image plane and the unit direction the light travels.
    intensity : float; res : int (pixels across); bias_pixels : float.
    samples : int, sample points per segment, at ``t = (i + 0.5) / samples`` of its axis.
    out : ``(n,)`` float64, overwritten.

    Returns
    -------
    ``out``: ``intensity x (share of the samples lit) x cos``, ``cos = |normal . d|`` where
    ``use_normal``, else ``sqrt(1 - (axis . d)^2)`` (a cylinder's side; 1 for a point).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0, 0, 0]]); e = np.array([[1.0, 1, 0], [1, 0, 0]])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> segment_light_kernel(s, e, np.full(2, 0.2), np.array([0, 2]), np.zeros((2, 3)),
    ...     np.zeros(2, np.bool_), u, v, d, 1.0, 64, 1.5, 1, np.empty(2)).tolist()
    [1.0, 0.0]
    """
    depth, ids, stamp, mask = _map_buffers(res)
    for p in range(offsets.shape[0] - 1):
        s0 = offsets[p]
        s1 = offsets[p + 1]
        ox, oy, pix = _render(start, end, radius, s0, s1, u, v, d, res, depth, ids, stamp, p, mask)
        bias = bias_pixels * pix
        for s in range(s0, s1):
            ex = end[s, 0] - start[s, 0]
            ey = end[s, 1] - start[s, 1]
            ez = end[s, 2] - start[s, 2]
            if use_normal[s]:
                c = abs(normal[s, 0] * d[0] + normal[s, 1] * d[1] + normal[s, 2] * d[2])
            else:
                L = math.sqrt(ex * ex + ey * ey + ez * ez)
                if L > 0.0:
                    ad = (ex * d[0] + ey * d[1] + ez * d[2]) / L
                    c = math.sqrt(max(0.0, 1.0 - ad * ad))
                else:
                    c = 1.0
            if c == 0.0 or intensity == 0.0:
                out[s] = 0.0
                continue
            lit = 0
            for q in range(samples):
                t = (q + 0.5) / samples
                qx = start[s, 0] + t * ex
                qy = start[s, 1] + t * ey
                qz = start[s, 2] + t * ez
                pu = qx * u[0] + qy * u[1] + qz * u[2]
                pv = qx * v[0] + qy * v[1] + qz * v[2]
                pz = qx * d[0] + qy * d[1] + qz * d[2]
                if _lit(pu, pv, pz, s, ox, oy, pix, bias, depth, ids, stamp, p):
                    lit += 1
            out[s] = intensity * c * lit / samples
    return out


@njit
def point_light_kernel(
    start, end, radius, offsets, points, normals, point_offsets, u, v, d, intensity, res,
    bias_pixels, out,
):  # fmt: skip
    """Light at sample points, one shadow map per plant: the points
    ``point_offsets[p]:point_offsets[p + 1]`` are judged against plant ``p``'s map.

    ``out[i] = intensity x lit x max(0, -normals[i] . d)`` (``normals`` unit ``(m, 3)``); a
    point outside the plant's shadow frame or on an empty pixel is lit.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> pts = np.array([[0.5, 0, 0], [0.5, 2, 0], [3, 0, 0]]); up = np.tile([0.0, 1, 0], (3, 1))
    >>> point_light_kernel(s, e, np.array([0.2]), np.array([0, 1]), pts, up, np.array([0, 3]),
    ...     u, v, d, 1.0, 64, 1.5, np.empty(3)).tolist()
    [0.0, 1.0, 1.0]
    """
    depth, ids, stamp, mask = _map_buffers(res)
    for p in range(offsets.shape[0] - 1):
        first, stop = offsets[p], offsets[p + 1]  # this plant's segments: its own map
        ox, oy, pix = _render(
            start, end, radius, first, stop, u, v, d, res, depth, ids, stamp, p, mask
        )
        for i in range(point_offsets[p], point_offsets[p + 1]):
            c = -(normals[i, 0] * d[0] + normals[i, 1] * d[1] + normals[i, 2] * d[2])
            if c <= 0.0 or intensity == 0.0:
                out[i] = 0.0
                continue
            qx = points[i, 0]
            qy = points[i, 1]
            qz = points[i, 2]
            pu = qx * u[0] + qy * u[1] + qz * u[2]
            pv = qx * v[0] + qy * v[1] + qz * v[2]
            pz = qx * d[0] + qy * d[1] + qz * d[2]
            lit = stop <= first or _lit(
                pu, pv, pz, -1, ox, oy, pix, bias_pixels * pix, depth, ids, stamp, p
            )
            out[i] = intensity * c if lit else 0.0
    return out
