"""The stages of a fit, in order (:data:`~growsim.fitting.state.STAGES`), each a function
:func:`~growsim.fitting.fit.fit_image` calls with what the one before returned:

1. :func:`choose`: drawing or photo, reconstructed or searched, which models, each
   model's settings (:class:`Chosen`);
2. :func:`segment`: the silhouettes (each run's first plan compiled: a bad picture is
   refused here, before any evolution) and how each photo's tree was found (:class:`Segmented`);
3. :func:`reconstruct_or_search`: the kept fit: a photograph's tree reconstructed
   (:func:`reconstruct_tree`, :class:`Reconstructed`), or a model searched (:func:`search`:
   the runs at the first size, judged, the best carried on; :class:`Searched`);
4. :func:`grow`: the fitted tree grown from the kept values; a reconstruction's tree as
   reconstructed, and a Honda tree regrown from its statistics (:class:`Grown`);
5. :func:`judge`: the tree against the pictures: NCC per view, its views framed as the
   pictures, its area over theirs (:class:`Judged`);
6. :func:`write`: the tree, the pictures and ``fit.json`` into the fit's directory.

:class:`Runs` names the runs of a fit and makes each its job
(:class:`~growsim.fitting.runs.RunJob`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from growsim.experiment import load_plan
from growsim.fitting.choices import (
    candidates,
    fit_settings,
    kept_candidate,
    method_choice,
    picture_kind,
)
from growsim.fitting.options import FitOptions
from growsim.fitting.runs import FitRun, RunJob, run_job, run_jobs
from growsim.fitting.setups import FIT_SETUPS, search_score
from growsim.fitting.state import Decision, FitState
from growsim.kernels.views import ncc
from growsim.models import honda
from growsim.objectives.silhouette import phenotype_views
from growsim.pictures.images import (
    frame_silhouettes,
    photo_segmentations,
    unframe,
)
from growsim.reconstruction import (
    Reconstruction,
    infer_honda,
    reconstruct,
)
from growsim.reconstruction.judge import JUDGE_SIZE, front_view

__all__ = [
    "AUTO_ENOUGH",
    "KINDS",
    "Chosen",
    "Grown",
    "Judged",
    "Reconstructed",
    "Runs",
    "Searched",
    "Segmented",
    "choose",
    "grow",
    "judge",
    "reconstruct_or_search",
    "reconstruct_tree",
    "search",
    "segment",
]

#: each kind of tree (``leaves`` mode of one fit) as results name it
KINDS = {"fit": "leafy", "bare": "bare", "keep": "setup's"}

#: ``--model auto`` on a drawing: a model whose fit matches it this well at the first size
#: (binary NCC) ends the search, the next models are not fitted (none can do much better)
AUTO_ENOUGH = 0.95

#: the options of a fit that each model's settings take
#: (:func:`~growsim.fitting.choices.fit_settings`)
_SETTINGS = ("line_width", "sizes", "size", "leaves", "evaluations", "refine", "arrange",
             "blur", "restarts", "carry")  # fmt: skip


@dataclass
class Chosen:
    """What :func:`choose` chose: whether the pictures are drawings (``drawing``), the
    ``segmentation`` and ``model`` choices (``{"value", "why"}``), the candidate models
    ``names``, each model's ``settings`` (:func:`~growsim.fitting.choices.fit_settings`)
    and the ``runs`` fitted at the first size (model, leaves mode, seed); ``method``: the
    tree reconstructed or searched (:func:`~growsim.fitting.choices.method_choice`)."""

    drawing: bool
    segmentation: dict
    model: dict
    names: list[str]
    settings: dict[str, dict]
    runs: list[tuple[str, str, int]]
    method: dict = field(default_factory=lambda: {"value": "search", "why": "given"})


def choose(options: FitOptions) -> Chosen:
    """The first stage: drawing or photo (:func:`~growsim.fitting.choices.picture_kind`,
    the pictures read), reconstructed or searched
    (:func:`~growsim.fitting.choices.method_choice`), which models
    (:func:`~growsim.fitting.choices.candidates`), each model's settings, and the runs:
    every model, kind of tree and restart. Bad settings and unknown models raise
    :class:`~growsim.errors.UserInputError`.

    Examples
    --------
    >>> c = choose(FitOptions(front="tree.jpg", model="honda", restarts=2))  # doctest: +SKIP
    >>> c.drawing, c.names, c.runs[:2], c.method["value"]  # doctest: +SKIP
    (False, ['honda'], [('honda', 'bare', 0), ('honda', 'bare', 1)], 'search')
    """
    if options.model != "auto":
        FIT_SETUPS.get(options.model)  # an unknown name is refused before the pictures
    drawing, segmentation = picture_kind(options.front, options.side, options.segmentation)
    method = method_choice(options, drawing)
    names, model = candidates(options.model, drawing, options.side)
    given = {k: getattr(options, k) for k in _SETTINGS}
    settings = {m: fit_settings(m, drawing, given, options.budget) for m in names}
    runs = [(m, mode, options.seed + r) for m in names for mode in settings[m]["modes"]
            for r in range(settings[m]["restarts"])]  # fmt: skip
    return Chosen(drawing, segmentation, model, names, settings, runs, method)


@dataclass(frozen=True)
class Runs:
    """The runs of one fit and where they go: each run's directory (:meth:`name`; the fit's
    ``out_dir`` itself when there is one run), its label in progress bars and ``fit.json``
    (:meth:`label`) and its job (:meth:`job`). ``resume``: the fit goes on from its state;
    ``workers``: local processes; ``progress``: progress bars.

    Examples
    --------
    >>> from growsim.fitting.choices import fit_settings
    >>> st = fit_settings("honda", False, {"restarts": 2}, 1.0)
    >>> c = Chosen(False, {}, {}, ["honda"], {"honda": st},
    ...            [("honda", m, s) for m in ("bare", "fit") for s in (0, 1)])
    >>> runs = Runs(FitOptions(front="tree.jpg"), c, {}, Path("fit"))
    >>> runs.name(("honda", "fit", 1)), runs.label(("honda", "fit", 1))
    ('leafy-1', 'honda leafy seed 1')
    >>> runs.job(("honda", "bare", 0), 0).out
    PosixPath('fit/bare-0')
    """

    options: FitOptions
    chosen: Chosen
    pictures: dict
    out_dir: Path
    resume: bool = False
    workers: int | None = None
    progress: bool = False

    def name(self, r) -> str:
        """The directory name of run ``r`` (model, leaves mode, seed)."""
        m, mode, s = r
        name = KINDS[mode] if mode != "keep" else "run"
        if len(self.chosen.names) > 1:
            name = f"{m}-{name}"
        return name + (f"-{s}" if self.chosen.settings[m]["restarts"] > 1 else "")

    def label(self, r) -> str:
        """How progress bars and ``fit.json`` name run ``r``."""
        m, mode, s = r
        kind = "" if mode == "keep" else f" {KINDS[mode]}"
        return f"{m}{kind}" + (f" seed {s}" if self.chosen.settings[m]["restarts"] > 1 else "")

    def job(self, r, last: int, again: bool | None = None) -> RunJob:
        """Run ``r`` as a job up to its size index ``last`` (``again``: go on from its saved
        state; ``None``: when the fit is resumed); a single run's GA takes the workers."""
        one = len(self.chosen.runs) == 1
        return RunJob(self.options.front, self.options.side, *r, self.chosen.settings[r[0]],
                      self.pictures, self.out_dir if one else self.out_dir / self.name(r), last,
                      self.resume if again is None else again, self.workers if one else None,
                      self.label(r) if self.progress else None)  # fmt: skip


