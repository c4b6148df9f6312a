"""Honda's nutrient-split tree (Endo's report, "C G による枝ぶり生成法", ATR TR-C-0067, 1991,
after Honda, Tomlinson & Fisher 1981).

Topology: every branching makes two children; the continuation keeps the parent's ration
per step, the lateral gets ``f`` times it; a tip accumulates its ration each step and
branches when the total reaches 1; the main trunk's tip branches every step. Geometry: the
report's absolute angles (theta from vertical, phi azimuth), droop ``thq`` for the branches of
the first two trunk nodes and their descendants, a straight-or-wandering trunk ``thr``.
See ``docs/models/honda.md``.

Random draws are continuous (``theta0 + U[0,1) * theta_max``) where the report used
integer ``random() % n`` degrees, so every real parameter value is meaningful to the GA.

Lengths (``bd``, ``b0``, ``b_max``, ``radius``, ``leaf_radius``) are in metres: the report
gives them no unit, and growsim reads them as metres, as the environment's gravity, light
and stands do (``docs/environment.md``, ``docs/models/stand.md``), so the presets are tall
trees (the zelkova 84 m).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping

import numpy as np

from growsim.env import Environment
from growsim.errors import ResourceError, UserInputError
from growsim.kernels.honda import (
    N_DRAWS,
    grow_kernel,
    leaves_kernel,
    sag_kernel,
    subtree_tips_kernel,
)
from growsim.models.base import Model, Param, resolve_params
from growsim.phenotypes.plant import LEAF, Plant
from growsim.phenotypes.stand import place

__all__ = [
    "MAX_SEGMENTS",
    "MODEL",
    "NAME",
    "PARAMS",
    "PRESETS",
    "SAG_MAX_BEND",
    "count_topology",
    "develop",
    "draws",
    "leaf_bearing",
    "mixture",
]

NAME = "honda"

#: Largest tree :func:`develop` agrees to grow (stem + leaf segments). About 200 bytes per
#: segment for the plant and its draws, ~1 GB of mesh at 8 sides: a safe ceiling on a
#: small machine. Raise it knowingly.
MAX_SEGMENTS = 4_000_000

#: bend (radians) of the most loaded branch at ``sag = 1``; bends add up along a path, so
#: a twig 10 levels out can droop several times this much (tuned by eye on the presets)
SAG_MAX_BEND = math.radians(12.0)

PARAMS: tuple[Param, ...] = (
    Param("generations", 1, 30, 10, kind="int", doc="nutrient steps (the report's class_cnt)"),
    Param("seed", 0, 2**31 - 1, 3, kind="int", doc="random seed (the report's set_rnd)"),
    Param("f", 0.0, 1.0, 0.95, doc="lateral ration: lateral gets f times its parent's"),
    Param("theta0", 0.0, 90.0, 10.0, doc="least angle from vertical", unit="deg"),
    Param("phi0", 0.0, 180.0, 0.0, doc="least azimuth turn from the parent", unit="deg"),
    Param("theta_max", 0.0, 90.0, 40.0, doc="random extra angle from vertical", unit="deg"),
    Param("phi_max", 0.0, 180.0, 90.0, doc="random extra azimuth turn", unit="deg"),
    Param("thq", 0.0, 1.0, 0.2, doc="droop added per level (first two trunk nodes' branches)"),
    Param("thr", 0.0, 1.0, 0.7, doc="main-trunk angle factor: 0 straight (cedar), 1 wandering"),
    Param("bd", 0.1, 100.0, 20.0, doc="length of the first trunk segment", unit="m"),
    Param("b0", 0.1, 50.0, 5.0, doc="least branch length", unit="m"),
    Param("b_max", 0.0, 50.0, 3.0, doc="random extra branch length", unit="m"),
    Param("radius", 0.01, 10.0, 1.0, doc="trunk base radius (the report's mesh a)", unit="m"),
    Param("taper", 0.3, 1.0, 0.85, doc="radius ratio per level (the report's mesh b)"),
    Param("pipe", 0, 1, 0, kind="int", doc="1: pipe-model radii (area ~ tips above) instead"),
    Param("leaves", 0, 8, 3, kind="int", doc="leaves per leaf-bearing branch (the report's d)"),
    Param("leaf_radius", 0.0, 10.0, 1.2, doc="leaf hexagon radius (the report's e)", unit="m"),
    Param("leaf_cut", 0.0, 80.0, 40.0, doc="prism cut angle: blade length 2e/cos", unit="deg"),
    Param("sag", 0.0, 1.0, 0.0, doc="beyond the report: bending under sub-tree weight (0 off)"),
    Param(
        "avoid", 0.0, 1.0, 0.0, doc="beyond the report: turn laterals away from crowding (0 off)"
    ),
)

_SPECIES = {
    # Table 2 of the report: class_cnt, set_rnd, f, theta0, phi0, theta_max, phi_max, thq,
    # thr, bd, b0, b_max. Columns e-h have no species name in the report; the names below
    # describe the shapes its Fig. 14 shows.
    "zelkova": (10, 3, 0.95, 10, 0, 40, 90, 0.2, 0.7, 20, 5, 3),
    "cherry": (10, 3, 0.99, 20, 0, 20, 90, 0.5, 0.6, 15, 5, 3),
    "ginkgo": (13, 4, 0.45, 25, 0, 25, 90, 0.5, 0.1, 10, 6, 2),
    "plane": (10, 3, 0.6, 30, 0, 30, 90, 0.6, 0.1, 15, 6, 2),
    "e_wandering_bush": (10, 3, 0.9, 20, 0, 10, 90, 0.1, 0.9, 2, 10, 5),
    "f_dome": (10, 2, 1.0, 40, 0, 40, 90, 0.2, 0.6, 3, 3, 6),
    "g_tall_trunk": (10, 3, 0.78, 40, 0, 10, 90, 0.1, 0.3, 30, 2, 3),
    "h_columnar": (10, 2, 0.2, 10, 0, 20, 90, 0.4, 0.1, 30, 5, 2),
}
_KEYS = ("generations", "seed", "f", "theta0", "phi0", "theta_max", "phi_max", "thq", "thr")
_KEYS += ("bd", "b0", "b_max")

#: The eight species of the report's Table 2, each a full parameter dict (with its seed).
PRESETS: dict[str, dict[str, float]] = {
    name: resolve_params(PARAMS, dict(zip(_KEYS, row))) for name, row in _SPECIES.items()
}


@functools.lru_cache(maxsize=4096)
def count_topology(f: float, generations: int) -> tuple[int, int]:
    """``(n_stem_segments, n_tips)`` of the tree grown with ``(f, generations)``, computed
    without growing it: tips are grouped by their state (accumulated, ration, main), which
    is all the topology depends on. Cheap for any ``generations``.

    Examples
    --------
    >>> count_topology(1.0, 10)        # the full binary tree of the report's Table 3, f
    (2047, 1024)
    >>> count_topology(0.95, 10)[0]    # zelkova
    125
    """
    f32 = np.float32(f)
    one = np.float32(1.0)
    # state: (acc, ration, is_main) -> number of tips in that state (float32 like the kernel)
    states: dict[tuple, int] = {(np.float32(0.0), one, True): 1}
    n_segments = 1
    for _ in range(int(generations)):
        nxt: dict[tuple, int] = {}
        for (acc, ration, is_main), count in states.items():
            if not is_main:
                acc = np.float32(acc + ration)
                if acc < one:
                    key = (acc, ration, False)
                    nxt[key] = nxt.get(key, 0) + count
                    continue
            cont = (np.float32(0.0), ration, is_main)
            lat = (np.float32(0.0), f32 if is_main else np.float32(ration * f32), False)
            for key in (cont, lat):
                nxt[key] = nxt.get(key, 0) + count
            n_segments += 2 * count
        states = nxt
    return n_segments, sum(states.values())


def leaf_bearing(parent: np.ndarray) -> np.ndarray:
    """``(n,)`` bool: the segments the seed puts leaves on, from the stem ``parent``
    ``(n,)`` int64 array: every tip, and every segment whose children are all tips.

    Examples
    --------
    >>> leaf_bearing(np.array([-1, 0, 0, 1, 1])).tolist()
    [False, True, True, True, True]
    """
    n = parent.shape[0]
    has = parent >= 0
    nchild = np.bincount(parent[has], minlength=n)
    tip = nchild == 0
    # children that are not tips, counted per parent
    nontip_child = np.bincount(parent[has & ~tip], minlength=n)
    return tip | ((nchild > 0) & (nontip_child == 0))


def _geo(p: Mapping[str, float]) -> np.ndarray:
    rad = math.pi / 180.0
    return np.array(
        [
            p["theta0"] * rad,
            p["theta_max"] * rad,
            p["phi0"] * rad,
            p["phi_max"] * rad,
            p["thq"],
            p["thr"],
            p["bd"],
            p["b0"],
            p["b_max"],
            p["avoid"],
        ]
    )


def _resolved(params: Mapping[str, float] | None, seed) -> dict:
    """Every parameter, checked, ``seed`` (when given) in place of ``params["seed"]``."""
    p = resolve_params(PARAMS, params, where="honda.")
    if seed is not None:
        p["seed"] = Param("seed", 0, 2**63 - 1, 0, kind="int").check(seed, "honda.")
    return p


def _seed_draws(p: Mapping[str, float], n_branch: int) -> np.ndarray:
    """The report's ``(n_branch, N_DRAWS)`` uniforms, one row per branching."""
    return np.random.default_rng(int(p["seed"])).random((n_branch, N_DRAWS))


