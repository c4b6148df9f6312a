"""The light of the hormone model's modules (:mod:`growsim.kernels.hormone`): each wall's
light through the shadow map of the whole plant drawn with its leaves, and the light on
each module's leaves, read on top of its foliage (:func:`lights_kernel`); a module lying
on the soil gets none (:func:`soil_unlit`). Equations: ``docs/models/hormone.md`` (step 1).
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.light import point_light_into
from growsim.kernels.walls import wall_normals

__all__ = ["LEAVES", "WALLS", "lights_kernel", "module_ends", "soil_unlit", "walls_light"]

#: what :func:`lights_kernel` lights: the walls, the leaves, or both
WALLS, LEAVES = 1, 2


@njit
def module_ends(n, origin, length, R, end):
    """``end[m] = origin[m] + length[m] R[m][:, 2]`` for modules ``0..n-1``: each
    module's far end, along its growth axis.

    Examples
    --------
    >>> module_ends(1, np.zeros((1, 3)), np.array([0.5]), np.eye(3)[None], np.empty((1, 3)))
    array([[0. , 0. , 0.5]])
    """
    for m in range(n):
        for k in range(3):
            end[m, k] = origin[m, k] + length[m] * R[m, k, 2]
    return end


@njit
def soil_unlit(n, end, length, ground, wall_light, light, leaf_light, demand):
    """A module lying on the soil (its end on it:
    :func:`~growsim.kernels.hormone.ground_kernel` turned it up to the soil) gets no
    light and asks no water for photosynthesis: a stem on the ground is covered (litter,
    neighbours' shade); the plant must stand up to catch light.

    Examples
    --------
    >>> end = np.array([[0.0, 0.0, 0.3], [0.0, 0.4, 0.0]])
    >>> light, leaf, demand, walls = np.ones(2), np.ones(2), np.ones(2), np.ones((2, 6))
    >>> soil_unlit(2, end, np.array([0.3, 0.4]), 0.0, walls, light, leaf, demand)
    >>> light.tolist(), demand.tolist(), walls.sum(axis=1).tolist()
    ([0.0, 1.0], [0.0, 1.0], [0.0, 6.0])
    """
    for q in range(n):
        if end[q, 1] <= ground + 1e-9 * (1.0 + length[q]):
            light[q] = 0.0
            leaf_light[q] = 0.0
            demand[q] = 0.0
            for i in range(wall_light.shape[1]):
                wall_light[q, i] = 0.0


@njit
def walls_light(n, dims, modules, env, shifts, scratch):
    """``(n * walls,)`` the light on each wall of modules ``0..n-1`` (placed: ``origin``
    up to date; drawn: ``drawn`` up to date, :func:`drawn_kernel`) at its own point (on
    the drawn surface, halfway along the module) with its outward normal, through one
    shadow map per light of the modules drawn with their leaves, among their copies
    moved by ``shifts`` ``(k, 3)`` (a periodic stand, each copy's shadow read at the
    point moved back by its shift, :func:`growsim.kernels.light.point_light_into`;
    ``(0, 3)``: the plant alone). :func:`grow_step`'s exact light (:func:`lights_kernel`).

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models.hormone import PARAMS, environment_args, resolve_params, seedling
    >>> n, s = seedling(resolve_params(PARAMS, {"dims": 2}), Environment())
    >>> env, m = environment_args(Environment()), s["modules"]
    >>> walls_light(n, 2, m, env, np.zeros((0, 3)), s["scratch"]).tolist()  # from above
    [0.0, 0.0]
    """
    return lights_kernel(n, dims, modules, env, shifts, scratch, WALLS)


#: what :func:`lights_kernel` lights: the walls, the leaves, or both
WALLS, LEAVES = 1, 2


@njit
def lights_kernel(n, dims, modules, env, shifts, scratch, which):
    """The light on the walls (``which & WALLS``: ``n * walls`` values, as
    :func:`walls_light`) and then on the leaves (``which & LEAVES``: ``n`` values) of
    modules ``0..n-1``, through one shadow map per light for both. A module's leaves face
    up: their light is read at the point above the higher end of its axis by its drawn
    radius (``top + drawn y``: the top of its foliage, which its own module never
    shades) with the normal ``+y``, so leaves below others are in their shade.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models.hormone import PARAMS, environment_args, resolve_params, seedling
    >>> n, s = seedling(resolve_params(PARAMS, {"dims": 2}), Environment())
    >>> env, m = environment_args(Environment()), s["modules"]
    >>> lights_kernel(n, 2, m, env, np.zeros((0, 3)), s["scratch"], LEAVES).tolist()
    [1.0]
    """
    R, origin, length, drawn = modules.R, modules.origin, modules.length, modules.drawn
    walls = modules.hormone.shape[1] if which & WALLS else 0
    leaves = n if which & LEAVES else 0
    start = origin[:n]
    end = module_ends(n, origin, length, R, np.empty((n, 3)))
    trans = np.full(n, env.transmission) if env.soft else np.empty(0)
    m = n * walls + leaves
    normals = wall_normals(n, R, walls, dims, np.empty((n, walls, 3)))
    points = np.empty((m, 3))
    unit = np.zeros((m, 3))
    for q in range(n):
        for i in range(walls):
            nx, ny, nz = normals[q, i, 0], normals[q, i, 1], normals[q, i, 2]
            norm = math.sqrt(nx * nx + ny * ny + nz * nz)
            for a in range(3):
                mid = start[q, a] + 0.5 * (end[q, a] - start[q, a])
                points[q * walls + i, a] = mid + drawn[q] * normals[q, i, a]
                unit[q * walls + i, a] = normals[q, i, a] / norm
    for q in range(leaves):
        top = start[q] if start[q, 1] > end[q, 1] else end[q]
        k = n * walls + q
        points[k, 0], points[k, 1], points[k, 2] = top[0], top[1] + drawn[q], top[2]
        unit[k, 1] = 1.0
    return point_light_into(
        (start, end, drawn[:n], np.array([0, n], np.int64)),
        (points, np.array([0, m], np.int64), unit), (env.dirs, env.us, env.vs, env.weights),
        (env.resolution, env.bias, env.soft, trans), scratch, np.empty(m), shifts,
    )  # fmt: skip