@dataclass
class Segmented:
    """What :func:`segment` made of the pictures: each run's ``first`` plan (compiled at
    the first size: its objective holds the silhouettes) and ``found``, each photo's
    :class:`~growsim.pictures.photo.Segmentation` by view (``{}`` for a drawing)."""

    first: dict
    found: dict


def segment(runs: Runs) -> Segmented:
    """The silhouettes: each run's plan at the first size compiled (its objective reads and
    segments the pictures: a bad picture is refused here, naming it, before any
    evolution; a reconstruction compiles one run's alone, Honda's if it has one), and how
    each photo's tree was found, as the objectives read it (a
    picture's segmentation is remembered: not segmented twice).

    Examples
    --------
    >>> s = segment(runs)  # doctest: +SKIP
    >>> s.found["front"].record()["method"]  # doctest: +SKIP
    'sky and skyline'
    """
    st = runs.chosen.settings
    compiled = runs.chosen.runs
    if runs.chosen.method["value"] == "reconstruct":  # one plan: Honda's, as best.json's
        compiled = [r for r in compiled if r[0] == "honda"][:1] or compiled[:1]
    first = {r: load_plan(runs.job(r, 0).config(st[r[0]]["sizes"][0], st[r[0]]["blur"]))
             for r in compiled}  # fmt: skip
    found = {}
    if runs.pictures["segmentation"] == "photo":
        objective = next(iter(first.values())).objectives[0]
        keys = ("mask_front", "mask_side", "box_front", "point_front", "box_side", "point_side")
        side = runs.options.side if objective.n_views > 1 else None
        segs = photo_segmentations(runs.options.front, side, segmentation="photo",
                                   **{k: runs.pictures[k] for k in keys})  # fmt: skip
        found = dict(zip(("front", "side"), segs))
    return Segmented(first, found)