def draws(params: Mapping[str, float] | None = None, *, seed=None) -> np.ndarray:
    """The random draws a tree grows with: ``(n_branchings, N_DRAWS)`` float64 uniforms in
    ``[0, 1)``, row ``b`` used by the ``b``-th branching in birth order, one column per
    draw (:data:`growsim.kernels.honda.N_DRAWS`: theta of the continuation and of the
    lateral, their fall-backs beyond 90 degrees, which child turns which way, the two
    azimuth turns, the two lengths, spares). What ``params["seed"]`` (or ``seed``) gives;
    :func:`develop`'s ``draws`` replaces them (the fit chooses the arrangement of a
    picture's branches this way: ``growsim.fitting.setups.arrange``).

    Examples
    --------
    >>> d = draws(PRESETS["zelkova"])
    >>> d.shape
    (62, 9)
    >>> bool((develop(PRESETS["zelkova"], draws=d).end == develop(PRESETS["zelkova"]).end).all())
    True
    """
    p = _resolved(params, seed)
    n_stems, _ = count_topology(p["f"], int(p["generations"]))
    return _seed_draws(p, (n_stems - 1) // 2)


def develop(params: Mapping[str, float] | None = None, *, seed=None, env=None, draws=None) -> Plant:
    """Grow one Honda tree.

    ``params``: any subset of :data:`PARAMS` (defaults fill the rest; values are checked).
    ``seed``: overrides ``params["seed"]`` when given. ``env`` is unused (the report's tree
    has no environment), except in a mixture (``environment.stand.mode = "mixture"``):
    then the tree among copies of itself, :func:`mixture`. ``draws``: optional
    ``(m, N_DRAWS)`` uniforms in ``[0, 1]`` replacing the report's draws of the first ``m``
    branchings (the arrangement of the branches: see :func:`draws`; rows beyond the tree's
    branchings are ignored; without it, the tree is the report's, bit for bit). Returns a
    :class:`growsim.phenotypes.plant.Plant` whose first
    ``n_stems`` segments are the stems in the report's vertex order (segment ``v - 1`` ends
    at vertex ``v``), followed by the leaves (``kind == LEAF``). ``data`` holds
    ``generation``, ``depth``, ``main`` (bool) and ``radius_end``.

    Raises :class:`growsim.errors.ResourceError` before growing when the tree would exceed
    :data:`MAX_SEGMENTS`, naming the count it would need.

    Examples
    --------
    >>> t = develop(PRESETS["zelkova"])
    >>> t.n_stems, t.n_tips, t.n_branch_points
    (125, 63, 62)
    >>> develop({"f": 1.0, "generations": 3}).n_stems
    15
    >>> d = draws(PRESETS["zelkova"])
    >>> d[0, 5] = 0.9  # the first node's branches turned further round the trunk
    >>> bool((develop(PRESETS["zelkova"], draws=d).end == develop(PRESETS["zelkova"]).end).all())
    False
    """
    if env is not None and env.stand.mode == "mixture":  # among copies of itself
        return mixture(params, None, seed=seed, env=env, draws=draws)
    p = _resolved(params, seed)
    gens = int(p["generations"])
    n_stems, n_tips = count_topology(p["f"], gens)
    n_leaf_max = int(p["leaves"]) * n_tips * 2  # tips and their parents at most
    if n_stems + n_leaf_max > MAX_SEGMENTS:
        raise ResourceError(
            f"honda: generations={gens} with f={p['f']:g} needs {n_stems:,} stem segments "
            f"(and up to {n_leaf_max:,} leaves); the limit is {MAX_SEGMENTS:,} segments "
            "(growsim.models.honda.MAX_SEGMENTS): lower generations or f"
        )
    n_branch = (n_stems - 1) // 2
    U = _seed_draws(p, n_branch)
    if draws is not None:
        U = _override(U, draws)
    pos, vpar, depth, order, gen, main, _theta, _phi = grow_kernel(
        float(p["f"]), gens, _geo(p), U, n_stems + 1
    )
    start = pos[vpar[1:]]
    end = pos[1:]
    order = order[1:]
    parent = vpar[1:] - 1  # vertex 1's parent (vertex 0) -> -1
    a = p["radius"]
    if int(p["pipe"]):
        # pipe model: a branch's cross-section is proportional to the tips it feeds
        tips_below = subtree_tips_kernel(parent)
        radius = a * np.sqrt(tips_below / tips_below[0])
        has = parent >= 0
        child_r = np.zeros(n_stems)
        np.maximum.at(child_r, parent[has], radius[has])
        r_end = np.where(child_r > 0, child_r, radius)
    else:
        # the report's: radius shrinks by `taper` per level from the ground
        radius = a * p["taper"] ** depth[vpar[1:]]
        r_end = a * p["taper"] ** depth[1:]
    if p["sag"] > 0.0:
        start, end = sag_kernel(start, end, radius, parent, p["sag"], SAG_MAX_BEND)
    data = {
        "generation": gen[1:].astype(np.int32),
        "depth": depth[1:].astype(np.int32),
        "main": main[1:],
        "radius_end": r_end,
    }
    kind = np.zeros(n_stems, np.int8)
    if int(p["leaves"]) > 0 and p["leaf_radius"] > 0.0:
        la, lb, lr, lpar = leaves_kernel(
            start, end, parent, int(p["leaves"]), p["leaf_radius"], math.radians(p["leaf_cut"])
        )
        m = la.shape[0]
        start = np.concatenate([start, la])
        end = np.concatenate([end, lb])
        radius = np.concatenate([radius, lr])
        parent = np.concatenate([parent, lpar])
        order = np.concatenate([order, order[lpar]])
        kind = np.concatenate([kind, np.full(m, LEAF, np.int8)])
        data = {
            "generation": np.concatenate([data["generation"], data["generation"][lpar]]),
            "depth": np.concatenate([data["depth"], data["depth"][lpar] + 1]),
            "main": np.concatenate([data["main"], np.zeros(m, bool)]),
            "radius_end": np.concatenate([data["radius_end"], lr]),
        }
    # every array comes from the kernels with its final dtype and shape (the tests
    # re-validate develop()'s output through Plant(...)), so skip the checks
    return Plant._unchecked(
        np.ascontiguousarray(start),
        np.ascontiguousarray(end),
        radius.astype(np.float64, copy=False),
        parent.astype(np.int64, copy=False),
        order.astype(np.int32, copy=False),
        kind,
        data,
        {"model": NAME, "params": p, "seed": int(p["seed"])},
    )


def _override(U: np.ndarray, given) -> np.ndarray:
    """``U`` with its first rows replaced by ``given`` (checked: ``(m, N_DRAWS)`` in
    ``[0, 1]``; a 1 is taken as the largest float below 1, as the report's draws are)."""
    given = np.asarray(given, dtype=np.float64)
    if given.ndim != 2 or given.shape[1] != N_DRAWS:
        raise UserInputError(
            f"honda: draws must be an (m, {N_DRAWS}) array, got shape {given.shape}"
        )
    if not np.all((given >= 0.0) & (given <= 1.0)):
        raise UserInputError("honda: draws must lie in [0, 1]")
    m = min(given.shape[0], U.shape[0])
    U = U.copy()
    U[:m] = np.minimum(given[:m], np.nextafter(1.0, 0.0))
    return U


def mixture(params, neighbours=None, *, seed=None, env=None, draws=None) -> Plant:
    """The tree of ``params`` in a mixture (``environment.stand.mode = "mixture"``): the
    focal tree at the origin, grown as :func:`develop` (``seed``, ``draws``), with
    ``neighbours`` (a sequence of ``env.stand.neighbours`` parameter mappings, each grown
    with its own ``seed`` parameter; None: copies of the focal tree) on the lattice cells
    of ``env.stand.spacing`` nearest it (:meth:`growsim.env.stand.Stand.mixture_xz`).
    Honda's trees do not grow by light, so each grows alone; they meet in the light
    objective's shadow map (:meth:`growsim.objectives.light.LightObjective.scored`).

    Returns the focal tree (its segments, its wood, the measures of a tree alone) with
    ``meta["stand"]`` the positions ``[x, z]`` (focal first) and ``meta["neighbours"]``
    the neighbours placed at their positions, one plant's arrays (``start``, ``end``,
    ``radius``, ``parent``, ``order``, ``kind`` and ``plant``, each segment's position
    index, 1 to ``k``): what :func:`growsim.objectives.light.mixture_stand` joins into the
    stand. A wrong number of neighbours raises :class:`growsim.errors.UserInputError`
    naming ``environment.stand.neighbours``.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> env = Environment.parse({"stand": {"mode": "mixture", "neighbours": 2,
    ...                                    "spacing": 30.0}})
    >>> t = mixture(PRESETS["zelkova"], [PRESETS["ginkgo"], PRESETS["plane"]], env=env)
    >>> t.n_stems, t.meta["stand"]
    (125, [[0.0, 0.0], [0.0, -30.0], [-30.0, 0.0]])
    >>> sorted(set(t.meta["neighbours"]["plant"].tolist()))
    [1, 2]
    """

    env = env if env is not None else Environment()
    focal = develop(params, seed=seed, draws=draws)  # alone: env plays no part in growth
    k = env.stand.neighbours
    if neighbours is None:
        others = [focal] * k
    else:
        neighbours = list(neighbours)
        if len(neighbours) != k:
            raise UserInputError(
                f"environment.stand.neighbours = {k}: {len(neighbours)} neighbours given"
            )
        others = [develop(nb) for nb in neighbours]
    xz = env.stand.mixture_xz(3)
    placed = place(others, xz[1:])  # the neighbours at positions 1 to k
    nb = {
        "start": placed.start, "end": placed.end, "radius": placed.radius,
        "parent": placed.parent, "order": placed.order, "kind": placed.kind,
        "plant": placed.data["plant"] + 1,
    }  # fmt: skip
    meta = {**focal.meta, "stand": xz.tolist(), "neighbours": nb}
    return Plant._unchecked(
        focal.start, focal.end, focal.radius, focal.parent, focal.order, focal.kind,
        focal.data, meta,
    )  # fmt: skip


class Honda(Model):
    """Honda's tree under the model contract (:class:`growsim.models.base.Model`):
    :data:`PARAMS`, :data:`PRESETS` and :func:`develop` of this module.

    Examples
    --------
    >>> MODEL.develop(MODEL.preset("zelkova")).n_stems
    125
    """

    name = NAME
    phenotype = "plant"
    capabilities = frozenset({"draws", "mixture"})
    params = PARAMS
    presets = PRESETS

    def develop(self, params=None, *, seed=None, env=None, draws=None) -> Plant:
        """See :func:`develop`."""
        return develop(params, seed=seed, env=env, draws=draws)

    def draws(self, params=None, *, seed=None) -> np.ndarray:
        """See :func:`draws` (a capability: ``growsim.fitting.setups.arrange`` fits them)."""
        return draws(params, seed=seed)

    def mixture(self, params, neighbours, *, seed=None, env=None, draws=None) -> Plant:
        """See :func:`mixture` (the focal tree with its neighbours attached)."""
        return mixture(params, neighbours, seed=seed, env=env, draws=draws)


#: The registered model (``growsim.models.MODELS["honda"]``).
MODEL = Honda()
