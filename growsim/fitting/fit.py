"""Fitting a model to one picture of a tree, or to a front and a side picture:
:func:`fit_image`, the library call ``growsim fit-image`` parses its arguments for.

The pictures become silhouettes (:mod:`growsim.pictures`). By default
(``segmentation="auto"``) each picture is classified
(:func:`~growsim.pictures.images.classify_picture`): a drawing or silhouette (near grey,
two grey levels) is read by a grey threshold and fitted as the seed fitted them (thin
lines, the setup's ``drawing`` keywords: one size, the setup's leaves); a photo by the photo
segmentation (the tree apart from sky and ground), coarse to fine, bare and leafy. What
was chosen and why is ``fit.json``'s ``choices`` (:func:`_choices`); an option given
overrides its choice. A bad segmentation is refused with a message naming the picture, before any
evolution. The model is fitted coarse to fine: the setup's GA (and polish) at the first
of ``sizes`` (64 px), then a local refinement of the best at each finer size (128, 256
px, :func:`~growsim.fitting.setups.refine`), so branch structure counts. With ``leaves
= "auto"`` (the default) a bare and a leafy tree are both fitted and the leafy one is
kept only if clearly better (:data:`~growsim.fitting.setups.LEAF_MARGIN`), so a winter
tree is fitted by a bare tree; each kind is fitted ``restarts`` times (GA seeds
``seed``, ``seed + 1``, ...), the ``carry`` that scored best at the end of the first
size go on to the finer sizes, and the best at the final size is kept. Every value of a
discrete parameter (the leaves per branch) is tried at every size
(:func:`~growsim.fitting.setups.sweep_discrete`): the GA and the refinement seldom step
across an integer. For a model with the ``draws`` capability (Honda) the arrangement of
the branches is fitted too, after the GA and after each refinement (``arrange``
evaluations, :func:`~growsim.fitting.setups.arrange`): a picture's tree never has the
model's random arrangement. The searches before the last size score views blurred by
``blur`` pixels (partial credit for a branch near its place); every stage reports the
binary NCC. Every model is one :class:`~growsim.fitting.setups.FitSetup` in
:data:`~growsim.fitting.setups.FIT_SETUPS` (its tables, the parameters of its leaves and
of a bare tree, the views it has, its restarts, its arrangement search, its blur, the
file it is written to): adding a model is adding an entry. With one picture a 3D model's
front view is fitted and its side is left free (the silhouette objective's ``views =
"front"``).

Writes into ``out``: the first stage's run results (``config.toml``,
``history.parquet``, ``best.json``, ...; with several fits, one directory each:
``bare-0``, ``leafy-1``, ...), ``fit.json`` (every stage of the kept fit: size,
evaluations, seconds, NCC; the final parameters and the fitted arrangement, ``draws``;
``leaves``: which fit was kept and every fit's final NCC), the fitted tree
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
from growsim.fitting.setups import (
    FIT_SETUPS,
    LEAF_MARGIN,
    LEAF_MODES,
    SIZES,
    exact_score,
    fit_config,
    sweep_discrete,
)
from growsim.fitting.setups import arrange as search_arrangement
from growsim.fitting.setups import refine as refine_fit
from growsim.render import save_png

__all__ = ["FitResult", "fit_image", "raster_sizes"]

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


def raster_sizes(values) -> tuple[int, ...]:
    """The raster sizes of a coarse-to-fine fit, checked: increasing, each in 8..1024
    (``values``: ints, or a text such as ``"64,128,256"``). A bad list raises
    :class:`UserInputError`.

    Examples
    --------
    >>> raster_sizes("64,128, 256"), raster_sizes([32])
    ((64, 128, 256), (32,))
    >>> raster_sizes("128,64")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: expected increasing raster sizes in 8..1024, ... got '128,64'
    """
    try:
        if isinstance(values, str):
            sizes = tuple(int(v) for v in values.replace(",", " ").split())
        else:
            sizes = tuple(int(v) for v in values)
    except (TypeError, ValueError):
        sizes = ()
    if not sizes or any(not 8 <= v <= 1024 for v in sizes) or list(sizes) != sorted(set(sizes)):
        raise UserInputError(
            f"expected increasing raster sizes in 8..1024, e.g. '64,128,256', got {values!r}"
        )
    return sizes


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


def _evolve(plan, size: int, blur: float, out: Path, workers, progress: bool) -> _Fit:
    """The first stage of one fit: the setup's GA on ``plan`` (compiled at the first size,
    ``size``), run into ``out``; its row: size, evaluations, seconds, binary NCC (with
    ``blur``, the blurred ``score`` searched too)."""
    from growsim.experiment import run

    t0 = time.perf_counter()
    result = run(plan, out=out, workers=workers, progress=progress)
    fitness = plan.fitness()
    x = np.array([result.best_params[n] for n in fitness.evolved], dtype=np.float64)
    row = {
        "size": size,
        "stage": "ga",
        "evaluations": int(result.summary["evaluations"]),
        "seconds": round(time.perf_counter() - t0, 3),
        "ncc": exact_score(plan, x) if blur > 0 else float(result.best_fitness),
    }
    if blur > 0:
        row["score"] = float(result.best_fitness)
    return _Fit(plan, x, Path(result.out), stages=[row])


def _size_stages(fit: _Fit, k: int, config, sizes, setup, budgets, seed: int) -> None:
    """The searches of ``fit`` at ``sizes[k]``, in place: a refinement (at every size but
    the first, on the fit's config at that size, ``config(size, blur)``), the sweep of the
    discrete parameters (:func:`~growsim.fitting.setups.sweep_discrete`) and the search for
    the branches' arrangement (:func:`~growsim.fitting.setups.arrange`, for a model with
    the ``draws`` capability). ``budgets`` ``(refine, arrange, blur)``: the evaluations of
    each refinement and of each arrangement search (0: none), and the blur at the first
    size (scaled with the size; the searches at the last size are on the binary NCC). Each
    search appends its row to ``fit.stages`` (size, evaluations, seconds, binary NCC)."""
    from growsim.experiment import load_plan

    refine_evaluations, arrange_evaluations, blur = budgets
    size = sizes[k]

    def stage(name, evaluations, search):
        plan, x, draws = fit.plan, fit.x, fit.draws
        t = time.perf_counter()
        if name == "refine":
            x, score, start = search(plan, x, evaluations=evaluations, sigma=setup.refine_sigma,
                                     seed=seed * 1000 + k, draws=draws)  # fmt: skip
        elif name == "discrete":
            x, score, start, evaluations = search(plan, x, draws)
        else:
            draws, score, start = search(
                plan, x, draws, evaluations=evaluations, seed=seed * 1000 + 500 + k
            )
        fit.x, fit.draws = x, draws
        row = {"size": size, "stage": name, "evaluations": evaluations}
        row["seconds"] = round(time.perf_counter() - t, 3)
        if plan.objectives[0].blur > 0:
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


def _write_fits(objective, fitted, out: Path) -> list[Path]:
    """The fitted tree's views framed as the target: ``fit_<view>.png`` (black on white),
    the size and placement of ``silhouette_<view>.png``
    (:func:`~growsim.pictures.images.unframe`), so it can be scored any way."""
    from growsim.pictures.images import unframe

    masks = list(objective.pictures.values())[: objective.n_views]
    written = []
    for i, view in enumerate(list(objective.pictures)[: objective.n_views]):
        back = unframe(fitted[i], *masks, view=i, line_width=objective.line_width)
        written.append(save_png(np.where(back, 0, 255).astype(np.uint8), out / f"fit_{view}.png"))
    return written


#: ``segmentation`` of :func:`fit_image`: ``"auto"`` (a drawing by the threshold, a photo by
#: the photo segmentation: :func:`~growsim.pictures.images.classify_picture`)
SEGMENTATIONS = ("auto", "photo", "threshold")


def _choices(front, side, setup, segmentation, line_width, sizes, size, leaves) -> dict:
    """What :func:`fit_image` chose for the user, each ``{"value": ..., "why": ...}``:
    ``segmentation`` (``"auto"``: the threshold for drawings, all pictures
    :func:`~growsim.pictures.images.classify_picture` ``"drawing"``, else the photo
    segmentation), and, unless given, what follows from it: ``line_width`` (a drawing:
    ``"thin"``, the renderer's 1-pixel lines; a photo: the model's), ``sizes`` (a drawing:
    :attr:`~growsim.fitting.setups.FitSetup.drawing`; a photo: :data:`~growsim.fitting.setups.SIZES`) and ``leaves``
    (a drawing: ``"keep"``, the setup's tree as the seed fitted it; a photo: ``"auto"``)."""
    from growsim.pictures.images import classify_picture

    choices: dict[str, dict] = {}
    if segmentation == "auto":
        kinds = [(p, *classify_picture(p)) for p in (front, side) if p is not None]
        drawing = all(k == "drawing" for _, k, _ in kinds)
        why = "; ".join(f"{Path(p).name}: {w}" for p, _, w in kinds)
        value = "threshold" if drawing else "photo"
    else:
        drawing, why, value = segmentation == "threshold", "given", segmentation
    choices["segmentation"] = {"value": value, "why": why}
    kind = "a drawing" if drawing else "a photo"
    if line_width is not None:
        choices["line_width"] = {"value": line_width, "why": "given"}
    elif drawing:
        choices["line_width"] = {"value": "thin", "why": f"{kind}: 1-pixel lines, as drawn"}
    else:
        drawn = "branches at their width" if setup.line_width == "radius" else "thin lines"
        why = f"{kind}: the model's ({drawn})"
        choices["line_width"] = {"value": setup.line_width, "why": why}
    if size is not None:
        choices["sizes"] = {"value": [int(size)], "why": "given (--size)"}
    elif sizes is not None:
        choices["sizes"] = {"value": list(raster_sizes(sizes)), "why": "given"}
    elif drawing:
        why = f"{kind}: the lines frame exactly, no photo's refinement"
        choices["sizes"] = {"value": list(setup.drawing["sizes"]), "why": why}
    else:
        choices["sizes"] = {"value": list(SIZES), "why": f"{kind}: coarse to fine"}
    if leaves is not None:
        choices["leaves"] = {"value": leaves, "why": "given"}
    elif drawing:
        choices["leaves"] = {"value": "keep", "why": f"{kind}: the model's setup, as drawn"}
    else:
        why = f"{kind}: a bare and a leafy tree, the better kept"
        choices["leaves"] = {"value": "auto", "why": why}
    return choices


def _write_shape(phenotype, path: Path) -> None:
    """The fitted tree written to ``path``: a ``.png`` file its front view's picture,
    any other a mesh (:func:`growsim.phenotypes.plant.mesh.export`: ``.glb``, ...)."""
    if path.suffix.lower() == ".png":
        phenotype.screenshot(path, view="front")
    else:
        from growsim.phenotypes.plant.mesh import export

        export(phenotype, path)


def fit_image(
    front: str | os.PathLike,
    side: str | os.PathLike | None = None,
    *,
    out: str | os.PathLike,
    model: str = "ifs3d",
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
    """Fit ``model`` to the picture ``front`` of a tree, or to it and a ``side`` picture
    (from the right), into the results directory ``out`` (see the module docstring for the
    stages and the files written); returns the kept fit (:class:`FitResult`).

    The keywords are ``growsim fit-image``'s options, with its defaults: ``segmentation``
    (``"auto"``: by the picture, see the module docstring; ``"photo"`` or
    ``"threshold"``, with ``threshold``, ``"otsu"`` or a grey level, and ``polarity``,
    ``"auto"``, ``"dark"`` or ``"light"``); ``sizes``, the raster sizes coarse to fine
    (``size``: one size only, no refinement); ``line_width`` (``"radius"`` or
    ``"thin"``); ``leaves`` (:data:`~growsim.fitting.setups.LEAF_MODES`); ``None`` for
    these three: chosen by the segmentation (:func:`_choices`); ``mask_front``, ``mask_side``: mask
    pictures (only their white part may be tree); ``evaluations``: of the first stage
    (>= 100; the setup's polish share kept); ``refine``, ``arrange``: evaluations of the
    refinement at each finer size and of each arrangement search (0: none); ``blur``:
    sigma of the searches at the first size (pixels, scaled with the size; 0 at the last
    size); ``seed``: of the first restart; ``restarts``, ``carry``: fits of each kind of
    tree, and how many of them go on past the first size (0: all); ``workers``: local
    processes evaluating; ``progress``: a progress bar. ``None``: the model's own
    (:data:`~growsim.fitting.setups.FIT_SETUPS`). Bad options and pictures raise
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
    setup = FIT_SETUPS.get(model)
    choices = _choices(front, side, setup, segmentation, line_width, sizes, size, leaves)
    segmentation, line_width, leaves, sizes = (
        choices[k]["value"] for k in ("segmentation", "line_width", "leaves", "sizes")
    )
    if segmentation == "threshold":  # a drawing: the setup's keywords for drawings
        given = dict(restarts=restarts, carry=carry, evaluations=evaluations, refine=refine,
                     blur=blur)  # fmt: skip
        given = {k: setup.drawing.get(k) if v is None else v for k, v in given.items()}
        restarts, carry, evaluations, refine, blur = given.values()
    restarts = setup.restarts if restarts is None else restarts
    if restarts < 1:
        raise UserInputError(f"--restarts: at least 1, got {restarts}")
    carry = setup.carry if carry is None else carry
    if carry < 0:
        raise UserInputError(f"--carry: at least 0, got {carry}")
    if leaves not in LEAF_MODES:
        raise UserInputError(f"--leaves: expected one of {', '.join(LEAF_MODES)}, got {leaves!r}")
    sizes = raster_sizes(sizes)
    refine_evaluations = setup.refine if refine is None else refine
    arrange_evaluations = setup.arrange if arrange is None else arrange
    if arrange_evaluations < 0:
        raise UserInputError(f"--arrange: at least 0, got {arrange_evaluations}")
    blur = setup.blur if blur is None else blur
    widest = blur * (sizes[-2] if len(sizes) > 1 else sizes[0]) / sizes[0]
    if not (0.0 <= blur and widest <= 16.0):
        raise UserInputError(
            f"--blur: expected 0 or more pixels, at most 16 at the next-to-last size "
            f"(the blur grows with the size), got {blur:g} ({widest:g} at that size)"
        )
    kw = dict(model=model, threshold=threshold, polarity=polarity, mask_front=mask_front,
              mask_side=mask_side, line_width=line_width, evaluations=evaluations,
              segmentation=segmentation)  # fmt: skip
    if leaves == "auto":
        # a bare and a leafy tree, when the model has leaves to choose
        modes = ("bare", "fit") if setup.leaves and setup.bare else ("keep",)
    else:
        modes = (leaves,)
    runs = [(m, seed + r) for m in modes for r in range(restarts)]
    out_dir = Path(out)
    t0 = time.perf_counter()

    def config(size, m, seed, sigma=0.0):
        return fit_config(front, side, size=size, leaves=m, seed=seed, blur=sigma, **kw)

    # compiling builds the objective once: bad pictures fail here, before any evolution
    first = {run_: load_plan(config(sizes[0], *run_, blur)) for run_ in runs}
    budgets = (refine_evaluations, arrange_evaluations, blur)

    fits: dict[tuple[str, int], _Fit] = {}
    for m, s in runs:
        name = KINDS[m] if m != "keep" else "run"
        if restarts > 1:
            name += f"-{s}"
        run_out = out_dir / name if len(runs) > 1 else out_dir
        fits[m, s] = _evolve(first[m, s], sizes[0], blur, run_out, workers, progress)
        _size_stages(fits[m, s], 0, lambda size, sigma, m=m, s=s: config(size, m, s, sigma),
                     sizes, setup, budgets, s)  # fmt: skip
    # every restart's binary NCC at the end of the first size
    first_size = {f"{KINDS[m]} seed {s}": f.ncc for (m, s), f in fits.items()}
    # the restarts of each kind that scored best at the first size go on to the finer
    # sizes (the score there foretells the final one: benchmarks/log/fitting.md)
    carried = []
    for m in modes:
        ranked = sorted((r for r in runs if r[0] == m), key=lambda r: -fits[r].ncc)
        carried += ranked[: carry or len(ranked)]
    fits = {r: fits[r] for r in runs if r in carried}
    for (m, s), f in fits.items():
        for k in range(1, len(sizes)):
            _size_stages(f, k, lambda size, sigma, m=m, s=s: config(size, m, s, sigma),
                         sizes, setup, budgets, s)  # fmt: skip
    # per kind of tree its best restart at the final size, then bare or leafy
    best: dict[str, _Fit] = {}
    for (m, _), f in fits.items():
        if m not in best or f.ncc > best[m].ncc:
            best[m] = f
    chosen = modes[0]
    if len(modes) > 1:
        chosen = "fit" if best["fit"].ncc > best["bare"].ncc + LEAF_MARGIN else "bare"
    kept = best[chosen]
    plan, x, draws = kept.plan, kept.x, kept.draws
    objective = plan.objectives[0]
    out = kept.out if len(runs) == 1 else out_dir
    out.mkdir(parents=True, exist_ok=True)
    leaves_summary = {
        "mode": leaves,
        "chosen": KINDS[chosen],
        "ncc": {KINDS[m]: f.ncc for m, f in best.items()},
        "run": str(kept.out),
        "runs": {
            f"{KINDS[m]} seed {s}": {"ncc": f.ncc, "out": str(f.out)} for (m, s), f in fits.items()
        },
        "first_size": first_size,
    }
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
    pictures = {"front": front, "side": side}
    written = _write_masks(objective, out, pictures)
    written += _write_fits(objective, fitted, out)
    summary = {
        "model": model,
        "pictures": {k: str(v) for k, v in pictures.items() if v is not None},
        "views": ["front", "side"][: objective.n_views],
        "ncc": float(np.mean(views)),
        "ncc_views": dict(zip(("front", "side"), views)),
        "size": objective.size,
        "seconds": round(time.perf_counter() - t0, 3),
        "stages": kept.stages,
        "leaves": leaves_summary,
        # what was chosen for the user (segmentation, line width, sizes, leaves) and why
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
        model=model,
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
