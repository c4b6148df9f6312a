"""The walls of a hormone module (:mod:`growsim.kernels.hormone`): their angles about the
module's axis and their outward directions from its pose. A module's pose ``R`` ``(3, 3)``
has as columns the two axes across it and its growth axis; in 3D wall ``i`` of ``walls``
faces ``cos(2 pi i / walls) x + sin(2 pi i / walls) y``, in 2D (the plant in the x-y
plane) the two sides ``+-x``. The oracle is ``tests/naive/walls.py``.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = ["frame_of", "wall_angles", "wall_frame", "wall_normals"]


@njit
def wall_angles(walls, dims):
    """``(walls, 2)``: the cosine and sine of each wall's angle about a module's axis: in
    3D ``2 pi i / walls``; in 2D (the plant in the x-y plane) the two sides, ``(1, 0)`` and
    ``(-1, 0)``. Computed once per step, not per module.

    Examples
    --------
    >>> wall_angles(2, 2).tolist()
    [[1.0, 0.0], [-1.0, 0.0]]
    """
    out = np.empty((walls, 2))
    for i in range(walls):
        if dims == 2:
            out[i, 0] = 1.0 if i == 0 else -1.0
            out[i, 1] = 0.0
        else:
            a = 2.0 * math.pi * i / walls
            out[i, 0] = math.cos(a)
            out[i, 1] = math.sin(a)
    return out


@njit(inline="always")
def frame_of(R, cs, out_v):
    """:func:`wall_frame` with the walls' :func:`wall_angles` ``cs`` given (computed once
    per step, not per module).

    Examples
    --------
    >>> import numpy as np
    >>> frame_of(np.eye(3), wall_angles(2, 2), np.empty((2, 3))).tolist()
    [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    for i in range(cs.shape[0]):
        for c in range(3):
            out_v[i, c] = cs[i, 0] * R[c, 0] + cs[i, 1] * R[c, 1]
    return out_v


@njit
def wall_frame(R, walls, dims, out_v):
    """Unit outward directions ``(walls, 3)`` of a module's walls from its pose ``R``
    ``(3, 3)`` (columns: the two axes across the module and its growth axis): in 3D
    ``cos(2 pi i / walls) x + sin(2 pi i / walls) y``; in 2D (the plant in the x-y plane)
    the two sides ``+-x`` (:func:`wall_angles`).

    Examples
    --------
    >>> import numpy as np
    >>> wall_frame(np.eye(3), 2, 2, np.empty((2, 3))).tolist()
    [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    return frame_of(R, wall_angles(walls, dims), out_v)


@njit
def wall_normals(n, R, walls, dims, out):
    """``(n, walls, 3)``: :func:`wall_frame` of modules ``0..n-1``.

    Examples
    --------
    >>> import numpy as np
    >>> wall_normals(1, np.eye(3)[None], 2, 2, np.empty((1, 2, 3)))[0, 1].tolist()
    [-1.0, 0.0, 0.0]
    """
    cs = wall_angles(walls, dims)
    for m in range(n):
        frame_of(R[m], cs, out[m])
    return out
