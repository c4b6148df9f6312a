"""Numba kernels of water transport by negative pressure (:mod:`growsim.env.water`).

Two passes over segments stored parents first (``parent[i] < i``), as in
"Hormone-module growth: facts, formulas and a proposed design" (the research note's
"a reverse loop sums child -> parent, a forward loop carries parent -> child"):

1. :func:`subtree_demand_kernel`, child to parent: ``D[i] = d[i] + sum of D[c]`` over the
   children ``c`` of ``i`` (the pressure a segment pulls with).
2. :func:`distribute_kernel`, parent to child: the roots' water is shared down the tree in
   proportion to those sums, each segment passing on only a fraction ``exp(-x[i])`` of
   what enters it (``x[i]`` the pressure drop along it, see :mod:`growsim.env.water` for
   the equations), and each segment keeps ``min(d[i], a[i] d[i] / D[i])`` of what reaches
   its far end ``a[i]``: ``min(1, supply * exp(-(sum of x along the path))) * d[i]``.

Several plants joined into one forest (one root each, :meth:`growsim.phenotypes.plant.Plant.concat`)
run in one call: every root draws its own share.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = [
    "distribute_kernel",
    "subtree_demand_kernel",
    "transport_into_kernel",
    "transport_kernel",
]


@njit
def subtree_demand_kernel(parent, demand):
    """``(n,)`` float64: each segment's demand plus that of all its descendants.

    ``parent`` ``(n,)`` int64 with ``parent[i] < i`` (``-1`` for roots); ``demand`` ``(n,)``
    float64 ``>= 0``. One child-to-parent pass (the segments in reverse order).

    Examples
    --------
    >>> import numpy as np
    >>> subtree_demand_kernel(np.array([-1, 0, 0, 1]), np.array([0.0, 1.0, 2.0, 3.0]))
    array([6., 4., 2., 3.])
    """
    n = parent.shape[0]
    D = demand.copy()
    for i in range(n - 1, -1, -1):
        p = parent[i]
        if p >= 0:
            D[p] += D[i]
    return D


@njit(error_model="numpy")
def _pass_down(start, end, radius, parent, supply, resistance, lift, received, met):
    """The parent-to-child pass, in place and without scratch memory.

    On entry ``received`` holds the subtree demands ``D``; on exit ``met[i]`` holds
    ``s[i] = s[parent] + x[i]``, the pressure drop summed from the root to ``i``'s far
    end, and ``received[i]`` the root's inverse flux density ``r_root^2 / D_root`` (each
    slot is read before it is overwritten; children read only their parent's slots, which
    are final). Only an addition carries from parent to child, so the pass is not bound by
    ``exp``'s latency; :func:`_finish` turns ``s`` into shares."""
    n = parent.shape[0]
    for i in range(n):
        p = parent[i]
        Di = received[i]
        if p < 0:
            s0 = 0.0
            inv_ref = radius[i] * radius[i] / Di if Di > 0.0 else 0.0
        else:
            s0 = met[p]
            inv_ref = received[p]
        dy = end[i, 1] - start[i, 1]
        x = lift * max(dy, 0.0)
        if resistance > 0.0 and Di > 0.0:
            r2 = radius[i] * radius[i]
            if r2 > 0.0 and inv_ref > 0.0:
                dx = end[i, 0] - start[i, 0]
                dz = end[i, 2] - start[i, 2]
                L = math.sqrt(dx * dx + dy * dy + dz * dz)
                x += resistance * L * Di * inv_ref / r2
            else:
                x = np.inf
        met[i] = s0 + x
        received[i] = inv_ref


@njit(error_model="numpy")
def _finish(demand, supply, received, met):
    """``met[i] = min(1, supply * exp(-s[i]))`` (1 where ``demand[i] = 0``) from the drops
    ``s`` in ``met``; ``received[i] = met[i] * demand[i]``."""
    for i in range(demand.shape[0]):
        d = demand[i]
        m = min(supply * math.exp(-met[i]), 1.0) if d > 0.0 else 1.0
        met[i] = m
        received[i] = m * d


