"""Hormone-module growth (Uehara, Akamine and Endo, "Plants that acquire a 3D
structure by adapting to the environment").

A plant is a set of modules, each a short cylinder with a pose, length, thickness,
nutrient (a carbon reserve), chlorophyll, lignin and, in the ``growsim`` physics, a leaf
area, and ``walls`` light-sensing walls around it (2 in 2D). Two physics
(``physics``, :data:`growsim.kernels.hormone.PHYSICS`): ``growsim`` (the default), the
paper's model made sound, and ``paper``, the paper's model as its text gives it. Every
step, in the environment (:mod:`growsim.env`):

1. the modules are placed end to end (:func:`growsim.kernels.hormone.place_kernel`), each
   drawn in the shadow map with its leaves (a foliage cylinder whose side view is its
   leaf area);
2. each wall's light comes from the shadow map (:meth:`growsim.env.Light.point_light`: the
   wall's point, on the drawn surface halfway along the module, and its outward normal);
3. water: ``growsim``, the soil's fixed supply shared by path conductance among the
   leaves' transpiration (:meth:`growsim.env.Water.transport`); ``paper``, every module's
   pull met by the supply's share;
4. each wall makes ten hormones from what it senses, and the hormones drive elongation
   (uneven walls turn the module), thickening, branching (direction ``B = sum v_i H_i``),
   apical dominance, new apical modules, lignification (which slows growth and
   branching), greening, drought response, turning and leaf expansion; photosynthesis
   pays for growth (and, in ``growsim``, upkeep and the leaves' turnover)
   (:func:`growsim.kernels.hormone.step_kernel`);
5. the modules are placed again, none below the soil (``environment.ground``: a module
   whose end would go under it is turned up until its end touches it);
6. gravity loads every joint, leaves included (:meth:`growsim.env.Gravity.loads`, the
   strength rising with lignin from ``strength_young`` to the environment's wood
   strength): a joint that breaks stops a ``paper`` plant, as the paper says; a
   ``growsim`` plant sheds the broken branch and goes on, and thickens each module toward
   the radius its loads ask for.

:func:`grow` yields the plant after every step; :func:`develop` returns the last. The
plant's ``data`` holds per module ``nutrient`` (g C), ``chlorophyll``, ``lignin``,
``light`` (mean over its walls), ``water_met``, ``water`` (kg received in the last step)
and ``leaf_area`` (m^2); its ``meta`` holds ``steps``, ``stopped`` (``""``: it grew to
the end of its steps; ``"cap"`` when the module cap held back a new module, ``"nan"``,
``"broken"``, ``"starved"``), ``physics``, ``breaks`` and ``shed`` (joints broken and
modules shed on the way), ``total_nutrient`` (the paper's fitness) and ``ground`` (the
soil's height, ``environment.ground.height``: no module reaches below it, see
:func:`growsim.kernels.hormone.ground_kernel`). Renders colour each module by its
chlorophyll and lignin and draw the green ones as leaf blades
(:mod:`growsim.phenotypes.plant.mesh`). Every equation and constant, with units and
sources: ``docs/models/hormone.md``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from growsim.env import Environment
from growsim.errors import UserInputError
from growsim.kernels import hormone as K
from growsim.kernels import hormone_population as KP
from growsim.kernels import stand as KS
from growsim.kernels.light import shadow_scratch
from growsim.models.base import Model, Param, resolve_params
from growsim.phenotypes.plant import Plant

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "CONSTANTS",
    "MODEL",
    "PARAMS",
    "PRESETS",
    "PRESET_ENVIRONMENTS",
    "develop",
    "environment_args",
    "genes",
    "grow",
    "grow_periodic",
    "grow_stand",
    "leaves",
    "population",
    "seedling",
]

NAME = "hormone"

#: the stop codes that end a plant's growth (a NaN, a fall, starvation)
STOPPING = (K.STOP_NAN, K.STOP_BROKEN, K.STOP_STARVED)

#: settings (not genes): name, low, high, default, kind, doc
SETTINGS = (
    Param("dims", 2, 3, 3, kind="int", doc="2: the plant grows in the x-y plane; 3: in space"),
    Param("walls", 3, 16, 6, kind="int", doc="light-sensing walls per module (2D: always 2)"),
    Param("steps", 1, 1000, 40, kind="int", doc="growth steps (weeks)"),
    Param("max_modules", 1, 100000, 3000, kind="int",
          doc="module cap (no new modules past it): a safety net, not a size"),
    Param("strength_young", 1e3, 1e9, 2e7, unit="Pa",
          doc="strength of a module with no lignin (half the wood's: lignin doubles it)"),
    Param("physics", 0, 1, 0, kind="int", labels=K.PHYSICS,
          doc="'growsim': the paper's model made sound (leaves as organs, a fixed water "
          "supply shared by conductance, thickening by load, breaks that shed); 'paper': "
          "the paper's model as its text gives it"),
)  # fmt: skip

#: constants of the step (name, default, doc), passed to the kernel in this order (then
#: the physics). Units: m, a step of one week, g of carbon (g C), kg of water.
CONSTANTS = (
    ("elongation", 0.15, "largest elongation of a wall a step (m)"),
    ("max_length", 0.5, "a module elongates up to this length (m)"),
    ("turning", 0.3, "turning per unit of relative wall elongation difference (rad)"),
    ("thickening", 0.002, "largest thickening a step (m)"),
    ("new_length", 0.2, "length of a new module (m)"),
    ("new_radius", 0.002, "radius of a new module (m)"),
    ("branch_angle", math.radians(45.0), "angle of a lateral from its parent's axis (rad)"),
    ("threshold", 0.5, "hormone level that starts a module or a lateral"),
    ("inhibitor_transport", 0.5, "share of the children's inhibitor a module receives"),
    ("photosynthesis", 50.0, "g C per m2 of leaf (paper: of wall) a step at light 1"),
    ("half_saturation", 0.5, "light at which photosynthesis is half its largest (growsim)"),
    ("build_cost", 3e5, "g C per m3 of new wood"),
    ("upkeep", 150.0, "g C per m3 of wood a step (growsim)"),
    ("new_module_cost", 0.5, "g C to start a module beyond its wood and leaf (half to it)"),
    ("lignify", 0.1, "largest lignin gain a step"),
    ("greening", 0.05, "largest chlorophyll gain a step"),
    ("chlorophyll_loss", 1.0, "chlorophyll lost per unit of lignin gained"),
    ("drought", 0.5, "share of elongation, photosynthesis and transpiration the drought "
     "hormone can stop"),
    ("leaf_growth", 0.1, "largest new leaf area a step per m of shoot (m2/m, growsim)"),
    ("share", 0.5, "share of a parent-child nutrient difference evened out a step"),
    ("laterals", 2.0, "largest number of laterals per module"),
    ("leaf_cost", 30.0, "g C per m2 of new leaf (growsim)"),
    ("leaf_upkeep", 3.0, "g C per m2 of leaf a step (growsim)"),
    ("leaf_turnover", 0.05, "share of the leaf area shed a step (growsim)"),
    ("leaf_density", 0.3, "largest leaf area per m of shoot (m2/m, growsim)"),
    ("new_leaf", 0.01, "leaf area of a new module (m2, growsim)"),
    ("transpiration", 10.0, "kg of water per m2 of leaf a step at light 1 (growsim)"),
    ("huber", 1e-4, "sapwood area per leaf area above: the pipe model's radius (growsim)"),
    ("safety", 2.0, "strength over the stress thickening aims at (growsim)"),
    ("wind", 2.0, "drag of a breeze on the leaves, N per m2 of leaf (growsim)"),
    ("reserve", 2.0, "a seedling's nutrient, its seed's reserve (g C)"),
)  # fmt: skip

#: the genes: per hormone k, ``h{k}_bias``, ``h{k}_gain``, ``h{k}_decay`` and one weight
#: ``h{k}_w{j}`` per stimulus j (:data:`growsim.kernels.hormone.STIMULI`)
GENES = tuple(
    p
    for k in range(len(K.HORMONES))
    for p in (
        Param(f"h{k}_bias", -4.0, 4.0, 0.0, doc=f"{K.HORMONES[k]}: synthesis bias"),
        Param(f"h{k}_gain", 0.0, 1.0, 0.3, doc=f"{K.HORMONES[k]}: synthesis gain"),
        Param(f"h{k}_decay", 0.0, 1.0, 0.5, doc=f"{K.HORMONES[k]}: decay per step"),
        *(
            Param(f"h{k}_w{j}", -4.0, 4.0, 0.0, doc=f"{K.HORMONES[k]}: weight of {s}")
            for j, s in enumerate(K.STIMULI)
        ),
    )
)

PARAMS: tuple[Param, ...] = (
    SETTINGS + tuple(Param(n, 0.0, 1e6, d, doc=doc) for n, d, doc in CONSTANTS) + GENES
)


def _genes_demo() -> dict[str, float]:
    """A hand-set genome that grows a branching plant: elongation and meristem follow
    light, branching follows nutrient, lignification follows age (low chlorophyll)."""
    g = {}
    for k in range(len(K.HORMONES)):
        g[f"h{k}_gain"] = 1.0
        g[f"h{k}_decay"] = 0.5
    g.update({"h0_bias": 1.0, "h0_w0": -2.0})  # elongation: shade (turns to the light)
    g.update({"h1_bias": 1.0, "h1_w2": 2.0})  # thickening: nutrient
    g.update({"h2_bias": -2.0, "h2_w2": 3.0})  # branching: nutrient
    g.update({"h3_bias": -2.0, "h3_w0": 2.0, "h3_gain": 0.3})  # inhibitor: light
    g.update({"h4_bias": 1.0})  # meristem: always
    g.update({"h5_bias": -1.0, "h5_w3": -2.0, "h5_gain": 0.5})  # lignification
    g.update({"h6_bias": -2.0, "h6_w0": 2.0})  # greening: light
    g.update({"h7_bias": -3.0, "h7_w1": -3.0})  # drought: water
    g.update({"h8_bias": 0.0})  # turning
    g.update({"h9_bias": -1.0, "h9_w0": 1.0})  # expansion
    return g


#: the ``paper`` physics's tissue: the modules are green cell groups whose walls
#: photosynthesise (no leaves), so they are built at the cost of herbaceous tissue (about
#: 45 kg of carbon a cubic metre: 10 % dry matter at 45 % carbon) and thicken slowly
PAPER_TISSUE = {"physics": 1, "build_cost": 4.5e4, "thickening": 0.001}

#: presets: a hand-set genome in 2D and in 3D, in the ``growsim`` physics (``demo_*``) and
#: the ``paper`` physics (``paper_*``)
PRESETS = {
    "demo_2d": {"dims": 2, "steps": 30, **_genes_demo()},
    "demo_3d": {"dims": 3, "steps": 30, **_genes_demo()},
    "paper_2d": {"dims": 2, "steps": 30, **_genes_demo(), **PAPER_TISSUE},
    "paper_3d": {"dims": 3, "steps": 30, **_genes_demo(), **PAPER_TISSUE},
}

#: the environment each preset is shown in by ``growsim grow --preset`` (that of the
#: figure and counts of ``docs/models/hormone.md``, made by ``benchmarks/hormone_figures.py``:
#: the sun a little from the side, half the light from the sky, as in
#: ``experiments/hormone_3d.toml``; ``hormone_2d.toml``'s sun has no z part, where the 2D
#: demo grows 136 modules, not 140). Under the default light (the sun at the zenith, no
#: sky) the side walls see no light and the demo genome stays a stick of two modules.
PRESET_ENVIRONMENTS = {
    name: {"light": {"direction": [0.3, -1.0, 0.2], "diffuse": 0.5}, "water": {"supply": 1.0}}
    for name in ("demo_2d", "demo_3d", "paper_2d", "paper_3d")
}


def genes(params: Mapping[str, float]) -> np.ndarray:
    """The ``(10, 3 + 6)`` gene array of ``params`` (bias, gain, decay, weights per hormone).

    Examples
    --------
    >>> genes(resolve_params(PARAMS)).shape
    (10, 9)
    """
    H, J = len(K.HORMONES), len(K.STIMULI)
    out = np.empty((H, 3 + J))
    for k in range(H):
        out[k, 0] = params[f"h{k}_bias"]
        out[k, 1] = params[f"h{k}_gain"]
        out[k, 2] = params[f"h{k}_decay"]
        for j in range(J):
            out[k, 3 + j] = params[f"h{k}_w{j}"]
    return out


def environment_args(env) -> K.Surroundings:
    """The environment's settings as :func:`growsim.kernels.hormone.grow_step` takes them
    (:class:`growsim.kernels.hormone.Surroundings`): the light's passes
    (:meth:`growsim.env.Light.passes`), resolution, bias, soft shadows and transmission; the
    water's supply, soil, resistance and lift (scaled by ``g / 9.81``); the gravity's
    ``g``, wood density, leaf mass per area and wood strength; the ground's height;
    whether the walls share their module's exposure (``light.walls = "module"``).

    Raises :class:`growsim.errors.UserInputError` for the moderngl light backend (the
    model's step is one numba kernel, light included).

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = environment_args(Environment())
    >>> len(env), env.resolution == Environment().light.resolution, env.ground
    (18, True, 0.0)
    """

    light, water, gravity = env.light, env.water, env.gravity
    if light.backend != "numba":
        raise UserInputError(
            f"hormone: environment.light.backend = {light.backend!r} is not supported: the "
            "model's step runs in one numba kernel, light included; use 'numba'"
        )
    d, u, v, w = light.passes()
    return K.Surroundings(
        d, u, v, w, int(light.resolution), float(light.bias), light.shadows == "soft",
        float(light.transmission), float(water.supply), float(water.soil),
        float(water.resistance), float(water.lift) * float(gravity.g) / 9.81, float(gravity.g),
        float(gravity.density), float(gravity.leaf_mass_per_area), float(gravity.strength),
        float(env.ground.height),
        light.walls == "module",
    )  # fmt: skip


def grow(params: Mapping[str, float] | None = None, *, env=None) -> Iterator[Plant]:
    """Grow a plant step by step, yielding it after every step (see the module): one
    :func:`growsim.kernels.hormone.grow_step` per step. In a stand
    (``environment.stand.mode``): ``"periodic"`` grows it among its own copies
    (:func:`grow_periodic`), ``"explicit"`` grows the stand of copies and yields it
    (:func:`grow_stand`; its ``total_nutrient`` is the stand's), so :func:`develop` and
    the ``nutrient`` objective score the plant in its stand.

    Examples
    --------
    >>> plants = list(grow({**PRESETS["demo_2d"], "steps": 5}))
    >>> len(plants), plants[-1].n_segments >= plants[0].n_segments
    (5, True)
    """

    p = resolve_params(PARAMS, params, where="hormone.")
    env = env if env is not None else Environment()
    if env.stand.mode == "periodic":  # the plant among its own copies
        yield from grow_periodic(p, env=env)
        return
    if env.stand.mode == "explicit":  # a stand of copies: the stand is the phenotype
        yield from grow_stand(p, env=env)
        return
    if env.stand.mode == "mixture":  # no population to draw from: among its own copies
        yield from grow_mixture(p, None, env=env)
        return
    n, s = seedling(p, env)
    stopped = ""
    for step in range(int(p["steps"])):
        n, code = K.grow_step(n, *s.values())
        if code != K.STOP_NONE:
            stopped = K.STOPS[code]
        yield _plant(p, n, s["modules"], step + 1, stopped, s["env"])
        if code in STOPPING:
            return


def grow_stand(params=None, *, env=None, xz=None) -> Iterator[Plant]:
    """Grow an explicit stand step by step, yielding the stand (one :class:`Plant`, every
    plant's modules) after every step: copies of one genome (``params`` a mapping) or a
    plant of its own genome at each position (``params`` a sequence of mappings, one per
    position; they must agree on ``dims``, ``walls``, ``steps``, ``max_modules`` and
    ``physics``).

    The plants stand at ``xz`` ``(N, 2)`` (default: ``env.stand.xz()``, the
    ``[environment.stand]`` positions; ``[x, z]`` on the ground, ``z`` must be 0 in 2D). One
    module array holds them all (:func:`growsim.kernels.stand.new_stand`): every step they
    share one shadow map per light (each plant shades the others) and each root draws its
    own water; each plant grows at most ``max_modules`` modules. The stand's
    ``data["plant"]`` gives each module's plant; ``meta["stand"]`` the positions,
    ``meta["total_nutrient"]`` the stand's nutrient and ``meta["plant_nutrient"]`` each
    plant's. With one plant at the origin this is :func:`grow`, step for step.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})
    >>> xz = np.array([[-0.5, 0.0], [0.5, 0.0]])
    >>> stand = list(grow_stand({**PRESETS["demo_2d"], "steps": 5}, env=env, xz=xz))[-1]
    >>> sorted(set(stand.data["plant"].tolist())), stand.meta["stand"]
    ([0, 1], [[-0.5, 0.0], [0.5, 0.0]])
    """

    env = env if env is not None else Environment()
    xz = env.stand.xz() if xz is None else np.asarray(xz, dtype=np.float64).reshape(-1, 2)
    N = len(xz)
    each = params is not None and not isinstance(params, Mapping)
    plants = [resolve_params(PARAMS, q, where="hormone.") for q in params] if each else None
    if plants is not None and len(plants) != N:
        raise UserInputError(f"hormone.grow_stand: {len(plants)} genomes for {N} positions")
    p = plants[0] if plants else resolve_params(PARAMS, params, where="hormone.")
    for i, q in enumerate(plants or ()):
        for name in ("dims", "walls", "steps", "max_modules", "physics"):
            if q[name] != p[name]:
                raise UserInputError(
                    f"hormone.{name}: plant {i} has {q[name]:g}, plant 0 {p[name]:g}: the "
                    "plants of a stand grow with the same settings"
                )
    if int(p["dims"]) == 2 and np.any(xz[:, 1] != 0.0):
        raise UserInputError(
            "environment.stand.positions: a 2D plant grows in the x-y plane: every z must "
            "be 0 (use layout = 'row' or positions [[x, 0], ...])"
        )
    n, s = seedling({**p, "max_modules": int(p["max_modules"]) * N}, env)
    keys = ("genes", "c", "strength_young")
    if plants:  # a row of genes, constants and young strength per plant
        rows = [_rows(q) for q in plants]
        s.update({key: np.concatenate([r[i] for r in rows]) for i, key in enumerate(keys)})
    else:  # copies of one genome
        s.update({key: np.repeat(s[key], N, axis=0) for key in keys})
    n = KS.new_stand(s["modules"], s["c"], np.ascontiguousarray(xz), 0.0)
    stopped = ""
    for step in range(int(p["steps"])):
        n, code = K.grow_step(n, *s.values())
        if code != K.STOP_NONE:
            stopped = K.STOPS[code]
        yield _stand_plant(p, n, s["modules"], step + 1, stopped, s["env"], xz)
        if code in STOPPING:
            return


def grow_periodic(
    params: Mapping[str, float] | None = None, *, env=None, spacing=None, rings=None
) -> Iterator[Plant]:
    """Grow a plant in an endless monoculture of its own copies (periodic boundaries),
    yielding it after every step: each step the focal plant is shaded by its copies on a
    square lattice of ``spacing`` (default ``env.stand.spacing``; x-z plane in 3D, x in
    2D) within ``rings`` cells (default ``env.stand.rings``; 8 copies for one ring in
    3D), one shadow map per light (:func:`growsim.kernels.hormone.grow_step` with the
    copies' ``shifts``; each wall its own point). A plant
    wider than about ``2 rings + 1`` spacings misses the shade of copies further out.
    ``meta["spacing"]`` and ``meta["rings"]`` say how it was grown.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = Environment.model_validate(PRESET_ENVIRONMENTS["demo_3d"])
    >>> p = {**PRESETS["demo_3d"], "steps": 12}
    >>> dense = list(grow_periodic(p, env=env, spacing=0.5))[-1]
    >>> dense.meta["total_nutrient"] < develop(p, env=env).meta["total_nutrient"]
    True
    """

    p = resolve_params(PARAMS, params, where="hormone.")
    env = env if env is not None else Environment()
    spacing = float(env.stand.spacing if spacing is None else spacing)
    rings = int(env.stand.rings if rings is None else rings)
    shifts = KS.periodic_shifts(spacing, int(rings), int(p["dims"]))
    n, s = seedling(p, env)
    s["shifts"] = shifts
    stopped = ""
    for step in range(int(p["steps"])):
        n, code = K.grow_step(n, *s.values())
        if code != K.STOP_NONE:
            stopped = K.STOPS[code]
        plant = _plant(p, n, s["modules"], step + 1, stopped, s["env"])
        plant.meta.update(spacing=spacing, rings=int(rings))
        yield plant
        if code in STOPPING:
            return


def grow_mixture(params, neighbours=None, *, env=None) -> Iterator[Plant]:
    """Grow a plant among neighbours of other genomes (``environment.stand.mode =
    "mixture"``), yielding the focal plant after every step: the plant at the origin and
    ``neighbours`` (a sequence of ``env.stand.neighbours`` parameter mappings; None:
    copies of ``params``) on the lattice cells of ``env.stand.spacing`` nearest it
    (:meth:`growsim.env.stand.Stand.mixture_xz`), all grown together as one
    :func:`grow_stand`. The focal plant's ``meta["total_nutrient"]`` is its own nutrient
    (so the ``nutrient`` objective scores it among its neighbours);
    ``meta["neighbours_nutrient"]`` theirs, ``meta["stand"]`` the positions.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}, "stand": {
    ...     "mode": "mixture", "neighbours": 2, "spacing": 0.8}})
    >>> p = {**PRESETS["demo_2d"], "steps": 20, "max_modules": 80}
    >>> weak = {**p, "h0_gain": 0.0}  # a neighbour that does not elongate
    >>> *_, among_weak = grow_mixture(p, [weak, weak], env=env)
    >>> *_, among_copies = grow_mixture(p, None, env=env)
    >>> among_weak.meta["stand"][:2]
    [[0.0, 0.0], [-0.8, 0.0]]
    >>> among_weak.meta["total_nutrient"] > among_copies.meta["total_nutrient"]
    True
    """

    env = env if env is not None else Environment()
    p = resolve_params(PARAMS, params, where="hormone.")
    k = env.stand.neighbours
    neighbours = [p] * k if neighbours is None else list(neighbours)
    if len(neighbours) != k:
        raise UserInputError(
            f"environment.stand.neighbours = {k}: {len(neighbours)} neighbours given"
        )
    xz = env.stand.mixture_xz(int(p["dims"]))
    for stand in grow_stand([p, *neighbours], env=env, xz=xz):
        focal = stand.subset(stand.data["plant"] == 0)
        nutrient = stand.meta["plant_nutrient"]
        focal.meta.update(total_nutrient=float(nutrient[0]), neighbours_nutrient=nutrient[1:])
        focal.data.pop("plant")
        yield focal


def _stand_plant(p, n, modules, steps, stopped, env, xz) -> Plant:
    plant = _plant(p, n, modules, steps, stopped, env)
    N = len(xz)
    which = modules.plant[:n].copy()  # a module belongs to its parent's plant
    nutrient = np.bincount(which, weights=plant.data["nutrient"], minlength=N)
    data = {**plant.data, "plant": which}
    meta = {**plant.meta, "stand": xz.tolist(), "plant_nutrient": nutrient.tolist()}
    return Plant(plant.start, plant.end, plant.radius, plant.parent, plant.order, plant.kind,
                 data, meta)  # fmt: skip


def seedling(p: Mapping[str, float], env) -> tuple[int, dict]:
    """A new plant's state as :func:`growsim.kernels.hormone.grow_step` takes it: ``(n,
    state)``, ``n`` its module count (1) and ``state`` the rest of ``grow_step``'s
    arguments in their order (``dims``; ``modules``, the
    :class:`growsim.kernels.hormone.Modules` of the cap's length, updated in place by each
    step; the shadow maps' ``scratch``; ``genes``, constants ``c`` and ``strength_young``;
    ``env`` the environment's :func:`environment_args`), so that ``n, code =
    grow_step(n, *state.values())`` grows it a step. ``p`` are resolved parameters
    (:func:`growsim.models.base.resolve_params`).

    Examples
    --------
    >>> from growsim.env import Environment
    >>> n, state = seedling(resolve_params(PARAMS, PRESETS["demo_3d"]), Environment())
    >>> n, state["modules"].hormone.shape
    (1, (3000, 6, 10))
    """
    dims = int(p["dims"])
    walls = 2 if dims == 2 else int(p["walls"])
    cap = int(p["max_modules"])
    g, c, young = _rows(p)
    s = {
        "dims": dims,
        "modules": K.new_module_arrays(cap, walls, g.shape[1]),
        "scratch": shadow_scratch(int(env.light.resolution)),
        "genes": g,
        "c": c,
        "strength_young": young,
        "env": environment_args(env),
        "shifts": np.zeros((0, 3)),  # alone: no copies (a periodic stand's offsets)
    }
    n = K.new_plant(s["modules"], c[0])
    return n, s


def _rows(p):
    """A plant's rows of :func:`growsim.kernels.hormone.grow_step`'s per-plant arrays:
    genes ``(1, H, 3 + J)``, constants ``(1, N_CONSTANTS)`` (the physics last), young
    strength ``(1,)``."""
    c = np.array([[*(p[name] for name, _, _ in CONSTANTS), p["physics"]]])
    return genes(p)[None], c, np.array([float(p["strength_young"])])


def _plant(p, n, modules, steps, stopped, env) -> Plant:
    origin, R, length, radius = modules.origin, modules.R, modules.length, modules.radius
    nutrient = modules.nutrient
    start = origin[:n].copy()
    end = start + length[:n, None] * R[:n, :, 2]
    order = np.zeros(n, np.int32)
    return Plant(
        start,
        end,
        radius[:n].copy(),
        modules.parent[:n].copy(),
        order,
        np.zeros(n, np.int8),
        {
            "nutrient": nutrient[:n].copy(),
            "chlorophyll": modules.chlorophyll[:n].copy(),
            "lignin": modules.lignin[:n].copy(),
            "light": modules.light[:n].copy(),
            "water_met": modules.met[:n].copy(),
            "water": modules.water[:n].copy(),
            "leaf_area": modules.leaf[:n].copy(),
        },
        {
            "model": NAME,
            "params": dict(p),
            "physics": K.PHYSICS[int(p["physics"])],
            "steps": steps,
            "stopped": stopped,
            "breaks": int(modules.events[0]),
            "shed": int(modules.events[1]),
            "total_nutrient": float(K.total(nutrient, n)),
            "water_supply": float(env.supply * (env.soil if p["physics"] == K.GROWSIM else 1.0)),
            "ground": float(env.ground),
        },
    )


def leaves(plant: Plant) -> Plant:
    """The leaves of a hormone plant as the model draws them and weighs them: one blade
    (``kind`` leaf) along each module with leaves, from its start to its end, of radius
    ``leaf_area / (2 L)``, so that its area ``2 r L`` (the area the gravity pass weighs,
    :meth:`growsim.env.Gravity.loads`, and its shadow seen from the side) is the module's
    leaf area, the area that photosynthesises. In the shadow map a module is the union of
    its stem and this foliage cylinder (:func:`growsim.kernels.hormone.drawn_kernel`).

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = Environment.model_validate(PRESET_ENVIRONMENTS["demo_3d"])
    >>> plant = develop({**PRESETS["demo_3d"], "steps": 8}, env=env)
    >>> blades = leaves(plant)
    >>> bool(np.isclose((2 * blades.radius * blades.lengths()).sum(),
    ...                 plant.data["leaf_area"].sum()))
    True
    """
    A = np.asarray(plant.data["leaf_area"], dtype=np.float64)
    L = plant.lengths()
    keep = np.flatnonzero((A > 0) & (L > 0))
    return Plant(
        plant.start[keep], plant.end[keep], 0.5 * A[keep] / L[keep], np.full(len(keep), -1),
        np.zeros(len(keep), np.int32), np.ones(len(keep), np.int8),
        {"module": keep}, {"model": NAME},
    )  # fmt: skip


def population(params, names: Sequence[str], env=None) -> pd.DataFrame | None:
    """Grow every row of full parameters ``params`` ``(P, p)`` (columns ``names``, every
    parameter of :data:`PARAMS`) in ``env`` in one kernel call
    (:func:`growsim.kernels.hormone_population.grow_population`), keeping no plant: the population
    path of the ``nutrient`` objective. Returns a DataFrame with one row per plant:
    ``total_nutrient`` (as :func:`develop`'s ``meta``; NaN for a plant stopped by a NaN),
    ``modules``, ``stopped`` (``""``, ``"cap"``, ``"nan"``, ``"broken"``, ``"starved"``) and
    ``module_steps`` (modules alive summed over the steps), or ``None`` when the rows'
    settings (``dims``, ``walls``, ``steps``, ``max_modules``) differ or ``env`` has a
    stand (``environment.stand.mode`` not ``"alone"``: then each plant grows by
    :func:`grow`).

    Raises :class:`growsim.errors.UserInputError` for a missing column or a value out of
    its range (naming the parameter and row).

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})
    >>> row = resolve_params(PARAMS, {**PRESETS["demo_2d"], "steps": 10})
    >>> table = population(np.array([list(row.values())] * 2), list(row), env)
    >>> table.columns.tolist()
    ['total_nutrient', 'modules', 'stopped', 'module_steps']
    >>> bool(table.total_nutrient[0] == develop(row, env=env).meta["total_nutrient"])
    True
    """

    env = env if env is not None else Environment()
    if env.stand.mode != "alone":  # a stand: plant by plant (grow)
        return None
    x = np.atleast_2d(np.asarray(params, dtype=np.float64))
    col = {n: i for i, n in enumerate(names)}
    for q in PARAMS:
        if q.name not in col:
            raise UserInputError(f"hormone.population: no column {q.name!r}")
        v = x[:, col[q.name]]
        bad = ~((v >= q.low) & (v <= q.high))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise UserInputError(
                f"hormone.{q.name}: {v[i]!r} (row {i}) is out of range [{q.low:g}, {q.high:g}]"
            )
    settings = x[:, [col[q.name] for q in SETTINGS[:4]]]
    if len(x) and not (settings == settings[0]).all():
        return None
    dims, walls, steps, cap = (round(float(v)) for v in (settings[0] if len(x) else [2, 2, 0, 1]))
    walls = 2 if dims == 2 else walls
    H, J = len(K.HORMONES), len(K.STIMULI)
    gene_cols = [col[q.name] for q in GENES]
    g = np.ascontiguousarray(x[:, gene_cols].reshape(len(x), H, 3 + J))
    c = np.ascontiguousarray(x[:, [*(col[name] for name, _, _ in CONSTANTS), col["physics"]]])
    young = np.ascontiguousarray(x[:, col["strength_young"]])
    total, modules, stop, module_steps = KP.grow_population(
        g, c, young, dims, walls, steps, cap, environment_args(env)
    )
    return pd.DataFrame(
        {
            "total_nutrient": total,
            "modules": modules,
            "stopped": np.array(K.STOPS, dtype=object)[stop],
            "module_steps": module_steps,
        }
    )


def develop(params: Mapping[str, float] | None = None, *, seed=None, env=None) -> Plant:
    """The plant after its last step (or the step it broke at). ``seed`` is unused: the
    model is deterministic.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})  # side walls need sky
    >>> plant = develop(PRESETS["demo_3d"], env=env)
    >>> plant.n_segments > 10, plant.meta["stopped"] in ("", "cap", "broken")
    (True, True)
    """
    *_, last = grow(params, env=env)
    return last


class Hormone(Model):
    """The hormone-module model under the model contract (:func:`grow`, :func:`develop`).

    Examples
    --------
    >>> MODEL.stepwise, MODEL.phenotype
    (True, 'plant')
    """

    name = NAME
    phenotype = "plant"
    capabilities = frozenset({"population", "mixture", "grow_stand"})
    params = PARAMS
    presets = PRESETS
    preset_environments = PRESET_ENVIRONMENTS
    stepwise = True

    def develop(self, params=None, *, seed=None, env=None) -> Plant:
        """See :func:`develop`."""
        return develop(params, seed=seed, env=env)

    def grow(self, params, *, seed=None, env=None):
        """See :func:`grow`."""
        return grow(params, env=env)

    def population(self, params, names, seeds=None, env=None):
        """See :func:`population` (``seeds`` unused: the model is deterministic)."""
        return population(params, names, env)

    def mixture(self, params, neighbours, *, seed=None, env=None) -> Plant:
        """See :func:`grow_mixture` (the focal plant after its last step; ``seed``
        unused)."""
        *_, last = grow_mixture(params, neighbours, env=env)
        return last

    def grow_stand(self, params, *, seed=None, env=None) -> Iterator[Plant]:
        """See :func:`grow_stand` (the plants of ``env.stand`` grown together; ``seed``
        unused)."""
        return grow_stand(params, env=env)


#: The registered model (``growsim.models.MODELS["hormone"]``).
MODEL = Hormone()
