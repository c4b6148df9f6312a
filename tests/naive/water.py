"""Oracles of the water-transport kernels (:mod:`growsim.kernels.water`): explicit walks.

Subtree demands by testing every segment for being a descendant; each segment's inflow by
walking its path down from the root, segment by segment (O(n^2) and O(n * depth)).
"""

from __future__ import annotations

import math

import numpy as np


def _ancestors(parent, i):
    """Segments from ``i``'s root down to ``i`` (inclusive)."""
    path = [int(i)]
    while parent[path[-1]] >= 0:
        path.append(int(parent[path[-1]]))
    return path[::-1]


def subtree_demand_kernel(parent, demand):
    """``D[i]``: sum of ``demand[j]`` over every ``j`` whose path from the root passes ``i``.

    Examples
    --------
    >>> subtree_demand_kernel([-1, 0, 0, 1], [0.0, 1.0, 2.0, 3.0]).tolist()
    [6.0, 4.0, 2.0, 3.0]
    """
    parent = np.asarray(parent)
    n = len(parent)
    D = np.zeros(n)
    for j in range(n):
        for i in _ancestors(parent, j):
            D[i] += demand[j]
    return D


def distribute_kernel(start, end, radius, parent, demand, D, supply, resistance, lift):
    """``(received, met, drop)``: each segment's water from a walk down its path, sharing
    flows as the model states them (root inflow ``supply * D[root]``, a child's inflow
    ``a[parent] * D[child] / D[parent]``, ``a = inflow * exp(-x)`` at the far end, the
    segment keeping ``min(d, a d / D)``); ``drop`` the sum of ``x`` along the path.

    Examples
    --------
    >>> s = np.array([[0.0, 0, 0], [0, 1, 0]]); e = np.array([[0.0, 1, 0], [0, 2, 0]])
    >>> rec, met, drop = distribute_kernel(s, e, np.ones(2), [-1, 0], [0.0, 2.0],
    ...                                    [2.0, 2.0], 0.5, 0.0, 0.1)
    >>> rec.round(3).tolist(), met.round(3).tolist(), drop.tolist()
    ([0.0, 0.819], [1.0, 0.409], [0.1, 0.2])
    """
    parent = np.asarray(parent)
    n = len(parent)
    received = np.zeros(n)
    met = np.ones(n)
    drop = np.zeros(n)
    for i in range(n):
        path = _ancestors(parent, i)
        root = path[0]
        # the root's demand per cross-section: the flux density the resistance is relative to
        ref = D[root] / radius[root] ** 2 if radius[root] > 0 and D[root] > 0 else 0.0
        F = supply * D[root]
        a = 0.0
        for k, j in enumerate(path):
            if k > 0:
                prev = path[k - 1]
                F = a * D[j] / D[prev] if D[prev] > 0 else 0.0
            x = lift * max(0.0, end[j][1] - start[j][1])
            if resistance > 0 and D[j] > 0:
                if radius[j] > 0 and ref > 0:
                    L = float(np.linalg.norm(np.subtract(end[j], start[j])))
                    x += resistance * L * (D[j] / radius[j] ** 2) / ref
                else:
                    x = math.inf
            drop[i] += x
            a = F * math.exp(-x)
        if demand[i] > 0:
            received[i] = min(demand[i], a * demand[i] / D[i])
            met[i] = received[i] / demand[i]
    return received, met, drop


def transport_kernel(start, end, radius, parent, demand, supply, resistance, lift):
    """``(received, met)``: both oracles in a row."""
    D = subtree_demand_kernel(parent, demand)
    rec, met, _ = distribute_kernel(start, end, radius, parent, demand, D, supply, resistance, lift)
    return rec, met
