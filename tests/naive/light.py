"""Oracles of the shadow-map light (:mod:`growsim.kernels.light`): exact geometry, no
raster (and, for the rasteriser itself, a pixel-by-pixel NumPy z-buffer: :func:`render_depth`,
the map :func:`growsim.kernels.light.map_depth_kernel` reads). The production entries'
mirrors, :func:`segment_exposure_into` and :func:`point_light_into`, take the kernels'
tuples (without the scratch and ``out``).

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


def _shading(p, own, start, end, radius, u, v, d, bias, grow, slack):
    """``(n,)`` bool: which segments ``j != own`` shade point ``p`` (see
    :func:`shadowed`), every segment at once: the point of ``j``'s projected axis nearest
    to ``p``'s projection (parameter ``t`` in [0, 1]) within ``radius[j] + grow``, and
    ``j``'s axis there in front of ``p`` by more than the bias (moved by ``slack``)."""
    q = np.array([p @ u, p @ v])
    zp = float(p @ d)
    a = np.stack([start @ u, start @ v], axis=1)
    ab = np.stack([end @ u, end @ v], axis=1) - a
    L2 = (ab * ab).sum(axis=1)
    safe = np.where(L2 > 0, L2, 1.0)
    t = np.where(L2 > 0, np.clip(((q - a) * ab).sum(axis=1) / safe, 0.0, 1.0), 0.0)
    dist = np.hypot(*(a + t[:, None] * ab - q).T)
    za, zb = start @ d, end @ d
    proj = np.sqrt(L2)
    cot = np.abs(zb - za) / np.where(proj > 0, proj, 1.0) * (proj > 0)
    hit = (dist <= radius + grow) & (za + t * (zb - za) < zp - bias + slack * (1.0 + cot))
    if own >= 0:
        hit[own] = False
    return hit


def shadowed(p, own, start, end, radius, u, v, d, bias, grow=0.0, slack=0.0):
    """Whether point ``p`` (3-D) is shaded by a segment other than ``own`` (``-1``: none
    is its own). ``grow`` widens every capsule's shadow by that much (world units) and
    ``slack`` (world units per unit of ``cot`` of the occluder's axis with the light, plus
    one) moves the depth test; both 0 give the exact model."""
    return bool(_shading(p, own, start, end, radius, u, v, d, bias, grow, slack).any())


def transmitted(p, own, start, end, radius, u, v, d, bias, trans, grow=0.0, slack=0.0):
    """Product of ``trans[j]`` over the segments ``j != own`` that shade ``p`` (as
    :func:`shadowed`, each judged on its own, ``grow`` and ``slack`` as there): the soft
    shadow's exposure."""
    e = 1.0
    for x in trans[_shading(p, own, start, end, radius, u, v, d, bias, grow, slack)]:
        e *= x
    return e


def apply_cosines(start, end, normal, use_normal, d):
    """Mirror of :func:`growsim.kernels.light.apply_cosines` on ``out`` = ones and
    ``intensity`` 1: Lambert's cosine per segment, ``|n . d|`` for a blade, else the sine
    of the angle between the axis and the light."""
    out = np.empty(len(start))
    for s in range(len(start)):
        if use_normal[s]:
            out[s] = abs(float(normal[s] @ d))
            continue
        axis = end[s] - start[s]
        L = float(np.linalg.norm(axis))
        out[s] = 1.0 if L == 0 else math.sin(math.acos(min(1.0, abs(float(axis @ d)) / L)))
    return out


def plant_frames(start, end, radius, offsets, u, v, res):
    """Mirror of :func:`growsim.kernels.light.plant_frames`."""
    out = np.zeros((len(offsets) - 1, 3))
    for k in range(len(offsets) - 1):
        lo, hi = int(offsets[k]), int(offsets[k + 1])
        out[k] = frame(start[lo:hi], end[lo:hi], radius[lo:hi], u, v, res) if hi > lo else (0, 0, 1)
    return out


