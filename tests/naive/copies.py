"""Oracles of a plant among its copies (:mod:`growsim.kernels.copies`): every moved point
listed in NumPy, and each point judged exactly at itself and moved back by every shift
(:func:`naive.light.point_exposure`), no map.
"""

from __future__ import annotations

import numpy as np

from naive.light import point_exposure


def among_copies(points, point_offsets, frames, grid, shifts):
    """Mirror of :func:`growsim.kernels.copies.among_copies`: ``(queries, query_offsets,
    src)``, each point then each of its moved points ``point - shifts[j]`` whose pixel
    coordinates in its plant's frame lie within a pixel of the frame."""
    u, v, res = grid
    queries, src, offsets = [], [], [0]
    for p in range(len(point_offsets) - 1):
        ox, oy, pix = frames[p]
        for i in range(int(point_offsets[p]), int(point_offsets[p + 1])):
            queries.append(points[i])
            src.append(i)
            for shift in shifts:
                moved = points[i] - shift
                x, y = (moved @ u - ox) / pix, (moved @ v - oy) / pix
                if -1.0 <= x <= res + 1.0 and -1.0 <= y <= res + 1.0:
                    queries.append(moved)
                    src.append(i)
        offsets.append(len(src))
    return np.array(queries).reshape(-1, 3), np.array(offsets), np.array(src, np.int64)


def copies_hard(segments, plane, shadow, targets, shifts, tol_pixels=0.0):
    """Mirror of :func:`growsim.kernels.copies.copies_hard` (without frames, scratch and
    ``expo``): each point's hard exposure along the light among the copies
    (:func:`naive.light.point_exposure` with ``shifts``); with ``tol_pixels > 0``, the
    boolean ``(m,)`` of points near an edge."""
    points, point_offsets = targets
    res, bias_pixels = shadow
    return point_exposure(segments, points, point_offsets, plane, res, bias_pixels,
                          tol_pixels=tol_pixels, shifts=shifts)  # fmt: skip