@dataclass
class Searched:
    """The kept fit of :func:`reconstruct_or_search`: its ``model`` and leaves ``mode``, its
    ``run`` (:class:`~growsim.fitting.runs.FitRun`: plan at the final size, values, draws,
    stages); ``fits``: every run's fit; ``carried``: the runs taken past the first size;
    ``judged``: the best of each model and kind, judged at the final size;
    ``first_size``: every run's scores at the first size; ``names``: the models fitted;
    ``model_choice``: the model choice, with what ended the search; ``state``: the fit's
    state after it (:class:`~growsim.fitting.state.FitState`, the decision kept)."""

    model: str
    mode: str
    run: FitRun
    fits: dict
    carried: list[tuple[str, str, int]]
    judged: dict[tuple[str, str], float]
    first_size: dict[str, dict]
    names: list[str]
    model_choice: dict
    state: FitState


@dataclass
class Reconstructed:
    """The kept fit of :func:`reconstruct_tree`: the tree the photograph shows (``rec``, a
    :class:`~growsim.reconstruction.Reconstruction`), reconstructed from the silhouettes
    ``masks`` (by view, at the pictures' working size) in ``seconds``; ``plan``: the plan
    :func:`segment` compiled (its objective holds the silhouettes; its config, Honda's fit
    when the picture's kind has one, is the fit's ``config.toml``); ``state``: the fit's
    state."""

    rec: Reconstruction
    masks: dict[str, np.ndarray]
    plan: Any
    seconds: float
    state: FitState


def reconstruct_or_search(runs: Runs, segmented: Segmented,
                          state: FitState) -> Searched | Reconstructed:  # fmt: skip
    """The third stage: the kept fit, by the fit's ``method`` (``runs.chosen.method``,
    :func:`~growsim.fitting.choices.method_choice`): the tree the photograph shows
    reconstructed (:func:`reconstruct_tree`), or a model's parameters searched
    (:func:`search`; a drawing's always, unless told otherwise).

    Examples
    --------
    >>> found = reconstruct_or_search(runs, segment(runs), state)  # doctest: +SKIP
    >>> type(found).__name__, found.rec.method  # doctest: +SKIP
    ('Reconstructed', 'skeleton + space colonization')
    """
    if runs.chosen.method["value"] == "reconstruct":
        return reconstruct_tree(runs, segmented, state)
    return search(runs, segmented, state)


def reconstruct_tree(runs: Runs, segmented: Segmented, state: FitState) -> Reconstructed:
    """The tree of the silhouettes (front, and side when the fit has one) reconstructed
    (:func:`~growsim.reconstruction.reconstruct`: the visible skeleton, lifted into 3D by
    the side picture or a stated prior, twigs and leaves grown into a leafy crown), for
    the fit's seed. Fast (seconds): a resumed fit reconstructs it again, to the same tree.

    Examples
    --------
    >>> found = reconstruct_tree(runs, segment(runs), state)  # doctest: +SKIP
    >>> sorted(found.masks), found.rec.plant.n_segments > 0  # doctest: +SKIP
    (['front'], True)
    """
    plan = next(iter(segmented.first.values()))
    objective = plan.objectives[0]
    views = list(objective.pictures)[: objective.n_views]
    masks = {v: np.asarray(objective.pictures[v], bool) for v in views}
    t0 = time.perf_counter()
    rec = reconstruct(masks["front"], masks.get("side"), seed=runs.options.seed)
    return Reconstructed(rec, masks, plan, time.perf_counter() - t0, state)