def render_depth(a, b, za, zb, radius, res):
    """The z-buffer the kernels render, pixel by pixel: ``(depth, ids)`` ``(res, res)``
    (``inf`` / -1 where empty) of the capsules ``a-b`` (pixel coordinates ``(n, 2)``,
    radii ``(n,)`` in pixels), a pixel covered when its centre lies within the radius of
    the axis, its depth the axis' at the point nearest the centre; the first segment wins
    a tie."""
    jj, ii = np.meshgrid(np.arange(res) + 0.5, np.arange(res) + 0.5)
    depth = np.full((res, res), np.inf)
    ids = np.full((res, res), -1)
    for k in range(len(a)):
        ab = b[k] - a[k]
        L2 = float(ab @ ab)
        t = np.zeros_like(jj) if L2 == 0 else (jj - a[k, 0]) * ab[0] + (ii - a[k, 1]) * ab[1]
        t = np.clip(t / L2, 0.0, 1.0) if L2 > 0 else t
        dist2 = (a[k, 0] + t * ab[0] - jj) ** 2 + (a[k, 1] + t * ab[1] - ii) ** 2
        z = za[k] + t * (zb[k] - za[k])
        win = (dist2 <= radius[k] ** 2) & (z < depth)
        depth[win] = z[win]
        ids[win] = k
    return depth, ids


def segment_exposure_into(segments, frames, plane, samples, shadow, tol_pixels=0.0):
    """Mirror of :func:`growsim.kernels.light.segment_exposure_into` (without ``scratch``
    and ``out``; ``frames`` is ignored: the pixel size, for the bias, is computed here):
    hard shadows, or soft ones with the transmissions of ``shadow = (res, bias_pixels,
    soft, trans)``.

    With ``tol_pixels > 0`` it returns instead a boolean ``(n,)``: whether some sample has
    an occluder whose answer changes when every capsule's shadow grows or shrinks by
    ``tol_pixels`` pixels and the depth test moves by as much (scaled by the occluder's
    slope): the samples the raster may fairly get either way (within that many pixels of
    an occluder's edge).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0, 0, 0]]); e = np.array([[1.0, 1, 0], [1, 0, 0]])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> segments = (s, e, np.full(2, 0.2), [0, 2])
    >>> segment_exposure_into(segments, None, (u, v, d), 1, (64, 1.5, False, None))
    array([1., 0.])
    """
    start, end, radius, offsets = segments
    u, v, d = plane
    res, bias_pixels, soft, trans = shadow
    trans = trans if soft else None
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
            for i in range(samples):
                t = (i + 0.5) / samples
                p = start[s] + t * (end[s] - start[s])
                if trans is not None:
                    out[s] += transmitted(p, s - lo, S, E, R, u, v, d, bias, trans[lo:hi])
                else:
                    out[s] += not shadowed(p, s - lo, S, E, R, u, v, d, bias)
                if tol_pixels > 0:
                    # near an edge: some occluder's answer changes within the tolerance
                    g = tol_pixels * pix
                    if trans is None:
                        loose = shadowed(p, s - lo, S, E, R, u, v, d, bias, grow=g, slack=g)
                        strict = shadowed(p, s - lo, S, E, R, u, v, d, bias, grow=-g, slack=-g)
                    else:
                        tr = trans[lo:hi]
                        loose = transmitted(p, s - lo, S, E, R, u, v, d, bias, tr, g, g)
                        strict = transmitted(p, s - lo, S, E, R, u, v, d, bias, tr, -g, -g)
                    edge[s] |= loose != strict
            out[s] /= samples
    return edge if tol_pixels > 0 else out


def point_exposure(segments, points, point_offsets, plane, res, bias_pixels, trans=None,
                   tol_pixels=0.0, shifts=None):  # fmt: skip
    """The exposure of each point in its plant's shadow map along one light (the part of
    :func:`point_light_into` before the cosine): 1 or 0 (hard), or the product of the
    transmissions ``trans`` of the segments in front of it (soft); with ``tol_pixels > 0``,
    the boolean ``(m,)`` of points near an edge (as :func:`segment_exposure_into`). Among
    copies moved by ``shifts`` ``(k, 3)``: the product of the point's exposure and of each
    ``point - shifts[j]``'s (copy ``j`` shades the point as the plant shades the point
    moved back), an edge near any of them."""
    if shifts is not None:
        parts = [point_exposure(segments, points - move, point_offsets, plane, res,
                                bias_pixels, trans, tol_pixels)
                 for move in np.vstack([np.zeros((1, 3)), shifts])]  # fmt: skip
        return np.logical_or.reduce(parts) if tol_pixels > 0 else np.prod(parts, axis=0)
    start, end, radius, offsets = segments
    u, v, d = plane
    out = np.ones(len(points))
    edge = np.zeros(len(points), bool)
    for k in range(len(offsets) - 1):
        lo, hi = int(offsets[k]), int(offsets[k + 1])
        if hi == lo:
            continue
        S, E, R = start[lo:hi], end[lo:hi], radius[lo:hi]
        pix = frame(S, E, R, u, v, res)[2]
        bias = bias_pixels * pix
        for i in range(int(point_offsets[k]), int(point_offsets[k + 1])):
            if trans is not None:
                out[i] = transmitted(points[i], -1, S, E, R, u, v, d, bias, trans[lo:hi])
            else:
                out[i] = not shadowed(points[i], -1, S, E, R, u, v, d, bias)
            if tol_pixels > 0:
                g = tol_pixels * pix
                q = points[i]
                if trans is None:
                    loose = shadowed(q, -1, S, E, R, u, v, d, bias, grow=g, slack=g)
                    strict = shadowed(q, -1, S, E, R, u, v, d, bias, grow=-g, slack=-g)
                else:
                    loose = transmitted(q, -1, S, E, R, u, v, d, bias, trans[lo:hi], g, g)
                    strict = transmitted(q, -1, S, E, R, u, v, d, bias, trans[lo:hi], -g, -g)
                edge[i] = loose != strict
    return edge if tol_pixels > 0 else out


