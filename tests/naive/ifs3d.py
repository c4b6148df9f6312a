"""Oracles of the IFS tree's kernels (:mod:`growsim.kernels.ifs3d`): 4x4 matrix products.

The tree is built literally: every composition ``w_j1 ... w_jk`` of the maps as a product
of homogeneous matrices, applied to the trunk ``OS``; a population is scored one tree at a
time with the oracles of :mod:`naive.views`.
"""

from __future__ import annotations

import itertools

import numpy as np

from naive.views import blurred_ncc, frame_points, ncc, render_antialiased, render_thin


def _homogeneous(s, y, tz, ty):
    """4x4 ``Trans(0,y,0) Rot_y(ty) Rot_z(-tz) Scale(s)``, angles in degrees."""
    a, b = np.radians(-tz), np.radians(ty)
    T = np.eye(4)
    T[1, 3] = y
    Ry = np.eye(4)
    Ry[[0, 0, 2, 2], [0, 2, 0, 2]] = [np.cos(b), np.sin(b), -np.sin(b), np.cos(b)]
    Rz = np.eye(4)
    Rz[[0, 0, 1, 1], [0, 1, 0, 1]] = [np.cos(a), -np.sin(a), np.sin(a), np.cos(a)]
    S = np.diag([s, s, s, 1.0])
    return T @ Ry @ Rz @ S


def map_matrices(maps):
    """``(N, 3, 4)`` ``[A | t]`` of the maps ``(N, 4)`` rows ``(s, y, theta_z, theta_y)``.

    Examples
    --------
    >>> map_matrices([[0.5, 0.4, 90.0, 0.0]])[0] @ [0, 1, 0, 1]
    array([0.5, 0.4, 0. ])
    """
    return np.array([_homogeneous(*m)[:3] for m in np.asarray(maps, dtype=float)])


def compose_tree(maps, depth):
    """Every composition w_j1 ... w_jk (OS), level by level, lexicographic inside a level.

    Examples
    --------
    >>> s, e = compose_tree([[0.5, 0.4, 0.0, 0.0]], 1)
    >>> e[:, 1].tolist()
    [1.0, 0.9]
    """
    W = [_homogeneous(*m) for m in np.asarray(maps, dtype=float)]
    O = np.array([0, 0, 0, 1.0])
    S = np.array([0, 1, 0, 1.0])
    starts, ends = [], []
    for k in range(depth + 1):
        for js in itertools.product(range(len(W)), repeat=k):
            M = np.eye(4)
            for j in js:
                M = M @ W[j]
            starts.append((M @ O)[:3])
            ends.append((M @ S)[:3])
    return np.array(starts), np.array(ends)


def render_views(start, end, base, size):
    """Thin-line front and side views ``(2, size, size)`` of segments, framed."""
    coords, _ = frame_points(start, end, base, size)
    return render_thin(coords, size)


def score_population(params, depth, target, area_reject=False, blur=0.0):
    """``(n,)`` mean NCC of each tree ``(N, 4)`` of ``params`` against ``target``.

    ``blur > 0``: the blurred NCC of the anti-aliased views. A ``(1, S, S)`` target: the
    front alone, framed by its own extent (the depth set to the base's).
    """
    target = np.asarray(target)
    size = target.shape[1]
    out = []
    for maps in params:
        s, e = compose_tree(maps, depth)
        if target.shape[0] == 1:
            s[:, 2] = e[:, 2] = 0.0
        coords, _ = frame_points(s, e, np.zeros(3), size)
        coords = coords[: target.shape[0]]
        if blur > 0:
            out.append(blurred_ncc(render_antialiased(coords, size), target, blur, area_reject))
        else:
            out.append(ncc(render_thin(coords, size), target, area_reject))
    return np.array(out)
