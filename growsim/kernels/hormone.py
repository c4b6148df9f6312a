"""Numba kernels of the hormone-module model (:mod:`growsim.models.hormone`).

Modules are stored field by field in creation order (a parent before its children), so a
forward loop carries parent -> child (:func:`place_kernel`: positions) and a reverse loop
child -> parent (the inhibitor's transport to the base, in :func:`step_kernel`). The
equations are written out in ``docs/models/hormone.md``; the oracle is
``tests/naive/hormone.py``.

Constants ``c`` ``(P, N_CONSTANTS)`` (indices :data:`C_*`) and genes ``genes`` ``(P, H, 3
+ J)`` (per hormone: bias, gain, decay, then one weight per stimulus) are passed in, never
global: one row per plant (``P = 1`` for a plant alone). Module ``m`` belongs to plant
``modules.plant[m]`` (a child to its parent's plant) and reads that plant's row, so one
module array can hold a stand of different genomes.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.gravity import loads_kernel, radius_end_kernel
from growsim.kernels.light import module_light_into, point_light_into
from growsim.kernels.walls import frame_of, wall_angles, wall_normals
from growsim.kernels.water import transport_into_kernel

__all__ = [
    "GOLDEN_ANGLE",
    "HORMONES",
    "STIMULI",
    "STOPS",
    "Modules",
    "Surroundings",
    "ground_kernel",
    "grow_step",
    "new_plant",
    "place_kernel",
    "step_kernel",
    "total",
    "walls_light",
]

#: the hormones and their roles (index: role)
HORMONES = (
    "elongation",
    "thickening",
    "branching",
    "inhibitor",
    "meristem",
    "lignification",
    "greening",
    "drought",
    "turning",
    "expansion",
)
#: the stimuli a wall senses (index: stimulus)
STIMULI = ("wall light", "water met", "nutrient", "chlorophyll", "wall up", "inhibitor")

#: the angle between successive laterals of a module about its axis in 3D (phyllotaxis;
#: in 2D they alternate sides): no two laterals of a module coincide
GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))

#: why a plant stopped (index: code returned by :func:`grow_step`); "cap" does not stop it
STOPS = ("", "cap", "nan", "broken")
STOP_NONE, STOP_CAP, STOP_NAN, STOP_BROKEN = range(4)

# indices of the constants array
(C_ELONG, C_MAXLEN, C_TURN, C_THICK, C_NEWLEN, C_NEWRAD, C_BRANCH_ANGLE, C_THRESHOLD,
 C_INH_TRANSPORT, C_PHOTO, C_HALF_SAT, C_BUILD, C_UPKEEP, C_NEW_COST, C_LIGNIFY, C_GREEN,
 C_CHL_LOSS, C_DROUGHT, C_EXPAND, C_SHARE, C_LATERALS) = range(21)  # fmt: skip
N_CONSTANTS = 21


class Modules(NamedTuple):
    """A plant's modules, field by field, ``cap`` rows each (the module arrays every kernel
    here updates in place; :func:`new_module_arrays` makes them)."""

    parent: np.ndarray  #: ``(cap,)`` int64, -1 for the root
    R: np.ndarray  #: ``(cap, 3, 3)`` pose: columns the two axes across and the growth axis
    origin: np.ndarray  #: ``(cap, 3)``
    length: np.ndarray  #: ``(cap,)``
    radius: np.ndarray  #: ``(cap,)``
    nutrient: np.ndarray  #: ``(cap,)``
    chlorophyll: np.ndarray  #: ``(cap,)``
    lignin: np.ndarray  #: ``(cap,)``
    apex: np.ndarray  #: ``(cap,)`` bool: a meristem
    laterals: np.ndarray  #: ``(cap,)`` int64: laterals grown
    hormone: np.ndarray  #: ``(cap, walls, H)``
    wall_light: np.ndarray  #: ``(cap, walls)`` the light each wall receives
    met: np.ndarray  #: ``(cap,)`` the share of each module's water demand met
    light: np.ndarray  #: ``(cap,)`` the mean wall light
    plant: np.ndarray  #: ``(cap,)`` int64: the module's plant (a row of the genes; 0 alone)


class Surroundings(NamedTuple):
    """The environment as :func:`grow_step` takes it (one tuple, the same for every plant)."""

    dirs: np.ndarray  #: ``(j, 3)`` the lights' unit directions
    us: np.ndarray  #: ``(j, 3)`` their image planes' first axes
    vs: np.ndarray  #: ``(j, 3)`` and second axes
    weights: np.ndarray  #: ``(j,)`` their intensities
    resolution: int  #: shadow-map pixels across
    bias: float  #: depth bias in pixels
    soft: bool  #: soft shadows (else hard)
    transmission: float  #: a module's transmission (soft shadows)
    supply: float  #: water supply
    resistance: float  #: water resistance
    lift: float  #: water lift, scaled by ``g / 9.81``
    g: float  #: gravity
    density: float  #: wood density
    leaf_mass_per_area: float
    strength: float  #: wood strength (lignified)
    ground: float  #: height of the soil surface (:func:`ground_kernel`)
    shared: bool = False  #: walls share their module's exposure (``light.walls = "module"``)


def new_module_arrays(cap: int, walls: int, hormones: int = len(HORMONES)) -> Modules:
    """Uninitialised :class:`Modules` of ``cap`` rows (the wall light, water met and light
    zeroed); :func:`new_plant` makes them a seedling.

    Examples
    --------
    >>> new_module_arrays(4, 2).hormone.shape
    (4, 2, 10)
    """
    return Modules(
        np.empty(cap, np.int64), np.empty((cap, 3, 3)), np.empty((cap, 3)),
        *(np.empty(cap) for _ in range(5)), np.empty(cap, np.bool_), np.empty(cap, np.int64),
        np.empty((cap, walls, hormones)), np.zeros((cap, walls)), np.zeros(cap), np.zeros(cap),
        np.zeros(cap, np.int64),
    )  # fmt: skip


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
    ``c[plant[m]]`` (``plant`` = ``modules.plant``); each of the ``P`` plants (rows of
    ``genes``) grows at most ``cap // P`` modules.

    Reads ``wall_light`` ``(cap, walls)`` the light each wall receives and ``met``
    ``(cap,)`` the share of each module's water demand met; ``hormone`` ``(cap, walls,
    H)`` is updated in place, as are the module fields (``origin`` and ``light`` are not
    read). See ``docs/models/hormone.md`` for the equations, in
    the order they run: synthesis, transport of the inhibitor, photosynthesis, costs,
    elongation and turning, thickening, lignification and greening, nutrient sharing,
    new modules.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models.hormone import MODEL
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})
    >>> MODEL.develop({**MODEL.preset("demo_3d"), "steps": 10}, env=env).n_segments > 1
    True
    """
    parent, R, _, length, radius, nutrient, chlorophyll, lignin = modules[:8]
    apex, laterals, hormone = modules[8:11]
    wall_light, met = modules.wall_light, modules.met
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
        frame_of(R[m], cs, v)
        L = length[m]
        r = radius[m]
        area = 2.0 * math.pi * r * L / walls if dims == 3 else 2.0 * r * L / 2.0
        area *= 1.0 + cm[C_EXPAND] * mean_h[m, 9]
        # photosynthesis: saturating in the wall's light, limited by water and chlorophyll
        photo = 0.0
        for i in range(walls):
            li = wall_light[m, i]
            photo += area * li * (1.0 + cm[C_HALF_SAT]) / (li + cm[C_HALF_SAT])
        drought = 1.0 - cm[C_DROUGHT] * min(1.0, mean_h[m, 7])
        photo *= cm[C_PHOTO] * chlorophyll[m] * met[m] * drought
        gained += photo
        vol = math.pi * r * r * L
        nutrient[m] += photo - cm[C_UPKEEP] * vol * (0.2 + 0.8 * chlorophyll[m])
        # elongation per wall (turgor: water met), the module by the mean of its walls
        e_mean = 0.0
        for i in range(walls):
            e[i] = cm[C_ELONG] * hormone[m, i, 0] * met[m] * drought
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
        # thickening (walls move out)
        dr = cm[C_THICK] * min(1.0, mean_h[m, 1])
        cost = cm[C_BUILD] * 2.0 * math.pi * r * length[m] * dr
        if dr > 0.0 and nutrient[m] >= cost:
            nutrient[m] -= cost
            radius[m] = r + dr
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
    # new modules: an apical child from a meristem, laterals from the branching hormone;
    # each plant of the P rows holds at most cap // P modules (its share of the arrays)
    share = cap // genes.shape[0]
    count = np.zeros(genes.shape[0], np.int64)
    for m in range(n):
        count[plant[m]] += 1
    for m in range(n):
        if n_new >= cap:
            break
        owner = plant[m]
        cm = c[owner]
        grown = length[m] >= 0.999 * cm[C_MAXLEN]
        if (
            apex[m] and grown and mean_h[m, 4] > cm[C_THRESHOLD]
            and nutrient[m] > cm[C_NEW_COST] and count[owner] < share
        ):  # fmt: skip
            q = n_new
            n_new += 1
            count[owner] += 1
            _new(q, m, R[m], modules, cm)
            apex[m] = False
        if n_new >= cap:
            break
        if (
            count[owner] < share
            and mean_h[m, 2] > cm[C_THRESHOLD]
            and inh[m] < cm[C_THRESHOLD]
            and laterals[m] < cm[C_LATERALS]
            and length[m] >= 0.5 * cm[C_MAXLEN]
            and nutrient[m] > cm[C_NEW_COST]
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
            _new(q, m, Rl, modules, cm)
            laterals[m] += 1
    return n_new, gained


@njit
def _new(q, m, Rq, modules, c):
    """Module ``q``: a child of ``m`` with pose ``Rq``, new length and radius, full
    chlorophyll, no lignin, its parent's cost of a new module as its nutrient, its parent's
    plant; ``c`` the constants of that plant."""
    parent, R, _, length, radius, nutrient, chlorophyll, lignin = modules[:8]
    apex, laterals, hormone = modules[8:11]
    parent[q] = m
    R[q] = Rq
    length[q] = c[C_NEWLEN]
    radius[q] = min(c[C_NEWRAD], radius[m])
    nutrient[m] -= c[C_NEW_COST]
    nutrient[q] = 0.5 * c[C_NEW_COST]
    chlorophyll[q] = 1.0
    lignin[q] = 0.0
    apex[q] = True
    laterals[q] = 0
    hormone[q] = 0.0
    modules.plant[q] = modules.plant[m]


@njit
def new_plant(modules, c):
    """Reset :class:`Modules` ``modules`` to a seedling: one root module at the origin
    growing up (``+y``; its walls face ``+-x`` and, in 3D, around), of the new length and
    radius, nutrient 0.1, full chlorophyll, a meristem (the wall light, water met and light
    are left as they are). Returns the module count, 1.

    Examples
    --------
    >>> import numpy as np
    >>> modules = new_module_arrays(4, 2)
    >>> new_plant(modules, np.full(N_CONSTANTS, 0.1)), modules.R[0, :, 2].tolist()
    (1, [0.0, 1.0, 0.0])
    """
    parent, R, origin, length, radius, nutrient, chlorophyll, lignin = modules[:8]
    apex, laterals, hormone = modules[8:11]
    parent[:] = -1
    R[:] = 0.0
    R[0, 0, 0] = 1.0
    R[0, 2, 1] = -1.0
    R[0, 1, 2] = 1.0
    origin[:] = 0.0
    length[:] = 0.0
    radius[:] = 0.0
    nutrient[:] = 0.0
    chlorophyll[:] = 0.0
    lignin[:] = 0.0
    apex[:] = False
    laterals[:] = 0
    hormone[:] = 0.0
    modules.plant[:] = 0
    length[0] = c[C_NEWLEN]
    radius[0] = c[C_NEWRAD]
    nutrient[0] = 0.1
    chlorophyll[0] = 1.0
    apex[0] = True
    return 1


@njit
def _ends(n, origin, length, R, end):
    """``end[m] = origin[m] + length[m] R[m][:, 2]`` for modules ``0..n-1``."""
    for m in range(n):
        for k in range(3):
            end[m, k] = origin[m, k] + length[m] * R[m, k, 2]
    return end


@njit
def _on_soil_unlit(n, end, length, ground, wall_light, light, demand):
    """A module lying on the soil (its end on it: :func:`ground_kernel` turned it up to
    the soil) gets no light and asks no water for photosynthesis: a stem on the ground
    is covered (litter, neighbours' shade); the plant must stand up to catch light."""
    for q in range(n):
        if end[q, 1] <= ground + 1e-9 * (1.0 + length[q]):
            light[q] = 0.0
            demand[q] = 0.0
            for i in range(wall_light.shape[1]):
                wall_light[q, i] = 0.0


@njit
def grow_step(n, dims, modules, scratch, genes, c, strength_young, env, shifts):
    """One step of a plant in its environment ``env`` (:class:`Surroundings`), all in one
    call; returns ``(n_new, stop)``, ``stop`` an index into :data:`STOPS` (``STOP_CAP``
    when the cap held back new modules, which does not stop the plant; ``STOP_NAN``,
    ``STOP_BROKEN`` stop it).

    1. place the modules end to end (:func:`place_kernel`);
    2. each wall's light at its point (on the surface, halfway along the module) with its
       outward normal, through the shadow maps of every light ``env.dirs`` ``(j, 3)``
       with image planes ``env.us, env.vs`` and intensities ``env.weights``
       (:func:`growsim.kernels.light.point_light_into`; ``env.resolution``, ``env.bias``
       in pixels, ``env.soft`` shadows with one ``env.transmission``) into
       ``modules.wall_light``; with ``env.shared`` (``light.walls = "module"``) one point
       per module and light, its exposure shared by its walls, each its own cosine
       (:func:`growsim.kernels.light.module_light_into`);
    3. water (:func:`growsim.kernels.water.transport_into_kernel`): demand = mean wall
       light x side area; ``env.supply``, ``env.resistance``, ``env.lift`` (already scaled
       by g) give ``modules.met``; a module lying on the soil gets no light
       (:func:`_on_soil_unlit`);
    4. :func:`step_kernel` (``genes`` ``(P, H, 3 + J)``, constants ``c`` ``(P,
       N_CONSTANTS)``, a row per plant); a NaN or infinity in the modules
       stops the plant (``n`` modules kept);
    5. ``modules.light`` the mean wall light of the old modules (0 for new ones), ``met``
       1 for new ones; modules placed again, none below the soil ``env.ground``
       (:func:`ground_kernel`: a module whose end would be under it is turned up);
    6. gravity (:func:`growsim.kernels.gravity.loads_kernel`): strength
       ``young + (env.strength - young) x lignin`` (``young`` the module's plant's
       ``strength_young`` ``(P,)``); a joint whose stress
       reaches it stops the plant.

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
    parent, R, origin, length, radius, nutrient = modules[:6]
    lignin, hormone, wall_light, met, light = modules[7], *modules[10:14]
    plant = modules.plant
    for q in range(n):  # every module's plant has its row of genes, constants, strength
        if plant[q] < 0 or plant[q] >= min(genes.shape[0], c.shape[0], strength_young.shape[0]):
            raise ValueError("grow_step: a module's plant has no row of genes or constants")
    cap, walls = hormone.shape[0], hormone.shape[1]
    place_kernel(n, parent, R, length, origin)
    start = origin[:n]
    end = _ends(n, origin, length, R, np.empty((n, 3)))
    offsets = np.array([0, n], np.int64)
    trans = np.full(n, env.transmission) if env.soft else np.empty(0)
    lights = (env.dirs, env.us, env.vs, env.weights)
    shadow = (env.resolution, env.bias, env.soft, trans)
    if env.shared and shifts.shape[0] == 0:  # one exposure per module and light
        lit = module_light_into((start, end, radius[:n], offsets),
                                (R, wall_angles(walls, dims)), lights, shadow, scratch,
                                wall_light[:n]).reshape(n * walls)  # fmt: skip
    else:  # each wall's own point (in a periodic stand, among the plant's copies)
        lit = walls_light(n, dims, modules, env, shifts, scratch)
    demand = np.empty(n)
    for q in range(n):
        acc = 0.0
        for i in range(walls):
            wall_light[q, i] = lit[q * walls + i]
            acc += lit[q * walls + i]
        light[q] = acc / walls
        demand[q] = light[q] * 2.0 * math.pi * radius[q] * length[q]
    _on_soil_unlit(n, end, length, env.ground, wall_light, light, demand)
    transport_into_kernel(start, end, radius[:n], parent[:n], demand, env.supply,
                          env.resistance, env.lift, np.empty(n), met[:n])  # fmt: skip
    n_new, _ = step_kernel(n, dims, modules, genes, c)
    if not _finite(n_new, R, length, radius, nutrient, hormone):
        ground_kernel(n, parent, R, length, origin, env.ground)
        return n, STOP_NAN
    for q in range(n, n_new):
        light[q] = 0.0
        met[q] = 1.0
    ground_kernel(n_new, parent, R, length, origin, env.ground)
    end = _ends(n_new, origin, length, R, np.empty((n_new, 3)))
    kind = np.zeros(n_new, np.int8)
    r_end = radius_end_kernel(parent[:n_new], kind, radius[:n_new], np.empty(n_new))
    wood = np.empty(n_new)
    for q in range(n_new):
        young = strength_young[plant[q]]
        wood[q] = young + (env.strength - young) * lignin[q]
    loads = loads_kernel(origin[:n_new], end, radius[:n_new], r_end, parent[:n_new], kind, wood,
                         (env.density, env.leaf_mass_per_area, env.g),
                         np.empty((4, n_new)))  # fmt: skip
    for q in range(n_new):
        if loads[3, q] >= 1.0:
            return n_new, STOP_BROKEN
    return n_new, STOP_CAP if n_new >= cap else STOP_NONE


@njit
def walls_light(n, dims, modules, env, shifts, scratch):
    """``(n * walls,)`` the light on each wall of modules ``0..n-1`` (placed: ``origin``
    up to date) at its own point (on the surface, halfway along the module) with its
    outward normal, through one shadow map per light of the modules, among their copies
    moved by ``shifts`` ``(k, 3)`` (a periodic stand, each copy's shadow read at the
    point moved back by its shift, :func:`growsim.kernels.light.point_light_into`;
    ``(0, 3)``: the plant alone). :func:`grow_step`'s exact light.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models.hormone import PARAMS, environment_args, resolve_params, seedling
    >>> n, s = seedling(resolve_params(PARAMS, {"dims": 2}), Environment())
    >>> env, m = environment_args(Environment()), s["modules"]
    >>> walls_light(n, 2, m, env, np.zeros((0, 3)), s["scratch"]).tolist()  # from above
    [0.0, 0.0]
    """
    R, origin, length, radius = modules.R, modules.origin, modules.length, modules.radius
    walls = modules.hormone.shape[1]
    start = origin[:n]
    end = _ends(n, origin, length, R, np.empty((n, 3)))
    trans = np.full(n, env.transmission) if env.soft else np.empty(0)
    m = n * walls
    normals = wall_normals(n, R, walls, dims, np.empty((n, walls, 3)))
    points = np.empty((m, 3))
    unit = np.empty((m, 3))
    for q in range(n):
        for i in range(walls):
            nx, ny, nz = normals[q, i, 0], normals[q, i, 1], normals[q, i, 2]
            norm = math.sqrt(nx * nx + ny * ny + nz * nz)
            for a in range(3):
                mid = start[q, a] + 0.5 * (end[q, a] - start[q, a])
                points[q * walls + i, a] = mid + radius[q] * normals[q, i, a]
                unit[q * walls + i, a] = normals[q, i, a] / norm
    return point_light_into(
        (start, end, radius[:n], np.array([0, n], np.int64)),
        (points, np.array([0, m], np.int64), unit), (env.dirs, env.us, env.vs, env.weights),
        (env.resolution, env.bias, env.soft, trans), scratch, np.empty(m), shifts,
    )  # fmt: skip


@njit
def _finite(n, R, length, radius, nutrient, hormone):
    """Whether modules ``0..n-1`` hold only finite numbers."""
    for q in range(n):
        if not (math.isfinite(length[q]) and math.isfinite(radius[q])
                and math.isfinite(nutrient[q])):  # fmt: skip
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
