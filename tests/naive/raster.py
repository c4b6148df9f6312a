"""Oracle of the segment rasteriser (:mod:`growsim.kernels.raster`): per-pixel NumPy.

A thin line covers a pixel if the segment meets the pixel's half-open square (an interval
intersection per pixel); a wide line adds the pixels whose centre is within half the width.
"""

from __future__ import annotations

import numpy as np


def _axis_interval(a0, d, lo_edge):
    """t-interval where lo_edge <= a0 + t d < lo_edge + 1, as (lo, lo_closed, hi, hi_closed)."""
    n = a0.shape
    lo = np.full(n, -np.inf)
    hi = np.full(n, np.inf)
    lo_c = np.ones(n, bool)
    hi_c = np.ones(n, bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        t_in = (lo_edge - a0) / d
        t_out = (lo_edge + 1 - a0) / d
    pos = d > 0
    neg = d < 0
    zero = d == 0
    lo[pos], hi[pos], hi_c[pos] = t_in[pos], t_out[pos], False
    lo[neg], lo_c[neg], hi[neg] = t_out[neg], False, t_in[neg]
    inside = (a0 >= lo_edge) & (a0 < lo_edge + 1)
    empty = zero & ~inside
    lo[empty], hi[empty] = 1.0, 0.0
    return lo, lo_c, hi, hi_c


def _intersect(*ivals):
    lo, lo_c, hi, hi_c = ivals[0]
    lo, lo_c, hi, hi_c = lo.copy(), lo_c.copy(), hi.copy(), hi_c.copy()
    for l2, lc2, h2, hc2 in ivals[1:]:
        gt = l2 > lo
        eq = l2 == lo
        lo_c = np.where(gt, lc2, np.where(eq, lo_c & lc2, lo_c))
        lo = np.maximum(lo, l2)
        lt = h2 < hi
        eq = h2 == hi
        hi_c = np.where(lt, hc2, np.where(eq, hi_c & hc2, hi_c))
        hi = np.minimum(hi, h2)
    return (lo < hi) | ((lo == hi) & lo_c & hi_c)


def _supercover(a, b, H, W):
    """Per segment, the boolean (H, W) mask of pixel squares the segment touches."""
    ii, jj = np.meshgrid(np.arange(H, dtype=float), np.arange(W, dtype=float), indexing="ij")
    masks = []
    for (ax, ay), (bx, by) in zip(a, b):
        dx, dy = bx - ax, by - ay
        one = np.ones(ii.shape)
        ix = _axis_interval(ax * one, dx * one, jj)
        iy = _axis_interval(ay * one, dy * one, ii)
        unit = (
            np.zeros(ii.shape),
            np.ones(ii.shape, bool),
            np.ones(ii.shape),
            np.ones(ii.shape, bool),
        )
        masks.append(_intersect(ix, iy, unit))
    return masks


def _dist2_t(a, b, H, W):
    """Per segment, (squared distance, t) of each pixel centre to the segment."""
    cy, cx = np.meshgrid(np.arange(H) + 0.5, np.arange(W) + 0.5, indexing="ij")
    out = []
    for (ax, ay), (bx, by) in zip(a, b):
        dx, dy = bx - ax, by - ay
        L2 = dx * dx + dy * dy
        t = np.zeros(cx.shape) if L2 == 0 else np.clip(((cx - ax) * dx + (cy - ay) * dy) / L2, 0, 1)
        d2 = (ax + t * dx - cx) ** 2 + (ay + t * dy - cy) ** 2
        out.append((d2, t))
    return out


def _masks(a, b, width, H, W):
    thin = _supercover(a, b, H, W)
    dt = _dist2_t(a, b, H, W)
    masks = []
    for k in range(len(a)):
        m = thin[k].copy()
        if width[k] > 1:
            m |= dt[k][0] <= (0.5 * width[k]) ** 2
        masks.append(m)
    return masks, dt


def draw_segments(a, b, width, H, W):
    """The ``(H, W)`` uint8 image of segments ``a``-``b`` ``(n, 2)`` of ``width`` ``(n,)``.

    Examples
    --------
    >>> import numpy as np
    >>> draw_segments(np.array([[0.5, 1.5]]), np.array([[2.5, 1.5]]), [1.0], 3, 3).tolist()
    [[0, 0, 0], [1, 1, 1], [0, 0, 0]]
    """
    masks, _ = _masks(a, b, width, H, W)
    out = np.zeros((H, W), np.uint8)
    for m in masks:
        out[m] = 1
    return out


def draw_segments_depth(a, b, za, zb, width, H, W):
    """The z-buffer ``(H, W)`` (``inf`` where uncovered) and nearest segment ids (-1)."""
    masks, dt = _masks(a, b, width, H, W)
    depth = np.full((H, W), np.inf)
    ids = np.full((H, W), -1, np.int64)
    for k, m in enumerate(masks):
        z = za[k] + dt[k][1] * (zb[k] - za[k])
        upd = m & (z < depth)
        depth[upd] = z[upd]
        ids[upd] = k
    return depth, ids