def search(runs: Runs, segmented: Segmented, state: FitState) -> Searched:
    """Every run fitted at the first size (a drawing's one after the other, a model that
    matches it (:data:`AUTO_ENOUGH`) ending the search; a photo's side by side), judged
    (:func:`_decide`, kept in the fit's ``state``, so a resumed fit carries the same runs
    on), the carried runs refined through the finer sizes, the best kept.

    Examples
    --------
    >>> found = search(runs, segment(runs), state)  # doctest: +SKIP
    >>> [s["stage"] for s in found.run.stages]  # doctest: +SKIP
    ['ga', 'arrange', 'refine', 'arrange']
    """
    chosen, first = runs.chosen, segmented.first
    names, model_choice = list(chosen.names), dict(chosen.model)
    fits: dict[tuple[str, str, int], FitRun] = {}
    if chosen.drawing:
        # one after the other: a model that matched the drawing ends the search
        enough = None
        for r in chosen.runs:
            if enough is not None and r[0] != enough:
                continue
            fits[r] = run_job(runs.job(r, 0), first[r])
            if len(names) > 1 and fits[r].ncc >= AUTO_ENOUGH:
                enough = r[0]
        if enough is not None:
            names = [m for m in names if any(r[0] == m for r in fits)]
            model_choice["why"] += (f"; {enough}'s fit matched the drawing (NCC >= "
                                    f"{AUTO_ENOUGH}), the next models were not fitted")  # fmt: skip
    else:
        # a photo's runs side by side on the cores (the same runs on any number)
        processes = 1 if len(chosen.runs) == 1 else runs.workers
        sizes = chosen.settings[chosen.runs[0][0]]["sizes"]
        label = f"fits at {sizes[0]} px" if runs.progress else None
        fits = dict(zip(chosen.runs, run_jobs([runs.job(r, 0) for r in chosen.runs],
                                              processes, label)))  # fmt: skip
    # every fit at the end of the first size; the best of each model and kind of tree,
    # judged at its model's final size (finer: a blob that passes at 64 px shows there)
    decided = state.decided if runs.resume else None
    if decided is None:
        decided = Decision.model_validate(_decide(fits, runs, names))
        state = state.updated(decided=decided)
        state.write(runs.out_dir)
    decided = decided.model_dump()
    kept_model, mode = decided["kept"]
    carried = [tuple(r) for r in decided["carried"]]
    st = chosen.settings[kept_model]
    if len(st["sizes"]) > 1:
        label = f"fits at {', '.join(map(str, st['sizes'][1:]))} px" if runs.progress else None
        jobs = [runs.job(r, len(st["sizes"]) - 1, True) for r in carried]
        processes = 1 if chosen.drawing or len(chosen.runs) == 1 else runs.workers
        fits.update(zip(carried, run_jobs(jobs, processes, label)))
    return Searched(
        model=kept_model,
        mode=mode,
        run=fits[max(carried, key=lambda r: fits[r].score)],
        fits=fits,
        carried=carried,
        judged={tuple(k.split("/")): v for k, v in decided["judged"].items()},
        first_size=decided["first_size"],
        names=names,
        model_choice=model_choice,
        state=state,
    )


def _decide(fits, runs: Runs, names) -> dict:
    """What the fits at the first size decide: each fit's scores there (``first_size``),
    the best of each model and kind of tree judged at its model's final size
    (``judged``), the ``kept`` model and kind, and the runs ``carried`` to the finer sizes
    (the restarts of the kept kind that scored best at the first size: the score there
    foretells the final one, benchmarks/log/fitting.md)."""

    settings = runs.chosen.settings
    first_size = {runs.label(r): {"ncc": f.ncc, "score": f.score} for r, f in fits.items()}
    best_of: dict[tuple[str, str], tuple] = {}
    for r, f in fits.items():
        if r[:2] not in best_of or f.score > fits[best_of[r[:2]]].score:
            best_of[r[:2]] = r
    judged: dict[tuple[str, str], float] = {}
    for key, r in best_of.items():
        last = settings[r[0]]["sizes"][-1]
        if len(best_of) == 1 or last == settings[r[0]]["sizes"][0]:
            judged[key] = fits[r].score
        else:
            judged[key] = search_score(load_plan(runs.job(r, 0).config(last)), fits[r].x,
                                       fits[r].draws)  # fmt: skip
    kept = kept_candidate(judged, names)
    ranked = sorted((r for r in runs.chosen.runs if r[:2] == kept), key=lambda r: -fits[r].score)
    return {
        "first_size": first_size,
        "judged": {"/".join(k): v for k, v in judged.items()},
        "kept": list(kept),
        "carried": ranked[: settings[kept[0]]["carry"] or len(ranked)],
    }


