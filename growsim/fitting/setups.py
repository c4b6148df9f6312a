"""Fitting a model to pictures of a tree: what ``growsim fit-image`` runs.

Every fittable model is one :class:`FitSetup` in :data:`FIT_SETUPS` (its config tables,
the parameters of its leaves and of a bare tree, the views it has, its restarts): adding a
model is adding an entry. :func:`fit_config` builds the experiment config of one fit (the
pictures as the silhouette objective's target), :func:`refine` refines a fit's best at
a finer raster size (coarse to fine), :func:`sweep_discrete` tries every value of its
discrete parameters and :func:`arrange` searches its branches' arrangement. The command
itself (the chain of sizes, bare and leafy fits, the files written) is
:func:`growsim.fitting.fit.fit_image`.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib.resources import files
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.fitting.options import LEAF_MODES
from growsim.ga.polish import PolishOptions, polish_steps
from growsim.models.ifs2d import FIT_N_MAPS, fit_tables
from growsim.registry import Registry

__all__ = [
    "ARRANGE_SIGMA",
    "BEST_SETUP",
    "FIT_OUTPUT",
    "FIT_SETUPS",
    "HONDA_EVOLVE",
    "HONDA_FIXED",
    "HONDA_GA",
    "LEAF_MARGIN",
    "LEAF_MODES",
    "PHOTO_SCORE",
    "SIZES",
    "FitSetup",
    "arrange",
    "best_setup",
    "exact_score",
    "fit_config",
    "refine",
    "search_score",
    "sweep_discrete",
]

#: The package data file holding the best ifs3d setup (how it was chosen:
#: benchmarks/log/reproduction-history.md): its ``[model]``, ``[ga]`` and ``[output]``
#: tables are what ``fit-image --model ifs3d`` runs; ``experiments/ifs_tree_best.toml`` is a
#: link to it.
BEST_SETUP = "ifs_tree_best.toml"

#: Honda parameters fitted to pictures (the rest come from the ``cherry`` preset; the
#: leaves are added by the setup, :data:`FIT_SETUPS`). The branches' radii follow the pipe
#: model (:data:`HONDA_FIXED`): only the trunk's is fitted.
HONDA_EVOLVE: dict = {
    "f": [0.5, 1.0],
    "theta0": True,
    "theta_max": True,
    "thq": True,
    "thr": True,
    "bd": [5.0, 40.0],
    "b0": [1.0, 12.0],
    "b_max": [0.0, 6.0],
    # how thick the trunk is drawn (photos show branches at their width)
    "radius": [0.05, 3.0],
}

#: Honda parameters fixed in a fit: pipe-model radii (a branch's cross-section in
#: proportion to the tips it feeds), so no branch is drawn as thick as the crown
HONDA_FIXED: dict = {"pipe": 1}

#: The silhouette objective's shape terms a photo's searches score with
#: (:func:`~growsim.objectives.silhouette.shape_score`): three pyramid levels, the fit's
#: area within 0.8x-1.15x of the picture's and its trunk's width within 0.8x-1.25x, the
#: crown's outline
PHOTO_SCORE: dict = {
    "scales": 3,
    "area_band": [0.8, 1.15],
    "trunk_band": [0.8, 1.25],
    "outline": True,
}

#: The ``[output]`` of a fit's runs: no meshes or screenshots (``fit-image`` writes the
#: kept fit's)
FIT_OUTPUT: dict = {"mesh": [], "screenshots": []}

#: Honda's GA: 60 generations of 100, then 1,500 evaluations of polish (7,500 in all).
HONDA_GA: dict = {
    "population": 100,
    "generations": 60,
    # the real-coded GA as it was before issue 15 changed the defaults (results kept)
    "model": "generational",
    "selection": "tournament",
    "selection_options": {"size": 4},
    "crossover": "sbx",
    "mutation": "polynomial",
    "polish": {"evaluations": 1500},
}

#: The raster sizes of the coarse-to-fine fit: the GA at the first, a refinement at each
#: next (``--sizes``).
SIZES = (64, 128, 256)


#: ``--leaves auto``: the leafy fit is kept only when its final NCC beats the bare fit's by
#: more than this (leaves are two more parameters and can stand in for thickness; a bare
#: tree's photo must not be fitted by a leafy blob)
LEAF_MARGIN = 0.01


def best_setup() -> dict:
    """The tables of the best ifs3d setup, ``growsim/data/ifs_tree_best.toml`` (a fresh
    dict on every call).

    Examples
    --------
    >>> setup = best_setup()
    >>> setup["ga"]["evaluations"], setup["ga"]["polish"]["evaluations"]
    (50000, 35000)
    """

    return tomllib.loads((files("growsim") / "data" / BEST_SETUP).read_text(encoding="utf-8"))


def __getattr__(name: str):
    # ``BEST_GA`` (used by benchmarks/ifs_fit.py): the best setup's [ga] table, read from
    # the data file when asked
    if name == "BEST_GA":
        return best_setup()["ga"]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@dataclass(frozen=True)
class FitSetup:
    """How ``fit-image`` fits one registered model.

    ``tables()``: fresh ``[model]``, ``[ga]`` and ``[output]`` tables (a dict with those
    keys) of the first, coarse stage; ``leaves``: the ``[model.evolve]`` entries of the
    model's leaves (count, size), evolved when the leaves are fitted; ``bare``: the
    ``[model.params]`` of a bare tree (no leaves), fitted beside the leafy one so a
    winter tree is fitted by a bare tree (``fit-image --leaves auto``); ``line_width``:
    how the fitted tree is drawn by default (``"radius"``: the branches at their
    thickness, as photos show them); ``views``: the views the model has (``("front",
    "side")`` for a 3D tree; a 2D model has only ``("front",)`` and takes one picture);
    ``refine``: evaluations of the local refinement at each finer size, and its step
    (``sigma``, unit box); ``restarts``: independent fits (GA seeds) of each kind of tree,
    the best kept at the final size (``--restarts``); ``carry``: how many of them, the
    best at the end of the first size, go on to the finer sizes (``--carry``; 0: all); ``arrange``:
    evaluations of the search for the arrangement of the branches (:func:`arrange`) at
    each size, for a model with the ``draws`` capability (``--arrange``; 0: the model's own random
    arrangement, as its seed gives it); ``blur``: the search's score at the first size is
    the NCC of views blurred by this sigma (pixels, scaled with the size; ``--blur``), the
    searches at the final size on the binary NCC (0: binary throughout); ``shape``: the
    file the fitted tree is written to in the results (a mesh, ``.glb``, ``.vtp``, ``.ply``
    or ``.obj``: :func:`growsim.phenotypes.plant.mesh.export`; or ``.png``: its front
    view's picture, for a model without a mesh); ``drawing``: the
    :func:`~growsim.fitting.fit.fit_image` keywords a drawing is fitted with, where the
    user gives none (``sizes``, ``restarts``, ``carry``, ``evaluations``, ``refine``,
    ``blur``; default: one size, 64 px, the seed's); ``evaluations``: of a photo's
    first stage (``None``: the tables' own budget); ``auto_leafy``: ``--leaves auto`` fits
    a leafy tree beside the bare one (``False``: the bare one alone; ``--leaves fit``
    still fits leaves); ``kinds``: the pictures ``--model
    auto`` fits this model to (``"photo"``, ``"drawing"``); ``score``: the silhouette
    objective's shape terms a photo's searches score with
    (:func:`~growsim.objectives.silhouette.shape_score`: ``scales``, ``area_band``; the
    stages report the binary NCC).

    Examples
    --------
    >>> setup = FIT_SETUPS["honda"]
    >>> setup.tables()["model"]["preset"], setup.line_width, setup.views
    ('cherry', 'radius', ('front', 'side'))
    >>> setup.shape, FIT_SETUPS["ifs2d"].shape
    ('tree.glb', 'attractor.png')
    """

    tables: Callable[[], dict]
    leaves: dict = field(default_factory=dict)
    bare: dict = field(default_factory=dict)
    line_width: str = "radius"
    views: tuple[str, ...] = ("front", "side")
    refine: int = 1000
    refine_sigma: float = 0.03
    restarts: int = 1
    carry: int = 0
    arrange: int = 0
    blur: float = 0.0
    shape: str = "tree.glb"
    drawing: dict = field(default_factory=lambda: {"sizes": (64,)})
    kinds: tuple[str, ...] = ("photo", "drawing")
    evaluations: int | None = None
    auto_leafy: bool = True
    score: dict = field(default_factory=dict)


def _ifs3d_tables() -> dict:
    setup = best_setup()
    return {"model": setup["model"], "ga": setup["ga"], "output": dict(FIT_OUTPUT)}


def _honda_tables() -> dict:
    return {
        "model": {
            "kind": "honda",
            "preset": "cherry",
            "evolve": dict(HONDA_EVOLVE),
            "params": dict(HONDA_FIXED),
        },
        "ga": {**HONDA_GA, "polish": dict(HONDA_GA["polish"])},
        "output": dict(FIT_OUTPUT),
    }


def _ifs2d_tables() -> dict:

    return fit_tables(FIT_N_MAPS)


#: model name -> its :class:`FitSetup`. ifs3d: the best setup of
#: ``experiments/ifs_tree_best.toml`` (its GA at 64 px: 50,000 evaluations, 70 % CMA-ES);
#: honda: the ``cherry`` preset's fixed values with :data:`HONDA_EVOLVE` evolved,
#: :data:`HONDA_GA`. Both also fit their leaves: how many per leaf-bearing branch (0: a
#: bare tree) and their size.
FIT_SETUPS: Registry[FitSetup] = Registry(
    "fit setup",
    {
        # a photo: 10,000 evaluations (the drawings' 50,000 cost 35 s with tubes drawn); a
        # bare tree only unless --leaves fit (a leafy IFS tree is 14x slower to draw; Honda
        # fits the leafy photos)
        "ifs3d": FitSetup(
            _ifs3d_tables,
            leaves={"leaves": True, "leaf_radius": [0.005, 0.1]},
            bare={"leaves": 0},
            refine=600,
            evaluations=10_000,
            auto_leafy=False,
            score=PHOTO_SCORE,
        ),
        # three GA seeds of each kind, the two best carried on (the GA at 64 px ends in
        # crowns of different quality by its seed; eight seeds of 2,000 arrangement
        # evaluations took 431 s a photo: three of 1,000 fit the minute and a half of
        # issue 27); pipe-model radii, the photo score (benchmarks/log/fitting.md)
        "honda": FitSetup(
            _honda_tables,
            leaves={"leaves": [1, 3], "leaf_radius": [0.3, 6.0]},
            bare={"leaves": 0},
            restarts=3,
            carry=2,
            arrange=1000,
            kinds=("photo",),
            score=PHOTO_SCORE,
        ),
        # a 2D IFS code fitted to one picture of an attractor (docs/models/ifs2d.md); no
        # mesh: its picture. A drawing at 64 px (the exact code of Bourke's tree scores 0.88
        # there with the fit's 20,000 points, 0.54 at 256 px: a point cloud's binary NCC
        # is bounded by its density, benchmarks/attractor_fit.py); six maps (fit_tables(6))
        # and half the tables' budget: the three classic attractors mean NCC 0.887 ->
        # 0.889 (Bourke's tree 0.863 -> 0.885), 126 -> 64 s a picture (load 7, 2 cores)
        "ifs2d": FitSetup(
            _ifs2d_tables,
            line_width="thin",
            views=("front",),
            shape="attractor.png",
            kinds=("drawing",),
            drawing={"sizes": (64,), "evaluations": 20_000},
        ),
    },
)


def fit_config(
    front,
    side=None,
    *,
    model: str = "ifs3d",
    size: int = 64,
    threshold="otsu",
    polarity: str = "auto",
    mask_front=None,
    mask_side=None,
    box_front=None,
    point_front=None,
    box_side=None,
    point_side=None,
    line_width: str | None = None,
    evaluations: int | None = None,
    seed: int = 0,
    segmentation: str = "photo",
    leaves: str | bool = "fit",
    blur: float = 0.0,
    score: dict | None = None,
) -> dict:
    """The experiment config (a dict for :func:`growsim.experiment.load_config`) of a fit's
    first stage (at ``size`` pixels).

    The model's :class:`FitSetup` (:data:`FIT_SETUPS`) gives the tables; ``leaves``:
    ``"fit"`` (or ``True``): its leaves' parameters are evolved too; ``"bare"``: a bare
    tree (the setup's ``bare`` parameters fixed); ``"keep"`` (or ``False``): the setup's
    own leaves, fixed (:data:`LEAF_MODES`). ``side = None``: one picture, the
    front view alone (the objective's ``views = "front"``). ``evaluations`` replaces the
    budget and keeps the polish's share of it (ifs3d: 70 %, honda: 20 %), with enough
    generations for the GA's share. ``line_width``: ``"thin"`` or ``"radius"``; ``None``,
    the setup's. ``segmentation``: ``"photo"`` or ``"threshold"`` (with ``threshold`` and
    ``polarity``); ``box_front``, ``point_front``, ``box_side``, ``point_side``: a photo's
    hints where the tree is (the silhouette objective's). ``blur``: the search's score is
    the NCC of views blurred by this sigma (pixels; the silhouette objective's ``blur``:
    partial credit for a branch near its place), 0 the binary NCC. ``score``: more
    options of the silhouette objective (its shape terms, ``scales`` and ``area_band``).
    Picture paths are made absolute, so the config runs from any directory.

    Examples
    --------
    >>> cfg = fit_config("front.png", "side.png")
    >>> cfg["model"]["kind"], cfg["ga"]["coding"], cfg["objective"][0]["kind"]
    ('ifs3d', 'real', 'silhouette')
    >>> ga = fit_config("front.png", "side.png", evaluations=10_000)["ga"]
    >>> ga["evaluations"], ga["polish"]["evaluations"]
    (10000, 7000)
    >>> fit_config("tree.jpg", model="honda")["objective"][0]["views"]
    'front'
    >>> fit_config("tree.jpg", model="honda", leaves="bare")["model"]["params"]
    {'pipe': 1, 'leaves': 0}
    """
    setup = FIT_SETUPS.get(model)
    if line_width is None:
        line_width = setup.line_width
    if line_width not in ("thin", "radius"):
        raise UserInputError(f"--line-width: expected thin or radius, got {line_width!r}")
    if side is not None and "side" not in setup.views:
        raise UserInputError(f"{side}: the {model} model has one view: give one picture")
    objective = {
        "kind": "silhouette",
        "front": str(Path(front).absolute()),
        "views": "both" if side is not None else "front",
        "size": int(size),
        "segmentation": segmentation,
        "line_width": line_width,
    }
    if blur > 0.0:
        objective["blur"] = float(blur)
    objective.update(score or {})
    if side is not None:
        objective["side"] = str(Path(side).absolute())
    if segmentation == "threshold":
        objective.update(threshold=threshold, polarity=polarity)
    elif threshold != "otsu" or polarity != "auto":
        raise UserInputError(
            "--threshold/--polarity: they apply to --segmentation threshold, not photo"
        )
    if mask_front is not None:
        objective["mask_front"] = str(Path(mask_front).absolute())
    if mask_side is not None:
        if side is None:
            raise UserInputError("--mask-side: there is no side picture")
        objective["mask_side"] = str(Path(mask_side).absolute())
    # a photo's hints, where the tree is (--box, --point; the side picture's)
    for key, value in (("box_front", box_front), ("point_front", point_front),
                       ("box_side", box_side), ("point_side", point_side)):  # fmt: skip
        if value is None:
            continue
        flag = "--" + key.replace("_front", "").replace("_", "-")
        if segmentation != "photo":
            raise UserInputError(f"{flag}: it applies to the photo segmentation, not the threshold")
        if key.endswith("side") and side is None:
            raise UserInputError(f"{flag}: there is no side picture")
        objective[key] = [float(v) for v in value]
    tables = setup.tables()
    model_cfg, ga, output = tables["model"], tables["ga"], tables["output"]
    leaves = {True: "fit", False: "keep"}.get(leaves, leaves)
    if leaves not in LEAF_MODES[1:]:
        raise UserInputError(f"--leaves: expected fit, bare or keep, got {leaves!r}")
    if leaves == "fit" and setup.leaves:
        model_cfg = dict(model_cfg, evolve={**model_cfg.get("evolve", {}), **setup.leaves})
    elif leaves == "bare" and setup.bare:
        evolve = {k: v for k, v in model_cfg.get("evolve", {}).items() if k not in setup.leaves}
        params = {**model_cfg.get("params", {}), **setup.bare}
        model_cfg = dict(model_cfg, evolve=evolve, params=params)
    if evaluations is not None:
        evaluations = int(evaluations)
        pol = ga.get("polish")
        polish = 0
        if pol is not None:
            # keep the setup's share of the budget for the polish
            if ga.get("evaluations"):
                share = pol["evaluations"] / ga["evaluations"]
            else:
                share = pol["evaluations"] / (
                    ga["generations"] * ga["population"] + pol["evaluations"]
                )
            polish = max(1, int(evaluations * share))
            ga["polish"] = dict(pol, evaluations=polish)
        ga["evaluations"] = evaluations
        # the evaluation budget stops the GA: enough generations for its share
        per_generation = ga["population"] * ga.get("islands", 1)
        needed = math.ceil((evaluations - polish) / per_generation) + 1
        ga["generations"] = max(int(ga.get("generations", 0)), needed)
    return {
        "experiment": {"name": f"fit-image-{model}", "seed": int(seed)},
        "model": model_cfg,
        "objective": [objective],
        "ga": ga,
        "output": output,
    }


def refine(
    plan, x0, *, evaluations: int, sigma: float = 0.03, seed: int = 0, draws=None, tick=None
):
    """Refine evolved parameters ``x0`` ``(p,)`` on ``plan`` (a compiled fit at a finer
    size): an elitist (1+lambda)-ES (:func:`growsim.ga.polish.polish_steps`) from ``x0``
    for ``evaluations`` fitness evaluations, step ``sigma`` in the unit box, every tree
    grown with the random ``draws`` when given (:func:`arrange`); ``tick(n)`` is called
    after every ``n`` evaluations (a progress bar). Never ends worse than it starts.
    Returns ``(x, fitness, start_fitness)``.

    Examples
    --------
    >>> from growsim.experiment import load_plan
    >>> cfg = {"model": {"kind": "honda", "preset": "cherry", "evolve": {"f": [0.5, 1.0]}},
    ...        "objective": [{"kind": "silhouette", "target_model": "honda",
    ...                       "target_preset": "zelkova", "size": 32}]}
    >>> x, score, start = refine(load_plan(cfg), np.array([0.6]), evaluations=40)
    >>> score >= start
    True
    """

    fitness = _Scorer(plan, draws)
    genome = plan.genome
    x0 = np.asarray(x0, dtype=np.float64)
    start = float(fitness(x0[None, :])[0])
    options = PolishOptions(evaluations=max(1, int(evaluations)), sigma=float(sigma))
    rng = np.random.default_rng(seed)
    steps = polish_steps(
        x0, start, genome.param_low, genome.param_high, genome.discrete, rng, options
    )
    best_x, best = x0, start
    try:
        step = next(steps)
        while True:
            scores = np.asarray(fitness(step.candidates), dtype=np.float64)
            scores = np.where(np.isfinite(scores), scores, -np.inf)
            if tick is not None:
                tick(len(scores))
            j = int(np.argmax(scores))
            if scores[j] > best:
                best_x, best = step.candidates[j].copy(), float(scores[j])
            step = steps.send(scores)
    except StopIteration:
        pass
    return best_x, best, start


#: :func:`sweep_discrete`: a discrete parameter with more values than this is left to the
#: other searches
SWEEP_MAX_VALUES = 32


def sweep_discrete(plan, x, draws=None, *, passes: int = 2):
    """Try every value of each discrete evolved parameter of ``x`` ``(k,)`` on ``plan`` (a
    compiled fit; an integer or a categorical of at most :data:`SWEEP_MAX_VALUES` values:
    Honda's leaves per branch), the others fixed, each tree grown with ``draws``
    (:func:`arrange`); keep the best value and go on to the next parameter, ``passes``
    rounds or until a round changes nothing. The GA and :func:`refine` cross an integer
    only by chance (a refinement's step of 0.03 of the unit box seldom leaves one), and a
    fit's other parameters adapt to a wrong count of leaves: a sweep finds the count the
    picture has (the plane's picture: 4 leaves, where the GA ended at 7). Never ends worse
    than it starts. Returns ``(x, fitness, start_fitness, evaluations)``.

    Examples
    --------
    >>> from growsim.experiment import load_plan
    >>> cfg = {"model": {"kind": "honda", "preset": "cherry", "evolve": {"leaves": True}},
    ...        "objective": [{"kind": "silhouette", "target_model": "honda",
    ...                       "target_preset": "cherry", "target_seed": 3, "size": 64}]}
    >>> plan = load_plan(cfg)     # the target: cherry's 3 leaves per branch
    >>> x, score, start, n = sweep_discrete(plan, np.array([7.0]))
    >>> x.tolist(), round(score, 6), score > start, n
    ([3.0], 1.0, True, 9)
    """
    scorer = _Scorer(plan, draws)
    genome = plan.genome
    x = np.asarray(x, dtype=np.float64).copy()
    best = start = float(scorer(x[None, :])[0])
    low, high = genome.param_low, genome.param_high
    genes = [j for j in np.flatnonzero(genome.discrete) if 1 <= high[j] - low[j] < SWEEP_MAX_VALUES]
    evaluations = 1
    for _ in range(passes if genes else 0):
        changed = False
        for j in genes:
            values = np.arange(low[j], high[j] + 1.0)
            values = values[values != x[j]]
            trials = np.repeat(x[None, :], len(values), axis=0)
            trials[:, j] = values
            scores = np.asarray(scorer(trials), dtype=np.float64)
            scores = np.where(np.isfinite(scores), scores, -np.inf)
            evaluations += len(values)
            i = int(np.argmax(scores))
            if scores[i] > best:
                x, best, changed = trials[i].copy(), float(scores[i]), True
        if not changed or len(genes) == 1:  # one parameter: a second round repeats the first
            break
    return x, best, start, evaluations


#: :func:`arrange`: the step of a draw's normal perturbation (the draws are uniforms in
#: ``[0, 1]``); half the moves perturb a branching's draws by it, half draw them anew
ARRANGE_SIGMA = 0.1


class _Scorer:
    """The fitness of a compiled fit (``plan.fitness()``: its objectives, weights and
    signs) for ``(n, k)`` evolved values, each tree grown with the random ``draws`` (``None``:
    the model's own, as the fit's GA grew it)."""

    def __init__(self, plan, draws=None):
        self.fitness = plan.fitness()
        self.draws = draws

    def params(self, x: np.ndarray) -> dict:
        """The ``{name: value}`` of every model parameter for evolved values ``x`` ``(k,)``."""
        return self.fitness.phenotype_of(x, grow=False).params

    def develop(self, x: np.ndarray, draws=None):
        """The phenotype of evolved values ``x`` ``(k,)`` with ``draws`` (default: this
        scorer's)."""
        draws = self.draws if draws is None else draws
        return self.fitness.phenotype_of(x, draws=draws).phenotype

    def exact(self, x: np.ndarray, draws=None) -> float:
        """The reported score of evolved values ``x`` ``(k,)``: each objective's ``exact``
        (the silhouette's binary NCC, whatever its ``blur``)."""
        f = self.fitness
        plant = self.develop(np.asarray(x, dtype=np.float64), draws)
        return float(
            sum(w * s * float(o.exact(plant)) for o, w, s in zip(f.objectives, f.weights, f.signs))
        )

    def score(self, phenotype) -> float:
        f = self.fitness
        return float(
            sum(w * s * float(o(phenotype)) for o, w, s in zip(f.objectives, f.weights, f.signs))
        )

    def __call__(self, x: np.ndarray) -> np.ndarray:
        if self.draws is None:
            return np.asarray(self.fitness(x), dtype=np.float64)
        x = np.atleast_2d(np.asarray(x, dtype=np.float64))
        return np.array([self.score(self.develop(row)) for row in x])


def arrange(
    plan, x, draws=None, *, evaluations: int, sigma: float = ARRANGE_SIGMA, seed=0, tick=None
):
    """Search the arrangement of the branches of the tree of evolved values ``x`` ``(k,)``
    on ``plan`` (a compiled fit): the random draws its model grows it with (a model with
    the capability ``draws(params) -> (m, d)`` uniforms, whose ``develop`` takes
    ``draws=``: Honda's azimuths, angles and lengths of every branching,
    :func:`growsim.models.honda.draws`), starting from ``draws`` (``None``: the model's
    own). An elitist (1+1) search for ``evaluations`` evaluations: each step changes one
    branching's draws (one row, picked uniformly: half the steps draw the row anew, half
    move it by a normal step ``sigma``, reflected into ``[0, 1]``) and keeps the change
    when the score is not worse, so a picture's limbs are placed where the picture has
    them, not where the model's seed put them. ``tick(n)``: called every 50 evaluations
    (a progress bar). Never ends worse than it starts.

    Returns ``(draws, fitness, start_fitness)``; ``draws`` is ``None`` when the model has no
    ``draws`` capability (nothing searched).

    Examples
    --------
    >>> from growsim.experiment import load_plan
    >>> cfg = {"model": {"kind": "honda", "preset": "zelkova", "evolve": {"f": [0.9, 1.0]},
    ...                  "params": {"generations": 6}},
    ...        "objective": [{"kind": "silhouette", "target_model": "honda",
    ...                       "target_preset": "zelkova", "size": 32}]}
    >>> d, score, start = arrange(load_plan(cfg), np.array([0.93]), evaluations=30)
    >>> d.shape[1], score >= start
    (9, True)
    """
    scorer = _Scorer(plan)
    x = np.asarray(x, dtype=np.float64)
    start = float(scorer(x[None, :])[0])
    model = scorer.fitness.model
    if "draws" not in model.capabilities:
        return None, start, start
    params = scorer.params(x)
    for n in plan.int_names:
        params[n] = round(params[n])
    own = np.asarray(model.draws(params), dtype=np.float64)
    current = own.copy() if draws is None else np.asarray(draws, dtype=np.float64).copy()
    if current.shape[0] < own.shape[0]:  # more branchings than given: the model's own
        current = np.concatenate([current, own[current.shape[0] :]])
    best = scorer.score(scorer.develop(x, current)) if draws is not None else start
    start = best
    rows = own.shape[0]
    rng = np.random.default_rng(seed)
    for i in range(int(evaluations) if rows else 0):
        if tick is not None and i % 50 == 49:
            tick(50)
        trial = current.copy()
        j = int(rng.integers(rows))
        if rng.random() < 0.5:
            trial[j] = rng.random(trial.shape[1])
        else:
            v = np.abs(trial[j] + sigma * rng.standard_normal(trial.shape[1]))
            trial[j] = np.where(v > 1.0, 2.0 - v, v)
        score = scorer.score(scorer.develop(x, trial))
        if score >= best:
            current, best = trial, score
    return current, best, start


def search_score(plan, x, draws=None) -> float:
    """The score the searches on ``plan`` maximise (the objectives' weighted fitness: the
    silhouette's shape score, blurred or not) of evolved values ``x`` ``(k,)``, the tree
    grown with ``draws`` (``None``: the model's own).

    Examples
    --------
    >>> from growsim.experiment import load_plan
    >>> cfg = {"model": {"kind": "honda", "preset": "zelkova", "evolve": {"f": [0.9, 1.0]}},
    ...        "objective": [{"kind": "silhouette", "target_model": "honda",
    ...                       "target_preset": "zelkova", "target_seed": 3, "size": 32,
    ...                       "scales": 3, "area_band": [0.8, 1.25]}]}
    >>> search_score(load_plan(cfg), np.array([0.95]))
    1.0
    """
    return float(_Scorer(plan, draws)(np.asarray(x, dtype=np.float64)[None, :])[0])


def exact_score(plan, x, draws=None) -> float:
    """The score to report of evolved values ``x`` ``(k,)`` on ``plan``, the tree grown
    with ``draws`` (:func:`arrange`; ``None``: the model's own): the objectives' exact
    scores (the silhouette's binary NCC, whatever its ``blur``), weighted.

    Examples
    --------
    >>> from growsim.experiment import load_plan
    >>> cfg = {"model": {"kind": "honda", "preset": "zelkova", "evolve": {"f": [0.9, 1.0]}},
    ...        "objective": [{"kind": "silhouette", "target_model": "honda",
    ...                       "target_preset": "zelkova", "target_seed": 3, "size": 32,
    ...                       "blur": 1.0}]}
    >>> plan = load_plan(cfg)
    >>> # the search's blurred score (anti-aliased lines against the binary target) and the
    >>> # binary NCC reported
    >>> bool(plan.fitness()([[0.95]])[0] < 1.0), exact_score(plan, np.array([0.95]))
    (True, 1.0)
    >>> exact_score(plan, np.array([1.0])) < 1.0
    True
    """
    return _Scorer(plan).exact(np.asarray(x, dtype=np.float64), draws)
