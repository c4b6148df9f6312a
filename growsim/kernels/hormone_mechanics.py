"""Mechanics of the hormone model's modules (:mod:`growsim.kernels.hormone`): gravity and
the wind on stems and leaves, the joints that break (:func:`gravity_kernel`); in the
``growsim`` physics the radius each module's loads ask for (:func:`design_kernel`), the
thickening toward it as far as the plant's carbon pays (:func:`thicken_kernel`) and the
shedding of a broken branch (:func:`shed_kernel`). Equations: ``docs/models/hormone.md``
(step 10); oracles in ``tests/naive/hormone.py``.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.gravity import loads_kernel, radius_end_kernel
from growsim.kernels.hormone_modules import (
    C_BUILD,
    C_HUBER,
    C_PHYSICS,
    C_SAFETY,
    C_THICK,
    C_WIND,
    STOP_BROKEN,
    STOP_NONE,
)

__all__ = ["design_kernel", "gravity_kernel", "shed_kernel", "thicken_kernel", "thicken_module"]


@njit(inline="always")
def thicken_module(m, dr, modules, c, partial):
    """Module ``m`` thickens by ``dr`` (walls move out), paying for the new wood,
    ``build_cost pi L ((r + dr)^2 - r^2)``: all of it if its nutrient allows, else (if
    ``partial``) as much as its nutrient pays for, all of it spent, else not at all.
    Returns its radius."""
    r = modules.radius[m]
    if dr <= 0.0:
        return r
    k = c[C_BUILD] * math.pi * modules.length[m]
    cost = k * dr * (2.0 * r + dr)
    if modules.nutrient[m] >= cost:
        modules.nutrient[m] -= cost
        modules.radius[m] = r + dr
    elif partial and modules.nutrient[m] > 0.0:  # what the nutrient pays for
        modules.radius[m] = math.sqrt(r * r + modules.nutrient[m] / k)
        modules.nutrient[m] = 0.0
    return modules.radius[m]


@njit
def design_kernel(n, modules, c, strength_young, material):
    """``modules.target[:n]``: the radius each module's loads ask for (``growsim``'s
    thickening goes toward it), in one child-to-parent pass: the larger of

    - the load's: the stem whose bending stress under the design moment ``D_m`` is
      ``1 / safety`` of its strength, ``r = (4 safety D_m / (pi strength_m))^(1/3)``; the
      design moment is the weight's, ``G_m``, plus the wind's, ``|V_m|``. ``G_m`` adds
      the moments of the module's own wood (a cylinder of ``density``) and leaves
      (``leaf_mass_per_area``) about its base, ``w_m h_m / 2``, and each child's design
      moment and weight carried over the module's horizontal extent, ``G_c + W_c h_m``
      (``W`` the weight above, ``h`` the horizontal extent): branches' moments add as
      magnitudes, never cancel. ``V_m = sum_k wind a_k (y_k - y_m)`` over the modules
      ``k`` above (itself included): the drag of a breeze, ``wind`` per m^2 of leaf
      (``a_k`` the leaf area, ``y_k`` the height of its middle, ``y_m`` that of ``m``'s
      base);
    - the pipe model's: sapwood in proportion to the leaf area above,
      ``pi r^2 = huber x leaf area above``.

    ``material`` ``(density, leaf_mass_per_area, g, strength)``; the strength of module
    ``m`` is ``young + (strength - young) lignin`` (``young`` its plant's
    ``strength_young``). The modules must be placed (``origin``). Returns
    ``modules.target``.

    Examples
    --------
    >>> from growsim.kernels.hormone_modules import N_CONSTANTS, new_module_arrays
    >>> import numpy as np
    >>> m = new_module_arrays(1, 2); c = np.zeros((1, N_CONSTANTS)); c[0, C_SAFETY] = 1.0
    >>> m.parent[0] = -1; m.R[0] = np.eye(3); m.origin[0] = 0.0  # a horizontal rod (z)
    >>> m.length[0], m.radius[0], m.leaf[0], m.lignin[0] = 1.0, 0.01, 0.0, 0.0
    >>> t = design_kernel(1, m, c, np.array([1e6]), (1000.0, 0.1, 10.0, 1e6))[0]
    >>> bool(np.isclose(t, (4 * 10.0 * 1000 * np.pi * 1e-4 * 0.5 / (np.pi * 1e6)) ** (1 / 3)))
    True
    """
    density, lma, g, wood = material
    parent, R, length, radius = modules.parent, modules.R, modules.length, modules.radius
    leaf, lignin, plant, target = modules.leaf, modules.lignin, modules.plant, modules.target
    weight = np.zeros(n)  # W: the weight above each joint
    moment = np.zeros(n)  # G: the weight's design moment
    area = np.zeros(n)  # leaf area above
    drag = np.zeros(n)  # the wind's force on the leaves above, and its first moment
    drag_y = np.zeros(n)
    for m in range(n - 1, -1, -1):
        cm = c[plant[m]]
        L = length[m]
        hx, hz = L * R[m, 0, 2], L * R[m, 2, 2]
        h = math.sqrt(hx * hx + hz * hz)
        own = g * (density * math.pi * radius[m] * radius[m] * L + lma * leaf[m])
        weight[m] += own
        moment[m] += 0.5 * own * h
        area[m] += leaf[m]
        f = cm[C_WIND] * leaf[m]
        drag[m] += f
        drag_y[m] += f * (modules.origin[m, 1] + 0.5 * L * R[m, 1, 2])
        wind = abs(drag_y[m] - drag[m] * modules.origin[m, 1])
        young = strength_young[plant[m]]
        strength = young + (wood - young) * lignin[m]
        load = (4.0 * cm[C_SAFETY] * (moment[m] + wind) / (math.pi * strength)) ** (1.0 / 3.0)
        target[m] = max(load, math.sqrt(cm[C_HUBER] * area[m] / math.pi))
        p = parent[m]
        if p >= 0:
            Lp = length[p]
            hp = Lp * math.sqrt(R[p, 0, 2] * R[p, 0, 2] + R[p, 2, 2] * R[p, 2, 2])
            weight[p] += weight[m]
            moment[p] += moment[m] + weight[m] * hp
            area[p] += area[m]
            drag[p] += drag[m]
            drag_y[p] += drag_y[m]
    return target


@njit
def thicken_kernel(n, modules, c):
    """``growsim``'s thickening, at the start of a step: each module thickens toward the
    radius its loads ask for (``modules.target``, :func:`design_kernel` at the end of the
    last step) by at most ``thickening x min(1, H1)`` (``H1`` its mean thickening
    hormone), paying ``build_cost`` for the new wood from its plant's carbon: the
    phloem feeds the cambium from the whole plant, so the cost is drawn from every
    module's positive nutrient in proportion to it. Modules thicken parents first (the
    base before the crown), each as far as what is left of the plant's carbon pays.
    ``paper`` plants' modules are left as they are (they thicken in :func:`step_kernel`).
    Returns ``modules.radius``.

    Examples
    --------
    >>> from growsim.kernels.hormone_modules import N_CONSTANTS, new_module_arrays
    >>> import numpy as np
    >>> m = new_module_arrays(2, 2); c = np.zeros((1, N_CONSTANTS))
    >>> c[0, C_THICK], c[0, C_BUILD] = 0.01, 1.0 / np.pi
    >>> m.parent[:], m.plant[:], m.radius[:], m.length[:] = (-1, 0), 0, 0.0, 1.0
    >>> m.target[:], m.hormone[:], m.nutrient[:] = (0.01, 0.0), 1.0, (0.0, 2e-4)
    >>> thicken_kernel(2, m, c).tolist(), m.nutrient.round(9).tolist()  # the child pays
    ([0.01, 0.0], [0.0, 0.0001])
    """
    walls = modules.hormone.shape[1]
    nutrient, radius, plant = modules.nutrient, modules.radius, modules.plant
    P = c.shape[0]
    pool = np.zeros(P)
    for m in range(n):
        pool[plant[m]] += max(0.0, nutrient[m])
    left = pool.copy()
    for m in range(n):
        cm = c[plant[m]]
        if cm[C_PHYSICS] > 0.5:
            continue
        h1 = 0.0
        for i in range(walls):
            h1 += modules.hormone[m, i, 1] / walls
        dr = min(cm[C_THICK] * min(1.0, h1), modules.target[m] - radius[m])
        if dr <= 0.0 or left[plant[m]] <= 0.0:
            continue
        r = radius[m]
        k = cm[C_BUILD] * math.pi * modules.length[m]
        cost = k * dr * (2.0 * r + dr)
        if cost <= left[plant[m]]:
            radius[m] = r + dr
            left[plant[m]] -= cost
        else:  # what is left pays for
            radius[m] = math.sqrt(r * r + left[plant[m]] / k)
            left[plant[m]] = 0.0
    for m in range(n):  # each module pays its share of its plant's thickening
        p = plant[m]
        if pool[p] > 0.0 and nutrient[m] > 0.0:
            nutrient[m] -= (pool[p] - left[p]) * nutrient[m] / pool[p]
    return radius


@njit
def shed_kernel(n, modules, broken):
    """Shed every module whose joint broke (``broken`` ``(n,)`` bool) with all its
    descendants, keeping the others in order (parents first, parents renumbered): the
    ``growsim`` physics's break, after which the plant goes on. Adds the joints broken and
    the modules shed to ``modules.events``; returns the modules kept.

    Examples
    --------
    >>> from growsim.kernels.hormone_modules import new_module_arrays
    >>> import numpy as np
    >>> m = new_module_arrays(4, 2); m.parent[:] = (-1, 0, 1, 0); m.length[:] = (1, 2, 3, 4)
    >>> shed_kernel(4, m, np.array([False, True, False, False])), m.parent[:2].tolist()
    (2, [-1, 0])
    >>> m.length[:2].tolist(), m.events.tolist()
    ([1.0, 4.0], [1, 2])
    """
    keep = np.empty(n, np.bool_)
    new = np.full(n, -1, np.int64)
    k = 0
    breaks = 0
    for q in range(n):
        p = modules.parent[q]
        breaks += broken[q]
        keep[q] = not broken[q] and (p < 0 or keep[p])
        if keep[q]:
            new[q] = k
            k += 1
    modules.events[0] += breaks
    modules.events[1] += n - k
    for q in range(n):
        j = new[q]
        if j < 0 or j == q:
            continue
        p = modules.parent[q]
        modules.parent[j] = new[p] if p >= 0 else -1
        modules.R[j] = modules.R[q]
        modules.origin[j] = modules.origin[q]
        modules.hormone[j] = modules.hormone[q]
        modules.wall_light[j] = modules.wall_light[q]
        for a in (modules.length, modules.radius, modules.nutrient, modules.chlorophyll,
                  modules.lignin, modules.met, modules.light, modules.leaf, modules.target,
                  modules.drawn, modules.water, modules.leaf_light):  # fmt: skip
            a[j] = a[q]
        modules.apex[j] = modules.apex[q]
        modules.laterals[j] = modules.laterals[q]
        modules.plant[j] = modules.plant[q]
    return k


@njit
def gravity_kernel(n, modules, c, strength_young, env, paper):
    """Gravity on modules ``0..n-1`` (placed): their stems (strength by lignin) and, in
    ``growsim``, their leaves as blades along them (segment ``n + q`` the leaves of module
    ``q``, its child in the loads' tree, of width ``leaf / L``: mass ``leaf_mass_per_area
    x leaf``) and the wind on the leaves (the bending stress of the moment ``|V_m|`` of
    :func:`design_kernel` added to gravity's). A broken joint stops a ``paper`` plant; in
    ``growsim`` it is shed (:func:`shed_kernel`) unless it is a root's: then the plant
    fell and is dead (its nutrient set to 0). Returns ``(n, code)``."""
    parent, R, origin, length, radius = (modules.parent, modules.R, modules.origin,
                                         modules.length, modules.radius)  # fmt: skip
    k = n if paper else 2 * n
    start = np.empty((k, 3))
    end = np.empty((k, 3))
    rad = np.empty(k)
    par = np.empty(k, np.int64)
    kind = np.zeros(k, np.int8)
    for q in range(n):
        for a in range(3):
            start[q, a] = origin[q, a]
            end[q, a] = origin[q, a] + length[q] * R[q, a, 2]
        rad[q] = radius[q]
        par[q] = parent[q]
    if not paper:
        for q in range(n):
            start[n + q] = start[q]
            end[n + q] = end[q]
            rad[n + q] = 0.5 * modules.leaf[q] / length[q] if length[q] > 0.0 else 0.0
            par[n + q] = q
            kind[n + q] = 1
    r_end = radius_end_kernel(par, kind, rad, np.empty(k))
    wood = np.empty(k)
    for q in range(k):
        young = strength_young[modules.plant[q % n]]
        wood[q] = young + (env.strength - young) * modules.lignin[q % n]
    loads = loads_kernel(start, end, rad, r_end, par, kind, wood,
                         (env.density, env.leaf_mass_per_area, env.g),
                         np.empty((4, k)))  # fmt: skip
    ratio = loads[3, :n].copy()
    if not paper:  # the wind on the leaves: its bending stress adds to gravity's
        drag = np.zeros(n)
        drag_y = np.zeros(n)
        for q in range(n - 1, -1, -1):
            f = c[modules.plant[q], C_WIND] * modules.leaf[q]
            drag[q] += f
            drag_y[q] += f * 0.5 * (start[q, 1] + end[q, 1])
            W = 0.25 * math.pi * radius[q] ** 3 * wood[q]
            V = abs(drag_y[q] - drag[q] * start[q, 1])
            if V > 0.0:
                ratio[q] += V / W if W > 0.0 else np.inf
            p = parent[q]
            if p >= 0:
                drag[p] += drag[q]
                drag_y[p] += drag_y[q]
    broken = np.zeros(n, np.bool_)
    any_broken = False
    for q in range(n):
        if ratio[q] >= 1.0:
            if paper or parent[q] < 0:
                modules.events[0] += 1
                if not paper:  # the plant fell: dead, its reserves lost
                    modules.nutrient[:n] = 0.0
                return n, STOP_BROKEN
            broken[q] = True
            any_broken = True
    if any_broken:
        n = shed_kernel(n, modules, broken)
    return n, STOP_NONE
