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
``segmentation_<view>.png`` (a photo's: the tree's outline over it beside the sky,
ground, clutter and standing objects found,
:func:`~growsim.pictures.photo.segmentation_picture`; a drawing's: the silhouette over
it) and ``silhouettes.png``
(target and fit, framed, at the final size). ``fit.json``'s ``segmentation``: how each
photo's tree was found (:meth:`~growsim.pictures.photo.Segmentation.record`).
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.experiment import load_plan
from growsim.files import atomic_write, jsonable
from growsim.fitting.choices import (
    SEGMENTATIONS,
    candidates,
    fit_settings,
    kept_candidate,
    picture_kind,
)
from growsim.fitting.runs import FitRun, RunJob, run_job, run_jobs
from growsim.fitting.setups import FIT_SETUPS, search_score
from growsim.objectives.silhouette import phenotype_views
from growsim.phenotypes.plant.mesh import export
from growsim.pictures.images import photo_segmentations, silhouette_image, unframe
from growsim.pictures.photo import load_rgb, segmentation_picture
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


def _write_masks(objective, out: Path, pictures: dict, found: dict) -> list[Path]:
    """The silhouettes used, at the pictures' size: ``silhouette_<view>.png`` (black tree
    on white) and ``segmentation_<view>.png``: for a photo, what its segmentation found
    (:func:`~growsim.pictures.photo.segmentation_picture`: the tree's outline over the
    photo beside the sky, ground and clutter it told apart; ``found``: each view's
    :class:`~growsim.pictures.photo.Segmentation`), else the picture with the tree tinted
    red."""

    written = []
    for view, mask in objective.pictures.items():
        path = save_png(np.where(mask, 0, 255).astype(np.uint8), out / f"silhouette_{view}.png")
        rgb = load_rgb(pictures[view])
        if view in found:
            over = segmentation_picture(found[view], rgb)
        else:
            over = 0.35 * rgb + 0.65  # washed out, the tree in red over it
            over[mask] = 0.4 * rgb[mask] + 0.6 * np.array([1.0, 0.0, 0.0])
            over = np.round(255 * over).astype(np.uint8)
        written += [path, save_png(over, out / f"segmentation_{view}.png")]
    return written


def _found(pictures: dict, front, side, n_views: int) -> dict:
    """Each photo's :class:`~growsim.pictures.photo.Segmentation` (``{}`` for a drawing's
    threshold), as the objective read it (remembered: no second segmentation)."""
    if pictures["segmentation"] != "photo":
        return {}
    keys = ("mask_front", "mask_side", "box_front", "point_front", "box_side", "point_side")
    hints = {k: pictures[k] for k in keys}
    segs = photo_segmentations(front, side if n_views > 1 else None, segmentation="photo",
                               **hints)  # fmt: skip
    return dict(zip(("front", "side"), segs))


def _write_fits(objective, fitted, phenotype, out: Path) -> tuple[list[Path], dict[str, float]]:
    """The fitted tree's views framed as the target: ``fit_<view>.png`` (black on white),
    the size and placement of ``silhouette_<view>.png``
    (:func:`~growsim.pictures.images.unframe`), so it can be scored any way; and each
    view's area over the target's there. Branches drawn at their width are drawn again at
    the picture's resolution (a raster as large as the picture, at most 1024 px), so a
    thin branch is as thin as the picture's; thin lines take ``fitted`` (the fitted size's
    views), which frame exactly."""

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
        export(phenotype, path)


#: the options of :func:`fit_image` a fit is started with, kept in its :data:`FIT_STATE`
_SAVED = ("front", "side", "model", "budget", "sizes", "size", "segmentation", "threshold",
          "polarity", "line_width", "leaves", "mask_front", "mask_side", "evaluations",
          "refine", "arrange", "blur", "seed", "restarts", "carry", "box", "point",
          "box_side", "point_side")  # fmt: skip


def _state(out_dir: Path) -> dict:
    """The state of the fit in ``out_dir`` (:data:`FIT_STATE`): the ``options`` it was
    started with and, once the first size's fits are judged, what they ``decided``
    (:func:`_decide`); refused when there is none, or the fit finished."""
    path = out_dir / FIT_STATE
    if (out_dir / "fit.json").is_file():
        raise UserInputError(f"{out_dir}: this fit is finished (fit.json); nothing to resume")
    if not path.is_file():
        raise UserInputError(f"{out_dir}: no fit to resume here (no {FIT_STATE})")
    return json.loads(path.read_text())


