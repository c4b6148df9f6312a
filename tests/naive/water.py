"""Oracles of the water-transport kernels (:mod:`growsim.kernels.water`): explicit walks.

Each segment's path conductance by walking its path down from the root, segment by
segment (O(n * depth)); each plant's level by bisection on the water it receives.
"""

from __future__ import annotations

import math

import numpy as np

REFERENCE_AREA = 1e-4


def _ancestors(parent, i):
    """Segments from ``i``'s root down to ``i`` (inclusive)."""
    path = [int(i)]
    while parent[path[-1]] >= 0:
        path.append(int(parent[path[-1]]))
    return path[::-1]


def conductance_kernel(start, end, radius, parent, resistance, lift):
    """``k[i] = 1 / (1 + x_i)``, ``x_i`` the sum along the path from the root to ``i`` of
    ``resistance L_j (1 cm^2 / (pi r_j^2))`` (infinite for a stem of radius 0) and ``lift``
    times the height each segment climbs.

    Examples
    --------
    >>> s = np.array([[0.0, 0, 0], [0, 1, 0]]); e = np.array([[0.0, 1, 0], [1, 1, 0]])
    >>> r = np.full(2, math.sqrt(1e-4 / math.pi))
    >>> np.round(conductance_kernel(s, e, r, [-1, 0], 0.5, 0.25), 6).tolist()
    [0.571429, 0.444444]
    """
    parent = np.asarray(parent)
    k = np.empty(len(parent))
    for i in range(len(parent)):
        x = 0.0
        for j in _ancestors(parent, i):
            L = float(np.linalg.norm(np.subtract(end[j], start[j])))
            if resistance > 0 and L > 0:
                area = math.pi * radius[j] ** 2
                x += resistance * L * REFERENCE_AREA / area if area > 0 else math.inf
            x += lift * max(0.0, end[j][1] - start[j][1])
        k[i] = 1.0 / (1.0 + x)
    return k


def fill_kernel(parent, demand, k, supply):
    """``met``: for each plant (a root and its descendants), the level ``lam`` at which
    ``sum d_i min(1, lam k_i)`` over its segments equals its ``supply`` (bisection), or
    every demand met when the supply covers the demand of its conducting segments; 1
    where the demand is 0, 0 where the conductance is."""
    parent = np.asarray(parent)
    demand, k = np.asarray(demand, float), np.asarray(k, float)
    n = len(parent)
    roots = np.array([_ancestors(parent, i)[0] for i in range(n)], dtype=np.int64)
    met = np.where(demand > 0, 0.0, 1.0)
    for r in set(roots.tolist()):
        mine = (roots == r) & (demand > 0) & (k > 0)
        if not mine.any():
            continue
        d, kk = demand[mine], k[mine]
        if supply >= d.sum():
            met[mine] = 1.0
            continue
        lo, hi = 0.0, 1.0 / kk.min()  # at hi every segment is saturated: too much
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if (d * np.minimum(1.0, mid * kk)).sum() > supply:
                hi = mid
            else:
                lo = mid
        met[mine] = np.minimum(1.0, lo * kk)
    return met


def transport_kernel(start, end, radius, parent, demand, supply, resistance, lift):
    """``(received, met)``: both oracles in a row, ``received = met * demand``."""
    k = conductance_kernel(start, end, radius, parent, resistance, lift)
    met = fill_kernel(parent, demand, k, supply)
    return met * np.asarray(demand, float), met
