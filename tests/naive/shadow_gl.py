"""Oracles of the OpenGL backend's CPU kernels (:mod:`growsim.kernels.shadow_gl`): the
same formulas on whole arrays with NumPy, plant by plant.

A point ``p`` of plant ``k`` lands at ``x = (p . u - ox) / pix``, ``y = (p . v - oy) /
pix`` in its frame ``(ox, oy, pix)``; its tile in the atlas starts at ``((k - p0) % cols
res, (k - p0) // cols res)``; its texel is ``(ty + floor(y)) width + tx + floor(x)``
inside the frame, else -1. The dot products are written out term by term (as the
kernels and every other backend compute them), so that a point picks the same pixel.
"""

from __future__ import annotations

import numpy as np


def _dot(p, w):
    """``p . w`` for the rows of ``p`` ``(m, 3)``, term by term."""
    return p[:, 0] * w[0] + p[:, 1] * w[1] + p[:, 2] * w[2]


def depth_ranges(start, end, offsets, d, p0, p1, zinfo):
    """Mirror of :func:`growsim.kernels.shadow_gl.depth_ranges` (returns a new array)."""
    zinfo = zinfo.copy()
    for p in range(p0, p1):
        z = np.concatenate([_dot(start[offsets[p] : offsets[p + 1]], d),
                            _dot(end[offsets[p] : offsets[p + 1]], d)])  # fmt: skip
        lo, hi = (z.min(), z.max()) if len(z) else (0.0, 0.0)
        zinfo[p] = lo, 2.0 * (hi - lo)
    return zinfo


def _tile(p, p0, cols, res):
    return ((p - p0) % cols) * res, ((p - p0) // cols) * res


def tile_vertices(segments, frames, plane, batch, atlas, zinfo):
    """Mirror of :func:`growsim.kernels.shadow_gl.tile_vertices`: the ``(4 (c1 - c0),
    10)`` float32 vertices (the segment's index in column 9 as int32 bits; rows of
    segments outside the batch's plants are left 0)."""
    start, end, radius, offsets = segments
    u, v, d = plane
    p0, p1, c0, c1 = batch
    cols, res = atlas[0], atlas[1]
    out = np.zeros((4 * (c1 - c0), 10), np.float32)
    for p in range(p0, p1):
        k = np.arange(max(offsets[p], c0), min(offsets[p + 1], c1))
        if len(k) == 0:
            continue
        ox, oy, pix = frames[p]
        zmin, span = zinfo[p]
        scale = 1.0 / span if span > 0 else 0.0
        tx, ty = _tile(p, p0, cols, res)
        row = np.column_stack([
            (_dot(start[k], u) - ox) * (1.0 / pix), (_dot(start[k], v) - oy) * (1.0 / pix),
            (_dot(end[k], u) - ox) * (1.0 / pix), (_dot(end[k], v) - oy) * (1.0 / pix),
            (_dot(start[k], d) - zmin) * scale, (_dot(end[k], d) - zmin) * scale,
            radius[k] * (1.0 / pix), np.full(len(k), float(tx)), np.full(len(k), float(ty)),
        ]).astype(np.float32)  # fmt: skip
        rows = 4 * (k - c0)[:, None] + np.arange(4)
        out[rows, :9] = row[:, None, :]
        out.view(np.int32)[rows, 9] = k[:, None]
    return out


def texel(pu, pv, frame, res, tx, ty, width):
    """Mirror of :func:`growsim.kernels.shadow_gl.texel` on arrays ``pu, pv``."""
    x = (np.asarray(pu) - frame[0]) * (1.0 / frame[2])
    y = (np.asarray(pv) - frame[1]) * (1.0 / frame[2])
    inside = (x >= 0) & (y >= 0) & (x < res) & (y < res)
    xi = np.floor(np.where(inside, x, 0)).astype(np.int64)
    yi = np.floor(np.where(inside, y, 0)).astype(np.int64)
    return np.where(inside, (ty + yi) * width + tx + xi, -1)


def segment_queries(segments, frames, plane, batch, atlas, samples):
    """Mirror of :func:`growsim.kernels.shadow_gl.segment_queries`: ``(q, z)`` of the
    samples of segments ``c0:c1`` (rows of segments outside the batch's plants 0)."""
    start, end, _, offsets = segments
    u, v, d = plane
    p0, p1, c0, c1 = batch
    cols, res, width = atlas
    q = np.zeros(((c1 - c0) * samples, 2), np.int64)
    z = np.zeros((c1 - c0) * samples)
    t = (np.arange(samples) + 0.5) / samples
    for p in range(p0, p1):
        for s in range(max(offsets[p], c0), min(offsets[p + 1], c1)):
            pts = start[s] + t[:, None] * (end[s] - start[s])
            rows = (s - c0) * samples + np.arange(samples)
            tx, ty = _tile(p, p0, cols, res)
            q[rows, 0] = texel(_dot(pts, u), _dot(pts, v), frames[p], res, tx, ty, width)
            q[rows, 1] = s
            z[rows] = _dot(pts, d)
    return q, z


def point_queries(points, point_offsets, frames, plane, batch, atlas):
    """Mirror of :func:`growsim.kernels.shadow_gl.point_queries`: ``(q, z)`` of the points
    ``c0:c1`` (rows of points outside the batch's plants 0)."""
    u, v, d = plane
    p0, p1, c0, c1 = batch
    cols, res, width = atlas
    q = np.zeros((c1 - c0, 2), np.int64)
    z = np.zeros(c1 - c0)
    for p in range(p0, p1):
        m = np.arange(max(point_offsets[p], c0), min(point_offsets[p + 1], c1))
        tx, ty = _tile(p, p0, cols, res)
        pts = points[m]
        q[m - c0, 0] = texel(_dot(pts, u), _dot(pts, v), frames[p], res, tx, ty, width)
        q[m - c0, 1] = -1
        z[m - c0] = _dot(pts, d)
    return q, z


def resolve_exposure(val, z, offsets, frames, zinfo, bias_pixels, batch, per, out):
    """Mirror of :func:`growsim.kernels.shadow_gl.resolve_exposure` (returns a new
    ``out``): the share of an item's samples that are lit, a sample lit when the pixel
    said so (``val`` 2) or its depth lies at most the bias behind the map's."""
    out = out.copy()
    p0, p1, c0, c1 = batch
    for p in range(p0, p1):
        items = np.arange(max(offsets[p], c0), min(offsets[p + 1], c1))
        rows = (items - c0)[:, None] * per + np.arange(per)
        w = val[rows].astype(np.float64)
        depth = zinfo[p, 0] + w * zinfo[p, 1]
        lit = (w > 1.5) | (z[rows] - depth <= bias_pixels * frames[p, 2])
        out[items] = lit.sum(axis=1) / per
    return out