def _decide(fits, runs, settings, names, label_of, job) -> dict:
    """What the fits at the first size decide: each fit's scores there (``first_size``),
    the best of each model and kind of tree judged at its model's final size
    (``judged``), the ``kept`` model and kind, and the runs ``carried`` to the finer sizes
    (the restarts of the kept kind that scored best at the first size: the score there
    foretells the final one, benchmarks/log/fitting.md)."""

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
            judged[key] = search_score(load_plan(job(r, 0).config(last)), fits[r].x,
                                       fits[r].draws)  # fmt: skip
    kept = kept_candidate(judged, names)
    ranked = sorted((r for r in runs if r[:2] == kept), key=lambda r: -fits[r].score)
    return {
        "first_size": first_size,
        "judged": {"/".join(k): v for k, v in judged.items()},
        "kept": list(kept),
        "carried": ranked[: settings[kept[0]]["carry"] or len(ranked)],
    }


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
    box=None,
    point=None,
    box_side=None,
    point_side=None,
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
    (``"auto"``: by the picture, see the module docstring; ``"photo"`` or ``"threshold"``,
    with ``threshold``, ``"otsu"`` or a grey level, and ``polarity``, ``"auto"``, ``"dark"``
    or ``"light"``); ``sizes``, the raster sizes coarse to fine (``size``: one size only, no
    refinement); ``line_width`` (``"radius"`` or ``"thin"``); ``leaves``
    (:data:`~growsim.fitting.setups.LEAF_MODES`); ``None`` for these three: chosen by the
    picture (:func:`~growsim.fitting.choices.model_choices`); ``mask_front``, ``mask_side``:
    mask pictures (only their white part may be tree); ``box``, ``point`` (``box_side``,
    ``point_side``): a photo's hint where its tree is, a box ``(x0, y0, x1, y1)`` around it
    or a point ``(x, y)`` on it, in pixels of the picture as given (for a photo where
    one tree cannot be told apart: the refusal names the hint); ``evaluations``: of the first stage
    (>= 100; the setup's polish share kept); ``refine``, ``arrange``: evaluations of the
    refinement at each finer size and of each arrangement search (0: none); ``blur``: sigma
    of the searches at the first size (pixels, scaled with the size; 0 at the last size);
    ``seed``: of the first restart; ``restarts``, ``carry``: fits of each kind of tree, and
    how many of the kept kind go on past the first size (0: all); ``workers``: local
    processes: a photo's runs side by side (``None``: the machine's cores; the same fit on
    any number), or a single run's GA evaluations; ``progress``: progress bars naming the
    stage. ``None``: the model's own (:data:`~growsim.fitting.setups.FIT_SETUPS`, a
    drawing's :attr:`~growsim.fitting.setups.FitSetup.drawing`). Bad options and pictures
    raise :class:`UserInputError` before any evolution.

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

    out_dir = Path(out)
    if resume:
        if front is not None or side is not None:
            raise UserInputError(
                "--resume: give the fit's directory alone; it goes on with the pictures and "
                "options it was started with"
            )
        saved = _state(out_dir)["options"]
        (front, side, model, budget, sizes, size, segmentation, threshold, polarity, line_width,
         leaves, mask_front, mask_side, evaluations, refine, arrange, blur, seed, restarts,
         carry, box, point, box_side, point_side) = (saved.get(k) for k in _SAVED)  # fmt: skip
    elif front is None:
        raise UserInputError("no picture given (or --resume DIR to continue a fit)")
    here = locals()
    options = {k: here[k] for k in _SAVED}
    for k in ("front", "side", "mask_front", "mask_side"):
        if options[k] is not None:
            options[k] = str(Path(options[k]).absolute())
    for k, n in (("box", 4), ("point", 2), ("box_side", 4), ("point_side", 2)):
        if options[k] is not None:
            flag = "--" + k.replace("_", "-")
            try:
                options[k] = [float(v) for v in options[k]]
            except (TypeError, ValueError):
                options[k] = []
            if len(options[k]) != n or not all(np.isfinite(options[k])):
                raise UserInputError(f"{flag}: expected {n} numbers, got {here[k]!r}")
    box, point, box_side, point_side = (options[k] for k in ("box", "point", "box_side",
                                                             "point_side"))  # fmt: skip
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
                    mask_side=mask_side, segmentation=segmentation, box_front=box,
                    point_front=point, box_side=box_side, point_side=point_side)  # fmt: skip
    runs = [(m, mode, seed + r) for m in names for mode in settings[m]["modes"]
            for r in range(settings[m]["restarts"])]  # fmt: skip
    processes = 1 if len(runs) == 1 else workers  # a single run's GA takes the workers
    t0 = time.perf_counter()

    def name_of(m, mode, s):
        name = KINDS[mode] if mode != "keep" else "run"
        if len(names) > 1:
            name = f"{m}-{name}"
        return name + (f"-{s}" if settings[m]["restarts"] > 1 else "")

    def label_of(m, mode, s):
        kind = "" if mode == "keep" else f" {KINDS[mode]}"
        return f"{m}{kind}" + (f" seed {s}" if settings[m]["restarts"] > 1 else "")

    def job(r, last, again=resume):
        # run r as a job up to its size index last (a single run's GA on the workers)
        return RunJob(front, side, *r, settings[r[0]], pictures,
                      out_dir / name_of(*r) if len(runs) > 1 else out_dir, last, again,
                      workers if len(runs) == 1 else None,
                      label_of(*r) if progress else None)  # fmt: skip

    # compiling builds the objective once: bad pictures fail here, before any evolution
    first = {r: load_plan(job(r, 0).config(settings[r[0]]["sizes"][0], settings[r[0]]["blur"]))
             for r in runs}  # fmt: skip
    if not resume:
        out_dir.mkdir(parents=True, exist_ok=True)
        atomic_write(out_dir / FIT_STATE, json.dumps({"options": jsonable(options)}, indent=1))
    fits: dict[tuple[str, str, int], FitRun] = {}
    if drawing:
        # one after the other: a model that matched the drawing ends the search
        enough = None
        for r in runs:
            if enough is not None and r[0] != enough:
                continue
            fits[r] = run_job(job(r, 0), first[r])
            if len(names) > 1 and fits[r].ncc >= AUTO_ENOUGH:
                enough = r[0]
        if enough is not None:
            names = [m for m in names if any(r[0] == m for r in fits)]
            model_choice["why"] += (f"; {enough}'s fit matched the drawing (NCC >= "
                                    f"{AUTO_ENOUGH}), the next models were not fitted")  # fmt: skip
    else:
        # a photo's runs side by side on the cores (the same runs on any number)
        label = f"fits at {settings[runs[0][0]]['sizes'][0]} px" if progress else None
        fits = dict(zip(runs, run_jobs([job(r, 0) for r in runs], processes, label)))
    # every fit at the end of the first size; the best of each model and kind of tree,
    # judged at its model's final size (finer: a blob that passes at 64 px shows there);
    # kept in the fit's state, so a resumed fit carries the same runs on
    decided = _state(out_dir).get("decided") if resume else None
    if decided is None:
        decided = _decide(fits, runs, settings, names, label_of, job)
        atomic_write(out_dir / FIT_STATE, json.dumps(
            {"options": jsonable(options), "decided": jsonable(decided)}, indent=1))  # fmt: skip
    first_size, kept_model, chosen = decided["first_size"], *decided["kept"]
    judged = {tuple(k.split("/")): v for k, v in decided["judged"].items()}
    carried = [tuple(r) for r in decided["carried"]]
    st = settings[kept_model]
    if len(st["sizes"]) > 1:
        label = f"fits at {', '.join(map(str, st['sizes'][1:]))} px" if progress else None
        jobs = [job(r, len(st["sizes"]) - 1, True) for r in carried]
        fits.update(zip(carried, run_jobs(jobs, 1 if drawing else processes, label)))
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
    found = _found(pictures, front, side, objective.n_views)
    written = _write_masks(objective, out, paths, found)
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
        # how each photo's tree was found (method, hint, horizon, skyline, contrast, ...)
        "segmentation": {view: seg.record() for view, seg in found.items()},
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
