"""Oracle of the capsule walk (:mod:`growsim.kernels.capsule`): every pixel of the map
tested against the capsule, no walk, no occupancy words.

A capsule (axis ``a-b`` in pixel coordinates, radius ``rr`` pixels) covers pixel ``(i,
j)`` when its centre ``(j + 0.5, i + 0.5)`` lies within ``rr`` of the axis; its depth
there is the axis' at the point nearest the centre. Each query ``q`` sits in pixel
``pix[q]`` at depth ``qz[q]``.
"""

from __future__ import annotations

import numpy as np


def coverage(ends, rr, res):
    """``(covered, depth, tie)``, ``(res, res)`` each: whether the capsule covers each
    pixel, the axis' depth at the point nearest its centre, and whether the centre lies
    so close to the capsule's edge (within ``1e-9`` of a pixel, relative) that rounding
    may decide it."""
    ax, ay, bx, by, za, zb = ends
    jj, ii = np.meshgrid(np.arange(res) + 0.5, np.arange(res) + 0.5)
    d = np.array([bx - ax, by - ay])
    L2 = float(d @ d)
    if L2 > 0:
        t = np.clip(((jj - ax) * d[0] + (ii - ay) * d[1]) / L2, 0.0, 1.0)
    else:
        t = np.zeros_like(jj)
    dist = np.hypot(ax + t * d[0] - jj, ay + t * d[1] - ii)
    tie = np.abs(dist - rr) <= 1e-9 * max(1.0, rr)
    return dist <= rr, za + t * (zb - za), tie


def walk_capsule(k, ends, rr, res, pix, qz, qown, bias, soft, trans_k, near_z, near_id, expo):
    """Mirror of :func:`growsim.kernels.capsule.walk_capsule` with the queries given by
    their pixels ``pix`` (the kernel reads them from its lists and occupancy words):
    returns new ``(near_z, near_id, expo)``. Hard shadows (``soft`` False): every covered
    pixel holding a query keeps the nearer of its depth so far and the capsule's (the
    capsule's segment ``k`` wins only when strictly nearer); soft: each query of a covered
    pixel that is not segment ``k``'s own and lies more than ``bias`` behind the capsule
    has its exposure multiplied by ``trans_k``."""
    near_z, near_id, expo = near_z.copy(), near_id.copy(), expo.copy()
    covered, depth, _ = coverage(ends, rr, res)
    covered, depth = covered.ravel(), depth.ravel()
    if soft:
        hit = covered[pix] & (qown != k) & (depth[pix] < qz - bias)
        expo[hit] *= trans_k
        return near_z, near_id, expo
    for px in np.unique(pix):
        if covered[px] and depth[px] < near_z[px]:
            near_z[px] = depth[px]
            near_id[px] = k
    return near_z, near_id, expo
