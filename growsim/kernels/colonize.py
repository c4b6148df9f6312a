"""Numba kernel of space colonization (:mod:`growsim.reconstruction.colonize`): one step's
nearest-node attraction (Runions, Lane and Prusinkiewicz, *Modeling trees with a space
colonization algorithm*, 2007).

Each attraction point keeps its nearest tree node and the squared distance to it; a step
compares the points left only with the nodes added since the last step (the nearest of
all nodes, found incrementally: on equal distances the first node wins, as ``argmin``),
removes the points within the kill distance of their nearest node, and adds, for every
node, the unit vectors towards the points within the radius of influence whose nearest it
is.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = ["colonize_step"]


@njit
def colonize_step(points, alive, nodes, n_nodes, first_new, best, best_d2, radii):
    """One step of space colonization's attraction, in place.

    Parameters
    ----------
    points : ``(P, 3)`` float64 attraction points.
    alive : ``(P,)`` bool, the points left; points killed here are set False.
    nodes : ``(N, 3)`` float64 tree nodes (the first ``n_nodes`` used).
    n_nodes, first_new : int, the nodes ``first_new .. n_nodes - 1`` are new since the
        last step (``0``: every node, the first step).
    best : ``(P,)`` int64 each point's nearest node (``-1`` none yet), updated.
    best_d2 : ``(P,)`` float64 its squared distance (``inf`` none yet), updated.
    radii : ``(influence, kill)`` floats: the radius of influence and the kill distance.

    Returns
    -------
    ``(pull (n_nodes, 3), count (n_nodes,))``: the sum of the unit vectors from each node
    towards the points within ``influence`` whose nearest it is, and their number.

    Examples
    --------
    >>> pts = np.array([[0.0, 2.0, 0.0], [0.0, 0.05, 0.0]])
    >>> alive = np.ones(2, np.bool_); nodes = np.zeros((4, 3))
    >>> best = np.full(2, -1); d2 = np.full(2, np.inf)
    >>> pull, count = colonize_step(pts, alive, nodes, 1, 0, best, d2, (5.0, 0.1))
    >>> alive.tolist(), pull[0].tolist(), count.tolist()
    ([True, False], [0.0, 1.0, 0.0], [1])
    """
    influence, kill = radii
    infl2 = influence * influence
    kill2 = kill * kill
    P = points.shape[0]
    pull = np.zeros((n_nodes, 3))
    count = np.zeros(n_nodes, np.int64)
    for i in range(P):
        if not alive[i]:
            continue
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        bd = best_d2[i]
        bj = best[i]
        for j in range(first_new, n_nodes):
            dx = px - nodes[j, 0]
            dy = py - nodes[j, 1]
            dz = pz - nodes[j, 2]
            d2 = dx * dx + dy * dy + dz * dz
            if d2 < bd:
                bd = d2
                bj = j
        best_d2[i] = bd
        best[i] = bj
        if bd < kill2:
            alive[i] = False
            continue
        if bd < infl2 and bj >= 0:
            d = math.sqrt(bd)
            pull[bj, 0] += (px - nodes[bj, 0]) / d
            pull[bj, 1] += (py - nodes[bj, 1]) / d
            pull[bj, 2] += (pz - nodes[bj, 2]) / d
            count[bj] += 1
    return pull, count
