"""A developmental model grown into this tree: Honda's parameters
(:mod:`growsim.models.honda`) inferred from a reconstructed tree, so that ``growsim grow
honda --params model.json`` regrows "a tree of this kind".

What is matched (:func:`~growsim.reconstruction.stats.tree_summary`, measured alike on
both trees): the median branching angle, the median length ratio of a branch to its
parent, and the number of branches; then the height, by scaling every length. Honda's
angles are absolute (from the vertical) and its ratios emerge from the nutrient split
``f`` and the segments' lengths, so there is no closed form from the statistics to the
parameters: they are searched, deterministically for a seed. First :data:`SEARCH`
parameter sets drawn at random in the ranges of :data:`RANGES`, then :data:`REFINE`
steps of a local search about the best (each parameter moved by a Gaussian of a tenth of
its range, shrinking); the cost is ``|log(A'/A)| + 2 |log(R'/R)| + 0.02 |log(N'/N)| +
0.5 |log(W'/W)|`` (``A`` angle, ``R`` length ratio, ``N`` branches, ``W`` width over
height). The trunk's radius is the reconstruction's at its base, the other radii by
Honda's pipe model (``pipe = 1``, as the reconstruction's; ``taper``, unused then, its
median radius ratio clipped to Honda's range); a leafy tree gets Honda's leaves.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.models import honda
from growsim.phenotypes.plant import LEAF, STEM
from growsim.reconstruction.stats import tree_summary

__all__ = ["RANGES", "REFINE", "SEARCH", "infer_honda"]

#: the searched parameters and their ranges (``b_max`` and ``bd`` as multiples of ``b0``)
RANGES = {
    "f": (0.05, 1.0),
    "theta0": (0.0, 90.0),
    "theta_max": (0.0, 90.0),
    "phi0": (0.0, 180.0),
    "phi_max": (0.0, 180.0),
    "thq": (0.0, 0.6),
    "thr": (0.0, 1.0),
    "b_max": (0.0, 1.5),
    "bd": (0.2, 4.0),
    "generations": (8.0, 12.0),
}
#: random parameter sets, then local steps
SEARCH = 120
REFINE = 80


def _honda_params(x: dict, seed: int) -> dict:
    return {
        "f": x["f"],
        "theta0": x["theta0"],
        "theta_max": x["theta_max"],
        "phi0": x["phi0"],
        "phi_max": x["phi_max"],
        "thq": x["thq"],
        "thr": x["thr"],
        "b0": 1.0,
        "b_max": x["b_max"],
        "bd": x["bd"],
        "generations": round(x["generations"]),
        "seed": int(seed),
        "leaves": 0,
    }


def _cost(s: dict, target: dict) -> float:
    if not (np.isfinite(s["angle"]) and np.isfinite(s["length_ratio"])):
        return math.inf
    return (abs(math.log(max(s["angle"], 1e-6) / target["angle"]))
            + 2.0 * abs(math.log(max(s["length_ratio"], 1e-6) / target["length_ratio"]))
            + 0.02 * abs(math.log(max(s["branches"], 1) / max(target["branches"], 1)))
            + 0.5 * abs(math.log(max(s["width_to_height"], 1e-6)
                                 / max(target["width_to_height"], 1e-6))))  # fmt: skip


def infer_honda(plant, *, seed: int = 0) -> dict:
    """Honda parameters (every one of :data:`growsim.models.honda.PARAMS`, JSON-able) that
    regrow a tree with ``plant``'s branch statistics (module docstring): its median
    branching angle and length ratio, about its number of branches, its height and trunk
    radius. Deterministic for a seed.

    Examples
    --------
    >>> from growsim.models import honda
    >>> from growsim.reconstruction.stats import tree_summary
    >>> tree = honda.develop(honda.PRESETS["plane"])
    >>> p = infer_honda(tree)
    >>> a, b = tree_summary(tree), tree_summary(honda.develop(p))
    >>> abs(b["angle"] / a["angle"] - 1) < 0.15
    True
    >>> abs(b["length_ratio"] / a["length_ratio"] - 1) < 0.15
    True
    """
    target = tree_summary(plant)
    if not (np.isfinite(target["angle"]) and np.isfinite(target["length_ratio"])):
        target = {**target, "angle": 30.0, "length_ratio": 0.5}
    target["angle"] = max(target["angle"], 1.0)
    target["length_ratio"] = max(target["length_ratio"], 1e-3)
    rng = np.random.default_rng(seed)
    names = list(RANGES)
    lo = np.array([RANGES[k][0] for k in names])
    hi = np.array([RANGES[k][1] for k in names])

    def score(v):
        x = dict(zip(names, v))
        try:
            s = tree_summary(honda.develop(_honda_params(x, seed)))
        except Exception:  # a tree too large or degenerate: not a candidate
            return math.inf
        return _cost(s, target)

    best_v, best_c = None, math.inf
    for _ in range(SEARCH):
        v = lo + (hi - lo) * rng.random(len(names))
        c = score(v)
        if c < best_c:
            best_v, best_c = v, c
    step = 0.1
    for _ in range(REFINE):
        v = np.clip(best_v + step * (hi - lo) * rng.normal(size=len(names)), lo, hi)
        c = score(v)
        if c < best_c:
            best_v, best_c = v, c
        else:
            step = max(step * 0.97, 0.01)
    x = dict(zip(names, best_v))
    params = _honda_params(x, seed)
    grown = tree_summary(honda.develop(params))
    k = target["height"] / max(grown["height"], 1e-12)
    for name in ("b0", "b_max", "bd"):
        params[name] = float(params[name] * k)
    stem = plant.kind == STEM
    roots = np.flatnonzero((plant.parent < 0) & stem)
    r0 = float(plant.radius[roots[0]]) if roots.size else 0.1
    rr = target["radius_ratio"]
    params["radius"] = float(np.clip(r0, 0.01, 10.0))
    params["taper"] = float(np.clip(rr if np.isfinite(rr) else 0.85, 0.3, 1.0))
    params["pipe"] = 1  # radii by the pipe model, as the reconstruction's
    if np.any(plant.kind == LEAF):
        leaf = plant.kind == LEAF
        params["leaves"] = 3
        params["leaf_radius"] = float(np.clip(np.median(plant.radius[leaf]) * 2.0, 0.0, 10.0))
    out = honda.develop(params).meta["params"]
    ints = {q.name for q in honda.PARAMS if q.kind == "int"}
    return {k: round(v) if k in ints else float(v) for k, v in out.items()}
