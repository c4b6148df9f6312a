"""Oracle of the space-colonization kernel (:mod:`growsim.kernels.colonize`): every
point's nearest node found afresh among all nodes (``argmin`` of the full distance
matrix), no incremental update."""

from __future__ import annotations

import numpy as np


def colonize_step(points, alive, nodes, n_nodes, first_new, best, best_d2, radii):
    """The kernel's step by its definition: ``first_new`` is ignored (all nodes are
    looked at), ``alive``, ``best`` and ``best_d2`` updated in place; returns ``(pull,
    count)``.

    Examples
    --------
    >>> pts = np.array([[0.0, 2.0, 0.0]]); alive = np.ones(1, bool)
    >>> pull, count = colonize_step(pts, alive, np.zeros((1, 3)), 1, 0, np.full(1, -1),
    ...                             np.full(1, np.inf), (5.0, 0.1))
    >>> pull.tolist(), count.tolist()
    ([[0.0, 1.0, 0.0]], [1])
    """
    influence, kill = radii
    used = nodes[:n_nodes]
    pull = np.zeros((n_nodes, 3))
    count = np.zeros(n_nodes, np.int64)
    idx = np.flatnonzero(alive)
    if idx.size == 0 or n_nodes == 0:
        return pull, count
    diff = points[idx, None, :] - used[None, :, :]
    d2 = (diff**2).sum(axis=2)
    near = np.argmin(d2, axis=1)
    nd2 = d2[np.arange(idx.size), near]
    best[idx] = near
    best_d2[idx] = nd2
    killed = nd2 < kill * kill
    alive[idx[killed]] = False
    pulled = ~killed & (nd2 < influence * influence)
    for i, j, d in zip(idx[pulled], near[pulled], np.sqrt(nd2[pulled])):
        pull[j] += (points[i] - used[j]) / d
        count[j] += 1
    return pull, count
