"""The write stage of :func:`growsim.fitting.fit_image` (:mod:`growsim.fitting.stages`):
``fit.json``, the pictures of the fit beside its targets, and for a reconstruction its
tree's meshes, skeleton over the photograph, Honda parameters and branch statistics.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from growsim.experiment.results import RunDir
from growsim.files import atomic_write, jsonable
from growsim.fitting.options import FitOptions
from growsim.fitting.stages import (
    KINDS,
    Grown,
    Judged,
    Reconstructed,
    Runs,
    Searched,
    Segmented,
)
from growsim.phenotypes.plant.mesh import export
from growsim.pictures.images import (
    silhouette_image,
)
from growsim.pictures.photo import load_rgb, segmentation_picture
from growsim.reconstruction import (
    Reconstruction,
    compare_statistics,
    skeleton_picture,
    trees_picture,
)
from growsim.reconstruction.judge import JUDGE_SIZE
from growsim.render import save_png

__all__ = ["write"]


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


def _write_pictures(objective, out: Path, judged: Judged, options: FitOptions,
                    segmented: Segmented) -> list[Path]:  # fmt: skip
    """``silhouettes.png`` (target and fit at the size judged), the masks used
    (:func:`_write_masks`) and ``fit_<view>.png`` (the fit framed as the pictures): the
    files written after the tree, ``silhouettes.png`` first."""
    target = objective.target if judged.target is None else judged.target
    n = len(judged.views)
    titles = [
        f"{v} target" if i % 2 == 0 else f"{v} fit" for v in ("front", "side") for i in (0, 1)
    ]
    panels = [a for i in range(n) for a in (target[i], judged.fitted[i])]
    written = [silhouette_image(panels, out / "silhouettes.png", titles=titles[: len(panels)],
                                scale=2)]  # fmt: skip
    paths = {"front": options.front, "side": options.side}
    written += _write_masks(objective, out, paths, segmented.found)
    for view, back in judged.framed.items():
        written.append(save_png(np.where(back, 0, 255).astype(np.uint8), out / f"fit_{view}.png"))
    return written[1:]


def _pictures(options: FitOptions) -> dict[str, str]:
    """``fit.json``'s ``pictures``: the pictures' paths by view."""
    paths = {"front": options.front, "side": options.side}
    return {k: str(v) for k, v in paths.items() if v is not None}


def _statistics(rec: Reconstruction, regrown) -> pd.DataFrame:
    """The branch statistics of the photo's tree beside the regrown Honda tree's, one row
    per tree and order (:func:`~growsim.reconstruction.order_summary`) and one per tree
    over every order (``order`` ``"all"``: the figures of
    :func:`~growsim.reconstruction.tree_summary`)."""
    summary, per_order = compare_statistics({"photo": rec.plant, "honda": regrown})
    per_order = per_order.astype({"order": object})
    whole = summary.T.rename_axis("tree").reset_index().assign(order="all")
    return pd.concat([per_order, whole], ignore_index=True)


def _write_reconstruction(runs: Runs, segmented: Segmented, found: Reconstructed, tree: Grown,
                          judged: Judged, seconds) -> tuple[Path, dict, list[Path]]:  # fmt: skip
    """A reconstruction's files, into the fit's ``out_dir``: the tree's meshes
    (``tree.glb``, ``tree.obj``, ``tree.vtp``), ``best_plant.npz``, ``best.json`` and
    ``config.toml`` (what ``growsim show DIR`` reads: the tree saved, the fit's first
    plan), the pictures as a search's (:func:`_write_pictures`), ``skeleton_front.png``
    (the visible skeleton over the photograph), ``model.json`` (the Honda parameters
    inferred, for ``growsim grow honda --params``), ``stats.csv`` (:func:`_statistics`),
    ``trees.png`` (the photo's tree and the regrown one, front and side) and ``fit.json``."""
    chosen, options, rec = runs.chosen, runs.options, found.rec
    plan = found.plan
    objective = plan.objectives[0]
    out = runs.out_dir
    out.mkdir(parents=True, exist_ok=True)
    meshes = [export(rec.plant, out / f"tree.{suffix}") for suffix in ("glb", "obj", "vtp")]
    rd = RunDir(out)
    rd.write_text("config.toml", plan.config.to_toml())
    saved = rec.plant.save(rd.phenotype_path("plant"))
    mean = float(np.mean(judged.views))
    rd.write_best(fitness=mean, generation=0, params=tree.params, evolved=[], model="honda",
                  phenotype="plant", plant_seed=options.seed, terms={})  # fmt: skip
    written = _write_pictures(objective, out, judged, options, segmented)
    photo = load_rgb(options.front)
    mask = found.masks["front"]
    if photo.shape[:2] != mask.shape:  # the silhouette at another size: draw over it
        photo = mask
    written.append(skeleton_picture(rec, photo, out / "skeleton_front.png"))
    model = {"model": "honda", "params": tree.params,
             "about": "Honda's parameters inferred from the reconstructed tree's branch "
                      "statistics (stats.csv): growsim grow honda --params model.json "
                      "grows a tree of this kind"}  # fmt: skip
    text = json.dumps(jsonable(model), indent=1)
    written.append(atomic_write(out / "model.json", lambda fh: fh.write(text.encode())))
    stats = _statistics(rec, tree.regrown)
    written.append(atomic_write(out / "stats.csv", lambda fh: fh.write(
        stats.to_csv(index=False, float_format="%.4g").encode())))  # fmt: skip
    written.append(trees_picture([rec.plant, tree.regrown], out / "trees.png",
                                 titles=["photo", "honda"]))  # fmt: skip
    n_views = len(judged.views)
    stage = {"size": JUDGE_SIZE, "stage": "reconstruct", "evaluations": 0,
             "seconds": round(found.seconds, 3), "ncc": mean}  # fmt: skip
    kind = "leafy" if rec.leafy else "bare"
    summary = {
        "model": "reconstruction",
        "method": "reconstruct",
        "reconstruction": {
            "method": rec.method,
            "leafy": rec.leafy,
            "metres_per_pixel": rec.scale,
            "segments": int(rec.plant.n_segments),
            "visible_branches": len(rec.skeleton.branches),
        },
        # every prior and setting the reconstruction took (what the picture cannot say)
        "assumptions": rec.assumptions,
        "pictures": _pictures(options),
        "views": ["front", "side"][:n_views],
        "ncc": mean,
        "ncc_views": dict(zip(("front", "side"), judged.views)),
        "size": JUDGE_SIZE,
        "area_ratio": judged.areas,
        "score": mean,
        "seconds": seconds(),
        "stages": [stage],
        "models": {"reconstruction": mean},
        "leaves": {
            "mode": "auto",
            "chosen": kind,
            "first_size": {},
            "why": "the crown's share thicker than the trunk (assumptions' leafy_rule)",
        },
        "choices": {"segmentation": chosen.segmentation, "method": chosen.method},
        "segmentation": {view: seg.record() for view, seg in segmented.found.items()},
        # Honda's parameters inferred from the tree (model.json): a tree of this kind
        "params": tree.params,
        "draws": None,
        "files": [
            meshes[0].name,
            "silhouettes.png",
            *[w.name for w in written],
            *[m.name for m in meshes[1:]],
            saved.name,
            "best.json",
            "config.toml",
        ],
    }
    text = json.dumps(jsonable(summary), indent=1)
    atomic_write(out / "fit.json", lambda fh: fh.write(text.encode()))
    files = [meshes[0], out / "silhouettes.png", *written, *meshes[1:]]
    return out, summary, files


def write(runs: Runs, segmented: Segmented, found: Searched | Reconstructed, tree: Grown,
          judged: Judged, seconds) -> tuple[Path, dict, list[Path]]:  # fmt: skip
    """The last stage: the fit's files into its directory (the fit's ``out_dir``, or the
    run's when it had one run): the fitted tree (the setup's
    :attr:`~growsim.fitting.setups.FitSetup.shape`: ``tree.glb``, a 2D model's
    ``attractor.png``), ``silhouettes.png`` (target and fit at the fit's size),
    ``silhouette_<view>.png`` and ``segmentation_<view>.png`` (the silhouettes used, and
    how they were found), ``fit_<view>.png`` (the fit framed as the pictures) and
    ``fit.json`` (every stage of the kept fit, the choices, the candidates' scores);
    ``seconds()``: the fit's time so far; a reconstruction's files
    (:func:`_write_reconstruction`). Returns the directory, ``fit.json``'s content and the
    files written before it (the tree first).

    Examples
    --------
    >>> out, summary, files = write(runs, segmented, found, tree, judged, clock)  # doctest: +SKIP
    >>> files[0].name, sorted(summary)[:3]  # doctest: +SKIP
    ('tree.glb', ['area_ratio', 'budget', 'choices'])
    """
    if isinstance(found, Reconstructed):
        return _write_reconstruction(runs, segmented, found, tree, judged, seconds)
    chosen, options, kept = runs.chosen, runs.options, found.run
    st = chosen.settings[found.model]
    objective = tree.plan.objectives[0]
    out = kept.out if len(chosen.runs) == 1 else runs.out_dir
    out.mkdir(parents=True, exist_ok=True)
    shape = out / st["setup"].shape
    if shape.suffix.lower() == ".png":  # a picture of its front view, else a mesh
        tree.phenotype.screenshot(shape, view="front")
    else:
        export(tree.phenotype, shape)
    written = _write_pictures(objective, out, judged, runs.options, segmented)
    leaves_summary = {
        "mode": st["leaves"],
        "chosen": KINDS[found.mode],
        # the score of each kind of the kept model's best fit at the first size, judged at
        # the final size
        "score": {KINDS[mode]: v for (m, mode), v in found.judged.items() if m == found.model},
        "run": str(kept.out),
        "runs": {
            runs.label(r): {
                "ncc": found.fits[r].ncc,
                "score": found.fits[r].score,
                "out": str(found.fits[r].out),
            }
            for r in found.carried
        },
        "first_size": found.first_size,
    }
    models_summary = {m: max(v for (mm, _), v in found.judged.items() if mm == m)
                      for m in found.names}  # fmt: skip
    choices = {"segmentation": chosen.segmentation, "model": found.model_choice, **st["choices"]}
    # a photo's: searched and why (a drawing's fit.json as ever, unless --method was given)
    recorded = not chosen.drawing or options.method != "auto"
    if recorded:
        choices["method"] = chosen.method
    method = {"method": "search"} if recorded else {}
    summary = {
        "model": found.model,
        **method,
        "pictures": _pictures(options),
        "views": ["front", "side"][: objective.n_views],
        "ncc": float(np.mean(judged.views)),
        "ncc_views": dict(zip(("front", "side"), judged.views)),
        "size": objective.size,
        # the fit's area over the target's in each view, at the picture's size
        # (fit_<view>.png against silhouette_<view>.png)
        "area_ratio": judged.areas,
        "score": kept.score,
        "seconds": seconds(),
        "budget": options.budget,
        "stages": kept.stages,
        "models": models_summary,
        "leaves": leaves_summary,
        # what was chosen for the user (segmentation, model, line width, sizes, leaves)
        # and why
        "choices": choices,
        # how each photo's tree was found (method, hint, horizon, skyline, contrast, ...)
        "segmentation": {view: seg.record() for view, seg in segmented.found.items()},
        "params": tree.params,
        # the arrangement of the branches fitted to the picture (None: the model's own):
        # model.develop(params, draws=np.array(draws)) grows the fitted tree
        "draws": None if tree.draws is None else tree.draws.tolist(),
        "files": [shape.name, "silhouettes.png", *[w.name for w in written]],
    }
    text = json.dumps(jsonable(summary), indent=1)
    atomic_write(out / "fit.json", lambda fh: fh.write(text.encode()))
    return out, summary, [shape, out / "silhouettes.png", *written]
