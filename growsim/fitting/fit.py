"""Fitting a tree to one picture of a tree, or to a front and a side picture:
:func:`fit_image`, the library call ``growsim fit-image`` parses its arguments for.

Two ways (``method``, :func:`~growsim.fitting.choices.method_choice`): a photograph's tree
is **reconstructed** by default (:func:`growsim.reconstruction.reconstruct`: the visible
skeleton from the silhouette, lifted into 3D by the side picture or a stated prior, twigs
and leaves grown into a leafy crown by space colonization; Honda's parameters inferred
from it, :func:`growsim.reconstruction.infer_honda`), judged and written as a search's
fit, with ``skeleton_front.png``, ``model.json``, ``stats.csv``, ``trees.png``, the meshes
and what ``growsim show`` reads (:func:`~growsim.fitting.writing.write`). A drawing, or a
photograph with ``method="search"`` or an option of the search given, is **searched**, as
below.

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

The options are one schema, :class:`~growsim.fitting.options.FitOptions`; the fit runs
in stages (:mod:`growsim.fitting.stages`: choose, segment, reconstruct or search, grow,
judge, write). One ``out`` holds one fit: a fit into a directory that holds files is
refused. The options and the fit's finished stages are kept in its state
(:class:`~growsim.fitting.state.FitState`, :data:`~growsim.fitting.state.FIT_STATE`) and
each run's finished searches in its :data:`~growsim.fitting.runs.RUN_STATE`, so
``resume=True`` continues an interrupted fit to the same result.

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

import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.fitting.options import FitOptions
from growsim.fitting.stages import (
    AUTO_ENOUGH,
    KINDS,
    Reconstructed,
    Runs,
    choose,
    grow,
    judge,
    reconstruct_or_search,
    segment,
)
from growsim.fitting.state import (
    FIT_STATE,
    RECONSTRUCTION_STAGES,
    STAGES,
    FitState,
    check_fresh,
)
from growsim.fitting.writing import write

__all__ = ["AUTO_ENOUGH", "FIT_STATE", "KINDS", "FitResult", "fit_image"]


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
    fitted tree; ``method``: the method choice (``{"value": "reconstruct" or "search",
    "why": ...}``). A reconstruction's ``model`` is ``"reconstruction"``, its ``params``
    the Honda parameters inferred from it (``model.json``), its ``run`` the fit's
    directory, its ``x`` empty.

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
    method: dict = field(default_factory=dict)


def fit_image(
    front: str | os.PathLike | None = None,
    side: str | os.PathLike | None = None,
    *,
    options: FitOptions | None = None,
    out: str | os.PathLike,
    resume: bool = False,
    workers: int | None = None,
    progress: bool = True,
    **kwargs,
) -> FitResult:
    """Fit a model to the picture ``front`` of a tree, or to it and a ``side`` picture
    (from the right), into the results directory ``out`` (new: one directory, one fit;
    see the module docstring for the stages and the files written); returns the kept fit
    (:class:`FitResult`). ``resume=True`` (no pictures, no options) continues the fit in
    ``out`` that was interrupted, with the options it was started with (its
    :class:`~growsim.fitting.state.FitState`), from each run's last finished stage (a GA
    from its checkpoint): the same fit as an uninterrupted one.

    The options of the fit are ``options`` (a
    :class:`~growsim.fitting.options.FitOptions`), or its fields given as keywords (the
    flags of ``growsim fit-image``, ``line_width`` for ``--line-width``, with their
    defaults and descriptions there), the keywords over ``options``. How it runs:
    ``workers``, local processes: a photo's runs side by side (``None``: the machine's
    cores; the same fit on any number), or a single run's GA evaluations; ``progress``:
    progress bars naming the stage. Bad options and pictures raise
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

    out_dir = Path(out)
    if resume:
        if front is not None or side is not None or options is not None or kwargs:
            raise UserInputError(
                "--resume: give the fit's directory alone; it goes on with the pictures and "
                "options it was started with"
            )
        state = FitState.read(out_dir)
        options = state.options
    else:
        data = {} if options is None else options.model_dump(exclude_unset=True)
        data.update(kwargs)
        data.update((k, v) for k, v in (("front", front), ("side", side)) if v is not None)
        if data.get("front") is None:
            raise UserInputError("no picture given (or --resume DIR to continue a fit)")
        options = FitOptions.parse(data)
        state = FitState(options=options.absolute())
    chosen = choose(options)
    if not resume:  # the options are sound: one directory, one fit
        check_fresh(out_dir)
    pictures = options.picture_keywords(chosen.segmentation["value"])
    runs = Runs(options, chosen, pictures, out_dir, resume, workers, progress)
    t0 = time.perf_counter()
    segmented = segment(runs)
    if not resume:
        out_dir.mkdir(parents=True, exist_ok=True)
        state = state.done("choose", "segment")
        state.write(out_dir)
    # the kept fit: a photograph's tree reconstructed, or a model searched
    found = reconstruct_or_search(runs, segmented, state)
    stages = RECONSTRUCTION_STAGES if isinstance(found, Reconstructed) else STAGES
    found.state.done(*stages[:3]).write(out_dir)
    tree = grow(found)
    judged = judge(tree)
    where, summary, files = write(runs, segmented, found, tree, judged,
                                  lambda: round(time.perf_counter() - t0, 3))  # fmt: skip
    found.state.done(*stages).write(out_dir)
    return FitResult(
        model=summary["model"],
        params=tree.params,
        draws=tree.draws,
        stages=tuple(summary["stages"]),
        ncc=summary["ncc"],
        ncc_views=summary["ncc_views"],
        size=summary["size"],
        summary=summary,
        out=where,
        run=where if isinstance(found, Reconstructed) else found.run.out,
        shape=files[0],
        files=(*files, where / "fit.json"),
        plan=tree.plan,
        x=tree.x,
        phenotype=tree.phenotype,
        method=chosen.method,
    )
