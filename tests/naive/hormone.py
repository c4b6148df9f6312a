"""Oracles of the hormone-module kernels (:mod:`growsim.kernels.hormone`): the same
equations, written plainly with NumPy (one module, one wall at a time; rotations as
matrices)."""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels import hormone as K
from naive.hormone_mechanics import thicken_module
from naive.walls import wall_frame


def place_kernel(n, parent, R, length, origin):
    """Mirror of :func:`growsim.kernels.hormone.place_kernel`."""
    origin = origin.copy()
    for m in range(n):
        if parent[m] >= 0:
            origin[m] = origin[parent[m]] + length[parent[m]] * R[parent[m]][:, 2]
    return origin


def ground_kernel(n, parent, R, length, origin, height):
    """Oracle of :func:`growsim.kernels.hormone.ground_kernel`, written another way: place
    each module (parents first); one whose end is under the soil ``y = height`` gets the
    new axis ``sqrt(1 - s^2) h + s y`` (``h`` its axis's horizontal direction, ``s`` the
    rise that puts the end on the soil) and its pose turns by the least rotation taking
    the old axis there. Updates ``R`` in place; returns the origins."""
    origin = origin.copy()
    up = np.array([0.0, 1.0, 0.0])
    for m in range(n):
        p = parent[m]
        if p >= 0:
            origin[m] = origin[p] + length[p] * R[p][:, 2]
        z = R[m][:, 2].copy()
        if origin[m, 1] + length[m] * z[1] >= height:
            continue
        h = np.array([z[0], 0.0, z[2]])
        if np.linalg.norm(h) < 1e-12:  # straight down: it turns about its first axis
            h = np.cross(R[m][:, 0], -up)
        h /= np.linalg.norm(h)
        s = np.clip((height - origin[m, 1]) / length[m], -1.0, 1.0)
        new = math.sqrt(1.0 - s * s) * h + s * up
        axis = np.cross(z, new)
        if np.linalg.norm(axis) > 0:
            angle = math.acos(np.clip(z @ new, -1.0, 1.0))
            R[m] = rotation(axis / np.linalg.norm(axis), angle) @ R[m]
    return origin


def rotation(axis, angle):
    """The rotation matrix about the unit ``axis`` by ``angle``."""
    x = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * x + (1 - math.cos(angle)) * x @ x


