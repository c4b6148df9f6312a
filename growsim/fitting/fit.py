"""Fitting a model to one picture of a tree, or to a front and a side picture:
:func:`fit_image`, the library call ``growsim fit-image`` parses its arguments for.

The pictures become silhouettes (:mod:`growsim.pictures`). By default
(``segmentation="auto"``) each picture is classified
(:func:`~growsim.pictures.images.classify_picture`): a drawing or silhouette (near grey,
two grey levels) is read by a grey threshold and fitted as the seed fitted them (thin
lines, binary NCC, the setup's ``drawing`` keywords: one size, the setup's leaves); a
photo by the photo segmentation (the tree apart from sky and ground), coarse to fine,
bare and leafy, on the shape score (:data:`~growsim.fitting.setups.PHOTO_SCORE`,
:func:`~growsim.objectives.silhouette.shape_score`: a score a blob or a lone trunk cannot
win). What was chosen and why is ``fit.json``'s ``choices``; an option given overrides
its choice. A bad picture is refused with a message naming it, before any evolution.

``model="auto"`` fits every model whose :class:`~growsim.fitting.setups.FitSetup` takes
the picture's kind (``kinds``): each candidate (model, and with ``leaves="auto"`` a bare
and a leafy tree) is fitted ``restarts`` times at the first size (the setup's GA and
polish, the sweep of its discrete parameters, :func:`~growsim.fitting.setups.sweep_discrete`,
and for a model with the ``draws`` capability the search of its branches' arrangement,
:func:`~growsim.fitting.setups.arrange`), its best judged at its final size; the leafy
tree is kept only if it beats the bare one by :data:`~growsim.fitting.setups.LEAF_MARGIN`,
then the best model. On a drawing, a model whose fit reaches :data:`AUTO_ENOUGH` ends the
search. The ``carry`` best restarts of the kept kind go on to the finer sizes (a local
refinement, :func:`~growsim.fitting.setups.refine`, then the sweep and the arrangement at
each), and the best at the final size is kept. ``budget`` multiplies every search's
evaluations. Every stage reports the binary NCC beside the score searched.

One ``out`` holds one fit: a fit into a directory that holds files is refused. The
options are kept in :data:`FIT_STATE` and each run's finished stages in its
:data:`RUN_STATE`, so ``resume=True`` continues an interrupted fit to the same result.

Writes into ``out``: each candidate's run results (``config.toml``, ``history.parquet``,
``best.json``, ...; with several fits, one directory each: ``bare-0``, ``honda-leafy-1``,
...), ``fit.json`` (every stage of the kept fit: size, evaluations, seconds, NCC, score;
the final parameters and the fitted arrangement, ``draws``; ``models`` and ``leaves``:
every candidate's score and which was kept; ``area_ratio``), the fitted tree
(:attr:`~growsim.fitting.setups.FitSetup.shape`: ``tree.glb``; a 2D model's
``attractor.png``), ``silhouette_<view>.png`` (the silhouette used, at the picture's
size), ``fit_<view>.png`` (the fitted tree framed as it: same size and placement,
:func:`~growsim.pictures.images.unframe`, to score it any way),
``segmentation_<view>.png`` (the silhouette over the picture) and ``silhouettes.png``
(target and fit, framed, at the final size).
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_write, jsonable
from growsim.fitting.choices import (
    SEGMENTATIONS,
    candidates,
    fit_settings,
    kept_candidate,
    picture_kind,
)
from growsim.fitting.setups import (
    FIT_SETUPS,
    exact_score,
    fit_config,
    search_score,
    sweep_discrete,
)
from growsim.fitting.setups import arrange as search_arrangement
from growsim.fitting.setups import refine as refine_fit
from growsim.render import save_png

__all__ = ["FitResult", "fit_image"]

#: each kind of tree (``leaves`` mode of one fit) as results name it
KINDS = {"fit": "leafy", "bare": "bare", "keep": "setup's"}


@dataclass(frozen=True, eq=False)
class FitResult:
    """What :func:`fit_image` returns: the kept fit.

    ``model``: the fitted model's name; ``params``: every model parameter of the fitted
    tree (integer parameters as ints); ``draws``: the arrangement of its branches fitted to
    the picture (``(m, d)`` uniforms; ``None``: the model's own, as its seed gives it);
    ``stages``: every stage of the kept fit, in order (``size``, ``stage`` (``"ga"``,
    ``"refine"``, ``"discrete"``, ``"arrange"``), ``evaluations``, ``seconds``, ``ncc``: the
    binary NCC at its end; ``ncc_start``, or ``score_start`` and ``score`` for a search on
    blurred views); ``ncc``: the final mean NCC over the views, ``ncc_views`` per view, at
    ``size`` pixels; ``summary``: the content of ``fit.json``; ``out``: the directory it
    and the other files (``files``: the fitted tree ``shape`` first, ``fit.json`` last)
    were written to; ``run``: the kept fit's run directory (config, history, best);
    ``plan``: its compiled plan at the final size, ``x`` its evolved values
    (``plan.fitness().phenotype_of(x, draws=draws)`` rebuilds it); ``phenotype``: the
    fitted tree.

    Examples
    --------
    >>> r = fit_image("tree.jpg", out="fit", model="honda")  # doctest: +SKIP
    >>> [(s["size"], s["stage"]) for s in r.stages][:3]  # doctest: +SKIP
    [(64, 'ga'), (64, 'discrete'), (64, 'arrange')]
    >>> r.phenotype.screenshot("fit/tree.png").name  # doctest: +SKIP
    'tree.png'
    >>> from dataclasses import fields
    >>> [f.name for f in fields(FitResult)][:5]
    ['model', 'params', 'draws', 'stages', 'ncc']
    """

    model: str
    params: dict[str, float]
    draws: np.ndarray | None
    stages: tuple[dict[str, Any], ...]
    ncc: float
    ncc_views: dict[str, float]
    size: int
    summary: dict[str, Any]
    out: Path
    run: Path
    shape: Path
    files: tuple[Path, ...]
    plan: Any
    x: np.ndarray
    phenotype: Any


#: ``--model auto`` on a drawing: a model whose fit matches it this well at the first size
#: (binary NCC) ends the search, the next models are not fitted (none can do much better)
AUTO_ENOUGH = 0.95

#: a fit's state in its ``--out``: the options it was started with (``--resume``)
FIT_STATE = "fit-state.json"

#: each run's state in its directory: the stages it finished, its values and draws
RUN_STATE = "fit-stages.json"


@dataclass
class _Fit:
    """One fit on its way through the sizes: its compiled plan (at the current size), the
    evolved values ``x``, the arrangement ``draws`` (``None``: the model's own), the stages
    so far and its run's directory."""

    plan: Any
    x: np.ndarray
    out: Path
    draws: np.ndarray | None = None
    stages: list[dict[str, Any]] = field(default_factory=list)

    @property
    def ncc(self) -> float:
        """The binary NCC at its last stage."""
        return self.stages[-1]["ncc"]

    def save(self, done: int) -> None:
        """Write its state after the searches of size ``done`` (an index into the sizes)."""
        state = {"done": done, "x": self.x.tolist(), "stages": self.stages,
                 "draws": None if self.draws is None else self.draws.tolist()}  # fmt: skip
        atomic_write(self.out / RUN_STATE, json.dumps(jsonable(state)))

    @classmethod
    def restore(cls, out: Path, config) -> tuple[_Fit, int] | None:
        """The fit saved in ``out`` (:meth:`save`) and the index of the last size done, its
        plan compiled by ``config(k)``; ``None`` if nothing was saved."""
        from growsim.experiment import load_plan

        path = out / RUN_STATE
        if not path.is_file():
            return None
        state = json.loads(path.read_text())
        draws = None if state["draws"] is None else np.asarray(state["draws"], dtype=np.float64)
        fit = cls(load_plan(config(state["done"])), np.asarray(state["x"], dtype=np.float64),
                  out, draws, state["stages"])  # fmt: skip
        return fit, state["done"]

    @property
    def score(self) -> float:
        """The score searched at its last stage (the shape score, blurred or not; the
        binary NCC when the search scored that)."""
        return self.stages[-1].get("score", self.stages[-1]["ncc"])


def _searched_apart(plan) -> bool:
    """Whether ``plan``'s searches score something else than the binary NCC (a blur, the
    shape terms)."""
    o = plan.objectives[0]
    return o.blur > 0 or o.has_shape_terms


class _Bar:
    """A progress bar of one stage (tqdm on stderr, labelled; nothing when disabled)."""

    def __init__(self, label: str, total: int, enabled: bool):
        self.bar = None
        if enabled and total > 0:
            import sys

            from tqdm.auto import tqdm

            if sys.stderr.isatty():
                self.bar = tqdm(total=total, desc=label, unit="eval", file=sys.stderr,
                                dynamic_ncols=True, leave=False)  # fmt: skip

    def __call__(self, n: int) -> None:
        if self.bar is not None:
            self.bar.update(n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _evolve(plan, size: int, out: Path, workers, progress, resume: bool = False) -> _Fit:
    """The first stage of one fit: the setup's GA on ``plan`` (compiled at the first size,
    ``size``), run into ``out`` (``progress``: ``False`` or the bar's label; ``resume``:
    continued from the run's checkpoint, or read back when it finished); its row: size,
    evaluations, seconds, binary NCC (and the ``score`` searched, when it differs)."""
    from growsim.experiment import read_run, run

    t0 = time.perf_counter()
    if resume and (out / "summary.json").is_file():
        result = read_run(out, history=False)
    elif resume and (out / "config.toml").is_file():
        result = run(None, out=out, workers=workers, progress=progress, resume=True)
    else:
        result = run(plan, out=out, workers=workers, progress=progress)
    fitness = plan.fitness()
    x = np.array([result.best_params[n] for n in fitness.evolved], dtype=np.float64)
    apart = _searched_apart(plan)
    row = {
        "size": size,
        "stage": "ga",
        "evaluations": int(result.summary["evaluations"]),
        "seconds": round(time.perf_counter() - t0, 3),
        "ncc": exact_score(plan, x) if apart else float(result.best_fitness),
    }
    if apart:
        row["score"] = float(result.best_fitness)
    return _Fit(plan, x, Path(result.out), stages=[row])


def _size_stages(fit: _Fit, k: int, config, sizes, setup, budgets, seed: int,
                 label: str | None = None) -> None:  # fmt: skip
    """The searches of ``fit`` at ``sizes[k]``, in place: a refinement (at every size but
    the first, on the fit's config at that size, ``config(size, blur)``), the sweep of the
    discrete parameters (:func:`~growsim.fitting.setups.sweep_discrete`) and the search for
    the branches' arrangement (:func:`~growsim.fitting.setups.arrange`, for a model with
    the ``draws`` capability). ``budgets`` ``(refine, arrange, blur)``: the evaluations of
    each refinement and of each arrangement search (0: none), and the blur at the first
    size (scaled with the size; the searches at the last size are on the binary NCC). Each
    search appends its row to ``fit.stages`` (size, evaluations, seconds, binary NCC);
    ``label``: a progress bar per search, labelled with it and the stage."""
    from growsim.experiment import load_plan

    refine_evaluations, arrange_evaluations, blur = budgets
    size = sizes[k]

    def stage(name, evaluations, search):
        plan, x, draws = fit.plan, fit.x, fit.draws
        t = time.perf_counter()
        bar = _Bar(f"{label}: {size} px {name}", evaluations, label is not None)
        try:
            if name == "refine":
                x, score, start = search(plan, x, evaluations=evaluations,
                                         sigma=setup.refine_sigma, seed=seed * 1000 + k,
                                         draws=draws, tick=bar)  # fmt: skip
            elif name == "discrete":
                x, score, start, evaluations = search(plan, x, draws)
            else:
                draws, score, start = search(plan, x, draws, evaluations=evaluations,
                                             seed=seed * 1000 + 500 + k, tick=bar)  # fmt: skip
        finally:
            bar.close()
        fit.x, fit.draws = x, draws
        row = {"size": size, "stage": name, "evaluations": evaluations}
        row["seconds"] = round(time.perf_counter() - t, 3)
        if _searched_apart(plan):
            row["score_start"], row["score"] = start, score
            row["ncc"] = exact_score(plan, x, draws)
        else:
            row["ncc_start"], row["ncc"] = start, score
        fit.stages.append(row)

    # blurred at every size but the last, whose searches are on the score reported
    sigma = blur * size / sizes[0] if k < len(sizes) - 1 else 0.0
    if k > 0:
        fit.plan = load_plan(config(size, sigma))
        stage("refine", refine_evaluations, refine_fit)
    elif blur > 0 and sigma == 0:  # one size: the GA's score was blurred
        fit.plan = load_plan(config(size, 0.0))
    # the discrete parameters (leaves per branch): every value tried at every size
    genome = fit.plan.genome
    if np.any(genome.discrete & (genome.param_high - genome.param_low >= 1)):
        stage("discrete", 0, sweep_discrete)
    if arrange_evaluations > 0 and "draws" in fit.plan.model.capabilities:
        stage("arrange", arrange_evaluations, search_arrangement)


def _write_masks(objective, out: Path, pictures: dict) -> list[Path]:
    """The silhouettes used, at the pictures' size: ``silhouette_<view>.png`` (black tree
    on white) and ``segmentation_<view>.png`` (the picture, the tree tinted red)."""
    from growsim.pictures.photo import load_rgb

    written = []
    for view, mask in objective.pictures.items():
        path = save_png(np.where(mask, 0, 255).astype(np.uint8), out / f"silhouette_{view}.png")
        rgb = load_rgb(pictures[view])
        over = 0.35 * rgb + 0.65  # washed out, the tree in red over it
        over[mask] = 0.4 * rgb[mask] + 0.6 * np.array([1.0, 0.0, 0.0])
        over = np.round(255 * over).astype(np.uint8)
        written += [path, save_png(over, out / f"segmentation_{view}.png")]
    return written


def _write_fits(objective, fitted, phenotype, out: Path) -> tuple[list[Path], dict[str, float]]:
    """The fitted tree's views framed as the target: ``fit_<view>.png`` (black on white),
    the size and placement of ``silhouette_<view>.png``
    (:func:`~growsim.pictures.images.unframe`), so it can be scored any way; and each
    view's area over the target's there. Branches drawn at their width are drawn again at
    the picture's resolution (a raster as large as the picture, at most 1024 px), so a
    thin branch is as thin as the picture's; thin lines take ``fitted`` (the fitted size's
    views), which frame exactly."""
    from growsim.objectives.silhouette import phenotype_views
    from growsim.pictures.images import unframe

    masks = list(objective.pictures.values())[: objective.n_views]
    if objective.line_width == "radius":
        size = min(1024, max(max(m.shape) for m in masks))
        fitted = phenotype_views(phenotype, size, "radius", views=objective.n_views)
    written, areas = [], {}
    for i, view in enumerate(list(objective.pictures)[: objective.n_views]):
        back = unframe(fitted[i], *masks, view=i, line_width=objective.line_width)
        written.append(save_png(np.where(back, 0, 255).astype(np.uint8), out / f"fit_{view}.png"))
        areas[view] = float(np.count_nonzero(back)) / max(float(np.count_nonzero(masks[i])), 1.0)
    return written, areas


def _write_shape(phenotype, path: Path) -> None:
    """The fitted tree written to ``path``: a ``.png`` file its front view's picture,
    any other a mesh (:func:`growsim.phenotypes.plant.mesh.export`: ``.glb``, ...)."""
    if path.suffix.lower() == ".png":
        phenotype.screenshot(path, view="front")
    else:
        from growsim.phenotypes.plant.mesh import export

        export(phenotype, path)


#: the options of :func:`fit_image` a fit is started with, kept in its :data:`FIT_STATE`
_SAVED = ("front", "side", "model", "budget", "sizes", "size", "segmentation", "threshold",
          "polarity", "line_width", "leaves", "mask_front", "mask_side", "evaluations",
          "refine", "arrange", "blur", "seed", "restarts", "carry")  # fmt: skip


def _saved(out_dir: Path) -> dict:
    """The options of the fit in ``out_dir`` to resume (:data:`FIT_STATE`); refused when
    there is none, or it finished."""
    path = out_dir / FIT_STATE
    if (out_dir / "fit.json").is_file():
        raise UserInputError(f"{out_dir}: this fit is finished (fit.json); nothing to resume")
    if not path.is_file():
        raise UserInputError(f"{out_dir}: no fit to resume here (no {FIT_STATE})")
    return json.loads(path.read_text())["options"]


def _check_fresh(out_dir: Path) -> None:
    """Refuse an ``--out`` that holds anything: one directory, one fit."""
    if out_dir.exists() and (not out_dir.is_dir() or any(out_dir.iterdir())):
        held = sorted(p.name + ("/" if p.is_dir() else "") for p in out_dir.iterdir())
        shown = ", ".join(held[:4]) + (", ..." if len(held) > 4 else "")
        hint = (f"continue it with: growsim fit-image --resume {out_dir}; "
                if (out_dir / FIT_STATE).is_file() and not (out_dir / "fit.json").is_file()
                else "")  # fmt: skip
        raise UserInputError(
            f"{out_dir} already holds files ({shown}); {hint}a fit needs a new --out"
        )


def fit_image(
    front: str | os.PathLike | None = None,
    side: str | os.PathLike | None = None,
    *,
    out: str | os.PathLike,
    resume: bool = False,
    model: str = "auto",
    budget: float = 1.0,
    sizes=None,
    size: int | None = None,
    segmentation: str = "auto",
    threshold: str | float = "otsu",
    polarity: str = "auto",
    line_width: str | None = None,
    leaves: str | None = None,
    mask_front: str | os.PathLike | None = None,
    mask_side: str | os.PathLike | None = None,
    evaluations: int | None = None,
    refine: int | None = None,
    arrange: int | None = None,
    blur: float | None = None,
    seed: int = 0,
    restarts: int | None = None,
    carry: int | None = None,
    workers: int | None = None,
    progress: bool = True,
) -> FitResult:
    """Fit a model to the picture ``front`` of a tree, or to it and a ``side`` picture
    (from the right), into the results directory ``out`` (new: one directory, one fit;
    see the module docstring for the stages and the files written); returns the kept fit
    (:class:`FitResult`). ``resume=True`` (no pictures, no options) continues the fit in
    ``out`` that was interrupted, with the options it was started with, from each run's
    last finished stage (a GA from its checkpoint): the same fit as an uninterrupted one.

    The keywords are ``growsim fit-image``'s options, with its defaults: ``model``
    (``"auto"``: every model of :data:`~growsim.fitting.setups.FIT_SETUPS` for the
    picture's kind fitted at the first size, the best kept); ``budget``: every search's
    evaluations times this (a photo: about 90 s at 1 on 2 cores); ``segmentation``
    (``"auto"``: by the picture, see the module docstring; ``"photo"`` or
    ``"threshold"``, with ``threshold``, ``"otsu"`` or a grey level, and ``polarity``,
    ``"auto"``, ``"dark"`` or ``"light"``); ``sizes``, the raster sizes coarse to fine
    (``size``: one size only, no refinement); ``line_width`` (``"radius"`` or ``"thin"``);
    ``leaves`` (:data:`~growsim.fitting.setups.LEAF_MODES`); ``None`` for these three:
    chosen by the picture (:func:`~growsim.fitting.choices.model_choices`); ``mask_front``,
    ``mask_side``: mask pictures (only their white part may be tree); ``evaluations``: of
    the first stage (>= 100; the setup's polish share kept); ``refine``, ``arrange``:
    evaluations of the refinement at each finer size and of each arrangement search (0:
    none); ``blur``: sigma of the searches at the first size (pixels, scaled with the size;
    0 at the last size); ``seed``: of the first restart; ``restarts``, ``carry``: fits of
    each kind of tree, and how many of the kept kind go on past the first size (0: all);
    ``workers``: local processes evaluating; ``progress``: a progress bar naming the
    stage. ``None``: the model's own (:data:`~growsim.fitting.setups.FIT_SETUPS`, a drawing's
    :attr:`~growsim.fitting.setups.FitSetup.drawing`). Bad options and pictures raise
    :class:`UserInputError` before any evolution.

    Examples
    --------
    >>> fit_image("tree.jpg", out="fit", model="honda", restarts=0)
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --restarts: at least 1, got 0
    >>> r = fit_image("zelkova.jpg", out="fit", model="honda", evaluations=200, sizes=(32, 64),
    ...               refine=40, restarts=3, carry=1, arrange=40, blur=0.7)  # doctest: +SKIP
    >>> r.summary["leaves"]["chosen"], round(r.ncc, 4), r.shape.name  # doctest: +SKIP
    ('leafy', 0.8563, 'tree.glb')
    """
    from growsim.experiment import load_plan
    from growsim.objectives.silhouette import phenotype_views
    from growsim.pictures.images import silhouette_image

    out_dir = Path(out)
    if resume:
        if front is not None or side is not None:
            raise UserInputError(
                "--resume: give the fit's directory alone; it goes on with the pictures and "
                "options it was started with"
            )
        saved = _saved(out_dir)
        (front, side, model, budget, sizes, size, segmentation, threshold, polarity, line_width,
         leaves, mask_front, mask_side, evaluations, refine, arrange, blur, seed, restarts,
         carry) = (saved[k] for k in _SAVED)  # fmt: skip
    elif front is None:
        raise UserInputError("no picture given (or --resume DIR to continue a fit)")
    here = locals()
    options = {k: here[k] for k in _SAVED}
    for k in ("front", "side", "mask_front", "mask_side"):
        if options[k] is not None:
            options[k] = str(Path(options[k]).absolute())
    if segmentation not in SEGMENTATIONS:
        raise UserInputError(
            f"--segmentation: expected one of {', '.join(SEGMENTATIONS)}, got {segmentation!r}"
        )
    if evaluations is not None and evaluations < 100:
        raise UserInputError(f"--evaluations: at least 100, got {evaluations}")
    if refine is not None and refine < 0:
        raise UserInputError(f"--refine: at least 0, got {refine}")
    if size is not None and not 8 <= size <= 1024:
        raise UserInputError(f"--size: expected 8..1024, got {size}")
    if restarts is not None and restarts < 1:
        raise UserInputError(f"--restarts: at least 1, got {restarts}")
    if not 0.01 <= budget <= 100:
        raise UserInputError(f"--budget: expected 0.01..100, got {budget:g}")
    if model != "auto":
        FIT_SETUPS.get(model)
    drawing, seg_choice = picture_kind(front, side, segmentation)
    segmentation = seg_choice["value"]
    names, model_choice = candidates(model, drawing, side)
    given = dict(line_width=line_width, sizes=sizes, size=size, leaves=leaves,
                 evaluations=evaluations, refine=refine, arrange=arrange, blur=blur,
                 restarts=restarts, carry=carry)  # fmt: skip
    settings = {m: fit_settings(m, drawing, given, budget) for m in names}
    if not resume:  # the options are sound: one directory, one fit
        _check_fresh(out_dir)
    pictures = dict(threshold=threshold, polarity=polarity, mask_front=mask_front,
                    mask_side=mask_side, segmentation=segmentation)  # fmt: skip
    runs = [(m, mode, seed + r) for m in names for mode in settings[m]["modes"]
            for r in range(settings[m]["restarts"])]  # fmt: skip
    t0 = time.perf_counter()

    def config(m, mode, s, size, sigma=0.0):
        st = settings[m]
        return fit_config(front, side, model=m, size=size, leaves=mode, seed=s, blur=sigma,
                          line_width=st["line_width"], evaluations=st["evaluations"],
                          score=st["score"], **pictures)  # fmt: skip

    def name_of(m, mode, s):
        name = KINDS[mode] if mode != "keep" else "run"
        if len(names) > 1:
            name = f"{m}-{name}"
        return name + (f"-{s}" if settings[m]["restarts"] > 1 else "")

    def label_of(m, mode, s):
        kind = "" if mode == "keep" else f" {KINDS[mode]}"
        return f"{m}{kind}" + (f" seed {s}" if settings[m]["restarts"] > 1 else "")

    # compiling builds the objective once: bad pictures fail here, before any evolution
    first = {r: load_plan(config(*r, settings[r[0]]["sizes"][0], settings[r[0]]["blur"]))
             for r in runs}  # fmt: skip

    def stages(r, k):
        m, mode, s = r
        st = settings[m]
        budgets = (st["refine"], st["arrange"], st["blur"])
        _size_stages(fits[r], k, lambda size, sigma: config(m, mode, s, size, sigma),
                     st["sizes"], st["setup"], budgets, s,
                     label_of(*r) if progress else None)  # fmt: skip

    def plan_at(r, k):
        # the plan of run r's searches at its k-th size (blurred but at the last)
        st = settings[r[0]]
        last = k == len(st["sizes"]) - 1
        sigma = 0.0 if last else st["blur"] * st["sizes"][k] / st["sizes"][0]
        return load_plan(config(*r, st["sizes"][k], sigma))

    if not resume:
        out_dir.mkdir(parents=True, exist_ok=True)
        atomic_write(out_dir / FIT_STATE, json.dumps({"options": jsonable(options)}, indent=1))
    fits: dict[tuple[str, str, int], _Fit] = {}
    done: dict[tuple[str, str, int], int] = {}
    enough = None  # a drawing's model that matched it: the next models are not fitted
    for r in runs:
        if enough is not None and r[0] != enough:
            continue
        size0 = settings[r[0]]["sizes"][0]
        run_out = out_dir / name_of(*r) if len(runs) > 1 else out_dir
        restored = _Fit.restore(run_out, lambda k, r=r: plan_at(r, k)) if resume else None
        if restored is not None:
            fits[r], done[r] = restored
        else:
            label = f"{label_of(*r)}: {size0} px GA" if progress else False
            fits[r] = _evolve(first[r], size0, run_out, workers, label, resume)
            stages(r, 0)
            fits[r].save(0)
            done[r] = 0
        if drawing and len(names) > 1 and fits[r].ncc >= AUTO_ENOUGH:
            enough = r[0]
    if enough is not None:
        names = [m for m in names if any(r[0] == m for r in fits)]
        model_choice["why"] += (f"; {enough}'s fit matched the drawing (NCC >= {AUTO_ENOUGH}), "
                                "the next models were not fitted")  # fmt: skip
    # every fit at the end of the first size; the best of each model and kind of tree,
    # judged at its model's final size (finer: a blob that passes at 64 px shows there)
    first_size = {label_of(*r): {"ncc": f.ncc, "score": f.score} for r, f in fits.items()}
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
            judged[key] = search_score(load_plan(config(*r, last)), fits[r].x, fits[r].draws)
    kept_model, chosen = kept_candidate(judged, names)
    st = settings[kept_model]
    # the restarts of the kept kind that scored best at the first size go on to the finer
    # sizes (the score there foretells the final one: benchmarks/log/fitting.md)
    ranked = [r for r in runs if r[:2] == (kept_model, chosen)]
    ranked.sort(key=lambda r: -fits[r].score)
    carried = ranked[: st["carry"] or len(ranked)]
    for r in carried:
        for k in range(done[r] + 1, len(st["sizes"])):
            stages(r, k)
            fits[r].save(k)
    kept = fits[max(carried, key=lambda r: fits[r].score)]
    setup = st["setup"]
    plan, x, draws = kept.plan, kept.x, kept.draws
    objective = plan.objectives[0]
    out = kept.out if len(runs) == 1 else out_dir
    out.mkdir(parents=True, exist_ok=True)
    leaves_summary = {
        "mode": st["leaves"],
        "chosen": KINDS[chosen],
        # the score of each kind of the kept model's best fit at the first size, judged at
        # the final size
        "score": {KINDS[mode]: v for (m, mode), v in judged.items() if m == kept_model},
        "run": str(kept.out),
        "runs": {
            label_of(*r): {"ncc": fits[r].ncc, "score": fits[r].score, "out": str(fits[r].out)}
            for r in carried
        },
        "first_size": first_size,
    }
    models_summary = {m: max(v for (mm, _), v in judged.items() if mm == m) for m in names}
    # the fitted tree, grown as the searches grew it (with the fitted arrangement)
    tree = plan.fitness().phenotype_of(x, draws=draws)
    params = {n: round(v) if n in plan.int_names else v for n, v in tree.params.items()}
    views = objective.view_scores(tree.phenotype)
    shape = out / setup.shape
    _write_shape(tree.phenotype, shape)
    fitted = phenotype_views(
        tree.phenotype, objective.size, objective.line_width, views=objective.n_views
    )
    titles = [
        f"{v} target" if i % 2 == 0 else f"{v} fit" for v in ("front", "side") for i in (0, 1)
    ]
    panels = [a for i in range(objective.n_views) for a in (objective.target[i], fitted[i])]
    silhouette_image(panels, out / "silhouettes.png", titles=titles[: len(panels)], scale=2)
    paths = {"front": front, "side": side}
    written = _write_masks(objective, out, paths)
    fit_files, areas = _write_fits(objective, fitted, tree.phenotype, out)
    written += fit_files
    choices = {"segmentation": seg_choice, "model": model_choice, **st["choices"]}
    summary = {
        "model": kept_model,
        "pictures": {k: str(v) for k, v in paths.items() if v is not None},
        "views": ["front", "side"][: objective.n_views],
        "ncc": float(np.mean(views)),
        "ncc_views": dict(zip(("front", "side"), views)),
        "size": objective.size,
        # the fit's area over the target's in each view, at the picture's size
        # (fit_<view>.png against silhouette_<view>.png)
        "area_ratio": areas,
        "score": kept.score,
        "seconds": round(time.perf_counter() - t0, 3),
        "budget": budget,
        "stages": kept.stages,
        "models": models_summary,
        "leaves": leaves_summary,
        # what was chosen for the user (segmentation, model, line width, sizes, leaves)
        # and why
        "choices": choices,
        "params": params,
        # the arrangement of the branches fitted to the picture (None: the model's own):
        # model.develop(params, draws=np.array(draws)) grows the fitted tree
        "draws": None if draws is None else draws.tolist(),
        "files": [shape.name, "silhouettes.png", *[w.name for w in written]],
    }
    text = json.dumps(jsonable(summary), indent=1)
    atomic_write(out / "fit.json", lambda fh: fh.write(text.encode()))
    return FitResult(
        model=kept_model,
        params=params,
        draws=draws,
        stages=tuple(kept.stages),
        ncc=summary["ncc"],
        ncc_views=summary["ncc_views"],
        size=objective.size,
        summary=summary,
        out=out,
        run=kept.out,
        shape=shape,
        files=(shape, out / "silhouettes.png", *written, out / "fit.json"),
        plan=plan,
        x=x,
        phenotype=tree.phenotype,
    )
