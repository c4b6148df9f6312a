"""Numba kernels of the hormone-module model (:mod:`growsim.models.hormone`).

Modules are stored field by field in creation order (a parent before its children), so a
forward loop carries parent -> child (:func:`place_kernel`: positions) and a reverse loop
child -> parent (the inhibitor's transport to the base, in :func:`step_kernel`; the
loads a module is thickened for, :func:`design_kernel`). The equations of both physics
(``growsim`` and ``paper``: :data:`PHYSICS`) are written out in
``docs/models/hormone.md``; the oracle is ``tests/naive/hormone.py``.

Constants ``c`` ``(P, N_CONSTANTS)`` (indices :data:`C_*`, the physics last) and genes
``genes`` ``(P, H, 3 + J)`` (per hormone: bias, gain, decay, then one weight per
stimulus) are passed in, never global: one row per plant (``P = 1`` for a plant alone).
Module ``m`` belongs to plant ``modules.plant[m]`` (a child to its parent's plant) and
reads that plant's row, so one module array can hold a stand of different genomes.

The module arrays, constants and a new module are in
:mod:`growsim.kernels.hormone_modules`, gravity, breaks and thickening in
:mod:`growsim.kernels.hormone_mechanics`; this module (their face) grows a step.

Units: metres, one step a week, grams of carbon (the nutrient), kilograms of water,
kilograms and newtons for gravity (:mod:`growsim.env.gravity`).
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.hormone_light import (
    LEAVES,
    WALLS,
    lights_kernel,
    module_ends,
    soil_unlit,
    walls_light,
)
from growsim.kernels.hormone_mechanics import (
    design_kernel,
    gravity_kernel,
    shed_kernel,
    thicken_kernel,
    thicken_module,
)
from growsim.kernels.hormone_modules import (
    C_BRANCH_ANGLE,
    C_BUILD,
    C_CHL_LOSS,
    C_DROUGHT,
    C_ELONG,
    C_GREEN,
    C_HALF_SAT,
    C_HUBER,
    C_INH_TRANSPORT,
    C_LATERALS,
    C_LEAF_COST,
    C_LEAF_DENSITY,
    C_LEAF_GROWTH,
    C_LEAF_TURNOVER,
    C_LEAF_UPKEEP,
    C_LIGNIFY,
    C_MAXLEN,
    C_NEW_COST,
    C_NEW_LEAF,
    C_NEWLEN,
    C_NEWRAD,
    C_PHOTO,
    C_PHYSICS,
    C_RESERVE,
    C_SAFETY,
    C_SHARE,
    C_THICK,
    C_THRESHOLD,
    C_TRANSPIRATION,
    C_TURN,
    C_UPKEEP,
    C_WIND,
    GOLDEN_ANGLE,
    GROWSIM,
    HORMONES,
    N_CONSTANTS,
    PAPER,
    PHYSICS,
    STIMULI,
    STOP_BROKEN,
    STOP_CAP,
    STOP_NAN,
    STOP_NONE,
    STOP_STARVED,
    STOPS,
    Modules,
    Surroundings,
    drawn_kernel,
    new_module,
    new_module_arrays,
    new_module_cost,
    new_plant,
)
from growsim.kernels.light import module_light_into
from growsim.kernels.walls import frame_of, wall_angles
from growsim.kernels.water import transport_into_kernel

__all__ = [
    "C_BRANCH_ANGLE",
    "C_BUILD",
    "C_CHL_LOSS",
    "C_DROUGHT",
    "C_ELONG",
    "C_GREEN",
    "C_HALF_SAT",
    "C_HUBER",
    "C_INH_TRANSPORT",
    "C_LATERALS",
    "C_LEAF_COST",
    "C_LEAF_DENSITY",
    "C_LEAF_GROWTH",
    "C_LEAF_TURNOVER",
    "C_LEAF_UPKEEP",
    "C_LIGNIFY",
    "C_MAXLEN",
    "C_NEWLEN",
    "C_NEWRAD",
    "C_NEW_COST",
    "C_NEW_LEAF",
    "C_PHOTO",
    "C_PHYSICS",
    "C_RESERVE",
    "C_SAFETY",
    "C_SHARE",
    "C_THICK",
    "C_THRESHOLD",
    "C_TRANSPIRATION",
    "C_TURN",
    "C_UPKEEP",
    "C_WIND",
    "GOLDEN_ANGLE",
    "GROWSIM",
    "HORMONES",
    "N_CONSTANTS",
    "PAPER",
    "PHYSICS",
    "STIMULI",
    "STOPS",
    "STOP_BROKEN",
    "STOP_CAP",
    "STOP_NAN",
    "STOP_NONE",
    "STOP_STARVED",
    "Modules",
    "Surroundings",
    "design_kernel",
    "drawn_kernel",
    "gravity_kernel",
    "ground_kernel",
    "grow_step",
    "lights_kernel",
    "new_module",
    "new_module_arrays",
    "new_module_cost",
    "new_plant",
    "place_kernel",
    "shed_kernel",
    "step_kernel",
    "thicken_kernel",
    "total",
    "walls_light",
]


@njit
def place_kernel(n, parent, R, length, origin):
    """Origins of modules ``0..n-1`` (forward, parents first): a root stays where it is, a
    child starts at its parent's far end ``origin[p] + length[p] R[p][:, 2]``.

    Examples
    --------
    >>> import numpy as np
    >>> R = np.tile(np.eye(3), (2, 1, 1)); o = np.zeros((2, 3))
    >>> place_kernel(2, np.array([-1, 0]), R, np.array([2.0, 1.0]), o)[1].tolist()
    [0.0, 0.0, 2.0]
    """
    for m in range(n):
        p = parent[m]
        if p >= 0:
            for c in range(3):
                origin[m, c] = origin[p, c] + length[p] * R[p, c, 2]
    return origin


@njit
def ground_kernel(n, parent, R, length, origin, ground):
    """Place modules ``0..n-1`` as :func:`place_kernel` does, keeping every module's end
    on or above the soil ``y = ground``: a module (parents first) whose end
    ``origin + length z`` would lie below it is turned up, the least turn (about the
    horizontal axis across it, ``z x y``; a module pointing straight down turns about its
    first axis), until the end touches the soil: it runs along the soil, never into it.
    The turn is kept in its pose ``R`` (walls included); its children start at the new
    end and are checked in turn. Returns ``origin``.

    Examples
    --------
    >>> import numpy as np
    >>> R = np.array([[[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]])  # growing straight down
    >>> o = ground_kernel(1, np.array([-1]), R, np.array([2.0]), np.zeros((1, 3)), -1.0)
    >>> np.round(R[0, :, 2], 6).tolist()     # turned up: the end 2 m along it at y = -1
    [0.0, -0.5, -0.866025]
    """
    axis = np.empty(3)
    for m in range(n):
        p = parent[m]
        if p >= 0:
            for c in range(3):
                origin[m, c] = origin[p, c] + length[p] * R[p, c, 2]
        L = length[m]
        zy = R[m, 1, 2]
        if not origin[m, 1] + L * zy < ground or L <= 0.0:
            continue
        target = min(1.0, max(-1.0, (ground - origin[m, 1]) / L))
        # z x y = (-z_z, 0, z_x): horizontal, across the module
        ax, az = -R[m, 2, 2], R[m, 0, 2]
        na = math.sqrt(ax * ax + az * az)
        if na > 1e-12:
            axis[0], axis[1], axis[2] = ax / na, 0.0, az / na
        else:  # straight down: any horizontal axis across it
            na = math.sqrt(R[m, 0, 0] ** 2 + R[m, 2, 0] ** 2)
            axis[0], axis[1], axis[2] = R[m, 0, 0] / na, 0.0, R[m, 2, 0] / na
        _rotate(R[m], axis, math.asin(target) - math.asin(min(1.0, max(-1.0, zy))))
    return origin


@njit
def _sigmoid(x):
    return 1.0 / (1.0 + math.exp(-x)) if x > -50.0 else 0.0


@njit
def _rotate(R, axis, angle):
    """``R`` turned by ``angle`` about the unit ``axis`` (Rodrigues), in place."""
    c, s = math.cos(angle), math.sin(angle)
    for col in range(3):
        x, y, z = R[0, col], R[1, col], R[2, col]
        d = axis[0] * x + axis[1] * y + axis[2] * z
        cx = axis[1] * z - axis[2] * y
        cy = axis[2] * x - axis[0] * z
        cz = axis[0] * y - axis[1] * x
        R[0, col] = x * c + cx * s + axis[0] * d * (1 - c)
        R[1, col] = y * c + cy * s + axis[1] * d * (1 - c)
        R[2, col] = z * c + cz * s + axis[2] * d * (1 - c)


@njit
def step_kernel(n, dims, modules, genes, c):
    """One growth step of modules ``0..n-1`` of :class:`Modules` ``modules`` (``cap`` rows,
    ``walls`` walls: the shape of ``modules.hormone``) in ``dims`` dimensions; returns the
    new module count (at most ``cap``) and the nutrient gained by photosynthesis this step.
    Module ``m`` reads its plant's genes ``genes[plant[m]]`` ``(H, 3 + J)`` and constants
    ``c[plant[m]]`` (``plant`` = ``modules.plant``; the physics in ``C_PHYSICS``); each of
    the ``P`` plants (rows of ``genes``) grows at most ``cap // P`` modules.

    Reads ``wall_light`` ``(cap, walls)`` the light each wall receives, ``leaf_light`` the
    light on each module's leaves (``growsim``) and ``met`` ``(cap,)`` the share of each
    module's water demand met; ``hormone`` ``(cap, walls, H)`` is updated in place, as
    are the module fields (``origin``, ``light``, ``target``, ``drawn`` and ``water`` are
    not read). See ``docs/models/hormone.md`` for the equations, in the order they run:
    synthesis, transport of the inhibitor, photosynthesis, upkeep and leaf turnover,
    elongation and turning, leaf growth (``growsim``), thickening (``paper``; ``growsim``
    thickens before the step, :func:`thicken_kernel`), lignification and greening,
    nutrient sharing, new modules.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models.hormone import MODEL
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})
    >>> MODEL.develop({**MODEL.preset("demo_3d"), "steps": 10}, env=env).n_segments > 1
    True
    """
    parent, R, length, radius = modules.parent, modules.R, modules.length, modules.radius
    nutrient, chlorophyll, lignin = modules.nutrient, modules.chlorophyll, modules.lignin
    apex, laterals, hormone = modules.apex, modules.laterals, modules.hormone
    wall_light, met, leaf = modules.wall_light, modules.met, modules.leaf
    cap, walls = hormone.shape[0], hormone.shape[1]
    plant = modules.plant
    H = genes.shape[1]
    J = genes.shape[2] - 3
    x = np.empty(J)
    v = np.empty((walls, 3))
    inh = np.zeros(n)
    mean_h = np.zeros((n, H))
    e = np.empty(walls)
    axis = np.empty(3)
    cs = wall_angles(walls, dims)
    gained = 0.0
    # synthesis per wall: s = gain sigmoid(bias + w . x); h = (1 - decay) h + s
    for m in range(n):
        g = genes[plant[m]]
        frame_of(R[m], cs, v)
        for i in range(walls):
            x[0] = wall_light[m, i]
            x[1] = met[m]
            x[2] = nutrient[m] / (1.0 + abs(nutrient[m]))
            x[3] = chlorophyll[m]
            x[4] = v[i, 1]
            x[5] = hormone[m, i, 3]
            for k in range(H):
                a = g[k, 0]
                for j in range(J):
                    a += g[k, 3 + j] * x[j]
                h = (1.0 - g[k, 2]) * hormone[m, i, k] + g[k, 1] * _sigmoid(a)
                hormone[m, i, k] = h
                mean_h[m, k] += h / walls
    # the inhibitor goes to the base: each module adds a share of its children's
    for m in range(n - 1, -1, -1):
        inh[m] += mean_h[m, 3]
        p = parent[m]
        if p >= 0:
            inh[p] += c[plant[m], C_INH_TRANSPORT] * inh[m]
    n_new = n
    for m in range(n):
        cm = c[plant[m]]
        paper = cm[C_PHYSICS] > 0.5
        frame_of(R[m], cs, v)
        L = length[m]
        r = radius[m]
        slow = 1.0 - lignin[m]  # lignin slows growth and branching
        drought = 1.0 - cm[C_DROUGHT] * min(1.0, mean_h[m, 7])
        photo = 0.0
        if paper:  # the walls photosynthesise, linear in their light
            area = 2.0 * math.pi * r * L / walls if dims == 3 else r * L
            for i in range(walls):
                photo += area * wall_light[m, i]
            upkeep = 0.0
        else:  # the leaves, facing up, saturating in their light
            li = modules.leaf_light[m]
            photo = leaf[m] * li * (1.0 + cm[C_HALF_SAT]) / (li + cm[C_HALF_SAT])
            upkeep = cm[C_LEAF_UPKEEP] * leaf[m] + cm[C_UPKEEP] * math.pi * r * r * L
            leaf[m] *= 1.0 - min(1.0, cm[C_LEAF_TURNOVER])  # leaves shed and lost
        photo *= cm[C_PHOTO] * chlorophyll[m] * met[m] * drought
        gained += photo
        nutrient[m] += photo - upkeep
        # elongation per wall (turgor: water met), the module by the mean of its walls
        e_mean = 0.0
        for i in range(walls):
            e[i] = cm[C_ELONG] * hormone[m, i, 0] * met[m] * drought * slow
            e_mean += e[i] / walls
        e_mean = min(e_mean, max(0.0, cm[C_MAXLEN] - L))
        cost = cm[C_BUILD] * math.pi * r * r * e_mean
        if e_mean > 0.0 and nutrient[m] >= cost:
            nutrient[m] -= cost
            length[m] = L + e_mean
            # turning: wall i's excess elongation turns the axis away from it, about the
            # normal of the triangle (origin, end, wall point): z x v_i
            gain = cm[C_TURN] * min(1.0, mean_h[m, 8]) / max(L, 1e-9)
            for i in range(walls):
                zx, zy, zz = R[m, 0, 2], R[m, 1, 2], R[m, 2, 2]
                nx = zy * v[i, 2] - zz * v[i, 1]
                ny = zz * v[i, 0] - zx * v[i, 2]
                nz = zx * v[i, 1] - zy * v[i, 0]
                nn = math.sqrt(nx * nx + ny * ny + nz * nz)
                if nn > 0.0:
                    axis[0], axis[1], axis[2] = nx / nn, ny / nn, nz / nn
                    _rotate(R[m], axis, -gain * (e[i] - e_mean))
        if not paper:  # leaves grow (expansion hormone), up to the shoot's leaf density
            room = cm[C_LEAF_DENSITY] * length[m] - leaf[m]
            da = min(cm[C_LEAF_GROWTH] * min(1.0, mean_h[m, 9]) * slow * length[m], room)
            if da > 0.0 and nutrient[m] > 0.0:  # as much as the nutrient pays for
                cost = cm[C_LEAF_COST] * da
                if nutrient[m] >= cost:
                    nutrient[m] -= cost
                else:
                    da = nutrient[m] / cm[C_LEAF_COST]
                    nutrient[m] = 0.0
                leaf[m] += da
        if paper:  # thickening after growth, by the hormone alone (the walls move out)
            thicken_module(m, cm[C_THICK] * min(1.0, mean_h[m, 1]), modules, cm, False)
        # lignification: chlorophyll down, strength up; greening: chlorophyll up
        lg = cm[C_LIGNIFY] * min(1.0, mean_h[m, 5])
        lignin[m] = min(1.0, lignin[m] + lg)
        chl = chlorophyll[m] - cm[C_CHL_LOSS] * lg + cm[C_GREEN] * min(1.0, mean_h[m, 6])
        chlorophyll[m] = min(1.0, max(0.0, chl))
    # nutrient sharing between parent and child (a share of the difference each step)
    for m in range(n - 1, 0, -1):
        p = parent[m]
        if p >= 0:
            flow = c[plant[m], C_SHARE] * 0.5 * (nutrient[m] - nutrient[p])
            nutrient[m] -= flow
            nutrient[p] += flow
    # new modules: an apical child from a meristem, laterals from the branching hormone,
    # both slowed by lignin; each plant of the P rows holds at most cap // P modules
    share = cap // genes.shape[0]
    count = np.zeros(genes.shape[0], np.int64)
    for m in range(n):
        count[plant[m]] += 1
    for m in range(n):
        if n_new >= cap:
            break
        owner = plant[m]
        cm = c[owner]
        slow = 1.0 - lignin[m]
        price = new_module_cost(min(cm[C_NEWRAD], radius[m]), cm)
        grown = length[m] >= 0.999 * cm[C_MAXLEN]
        if (
            apex[m] and grown and mean_h[m, 4] * slow > cm[C_THRESHOLD]
            and nutrient[m] > price and count[owner] < share
        ):  # fmt: skip
            q = n_new
            n_new += 1
            count[owner] += 1
            new_module(q, m, R[m], modules, cm)
            apex[m] = False
        if n_new >= cap:
            break
        if (
            count[owner] < share
            and mean_h[m, 2] * slow > cm[C_THRESHOLD]
            and inh[m] < cm[C_THRESHOLD]
            and laterals[m] < cm[C_LATERALS]
            and length[m] >= 0.5 * cm[C_MAXLEN]
            and nutrient[m] > price
        ):
            # lateral direction B = sum_i v_i H_i, tilted from the axis by the branch angle
            frame_of(R[m], cs, v)
            bx = by = bz = 0.0
            for i in range(walls):
                bx += v[i, 0] * hormone[m, i, 2]
                by += v[i, 1] * hormone[m, i, 2]
                bz += v[i, 2] * hormone[m, i, 2]
            z = R[m, :, 2]
            d = bx * z[0] + by * z[1] + bz * z[2]
            bx, by, bz = bx - d * z[0], by - d * z[1], bz - d * z[2]
            nb = math.sqrt(bx * bx + by * by + bz * bz)
            if nb < 1e-9 * walls:  # no side wins: modules take the walls in turn
                w = m % walls
                bx, by, bz, nb = v[w, 0], v[w, 1], v[w, 2], 1.0
            if dims == 2 and laterals[m] % 2 == 1:  # 2D: laterals alternate sides
                bx, by, bz = -bx, -by, -bz
            elif dims == 3 and laterals[m] > 0:  # the j-th turns B about the axis by j phi
                a = laterals[m] * GOLDEN_ANGLE
                ca, sa = math.cos(a), math.sin(a)
                cx, cy, cz = z[1] * bz - z[2] * by, z[2] * bx - z[0] * bz, z[0] * by - z[1] * bx
                bx, by, bz = bx * ca + cx * sa, by * ca + cy * sa, bz * ca + cz * sa
            Rl = R[m].copy()
            axis = np.array([
                z[1] * bz - z[2] * by, z[2] * bx - z[0] * bz, z[0] * by - z[1] * bx
            ]) / nb  # fmt: skip
            _rotate(Rl, axis, cm[C_BRANCH_ANGLE])
            q = n_new
            n_new += 1
            count[owner] += 1
            new_module(q, m, Rl, modules, cm)
            laterals[m] += 1
    return n_new, gained


@njit
def grow_step(n, dims, modules, scratch, genes, c, strength_young, env, shifts):
    """One step of a plant in its environment ``env`` (:class:`Surroundings`), all in one
    call; returns ``(n_new, stop)``, ``stop`` an index into :data:`STOPS` (``STOP_CAP``
    when the cap held back new modules, which does not stop the plant; ``STOP_NAN``,
    ``STOP_BROKEN`` and ``STOP_STARVED`` stop it). The physics is plant 0's
    (``c[0, C_PHYSICS]``: the plants of one call share it).

    1. place the modules end to end (:func:`place_kernel`) and draw each as the union
       of its stem and its leaves' foliage cylinder (:func:`drawn_kernel`);
    2. each wall's light at its point (on the drawn surface, halfway along the module) with its
       outward normal, through the shadow maps of every light ``env.dirs`` ``(j, 3)``
       with image planes ``env.us, env.vs`` and intensities ``env.weights``
       (:func:`growsim.kernels.light.point_light_into`; ``env.resolution``, ``env.bias``
       in pixels, ``env.soft`` shadows with one ``env.transmission``) into
       ``modules.wall_light``; with ``env.shared`` (``light.walls = "module"``) one point
       per module and light, its exposure shared by its walls, each its own cosine
       (:func:`growsim.kernels.light.module_light_into`); a module lying on the soil
       gets no light (:func:`~growsim.kernels.hormone_light.soil_unlit`);
    3. water into ``modules.met`` and ``modules.water``: ``growsim``, each leaf's
       transpiration ``transpiration x leaf area x mean wall light x drought factor``
       shared from the soil's ``env.supply x env.soil`` kg by path conductance
       (:func:`growsim.kernels.water.transport_into_kernel`, ``env.resistance``,
       ``env.lift`` already scaled by g); ``paper``, every module's pull (its mean wall
       light times its wall area) met by the share ``min(1, env.supply)``;
    4. ``growsim``: :func:`thicken_kernel` (toward the radius the loads of the last step
       asked for, from the whole plant's carbon); :func:`step_kernel` (``genes`` ``(P, H,
       3 + J)``, constants ``c`` ``(P, N_CONSTANTS)``, a row per plant); a NaN or
       infinity in the modules stops the plant (``n`` modules kept);
    5. ``modules.light`` the mean wall light of the old modules (0 for new ones), ``met``
       1 for new ones; modules placed again, none below the soil ``env.ground``
       (:func:`ground_kernel`);
    6. gravity (:func:`growsim.kernels.gravity.loads_kernel`) on the stems and, in
       ``growsim``, their leaves (blades of ``leaf_mass_per_area``): strength ``young +
       (env.strength - young) x lignin`` (``young`` the module's plant's
       ``strength_young`` ``(P,)``); a joint whose stress reaches it breaks: ``paper``,
       the plant stops; ``growsim``, the module and its descendants are shed
       (:func:`shed_kernel`) and the plant goes on, unless a root broke. ``growsim``
       then sets the radius each module's loads ask for (:func:`design_kernel`);
    7. a ``growsim`` plant whose nutrient sums below 0 has starved (``STOP_STARVED``; a
       ``paper`` plant pays no upkeep).

    ``modules`` (:class:`Modules`) are updated in place; ``scratch`` is the shadow maps'
    scratch (:func:`growsim.kernels.light.shadow_scratch` of ``env.resolution``);
    ``shifts`` ``(k, 3)``: a periodic stand, the plant among copies of it moved by each
    row (:func:`growsim.kernels.stand.periodic_shifts`, :func:`walls_light`; ``(0, 3)``:
    alone).
    :func:`growsim.models.hormone.grow` calls this once per step;
    :func:`growsim.kernels.hormone_population.grow_population` runs whole populations
    through it.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models.hormone import grow
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})
    >>> [p.n_segments for p in grow({"dims": 2, "steps": 3}, env=env)]
    [1, 1, 1]
    """
    parent, R, origin, length, radius = (modules.parent, modules.R, modules.origin,
                                         modules.length, modules.radius)  # fmt: skip
    hormone, wall_light, met, light = (modules.hormone, modules.wall_light, modules.met,
                                       modules.light)  # fmt: skip
    plant, leaf = modules.plant, modules.leaf
    for q in range(n):  # every module's plant has its row of genes, constants, strength
        if plant[q] < 0 or plant[q] >= min(genes.shape[0], c.shape[0], strength_young.shape[0]):
            raise ValueError("grow_step: a module's plant has no row of genes or constants")
    paper = c[0, C_PHYSICS] > 0.5
    cap, walls = hormone.shape[0], hormone.shape[1]
    place_kernel(n, parent, R, length, origin)
    drawn = drawn_kernel(n, modules)
    start = origin[:n]
    end = module_ends(n, origin, length, R, np.empty((n, 3)))
    which = WALLS if paper else WALLS | LEAVES
    if env.shared and shifts.shape[0] == 0:  # one exposure per module and light
        offsets = np.array([0, n], np.int64)
        trans = np.full(n, env.transmission) if env.soft else np.empty(0)
        lit = module_light_into((start, end, drawn[:n], offsets),
                                (R, wall_angles(walls, dims)),
                                (env.dirs, env.us, env.vs, env.weights),
                                (env.resolution, env.bias, env.soft, trans), scratch,
                                wall_light[:n]).reshape(n * walls)  # fmt: skip
        if not paper:
            modules.leaf_light[:n] = lights_kernel(n, dims, modules, env, shifts, scratch, LEAVES)
    else:  # each wall's own point (in a periodic stand, among the plant's copies)
        lit = lights_kernel(n, dims, modules, env, shifts, scratch, which)
        if not paper:
            modules.leaf_light[:n] = lit[n * walls :]
    demand = np.empty(n)
    H7 = 7
    for q in range(n):
        acc = 0.0
        h7 = 0.0
        for i in range(walls):
            wall_light[q, i] = lit[q * walls + i]
            acc += lit[q * walls + i]
            h7 += hormone[q, i, H7] / walls
        light[q] = acc / walls
        if paper:  # the module's pull: its light over its wall area
            demand[q] = light[q] * 2.0 * math.pi * radius[q] * length[q]
        else:  # its leaves' transpiration (the drought hormone closes the stomata)
            cq = c[plant[q]]
            s = 1.0 - cq[C_DROUGHT] * min(1.0, h7)
            demand[q] = cq[C_TRANSPIRATION] * leaf[q] * modules.leaf_light[q] * s
    soil_unlit(n, end, length, env.ground, wall_light, light, modules.leaf_light, demand)
    if paper:  # the paper's negative pressure, no losses: every pull met by the share
        share = min(1.0, env.supply)
        for q in range(n):
            met[q] = share if demand[q] > 0.0 else 1.0
            modules.water[q] = met[q] * demand[q]
    else:
        transport_into_kernel(start, end, radius[:n], parent[:n], demand,
                              env.supply * env.soil, env.resistance, env.lift,
                              modules.water[:n], met[:n])  # fmt: skip
    if not paper:  # thickening first, from the whole plant's carbon
        thicken_kernel(n, modules, c)
    n_new, _ = step_kernel(n, dims, modules, genes, c)
    if not _finite(n_new, modules):
        ground_kernel(n, parent, R, length, origin, env.ground)
        drawn_kernel(n, modules)
        return n, STOP_NAN
    for q in range(n, n_new):
        light[q] = 0.0
        met[q] = 1.0
        modules.water[q] = 0.0
    ground_kernel(n_new, parent, R, length, origin, env.ground)
    n_new, code = gravity_kernel(n_new, modules, c, strength_young, env, paper)
    if not paper:  # the radius the loads ask for: the next step thickens toward it
        design_kernel(n_new, modules, c, strength_young,
                      (env.density, env.leaf_mass_per_area, env.g, env.strength))  # fmt: skip
    drawn_kernel(n_new, modules)
    if code != STOP_NONE:
        return n_new, code
    if not paper and total(modules.nutrient, n_new) < 0.0:  # growsim: carbon ran out
        return n_new, STOP_STARVED
    return n_new, STOP_CAP if n_new >= cap else STOP_NONE


@njit
def _finite(n, modules):
    """Whether modules ``0..n-1`` hold only finite numbers."""
    R, hormone = modules.R, modules.hormone
    for q in range(n):
        if not (math.isfinite(modules.length[q]) and math.isfinite(modules.radius[q])
                and math.isfinite(modules.nutrient[q])
                and math.isfinite(modules.leaf[q])):  # fmt: skip
            return False
        for a in range(3):
            for b in range(3):
                if not math.isfinite(R[q, a, b]):
                    return False
        for i in range(hormone.shape[1]):
            for k in range(hormone.shape[2]):
                if not math.isfinite(hormone[q, i, k]):
                    return False
    return True


@njit
def total(values, n):
    """``values[0] + ... + values[n - 1]`` in order: a plant's total nutrient (the one sum
    the model's meta and the population path report).

    Examples
    --------
    >>> import numpy as np
    >>> total(np.array([1.0, 2.0, 4.0]), 2)
    3.0
    """
    acc = 0.0
    for q in range(n):
        acc += values[q]
    return acc