def point_light_into(segments, targets, lights, shadow, tol_pixels=0.0, shifts=None):
    """Mirror of :func:`growsim.kernels.light.point_light_into` (without ``scratch`` and
    ``out``): the sum over the lights ``(dirs, us, vs, weights)`` of
    :func:`point_exposure` times the clipped cosine ``max(0, -n . d)`` times the weight;
    with ``tol_pixels > 0``, the boolean ``(m,)`` of points near an edge along some light
    of non-zero weight that they face. Among copies moved by ``shifts`` ``(k, 3)``: as
    :func:`point_exposure` judges them.

    Examples
    --------
    >>> import numpy as np
    >>> segments = (np.array([[0.0, 1, 0]]), np.array([[1.0, 1, 0]]), np.array([0.2]), [0, 1])
    >>> targets = (np.array([[0.5, 0, 0], [3, 0, 0]]), [0, 2], np.array([[0.0, 1, 0]] * 2))
    >>> lights = (np.array([[0.0, -1, 0]]), np.array([[1.0, 0, 0]]), np.array([[0.0, 0, -1]]),
    ...           np.array([2.0]))
    >>> point_light_into(segments, targets, lights, (64, 0.1, False, None))
    array([0., 2.])
    """
    points, point_offsets, normals = targets
    res, bias_pixels, soft, trans = shadow
    out = np.zeros(len(points))
    edge = np.zeros(len(points), bool)
    for d, u, v, w in zip(*lights):
        if w == 0.0:
            continue
        cos = np.maximum(0.0, -(normals @ d))
        args = (segments, points, point_offsets, (u, v, d), res, bias_pixels,
                trans if soft else None)  # fmt: skip
        if tol_pixels > 0:
            edge |= point_exposure(*args, tol_pixels=tol_pixels, shifts=shifts) & (cos > 0)
        out += point_exposure(*args, shifts=shifts) * cos * w
    return edge if tol_pixels > 0 else out


