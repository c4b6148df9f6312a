"""The hormone model's modules (:mod:`growsim.kernels.hormone`): the hormones, stimuli,
physics and stop codes, the layout of the constants, the module arrays
(:class:`Modules`) and the environment (:class:`Surroundings`) the kernels take, a new
module and a seedling (:func:`new_plant`), and each module's radius in the shadow map,
its stem's or its leaves' (:func:`drawn_kernel`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from growsim.kernels.config import njit

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

#: the two physics (index: the constants' last column, ``C_PHYSICS``): ``growsim``, the
#: paper's model made sound (leaves as organs, a fixed water supply shared by conductance,
#: thickening by load, breaks that shed); ``paper``, the paper's model as its text gives it
PHYSICS = ("growsim", "paper")
GROWSIM, PAPER = range(2)

#: the angle between successive laterals of a module about its axis in 3D (phyllotaxis;
#: in 2D they alternate sides): no two laterals of a module coincide
GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))

#: why a plant stopped (index: code returned by :func:`grow_step`): "" it grew to the end
#: of its steps; "cap" the module cap held back a new module (it goes on); "nan" a NaN or
#: infinity; "broken" a joint broke (``paper``: any joint; ``growsim``: a root's, the
#: plant falls and dies, its nutrient lost; other breaks shed their branch and the plant
#: goes on); "starved" its
#: nutrient (carbon reserve) fell below 0 (``growsim``)
STOPS = ("", "cap", "nan", "broken", "starved")
STOP_NONE, STOP_CAP, STOP_NAN, STOP_BROKEN, STOP_STARVED = range(5)

# indices of the constants array (the model's CONSTANTS in this order, then the physics)
(C_ELONG, C_MAXLEN, C_TURN, C_THICK, C_NEWLEN, C_NEWRAD, C_BRANCH_ANGLE, C_THRESHOLD,
 C_INH_TRANSPORT, C_PHOTO, C_HALF_SAT, C_BUILD, C_UPKEEP, C_NEW_COST, C_LIGNIFY, C_GREEN,
 C_CHL_LOSS, C_DROUGHT, C_LEAF_GROWTH, C_SHARE, C_LATERALS, C_LEAF_COST, C_LEAF_UPKEEP,
 C_LEAF_TURNOVER, C_LEAF_DENSITY, C_NEW_LEAF, C_TRANSPIRATION, C_HUBER, C_SAFETY, C_WIND,
 C_RESERVE, C_PHYSICS) = range(32)  # fmt: skip
N_CONSTANTS = 32


class Modules(NamedTuple):
    """A plant's modules, field by field, ``cap`` rows each (the module arrays every kernel
    here updates in place; :func:`new_module_arrays` makes them)."""

    parent: np.ndarray  #: ``(cap,)`` int64, -1 for the root
    R: np.ndarray  #: ``(cap, 3, 3)`` pose: columns the two axes across and the growth axis
    origin: np.ndarray  #: ``(cap, 3)``
    length: np.ndarray  #: ``(cap,)`` m
    radius: np.ndarray  #: ``(cap,)`` m, the stem's (wood)
    nutrient: np.ndarray  #: ``(cap,)`` g C, the carbon reserve
    chlorophyll: np.ndarray  #: ``(cap,)``
    lignin: np.ndarray  #: ``(cap,)``
    apex: np.ndarray  #: ``(cap,)`` bool: a meristem
    laterals: np.ndarray  #: ``(cap,)`` int64: laterals grown
    hormone: np.ndarray  #: ``(cap, walls, H)``
    wall_light: np.ndarray  #: ``(cap, walls)`` the light each wall receives
    met: np.ndarray  #: ``(cap,)`` the share of each module's water demand met
    light: np.ndarray  #: ``(cap,)`` the mean wall light
    plant: np.ndarray  #: ``(cap,)`` int64: the module's plant (a row of the genes; 0 alone)
    leaf: np.ndarray  #: ``(cap,)`` m^2: the module's leaf area (``growsim``; 0 in ``paper``)
    target: np.ndarray  #: ``(cap,)`` m: the radius its loads ask for (``growsim``)
    drawn: np.ndarray  #: ``(cap,)`` m: its radius in the shadow map, the leaves' included
    water: np.ndarray  #: ``(cap,)`` kg: the water it received in the last step
    leaf_light: np.ndarray  #: ``(cap,)`` the light on its leaves (facing up; ``growsim``)
    events: np.ndarray  #: ``(2,)`` int64: joints broken and modules shed so far


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
    supply: float  #: the soil's water, a share of the ample soil's
    soil: float  #: the ample soil's water, kg a step
    resistance: float  #: path resistance a metre of stem of 1 cm^2 adds
    lift: float  #: path resistance a metre climbed adds, scaled by ``g / 9.81``
    g: float  #: gravity
    density: float  #: wood density
    leaf_mass_per_area: float
    strength: float  #: wood strength (lignified)
    ground: float  #: height of the soil surface (:func:`ground_kernel`)
    shared: bool = False  #: walls share their module's exposure (``light.walls = "module"``)


def new_module_arrays(cap: int, walls: int, hormones: int = len(HORMONES)) -> Modules:
    """Uninitialised :class:`Modules` of ``cap`` rows (the wall light, water met, light,
    leaf, target, drawn radius, water and leaf light zeroed); :func:`new_plant` makes them
    a seedling.

    Examples
    --------
    >>> new_module_arrays(4, 2).hormone.shape
    (4, 2, 10)
    """
    return Modules(
        np.empty(cap, np.int64), np.empty((cap, 3, 3)), np.empty((cap, 3)),
        *(np.empty(cap) for _ in range(5)), np.empty(cap, np.bool_), np.empty(cap, np.int64),
        np.empty((cap, walls, hormones)), np.zeros((cap, walls)), np.zeros(cap), np.zeros(cap),
        np.zeros(cap, np.int64), *(np.zeros(cap) for _ in range(5)), np.zeros(2, np.int64),
    )  # fmt: skip


@njit
def new_module_cost(r, c):
    """What a parent pays for a new module of radius ``r`` with constants ``c``: the
    start-up cost (half of it the child's reserve), the wood of the new length and, in
    ``growsim``, its first leaf area."""
    leaf = c[C_LEAF_COST] * c[C_NEW_LEAF] if c[C_PHYSICS] < 0.5 else 0.0
    return c[C_NEW_COST] + c[C_BUILD] * math.pi * r * r * c[C_NEWLEN] + leaf


@njit
def new_module(q, m, Rq, modules, c):
    """Module ``q``: a child of ``m`` with pose ``Rq``, new length and radius (at most its
    parent's), full chlorophyll, no lignin, ``growsim``'s new leaf area, its parent's
    plant; the parent pays :func:`new_module_cost`, half the start-up cost is the child's
    nutrient; ``c`` the constants of that plant."""
    r = min(c[C_NEWRAD], modules.radius[m])
    modules.nutrient[m] -= new_module_cost(r, c)
    modules.parent[q] = m
    modules.R[q] = Rq
    modules.length[q] = c[C_NEWLEN]
    modules.radius[q] = r
    modules.nutrient[q] = 0.5 * c[C_NEW_COST]
    modules.chlorophyll[q] = 1.0
    modules.lignin[q] = 0.0
    modules.apex[q] = True
    modules.laterals[q] = 0
    modules.hormone[q] = 0.0
    modules.plant[q] = modules.plant[m]
    modules.leaf[q] = c[C_NEW_LEAF] if c[C_PHYSICS] < 0.5 else 0.0
    modules.target[q] = 0.0


@njit
def new_plant(modules, c):
    """Reset :class:`Modules` ``modules`` to a seedling: one root module at the origin
    growing up (``+y``; its walls face ``+-x`` and, in 3D, around), of the new length and
    radius, the seed's reserve as its nutrient, full chlorophyll, a meristem and
    ``growsim``'s new leaf area (the wall light, water met and light are left as they
    are). Returns the module count, 1.

    Examples
    --------
    >>> import numpy as np
    >>> modules = new_module_arrays(4, 2)
    >>> new_plant(modules, np.full(N_CONSTANTS, 0.1)), modules.R[0, :, 2].tolist()
    (1, [0.0, 1.0, 0.0])
    """
    R = modules.R
    modules.parent[:] = -1
    R[:] = 0.0
    R[0, 0, 0] = 1.0
    R[0, 2, 1] = -1.0
    R[0, 1, 2] = 1.0
    modules.origin[:] = 0.0
    reals = (
        modules.length,
        modules.radius,
        modules.nutrient,
        modules.chlorophyll,
        modules.lignin,
        modules.leaf,
        modules.target,
        modules.drawn,
        modules.water,
        modules.leaf_light,
    )
    for a in reals:
        a[:] = 0.0
    modules.apex[:] = False
    modules.laterals[:] = 0
    modules.hormone[:] = 0.0
    modules.plant[:] = 0
    modules.events[:] = 0
    modules.length[0] = c[C_NEWLEN]
    modules.radius[0] = c[C_NEWRAD]
    modules.nutrient[0] = c[C_RESERVE]
    modules.chlorophyll[0] = 1.0
    modules.apex[0] = True
    modules.leaf[0] = c[C_NEW_LEAF] if c[C_PHYSICS] < 0.5 else 0.0
    modules.drawn[0] = _drawn(modules.radius[0], modules.leaf[0], modules.length[0])
    return 1


@njit(inline="always")
def _drawn(r, leaf, L):
    """A module's radius in the shadow map: the union of its stem (radius ``r``) and its
    leaves, a coaxial foliage cylinder of radius ``leaf / (2 L)`` (seen from the side its
    shadow is the leaf area ``leaf``)."""
    return max(r, 0.5 * leaf / L) if L > 0.0 else r


@njit
def drawn_kernel(n, modules):
    """``modules.drawn[:n]``: each module's radius in the shadow map, its stem's or its
    leaves' foliage cylinder's, ``max(r, leaf / (2 L))`` (see :func:`_drawn`). Returns
    ``modules.drawn``.

    Examples
    --------
    >>> import numpy as np
    >>> m = new_module_arrays(2, 2)
    >>> m.radius[:] = 0.01; m.length[:] = 0.5; m.leaf[:] = (0.0, 0.1)
    >>> drawn_kernel(2, m).tolist()
    [0.01, 0.1]
    """
    for q in range(n):
        modules.drawn[q] = _drawn(modules.radius[q], modules.leaf[q], modules.length[q])
    return modules.drawn
