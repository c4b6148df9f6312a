"""Oracles of the shadow-map light (:mod:`growsim.kernels.light`): no raster at all.

Each sample point is judged exactly against the model the z-buffer discretises: a segment
``j`` of the same plant shades the point ``p`` when ``p``'s projection on the image plane
lies within ``radius[j]`` of ``j``'s projected axis (the capsule's shadow) and ``j``'s axis,
at the point nearest to ``p`` in projection, lies more than ``bias`` in front of ``p``
along the light (the depth the rasteriser gives a capsule). The line through ``p`` along the
light passes within ``radius[j]`` of ``j``'s axis exactly when the projections do, so this is
"does another capsule lie between the point and the light", with a capsule's depth read
on its axis. The pixel size (for the bias) is the kernel's framing, computed directly.
"""

from __future__ import annotations

import math

import numpy as np


def frame(start, end, radius, u, v, res):
    """``(ox, oy, pix)``: the square raster framing the plant's shadow (one pixel margin)."""
    pts = np.concatenate([start, end])
    x, y = pts @ u, pts @ v
    rmax = float(radius.max())
    size = max(x.max() - x.min(), y.max() - y.min()) + 2 * rmax
    pix = size / (res - 2) if size > 0 else 1.0
    return x.min() - rmax - pix, y.min() - rmax - pix, pix


def _nearest_on_segment(p, a, b):
    """Parameter ``t`` in [0, 1] of the point of segment ``a-b`` (2-D) nearest to ``p``, and
    the distance."""
    ab = b - a
    L2 = float(ab @ ab)
    t = 0.0 if L2 == 0 else min(1.0, max(0.0, float((p - a) @ ab) / L2))
    return t, float(np.linalg.norm(a + t * ab - p))


def shadowed(p, own, start, end, radius, u, v, d, bias, grow=0.0, slack=0.0):
    """Whether point ``p`` (3-D) is shaded by a segment other than ``own`` (``-1``: none
    is its own). ``grow`` widens every capsule's shadow by that much (world units) and
    ``slack`` (world units per unit of ``cot`` of the occluder's axis with the light, plus
    one) moves the depth test; both 0 give the exact model."""
    q = np.array([p @ u, p @ v])
    zp = float(p @ d)
    for j in range(len(start)):
        if j == own:
            continue
        a = np.array([start[j] @ u, start[j] @ v])
        b = np.array([end[j] @ u, end[j] @ v])
        t, dist = _nearest_on_segment(q, a, b)
        if dist > radius[j] + grow:
            continue
        za, zb = float(start[j] @ d), float(end[j] @ d)
        proj = float(np.linalg.norm(b - a))
        cot = abs(zb - za) / proj if proj > 0 else 0.0
        if za + t * (zb - za) < zp - bias + slack * (1.0 + cot):
            return True
    return False


def _cos(s, start, end, normal, use_normal, d):
    if use_normal[s]:
        return abs(float(normal[s] @ d))
    axis = end[s] - start[s]
    L = float(np.linalg.norm(axis))
    if L == 0:
        return 1.0
    return math.sin(math.acos(min(1.0, abs(float(axis @ d)) / L)))


def segment_light_kernel(
    start, end, radius, offsets, normal, use_normal, u, v, d, intensity, res, bias_pixels,
    samples, tol_pixels=0.0,
):  # fmt: skip
    """Mirror of :func:`growsim.kernels.light.segment_light_kernel` (without ``out``).

    With ``tol_pixels > 0`` it returns instead a boolean ``(n,)``: whether some sample's
    answer changes when every capsule's shadow grows or shrinks by ``tol_pixels`` pixels
    and the depth test moves by as much (scaled by the occluder's slope): the samples the
    raster may fairly get either way (within that many pixels of a silhouette edge).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0, 0, 0]]); e = np.array([[1.0, 1, 0], [1, 0, 0]])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> segment_light_kernel(s, e, np.full(2, 0.2), [0, 2], np.zeros((2, 3)), [False] * 2,
    ...                      u, v, d, 1.0, 64, 1.5, 1).tolist()
    [1.0, 0.0]
    """
    n = len(start)
    out = np.zeros(n)
    edge = np.zeros(n, bool)
    for k in range(len(offsets) - 1):
        lo, hi = int(offsets[k]), int(offsets[k + 1])
        if hi == lo:
            continue
        S, E, R = start[lo:hi], end[lo:hi], radius[lo:hi]
        _, _, pix = frame(S, E, R, u, v, res)
        bias = bias_pixels * pix
        for s in range(lo, hi):
            lit = 0
            for i in range(samples):
                t = (i + 0.5) / samples
                p = start[s] + t * (end[s] - start[s])
                exact = shadowed(p, s - lo, S, E, R, u, v, d, bias)
                lit += not exact
                if tol_pixels > 0:
                    g = tol_pixels * pix
                    loose = shadowed(p, s - lo, S, E, R, u, v, d, bias, grow=g, slack=g)
                    strict = shadowed(p, s - lo, S, E, R, u, v, d, bias, grow=-g, slack=-g)
                    edge[s] |= loose != strict
            out[s] = intensity * _cos(s, start, end, normal, use_normal, d) * lit / samples
    return edge if tol_pixels > 0 else out


def point_light_kernel(
    start, end, radius, offsets, points, normals, point_offsets, u, v, d, intensity, res,
    bias_pixels, tol_pixels=0.0,
):  # fmt: skip
    """Mirror of :func:`growsim.kernels.light.point_light_kernel` (without ``out``); with
    ``tol_pixels > 0``, the boolean ``(m,)`` of points near an edge (as
    :func:`segment_light_kernel`)."""
    out = np.zeros(len(points))
    edge = np.zeros(len(points), bool)
    for k in range(len(offsets) - 1):
        lo, hi = int(offsets[k]), int(offsets[k + 1])
        S, E, R = start[lo:hi], end[lo:hi], radius[lo:hi]
        pix = frame(S, E, R, u, v, res)[2] if hi > lo else 0.0
        bias = bias_pixels * pix
        for i in range(int(point_offsets[k]), int(point_offsets[k + 1])):
            c = -float(normals[i] @ d)
            if c <= 0:
                continue
            if hi == lo or not shadowed(points[i], -1, S, E, R, u, v, d, bias):
                out[i] = intensity * c
            if tol_pixels > 0 and hi > lo:
                g = tol_pixels * pix
                loose = shadowed(points[i], -1, S, E, R, u, v, d, bias, grow=g, slack=g)
                strict = shadowed(points[i], -1, S, E, R, u, v, d, bias, grow=-g, slack=-g)
                edge[i] = loose != strict
    return edge if tol_pixels > 0 else out