def step_kernel(n, dims, modules, genes, c):
    """Mirror of :func:`growsim.kernels.hormone.step_kernel` (updates the arrays of
    ``modules`` in place, returns ``(n_new, gained)``): module ``m`` reads the genes
    ``genes[plant[m]]`` and constants ``c[plant[m]]`` of its plant, the physics in their
    last column."""
    parent, R, length, radius = modules.parent, modules.R, modules.length, modules.radius
    nutrient, chlorophyll, lignin = modules.nutrient, modules.chlorophyll, modules.lignin
    apex, laterals, hormone = modules.apex, modules.laterals, modules.hormone
    wall_light, met, plant = modules.wall_light, modules.met, modules.plant
    leaf, target = modules.leaf, modules.target
    cap, walls = hormone.shape[:2]
    sig = lambda a: 1 / (1 + math.exp(-a)) if a > -50 else 0.0  # noqa: E731
    H = genes.shape[1]
    mean_h = np.zeros((n, H))
    for m in range(n):
        g = genes[plant[m]]
        v = wall_frame(R[m], walls, dims)
        for i in range(walls):
            x = np.array([wall_light[m, i], met[m], nutrient[m] / (1 + abs(nutrient[m])),
                          chlorophyll[m], v[i, 1], hormone[m, i, 3]])  # fmt: skip
            s = g[:, 1] * np.array([sig(a) for a in g[:, 0] + g[:, 3:] @ x])
            hormone[m, i] = (1 - g[:, 2]) * hormone[m, i] + s
        mean_h[m] = hormone[m, :walls].mean(axis=0)
    inh = mean_h[:, 3].copy()
    for m in range(n - 1, -1, -1):
        if parent[m] >= 0:
            inh[parent[m]] += c[plant[m], K.C_INH_TRANSPORT] * inh[m]
    gained = 0.0
    for m in range(n):
        cm = c[plant[m]]
        paper = cm[K.C_PHYSICS] == K.PAPER
        v = wall_frame(R[m], walls, dims)
        L, r = length[m], radius[m]
        slow = 1 - lignin[m]
        li = wall_light[m, :walls]
        drought = 1 - cm[K.C_DROUGHT] * min(1.0, mean_h[m, 7])
        if paper:  # the walls, linear in light
            area = 2 * math.pi * r * L / walls if dims == 3 else r * L
            photo = np.sum(area * li)
            upkeep = 0.0
        else:  # the leaves, facing up, saturating in their light
            K_, up = cm[K.C_HALF_SAT], modules.leaf_light[m]
            photo = leaf[m] * up * (1 + K_) / (up + K_)
            upkeep = cm[K.C_LEAF_UPKEEP] * leaf[m] + cm[K.C_UPKEEP] * math.pi * r * r * L
            leaf[m] = leaf[m] * (1 - min(1.0, cm[K.C_LEAF_TURNOVER]))
        photo *= cm[K.C_PHOTO] * chlorophyll[m] * met[m] * drought
        gained += photo
        nutrient[m] += photo - upkeep
        e = cm[K.C_ELONG] * hormone[m, :walls, 0] * met[m] * drought * slow
        e_mean = min(e.mean(), max(0.0, cm[K.C_MAXLEN] - L))
        cost = cm[K.C_BUILD] * math.pi * r * r * e_mean
        if e_mean > 0 and nutrient[m] >= cost:
            nutrient[m] -= cost
            length[m] = L + e_mean
            gain = cm[K.C_TURN] * min(1.0, mean_h[m, 8]) / max(L, 1e-9)
            for i in range(walls):
                n_ = np.cross(R[m][:, 2], v[i])
                if np.linalg.norm(n_) > 0:
                    R[m] = rotation(n_ / np.linalg.norm(n_), -gain * (e[i] - e_mean)) @ R[m]
        if not paper:
            grow = cm[K.C_LEAF_GROWTH] * min(1.0, mean_h[m, 9]) * slow * length[m]
            da = min(grow, cm[K.C_LEAF_DENSITY] * length[m] - leaf[m])
            if da > 0 and nutrient[m] > 0:  # all of it, or what the nutrient pays for
                da = min(da, nutrient[m] / cm[K.C_LEAF_COST])
                nutrient[m] = max(0.0, nutrient[m] - cm[K.C_LEAF_COST] * da)
                leaf[m] += da
        if paper:  # thickening after growth, by the hormone
            thicken_module(modules, m, cm, cm[K.C_THICK] * min(1.0, mean_h[m, 1]), False)
        lg = cm[K.C_LIGNIFY] * min(1.0, mean_h[m, 5])
        lignin[m] = min(1.0, lignin[m] + lg)
        chl = chlorophyll[m] - cm[K.C_CHL_LOSS] * lg + cm[K.C_GREEN] * min(1.0, mean_h[m, 6])
        chlorophyll[m] = min(1.0, max(0.0, chl))
    for m in range(n - 1, 0, -1):
        if parent[m] >= 0:
            flow = c[plant[m], K.C_SHARE] * 0.5 * (nutrient[m] - nutrient[parent[m]])
            nutrient[m] -= flow
            nutrient[parent[m]] += flow
    n_new = n

    def price(m):  # the start-up cost, the new module's wood and (growsim) its leaf
        cm = c[plant[m]]
        r = min(cm[K.C_NEWRAD], radius[m])
        leaf_cost = cm[K.C_LEAF_COST] * cm[K.C_NEW_LEAF] if cm[K.C_PHYSICS] == K.GROWSIM else 0
        return cm[K.C_NEW_COST] + cm[K.C_BUILD] * math.pi * r * r * cm[K.C_NEWLEN] + leaf_cost

    def new(q, m, Rq):
        cm = c[plant[m]]
        nutrient[m] -= price(m)
        parent[q], R[q], plant[q] = m, Rq, plant[m]
        length[q], radius[q] = cm[K.C_NEWLEN], min(cm[K.C_NEWRAD], radius[m])
        nutrient[q] = 0.5 * cm[K.C_NEW_COST]
        chlorophyll[q], lignin[q], apex[q], laterals[q] = 1.0, 0.0, True, 0
        hormone[q] = 0.0
        leaf[q] = cm[K.C_NEW_LEAF] if cm[K.C_PHYSICS] == K.GROWSIM else 0.0
        target[q] = 0.0

    def room(m):  # each plant holds at most its share of the arrays
        return np.count_nonzero(plant[:n_new] == plant[m]) < cap // len(genes)

    for m in range(n):
        if n_new >= cap:
            break
        cm = c[plant[m]]
        slow = 1 - lignin[m]
        grown = length[m] >= 0.999 * cm[K.C_MAXLEN]
        ready = mean_h[m, 4] * slow > cm[K.C_THRESHOLD] and nutrient[m] > price(m)
        if apex[m] and grown and ready and room(m):
            new(n_new, m, R[m].copy())
            n_new += 1
            apex[m] = False
        if n_new >= cap:
            break
        if (room(m) and mean_h[m, 2] * slow > cm[K.C_THRESHOLD] and inh[m] < cm[K.C_THRESHOLD]
                and laterals[m] < cm[K.C_LATERALS] and length[m] >= 0.5 * cm[K.C_MAXLEN]
                and nutrient[m] > price(m)):  # fmt: skip
            v = wall_frame(R[m], walls, dims)
            b = (v * hormone[m, :walls, 2][:, None]).sum(axis=0)
            z = R[m][:, 2]
            b = b - (b @ z) * z
            if np.linalg.norm(b) < 1e-9 * walls:
                b = v[m % walls]
            if dims == 2:  # laterals alternate sides
                b = -b if laterals[m] % 2 else b
            else:  # the j-th lateral: B turned about the axis by j times the golden angle
                b = rotation(z, laterals[m] * K.GOLDEN_ANGLE) @ b
            axis = np.cross(z, b) / np.linalg.norm(b)
            new(n_new, m, rotation(axis, cm[K.C_BRANCH_ANGLE]) @ R[m])
            n_new += 1
            laterals[m] += 1
    return n_new, gained
