"""Oracles of the gravity kernels (:mod:`growsim.kernels.gravity`): direct sums, O(n^2).

For each segment its sub-tree is found by walking every segment's parents up to a root,
and the masses and moments of the sub-tree are summed directly, with no running sums.
"""

from __future__ import annotations

import itertools
import math

import numpy as np


def _segment_mass_and_centre(start, end, r0, r1, kind, density, leaf_mass_per_area):
    """A segment's mass and centre of mass: a stem is a truncated cone (radii ``r0`` at
    ``start``, ``r1`` at ``end``), a leaf a blade of ``length x 2 r0``."""
    axis = end - start
    length = float(np.linalg.norm(axis))
    if kind == 0:
        volume = math.pi * length * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0
        # the cone's centroid: integrate the area pi r(x)^2 along x in [0, 1]
        xs = np.linspace(0.0, 1.0, 20001)
        area = (r0 + (r1 - r0) * xs) ** 2
        total = np.trapezoid(area, xs)
        t = np.trapezoid(area * xs, xs) / total if total > 0 else 0.5
        return density * volume, start + t * axis
    return leaf_mass_per_area * 2.0 * r0 * length, start + 0.5 * axis


def _in_subtree(parent, i, s):
    """Whether segment ``i`` is ``s`` or one of its descendants (walk up from ``i``)."""
    while i >= 0:
        if i == s:
            return True
        i = int(parent[i])
    return False


def loads_kernel(start, end, radius, radius_end, parent, kind, strength, material):
    """Mirror of :func:`growsim.kernels.gravity.loads_kernel` (without ``out``): a
    ``(4, n)`` array of rows ``mass``, ``mass_above``, ``moment``, ``ratio``; ``material``
    is ``(density, leaf_mass_per_area, g)``.

    Examples
    --------
    >>> import numpy as np
    >>> out = loads_kernel(np.zeros((1, 3)), np.array([[2.0, 0, 0]]), [0.1], [0.1], [-1], [0],
    ...                    [1e6], (1000.0, 0.1, 10.0))
    >>> round(float(out[2, 0]), 2)  # weight x 1
    628.32
    """
    density, leaf_mass_per_area, g = material
    n = start.shape[0]
    strength = np.broadcast_to(np.asarray(strength, float), (n,))
    mc = [
        _segment_mass_and_centre(
            start[i], end[i], radius[i], radius_end[i], kind[i], density, leaf_mass_per_area
        )
        for i in range(n)
    ]
    mass = np.array([m for m, _ in mc])
    mass_above = np.zeros(n)
    moment = np.zeros(n)
    ratio = np.zeros(n)
    for s in range(n):
        torque = np.zeros(3)
        for i in range(n):
            if not _in_subtree(parent, i, s):
                continue
            m, c = mc[i]
            mass_above[s] += m
            weight = np.array([0.0, -m * g, 0.0])
            torque += np.cross(c - start[s], weight)  # r x F about the joint
        moment[s] = np.linalg.norm(torque)
        if kind[s] == 0 and moment[s] > 0:
            section = math.pi * radius[s] ** 3 / 4.0
            stress = moment[s] / section if section > 0 else np.inf
            ratio[s] = stress / strength[s]
    return np.stack([mass, mass_above, moment, ratio])


def first_break_kernel(ratio, offsets):
    """Mirror of :func:`growsim.kernels.gravity.first_break_kernel`."""
    out = []
    for a, b in itertools.pairwise(offsets):
        seg = np.asarray(ratio[a:b])
        if seg.size and seg.max() >= 1.0:
            out.append(int(a + np.argmax(seg)))
        else:
            out.append(-1)
    return np.array(out, np.int64)


def radius_end_kernel(parent, kind, radius):
    """Mirror of :func:`growsim.kernels.gravity.radius_end_kernel` (without ``out``): for
    each segment, its children of its own kind, their largest radius, capped by its own."""
    out = np.array(radius, dtype=np.float64)
    for s in range(len(parent)):
        kids = [c for c in range(len(parent)) if parent[c] == s and kind[c] == kind[s]]
        if kids:
            out[s] = min(max(radius[c] for c in kids), radius[s])
    return out
