"""Kernels of a stand of hormone plants (``[environment.stand]``): an explicit stand as
one module array with a root per plant (:func:`new_stand`), and the offsets of a
periodic stand's copies (:func:`periodic_shifts`) that
:func:`growsim.kernels.hormone.grow_step` shades the plant with.
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.hormone import C_NEW_LEAF, C_NEWLEN, C_NEWRAD, C_PHYSICS, new_plant

__all__ = ["nearest_shifts", "new_stand", "periodic_shifts"]


@njit
def new_stand(modules, c, xz, ground):
    """Reset :class:`Modules` ``modules`` to a stand of seedlings, one per row of ``xz``
    ``(N, 2)``: module ``i`` is plant ``i``'s root, a :func:`new_plant` seedling standing
    at ``(x, ground, z)`` with its row's new length, radius and (``growsim``) leaf
    area. Every module after them descends from one root (parents
    first), so one module array holds the whole stand and one :func:`grow_step` grows
    it: one shadow map for all plants, each root its own water. Returns ``N``.

    Examples
    --------
    >>> import numpy as np
    >>> from growsim.kernels.hormone import N_CONSTANTS, new_module_arrays
    >>> modules = new_module_arrays(4, 2)
    >>> xz = np.array([[-1.0, 0.0], [1.0, 0.5]])
    >>> new_stand(modules, np.full((2, N_CONSTANTS), 0.1), xz, 0.0), modules.plant[:2].tolist()
    (2, [0, 1])
    >>> modules.origin[1].tolist(), modules.R[1, :, 2].tolist()
    ([1.0, 0.0, 0.5], [0.0, 1.0, 0.0])
    """
    new_plant(modules, c[0])
    N = xz.shape[0]
    for i in range(N):
        modules.R[i] = modules.R[0]
        modules.length[i] = c[i, C_NEWLEN]
        modules.radius[i] = c[i, C_NEWRAD]
        modules.nutrient[i] = modules.nutrient[0]
        modules.chlorophyll[i] = 1.0
        modules.apex[i] = True
        modules.plant[i] = i
        modules.leaf[i] = c[i, C_NEW_LEAF] if c[i, C_PHYSICS] < 0.5 else 0.0
        modules.drawn[i] = max(modules.radius[i], 0.5 * modules.leaf[i] / modules.length[i])
        modules.origin[i, 0] = xz[i, 0]
        modules.origin[i, 1] = ground
        modules.origin[i, 2] = xz[i, 1]
    return N


def periodic_shifts(spacing, rings, dims):
    """``(k, 3)`` the offsets of a periodic stand's copies around the focal plant: a
    square lattice of ``spacing`` on the x-z plane (3D) or on x (2D), every cell within
    ``rings`` cells of the focal one but itself (8 for one ring in 3D, 2 in 2D).

    Examples
    --------
    >>> periodic_shifts(2.0, 1, 2).tolist()
    [[-2.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
    >>> periodic_shifts(1.0, 1, 3).shape
    (8, 3)
    """
    out = []
    zs = range(-rings, rings + 1) if dims == 3 else (0,)
    for j in zs:
        for i in range(-rings, rings + 1):
            if i or j:
                out.append([i * spacing, 0.0, j * spacing])
    return np.array(out, dtype=np.float64).reshape(-1, 3)


def nearest_shifts(spacing, count, dims):
    """``(count, 3)`` the offsets of the ``count`` lattice cells nearest the focal one
    (a mixture's neighbours): :func:`periodic_shifts`' cells, nearest first (ring by ring;
    within a distance in :func:`periodic_shifts`' order).

    Examples
    --------
    >>> nearest_shifts(1.0, 4, 3).tolist()
    [[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    >>> nearest_shifts(2.0, 3, 2).tolist()
    [[-2.0, 0.0, 0.0], [2.0, 0.0, 0.0], [-4.0, 0.0, 0.0]]
    """
    rings = 1
    while (2 * rings + 1) ** (2 if dims == 3 else 1) - 1 < count:
        rings += 1
    cells = periodic_shifts(spacing, rings, dims)
    d = np.round(np.hypot(cells[:, 0], cells[:, 2]) / spacing, 9)
    return cells[np.argsort(d, kind="stable")[:count]]
