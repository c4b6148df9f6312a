"""Oracles of the mesh kernel (:func:`growsim.kernels.mesh.mesh_kernel`): plain NumPy.

:func:`mesh_kernel` gives the vertices of a mesh without welding (tubes in segment order,
then leaves); :func:`tube` and :func:`leaf`, those of one stem and one leaf.
"""

from __future__ import annotations

import math

import numpy as np


def tube(a, b, r0, r1, sides, segments):
    """Vertices of one tube, ring by ring, with the kernel's frame rule."""
    d = b - a
    L = np.linalg.norm(d)
    ax = d / L if L > 0 else np.array([0.0, 1.0, 0.0])
    helper = np.eye(3)[int(np.argmin(np.abs(ax)))]  # first of equal minima, as the kernel
    u = np.cross(ax, helper)
    u /= np.linalg.norm(u)
    w = np.cross(ax, u)
    out = []
    for j in range(segments + 1):
        fr = j / segments
        c = a + fr * d
        r = r0 + fr * (r1 - r0)
        for k in range(sides):
            ang = 2 * math.pi * k / sides
            out.append(c + r * (math.cos(ang) * u + math.sin(ang) * w))
    return np.array(out)


def leaf(a, b, w):
    """Centre and six corners of one hexagon leaf along a->b, half-width ``w``."""
    d = b - a
    L = np.linalg.norm(d)
    ax = d / L
    s = np.array([-ax[2], 0.0, ax[0]])
    s /= np.linalg.norm(s)
    c = a + d / 2
    pts = [c]
    for k in range(6):
        ang = k * math.pi / 3
        pts.append(c + math.cos(ang) * L / 2 * ax + math.sin(ang) / math.sin(math.pi / 3) * w * s)
    return np.array(pts)


def mesh_kernel(start, end, r0, r1, kind, sides, segments):
    """The ``points`` of :func:`growsim.kernels.mesh.mesh_kernel` without welding.

    Every stem's tube (``kind == 0``), in segment order, then every leaf's hexagon.

    Examples
    --------
    >>> import numpy as np
    >>> a, b = np.zeros((2, 3)), np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    >>> mesh_kernel(a, b, np.ones(2), np.ones(2), np.array([0, 1]), 4, 2).shape
    (19, 3)
    """
    stems = [s for s in range(len(kind)) if kind[s] == 0]
    leaves = [s for s in range(len(kind)) if kind[s] == 1]
    pts = [tube(start[s], end[s], r0[s], r1[s], sides, segments) for s in stems]
    pts += [leaf(start[s], end[s], r0[s]) for s in leaves]
    return np.concatenate(pts) if pts else np.zeros((0, 3))