@dataclass
class Grown:
    """The fitted tree of :func:`grow`: its ``phenotype`` (a
    :class:`~growsim.phenotypes.plant.Plant`, or a 2D model's), every model parameter
    ``params`` (integer parameters as ints), and the ``plan``, values ``x`` and ``draws``
    that grew it. A reconstruction's: its tree as reconstructed, ``params`` Honda's
    inferred from it (:func:`~growsim.reconstruction.infer_honda`), ``regrown`` the Honda
    tree they grow, ``size`` the raster size it is judged at (:data:`JUDGE_SIZE`; ``None``:
    its plan's), ``rec`` the reconstruction (its front drawn where the picture shows it)."""

    phenotype: Any
    params: dict[str, float]
    plan: Any
    x: np.ndarray
    draws: np.ndarray | None
    regrown: Any = None
    size: int | None = None
    rec: Any = None


def grow(found: Searched | Reconstructed) -> Grown:
    """The fitted tree, grown as the searches grew it (from the kept values, with the
    fitted arrangement of its branches); a reconstruction's as reconstructed, with the
    Honda parameters inferred from it (a model grown into this tree) and the tree they
    regrow.

    Examples
    --------
    >>> tree = grow(found)  # doctest: +SKIP
    >>> sorted(tree.params)[:2]  # doctest: +SKIP
    ['a_1', 'a_2']
    """
    if isinstance(found, Reconstructed):
        params = infer_honda(found.rec.plant, seed=found.state.options.seed)
        return Grown(found.rec.plant, params, found.plan, np.empty(0), None,
                     regrown=honda.develop(params), size=JUDGE_SIZE, rec=found.rec)  # fmt: skip
    plan, x, draws = found.run.plan, found.run.x, found.run.draws
    tree = plan.fitness().phenotype_of(x, draws=draws)
    params = {n: round(v) if n in plan.int_names else v for n, v in tree.params.items()}
    return Grown(tree.phenotype, params, plan, x, draws)


@dataclass
class Judged:
    """The fitted tree against the pictures (:func:`judge`): the NCC of each ``view`` at
    the fit's size, its views there (``fitted``), its views framed as the pictures
    (``framed``, by view: same size and placement as the silhouettes used) and its area
    over the picture's tree there (``areas``); ``target``: the silhouettes at the size
    judged (``None``: the plan's objective's)."""

    views: list[float]
    fitted: np.ndarray
    framed: dict[str, np.ndarray] = field(default_factory=dict)
    areas: dict[str, float] = field(default_factory=dict)
    target: np.ndarray | None = None


def judge(tree: Grown) -> Judged:
    """The fitted tree judged against the pictures: each view's NCC at the fit's size, its
    views framed as the pictures (:func:`~growsim.pictures.images.unframe`) and its area
    over the picture's tree in each. Branches drawn at their width are drawn again at the
    picture's resolution (a raster as large as the picture, at most 1024 px), so a thin
    branch is as thin as the picture's; thin lines take the fit's size's views, which frame
    exactly.

    Examples
    --------
    >>> j = judge(grow(found))  # doctest: +SKIP
    >>> sorted(j.framed), round(j.areas["front"], 2)  # doctest: +SKIP
    (['front'], 0.97)
    """
    objective = tree.plan.objectives[0]
    masks = list(objective.pictures.values())[: objective.n_views]
    target, line_width = None, objective.line_width
    side = masks[1] if len(masks) > 1 else None
    if tree.size is None:
        views = objective.view_scores(tree.phenotype)
        fitted = phenotype_views(tree.phenotype, objective.size, line_width,
                                 views=objective.n_views)  # fmt: skip
    else:  # a reconstruction: binary NCC at its size, branches at their width, the front
        # drawn where the picture shows it
        line_width = "radius"
        target = frame_silhouettes(masks[0], side, tree.size, line_width)
        fitted = phenotype_views(tree.phenotype, tree.size, line_width, views=len(masks))
        fitted[0] = front_view(tree.rec, masks[0], tree.size, side)[0]
        views = [float(ncc(fitted[i : i + 1], target[i : i + 1])) for i in range(len(masks))]
    drawn = fitted
    if line_width == "radius":
        size = min(1024, max(max(m.shape) for m in masks))
        drawn = phenotype_views(tree.phenotype, size, "radius", views=objective.n_views)
        if tree.rec is not None:
            drawn[0] = front_view(tree.rec, masks[0], size, side)[0]
    judged = Judged(views, fitted, target=target)
    for i, view in enumerate(list(objective.pictures)[: objective.n_views]):
        back = unframe(drawn[i], *masks, view=i, line_width=line_width)
        judged.framed[view] = back
        judged.areas[view] = float(np.count_nonzero(back)) / max(
            float(np.count_nonzero(masks[i])), 1.0
        )
    return judged
