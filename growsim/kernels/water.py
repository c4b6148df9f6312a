"""Numba kernels of water transport (:mod:`growsim.env.water`): a fixed supply shared by
path conductance.

Segments are stored parents first (``parent[i] < i``). Two steps:

1. :func:`conductance_kernel`, parent to child: each segment's path resistance from the
   soil to its far end, ``x_i = x_parent + resistance L_i (a_ref / (pi r_i^2)) + lift
   max(0, dy_i)`` (``x = 0`` below a root; ``a_ref`` = :data:`REFERENCE_AREA`, 1 cm^2),
   and its path conductance ``k_i = 1 / (1 + x_i)``: the roots' own resistance is the 1,
   a metre of stem of 1 cm^2 adds ``resistance`` to it (sapwood conducts by its
   cross-section, as the pipe model's bundle of pipes), a metre climbed adds ``lift``.
2. :func:`fill_kernel`: each root's water ``supply`` (a fixed amount a step) is shared by
   water filling: segment ``i`` of demand ``d_i`` receives ``d_i min(1, lam k_i)``, ``lam``
   the one level at which the plant's segments receive the whole supply, or every
   demand met if the supply covers it. Water never exceeds the supply; a segment that
   needs less than its conductance would bring leaves the rest to the others; a segment
   of conductance 0 (a stem of radius 0 on its path) gets nothing.

Several plants joined into one forest (one root each,
:meth:`growsim.phenotypes.plant.Plant.concat`) run in one call: every root draws its own
``supply``. The oracle is ``tests/naive/water.py`` (paths walked one by one, the level
found by bisection).
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = [
    "REFERENCE_AREA",
    "conductance_kernel",
    "fill_kernel",
    "transport_into_kernel",
    "transport_kernel",
]

#: the cross-section ``resistance`` is given for: 1 cm^2 (m^2)
REFERENCE_AREA = 1e-4


@njit
def conductance_kernel(start, end, radius, parent, resistance, lift, out):
    """``out`` ``(n,)``: each segment's path conductance from the soil to its far end,
    ``1 / (1 + x_i)`` (see the module), overwritten and returned.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 0, 0], [0, 1, 0]]); e = np.array([[0.0, 1, 0], [1, 1, 0]])
    >>> r = np.full(2, np.sqrt(1e-4 / np.pi))  # 1 cm^2 each
    >>> conductance_kernel(s, e, r, np.array([-1, 0]), 0.5, 0.25, np.empty(2)).tolist()
    [0.5714285714285714, 0.4444444444444444]
    """
    n = parent.shape[0]
    path = np.empty(n)  # x: the path resistance from the soil to each far end
    for i in range(n):
        p = parent[i]
        x = 0.0 if p < 0 else path[p]
        dx = end[i, 0] - start[i, 0]
        dy = end[i, 1] - start[i, 1]
        dz = end[i, 2] - start[i, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        if resistance > 0.0 and L > 0.0:
            a = math.pi * radius[i] * radius[i]
            x += resistance * L * REFERENCE_AREA / a if a > 0.0 else np.inf
        if dy > 0.0:
            x += lift * dy
        path[i] = x
        out[i] = 1.0 / (1.0 + x)
    return out


@njit
def fill_kernel(parent, demand, k, supply, met):
    """``met`` ``(n,)``: the share of each segment's demand met when each root's
    ``supply`` is shared by water filling over the conductances ``k`` (see the module):
    ``met_i = min(1, lam k_i)`` with one level ``lam`` per plant, so that the plant
    receives ``min(supply, sum of the demand of its conducting segments)``; 1 where the
    demand is 0, 0 where the conductance is. Overwritten and returned.

    Examples
    --------
    >>> import numpy as np
    >>> par = np.array([-1, 0, 0]); d = np.array([0.0, 1.0, 1.0])
    >>> fill_kernel(par, d, np.array([1.0, 1.0, 0.25]), 1.0, np.empty(3)).tolist()
    [1.0, 0.8, 0.2]
    >>> fill_kernel(par, d, np.array([1.0, 1.0, 0.25]), 1.5, np.empty(3)).tolist()
    [1.0, 1.0, 0.5]
    """
    n = parent.shape[0]
    root = np.empty(n, np.int64)
    count = np.zeros(n + 1, np.int64)  # drawing segments per root, then offsets
    for i in range(n):
        root[i] = i if parent[i] < 0 else root[parent[i]]
        if demand[i] > 0.0 and k[i] > 0.0:
            count[root[i] + 1] += 1
        met[i] = 1.0 if demand[i] <= 0.0 else 0.0
    for i in range(n):
        count[i + 1] += count[i]
    # the drawing segments grouped by root, each group by conductance, highest first
    order = np.argsort(-k)
    group = np.empty(count[n], np.int64)
    fill = count[:n].copy()
    for j in range(n):
        i = order[j]
        if demand[i] > 0.0 and k[i] > 0.0:
            group[fill[root[i]]] = i
            fill[root[i]] += 1
    tail = np.empty(count[n] + 1)  # sum of d k from a position to its group's end
    for r in range(n):
        a, b = count[r], count[r + 1]
        if b <= a:
            continue
        tail[b] = 0.0
        total = 0.0
        for j in range(b - 1, a - 1, -1):
            i = group[j]
            tail[j] = tail[j + 1] + demand[i] * k[i]
            total += demand[i]
        if supply >= total:  # every demand met
            for j in range(a, b):
                met[group[j]] = 1.0
            continue
        # the most conductive segments saturate first: find the first that does not
        head = 0.0  # demand of the saturated segments
        lam = 0.0
        for j in range(a, b):
            i = group[j]
            lam = (supply - head) / tail[j]
            if lam * k[i] <= 1.0:
                break
            head += demand[i]
        for j in range(a, b):
            i = group[j]
            met[i] = min(1.0, lam * k[i])
    return met


@njit
def transport_into_kernel(
    start, end, radius, parent, demand, supply, resistance, lift, received, met
):
    """Both steps into ``received`` and ``met`` (``(n,)`` float64, any content): the
    conductances (:func:`conductance_kernel`, written into ``received`` first), the shares
    met (:func:`fill_kernel`), then ``received = met * demand``. ``supply`` the water each
    root draws (a fixed amount); ``resistance`` and ``lift`` as
    :func:`conductance_kernel`.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((2, 3)); e = np.zeros((2, 3)); e[:, 0] = 1.0
    >>> rec = np.empty(2); met = np.empty(2)
    >>> transport_into_kernel(s, e, np.ones(2), np.array([-1, 0]), np.array([1.0, 3.0]),
    ...                       2.0, 0.0, 0.0, rec, met)
    >>> rec.tolist(), met.tolist()
    ([0.5, 1.5], [0.5, 0.5])
    """
    conductance_kernel(start, end, radius, parent, resistance, lift, received)
    fill_kernel(parent, demand, received, supply, met)
    for i in range(parent.shape[0]):
        received[i] = met[i] * demand[i]


@njit
def transport_kernel(start, end, radius, parent, demand, supply, resistance, lift):
    """:func:`transport_into_kernel` into new arrays: ``(received, met)``.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((1, 3)); e = np.ones((1, 3))
    >>> transport_kernel(s, e, np.ones(1), np.array([-1]), np.full(1, 2.0), 8.0, 0.0, 0.0)
    (array([2.]), array([1.]))
    """
    n = parent.shape[0]
    received = np.empty(n)
    met = np.empty(n)
    transport_into_kernel(
        start, end, radius, parent, demand, supply, resistance, lift, received, met
    )
    return received, met
