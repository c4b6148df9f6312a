"""Slow NumPy oracle of :mod:`growsim.kernels.hormone_mechanics`: the radius each
module's loads ask for, the thickening toward it, the shedding of a broken branch."""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels import hormone as K


def thicken_module(modules, m, cm, dr, partial):
    """Module ``m`` thickens by ``dr`` if its nutrient pays for the annulus of wood; else,
    if ``partial``, to the radius its whole nutrient pays for."""
    r = modules.radius[m]
    if dr <= 0:
        return r
    cost = cm[K.C_BUILD] * math.pi * ((r + dr) ** 2 - r * r) * modules.length[m]
    if modules.nutrient[m] >= cost:
        modules.nutrient[m] -= cost
        modules.radius[m] = r + dr
    elif partial and modules.nutrient[m] > 0:  # pi L (R^2 - r^2) b = nutrient
        area = modules.nutrient[m] / (cm[K.C_BUILD] * math.pi * modules.length[m])
        modules.radius[m] = math.sqrt(r * r + area)
        modules.nutrient[m] = 0.0
    return modules.radius[m]


def thicken_kernel(n, modules, c):
    """Mirror of :func:`growsim.kernels.hormone.thicken_kernel`: each ``growsim`` module,
    parents first, toward its target by at most ``thickening x min(1, mean H1)``, as far
    as its plant's carbon (the sum of its modules' positive nutrient) pays; then every
    module of the plant gives the same share of its positive nutrient."""
    plant, nutrient = modules.plant[:n], modules.nutrient
    plants = sorted(set(plant.tolist()))
    pool = {p: float(np.sum(np.maximum(nutrient[:n][plant == p], 0.0))) for p in plants}
    spent = dict.fromkeys(plants, 0.0)
    for m in range(n):
        cm = c[plant[m]]
        if cm[K.C_PHYSICS] != K.GROWSIM:
            continue
        dr = min(cm[K.C_THICK] * min(1.0, modules.hormone[m, :, 1].mean()),
                 modules.target[m] - modules.radius[m])  # fmt: skip
        left = pool[plant[m]] - spent[plant[m]]
        if dr <= 0 or left <= 0:
            continue
        r, L = modules.radius[m], modules.length[m]
        cost = cm[K.C_BUILD] * math.pi * ((r + dr) ** 2 - r * r) * L
        if cost <= left:
            modules.radius[m] = r + dr
            spent[plant[m]] += cost
        else:  # pi L (R^2 - r^2) b = what is left
            modules.radius[m] = math.sqrt(r * r + left / (cm[K.C_BUILD] * math.pi * L))
            spent[plant[m]] = pool[plant[m]]
    for m in range(n):
        p = plant[m]
        if pool[p] > 0 and nutrient[m] > 0:
            nutrient[m] -= spent[p] * nutrient[m] / pool[p]
    return modules.radius


def design_kernel(n, modules, c, strength_young, material):
    """Mirror of :func:`growsim.kernels.hormone.design_kernel`, written by subtrees: a
    module's design moment is, over every module ``k`` of its subtree (itself included),
    the weight of ``k`` (wood and leaves) times its lever, half ``k``'s own horizontal
    extent plus the whole horizontal extent of every module on the path from ``k``'s
    parent down to the module (each path walked), plus the wind's moment, the leaves'
    drag times their middle's height over the module's base, summed over the subtree;
    the target is the larger of the load's radius and the pipe model's."""
    density, lma, g, wood = material
    parent, R, length, origin = modules.parent, modules.R, modules.length, modules.origin
    ext = np.array([length[m] * math.hypot(R[m, 0, 2], R[m, 2, 2]) for m in range(n)])
    w = np.array([g * (density * math.pi * modules.radius[m] ** 2 * length[m]
                       + lma * modules.leaf[m]) for m in range(n)])  # fmt: skip
    for m in range(n):
        moment = area = wind = 0.0
        for k in range(n):
            path = [k]  # k up to m (excluded)
            while path[-1] != m and path[-1] >= 0:
                path.append(int(parent[path[-1]]))
            if path[-1] != m:
                continue
            # k's own half extent, then the full extent of every module below it up to m
            lever = 0.5 * ext[k] + sum(ext[j] for j in path[1:])
            moment += w[k] * lever
            area += modules.leaf[k]
            middle = origin[k, 1] + 0.5 * length[k] * R[k, 1, 2]
            wind += c[modules.plant[k], K.C_WIND] * modules.leaf[k] * (middle - origin[m, 1])
        cm = c[modules.plant[m]]
        young = strength_young[modules.plant[m]]
        strength = young + (wood - young) * modules.lignin[m]
        load = (4 * cm[K.C_SAFETY] * (moment + abs(wind)) / (math.pi * strength)) ** (1 / 3)
        modules.target[m] = max(load, math.sqrt(cm[K.C_HUBER] * area / math.pi))
    return modules.target


def shed_kernel(n, modules, broken):
    """Mirror of :func:`growsim.kernels.hormone.shed_kernel`: the modules none of whose
    ancestors (nor itself) broke, kept in order, parents renumbered."""

    def lost(q):
        while q >= 0:
            if broken[q]:
                return True
            q = int(modules.parent[q])
        return False

    keep = [q for q in range(n) if not lost(q)]
    index = {q: i for i, q in enumerate(keep)}
    fields = [f for f in modules._fields if f not in ("parent", "events")]
    old = {f: np.array(getattr(modules, f)[:n], copy=True) for f in fields}
    parents = [int(modules.parent[q]) for q in keep]
    for i, q in enumerate(keep):
        for f in fields:
            getattr(modules, f)[i] = old[f][q]
        modules.parent[i] = index[parents[i]] if parents[i] >= 0 else -1
    modules.events[0] += int(np.sum(broken[:n]))
    modules.events[1] += n - len(keep)
    return len(keep)