def module_light_into(segments, walls, lights, shadow, tol_pixels=0.0):
    """Mirror of :func:`growsim.kernels.light.module_light_into` (without ``scratch`` and
    ``out``): ``(n, W)`` light on each segment's walls, ``walls`` ``(R, cs)``: wall ``i``
    of segment ``s`` faces ``n_si = cs[i, 0] R[s][:, 0] + cs[i, 1] R[s][:, 1]``; along
    each light, the segment's one point ``mid + radius n*`` (``n*`` the unit sum of its
    walls' normals weighted by their clipped cosines ``max(0, -n_si . d)``) judged as
    :func:`point_exposure` does, its exposure times each wall's clipped cosine times the
    weight; a segment none of whose walls faces the light gets none of it. With
    ``tol_pixels > 0``, the boolean ``(n,)`` of segments whose point lies near an edge
    along some light.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0.0, 0, 0]]); e = s + np.array([0.0, 0, 1])
    >>> R = np.tile(np.eye(3), (2, 1, 1)); cs = np.array([[0.0, 1], [0.0, -1]])
    >>> lights = (np.array([[0.0, -1, 0]]), np.array([[1.0, 0, 0]]),
    ...           np.array([[0.0, 0, -1]]), np.array([1.0]))
    >>> module_light_into((s, e, np.full(2, 0.1), [0, 2]), (R, cs), lights,
    ...                   (64, 0.1, False, None)).tolist()
    [[1.0, 0.0], [0.0, 0.0]]
    """
    start, end, radius, offsets = segments
    R, cs = walls
    res, bias_pixels, soft, trans = shadow
    n = len(start)
    out = np.zeros((n, len(cs)))
    edge = np.zeros(n, bool)
    for d, u, v, w in zip(*lights):
        if w == 0.0:
            continue
        x, y = R[:n, None, :, 0], R[:n, None, :, 1]  # the axes across each segment
        normals = cs[None, :, 0, None] * x + cs[None, :, 1, None] * y  # (n, W, 3)
        cos = np.maximum(0.0, -(normals @ d))  # (n, W)
        toward = (cos[:, :, None] * normals).sum(axis=1)
        norm = np.linalg.norm(toward, axis=1)
        lit = norm > 0
        mid = start + 0.5 * (end - start)
        pts = mid + radius[:, None] * toward / np.where(lit, norm, 1.0)[:, None]
        pick = np.flatnonzero(lit)
        # the facing segments' points, plant by plant
        point_offsets = np.searchsorted(pick, np.asarray(offsets))
        args = (segments, pts[pick], point_offsets, (u, v, d), res, bias_pixels,
                trans if soft else None)  # fmt: skip
        out[pick] += point_exposure(*args)[:, None] * cos[pick] * w
        if tol_pixels > 0:
            edge[pick] |= point_exposure(*args, tol_pixels=tol_pixels)
    return edge if tol_pixels > 0 else out


def map_exposure(segments, points, plane, res, bias_pixels, trans=None, framing=None):
    """The exposure of points judged in one plant's whole map (no capsule left out), the
    pixel-by-pixel mirror of :func:`growsim.kernels.light.judge_queries` with its culling
    (:func:`growsim.kernels.light._culled`) for points owned by no segment: the map framed
    over every segment (:func:`growsim.kernels.light.plant_frames`' frame), each point
    at its pixel (``framing`` ``(ox, oy, pix)``: that frame, as the kernel computed it; None:
    :func:`frame`'s); hard shadows (``trans`` None): lit (1) when the pixel is empty or its
    nearest depth (:func:`render_depth`) lies at most the bias in front of the point,
    else 0; soft: the product of ``trans`` over the capsules covering the pixel more than
    the bias in front, in the segments' order. A point outside the frame is lit.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]])
    >>> plane = (np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0]))
    >>> map_exposure((s, e, np.array([0.2])), np.array([[0.5, 0, 0], [0.5, 2, 0]]), plane,
    ...              64, 0.1).tolist()
    [0.0, 1.0]
    """
    start, end, radius = segments
    u, v, d = plane
    ox, oy, pix = frame(start, end, radius, u, v, res) if framing is None else framing
    inv = 1.0 / pix

    def px(p, axis, o):
        return (p[:, 0] * axis[0] + p[:, 1] * axis[1] + p[:, 2] * axis[2] - o) * inv

    a = np.stack([px(start, u, ox), px(start, v, oy)], 1)
    b = np.stack([px(end, u, ox), px(end, v, oy)], 1)
    za = start[:, 0] * d[0] + start[:, 1] * d[1] + start[:, 2] * d[2]
    zb = end[:, 0] * d[0] + end[:, 1] * d[1] + end[:, 2] * d[2]
    x, y = px(points, u, ox), px(points, v, oy)
    qz = points[:, 0] * d[0] + points[:, 1] * d[1] + points[:, 2] * d[2]
    bias = bias_pixels * pix
    inside = (x >= 0) & (y >= 0) & (x < res) & (y < res)
    out = np.ones(len(points))
    if trans is None:
        depth, _ = render_depth(a, b, za, zb, radius * inv, res)
        for i in np.flatnonzero(inside):
            z = depth[int(y[i]), int(x[i])]
            out[i] = 1.0 if not np.isfinite(z) or qz[i] - z <= bias else 0.0
        return out
    for k in range(len(start)):  # the deep map, a capsule at a time
        depth, _ = render_depth(a[k : k + 1], b[k : k + 1], za[k : k + 1], zb[k : k + 1],
                                radius[k : k + 1] * inv, res)  # fmt: skip
        for i in np.flatnonzero(inside):
            z = depth[int(y[i]), int(x[i])]
            if np.isfinite(z) and z < qz[i] - bias:
                out[i] *= trans[k]
    return out
