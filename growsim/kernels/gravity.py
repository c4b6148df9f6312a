"""Numba kernels of the gravity loads at joints (:mod:`growsim.env.gravity`).

One child-to-parent pass over segments stored parents first (``parent[s] < s``): going
from the last segment to the first, each segment's own mass and first moment are added to
its running sub-tree sums (its descendants, all stored after it, are already in), its
joint's moment is read off, and the sums are handed to its parent. Several roots (a
forest of concatenated plants) are fine.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = ["first_break_kernel", "loads_kernel", "radius_end_kernel"]


@njit
def loads_kernel(start, end, radius, radius_end, parent, kind, strength, material, out):
    """Mass above, bending moment and stress ratio at the base of every segment, in one
    child-to-parent pass.

    Parameters
    ----------
    start, end : ``(n, 3)`` float64 end points (y up).
    radius, radius_end : ``(n,)`` float64 radius at the base and at the far end.
    parent : ``(n,)`` int64, ``-1`` for a root, ``parent[s] < s`` (not checked here).
    kind : ``(n,)`` int8, 0 = stem (a truncated cone of wood of ``density``), 1 = leaf (a
        blade of ``length x 2 radius`` with ``leaf_mass_per_area`` per unit area).
    strength : ``(n,)`` or ``(1,)`` float64 modulus of rupture (``(1,)``: one for all).
    material : ``(density, leaf_mass_per_area, g)`` floats.
    out : ``(4, n)`` float64, overwritten (reuse it across calls to skip allocating).

    Returns
    -------
    ``out``: row 0 each segment's own mass; row 1 ``mass_above`` (its sub-tree, itself
    included); row 2 the ``moment`` about its base, ``g |sum m_i (c_i - start_s)|`` over
    the sub-tree's segments (mass ``m_i``, centre of mass ``c_i``; x and z parts); row 3
    the stress ratio ``moment / (pi r^3 / 4) / strength`` (0 for leaves and unloaded
    joints; ``inf`` for a loaded stem of radius 0).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((1, 3)); e = np.array([[1.0, 0.0, 0.0]])
    >>> r = np.array([0.1]); p = np.array([-1]); k = np.zeros(1, np.int8)
    >>> material = (1000.0, 0.1, 10.0)  # density, leaf mass per area, g
    >>> out = loads_kernel(s, e, r, r, p, k, np.array([1e6]), material, np.empty((4, 1)))
    >>> np.round(out[:, 0], 3).tolist()  # mass, mass above, moment (weight x 0.5), ratio
    [31.416, 31.416, 157.08, 0.2]
    """
    density, leaf_mass_per_area, g = material
    n = start.shape[0]
    mass = out[0]
    mass_above = out[1]
    moment = out[2]  # holds the sub-tree's first moment in x until its segment is done
    ratio = out[3]  # ... and in z
    mass_above[:] = 0.0
    moment[:] = 0.0
    ratio[:] = 0.0
    one_strength = strength.shape[0] == 1
    k_cone = density * math.pi
    for s in range(n - 1, -1, -1):
        x0 = start[s, 0]
        z0 = start[s, 2]
        dx = end[s, 0] - x0
        dy = end[s, 1] - start[s, 1]
        dz = end[s, 2] - z0
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        r0 = radius[s]
        if kind[s] == 0:
            # a truncated cone: m = rho pi L (r0^2 + r0 r1 + r1^2) / 3, its centroid at
            # t = (r0^2 + 2 r0 r1 + 3 r1^2) / (4 (r0^2 + r0 r1 + r1^2)) of L; mt = m t
            r1 = radius_end[s]
            m = k_cone * L * (r0 * r0 + r0 * r1 + r1 * r1) * (1.0 / 3.0)
            mt = k_cone * L * (r0 * r0 + 2.0 * r0 * r1 + 3.0 * r1 * r1) * (1.0 / 12.0)
        else:
            m = leaf_mass_per_area * 2.0 * r0 * L
            mt = 0.5 * m
        mass[s] = m
        # the children (stored after s) have already added their sums into row s
        ma = mass_above[s] + m
        ax = moment[s] + m * x0 + mt * dx
        az = ratio[s] + m * z0 + mt * dz
        mass_above[s] = ma
        p = parent[s]
        if p >= 0:
            mass_above[p] += ma
            moment[p] += ax
            ratio[p] += az
        hx = ax - ma * x0
        hz = az - ma * z0
        M = g * math.sqrt(hx * hx + hz * hz)
        moment[s] = M
        if kind[s] != 0 or M == 0.0:
            ratio[s] = 0.0
        else:
            W = 0.25 * math.pi * r0 * r0 * r0 * (strength[0] if one_strength else strength[s])
            ratio[s] = M / W if W > 0.0 else np.inf
    return out


@njit
def first_break_kernel(ratio, offsets):
    """For each plant ``k`` (segments ``offsets[k]:offsets[k + 1]``), the index (into the
    whole array) of its most overloaded joint if its ratio is ``>= 1`` (the first such
    index on a tie), else ``-1``. Returns ``(len(offsets) - 1,)`` int64.

    Examples
    --------
    >>> import numpy as np
    >>> first_break_kernel(np.array([0.5, 2.0, 3.0, 0.2, 0.9]), np.array([0, 3, 5])).tolist()
    [2, -1]
    """
    k = offsets.shape[0] - 1
    out = np.full(k, -1, np.int64)
    for j in range(k):
        best = 1.0
        for s in range(offsets[j], offsets[j + 1]):
            if ratio[s] > best or (ratio[s] == best and out[j] < 0):
                best = ratio[s]
                out[j] = s
    return out


@njit
def radius_end_kernel(parent, kind, radius, out):
    """``out`` ``(n,)``: each segment's radius at its far end when a model gave none: the
    largest radius of its children of the same kind, capped by its own radius (a tip does
    not narrow). Overwritten and returned.

    Examples
    --------
    >>> import numpy as np
    >>> radius_end_kernel(np.array([-1, 0]), np.zeros(2, np.int8), np.array([0.2, 0.1]),
    ...                   np.empty(2)).tolist()
    [0.1, 0.1]
    """
    n = parent.shape[0]
    out[:n] = -1.0
    for s in range(n):
        p = parent[s]
        if p >= 0 and kind[s] == kind[p] and radius[s] > out[p]:
            out[p] = radius[s]
    for s in range(n):
        out[s] = radius[s] if out[s] < 0.0 else min(out[s], radius[s])
    return out