@njit
def distribute_kernel(start, end, radius, parent, demand, D, supply, resistance, lift):
    """Share the roots' water down the tree: ``(received, met, drop)``, each ``(n,)``.

    Parameters
    ----------
    start, end : ``(n, 3)`` float64 segment end points (y up).
    radius : ``(n,)`` float64 radii ``>= 0``.
    parent : ``(n,)`` int64, ``parent[i] < i``, ``-1`` for roots.
    demand : ``(n,)`` float64 ``>= 0``; ``D`` its subtree sums
        (:func:`subtree_demand_kernel`).
    supply : float ``>= 0``, each root's inflow as a share of its subtree demand.
    resistance : float ``>= 0``, loss per unit length where the demand per cross-section
        ``D / r^2`` equals the root's.
    lift : float ``>= 0``, loss per unit of height climbed.

    Returns
    -------
    received ``(n,)`` water kept by each segment, met ``(n,)`` ``received / demand`` (1
    where the demand is 0), drop ``(n,)`` the pressure drop ``s`` summed from the root to
    each segment's far end (what arrives there is ``exp(-s)`` of what the root gave).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 0, 0], [0, 1, 0]]); e = np.array([[0.0, 1, 0], [0, 2, 0]])
    >>> par = np.array([-1, 0]); d = np.array([0.0, 2.0])
    >>> D = subtree_demand_kernel(par, d)
    >>> rec, met, drop = distribute_kernel(s, e, np.ones(2), par, d, D, 0.5, 0.0, 0.1)
    >>> rec.round(3).tolist(), met.round(3).tolist(), drop.tolist()
    ([0.0, 0.819], [1.0, 0.409], [0.1, 0.2])
    """
    received = D.copy()
    met = np.empty(parent.shape[0])
    _pass_down(start, end, radius, parent, supply, resistance, lift, received, met)
    drop = met.copy()
    _finish(demand, supply, received, met)
    return received, met, drop


@njit
def transport_into_kernel(
    start, end, radius, parent, demand, supply, resistance, lift, received, met
):
    """:func:`transport_kernel` writing into ``received`` and ``met`` (``(n,)`` float64,
    any content): callers that reuse buffers skip the page faults of fresh memory (about
    a third of the time at 300,000 segments).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((1, 3)); e = np.ones((1, 3)); rec = np.empty(1); met = np.empty(1)
    >>> transport_into_kernel(s, e, np.ones(1), np.array([-1]), np.full(1, 2.0), 0.25,
    ...                       0.0, 0.0, rec, met)
    >>> rec.tolist(), met.tolist()
    ([0.5], [0.25])
    """
    received[:] = demand
    for i in range(parent.shape[0] - 1, -1, -1):  # subtree_demand_kernel, in place
        p = parent[i]
        if p >= 0:
            received[p] += received[i]
    _pass_down(start, end, radius, parent, supply, resistance, lift, received, met)
    _finish(demand, supply, received, met)


@njit
def transport_kernel(start, end, radius, parent, demand, supply, resistance, lift):
    """Both passes: ``(received, met)`` (see :func:`distribute_kernel`); no memory but
    the two outputs.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((2, 3)); e = np.zeros((2, 3)); e[:, 0] = 1.0
    >>> rec, met = transport_kernel(s, e, np.ones(2), np.array([-1, 0]), np.ones(2),
    ...                             0.5, 0.0, 0.0)
    >>> rec.tolist(), met.tolist()
    ([0.5, 0.5], [0.5, 0.5])
    """
    n = parent.shape[0]
    received = np.empty(n)
    met = np.empty(n)
    transport_into_kernel(
        start, end, radius, parent, demand, supply, resistance, lift, received, met
    )
    return received, met
