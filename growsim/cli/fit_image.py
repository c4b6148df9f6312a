"""``growsim fit-image PICTURE [SIDE]``: fit a tree model to one picture, or to a front and
a side picture.

The pictures become silhouettes (:mod:`growsim.pictures.images`: by default the photo segmentation,
the tree apart from sky and ground; ``--segmentation threshold`` for clean drawings); a
bad segmentation is refused with a message naming the picture. The model is fitted coarse
to fine: the setup's GA (and polish) at the first of ``--sizes`` (64 px), then a local
refinement of the best at each finer size (128, 256 px), so branch structure counts. With
``--leaves auto`` (the default) a bare and a leafy tree are both fitted and the leafy one
is kept only if clearly better (:data:`LEAF_MARGIN`), so a winter tree is fitted by a bare
tree; each kind is fitted ``--restarts`` times (GA seeds), the ``--carry`` that scored
best at the end of the first size go on to the finer sizes, and the best at the final size
is kept. Every value of a discrete parameter (the leaves per branch) is tried at every
size (:func:`growsim.fitting.setups.sweep_discrete`): the GA and the refinement seldom step
across an integer. For a model with random draws (Honda's ``draws`` capability) the
arrangement of the branches is fitted too, after the GA and after each refinement (``--arrange``,
:func:`growsim.fitting.setups.arrange`): a picture's tree never has the model's random
arrangement. The searches before the last size score views blurred by ``--blur`` pixels
(partial credit for a branch near its place); every stage reports the binary NCC. Every
model is one :class:`FitSetup` in :data:`FIT_SETUPS` (its tables, the parameters of its
leaves and of a bare tree, the views it has, its restarts, its arrangement search and
blur): adding a model is adding an entry. With one picture a 3D model's front view is
fitted and its side is left free (the silhouette objective's ``views = "front"``).

Writes into ``--out``: the first stage's run results (``config.toml``, ``history.parquet``,
``best.json``, ...; with several fits, one directory each: ``bare-0``, ``leafy-1``, ...),
``fit.json`` (every stage of the kept fit: size, evaluations, seconds, NCC; the final
parameters and the fitted arrangement, ``draws``; ``leaves``: which fit was kept and every
fit's final NCC), ``tree.glb`` (the
fitted tree), ``silhouette_<view>.png`` (the silhouette used, at the picture's size) and
``segmentation_<view>.png`` (it over the picture), and ``silhouettes.png`` (target and
fit, framed, at the final size).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

from growsim.errors import UserInputError
from growsim.fitting.setups import (
    FIT_SETUPS,
    LEAF_MARGIN,
    LEAF_MODES,
    SIZES,
    arrange,
    exact_score,
    fit_config,
    refine,
    sweep_discrete,
)

__all__ = ["register"]


def _threshold(text: str):
    if text == "otsu":
        return text
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 < value < 1.0:
        raise argparse.ArgumentTypeError(
            f"expected 'otsu' or a grey level between 0 (black) and 1 (white), got {text!r}"
        )
    return value


def _sizes(text: str) -> tuple[int, ...]:
    try:
        sizes = tuple(int(v) for v in text.replace(",", " ").split())
    except ValueError:
        sizes = ()
    if not sizes or any(not 8 <= v <= 1024 for v in sizes) or list(sizes) != sorted(set(sizes)):
        raise argparse.ArgumentTypeError(
            f"expected increasing raster sizes in 8..1024, e.g. '64,128,256', got {text!r}"
        )
    return sizes


def register(subparsers) -> None:
    """Add the ``fit-image`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> args = build_parser().parse_args(["fit-image", "f.png", "s.png", "--out", "o",
    ...                                   "--line-width", "radius", "--sizes", "64,128"])
    >>> args.line_width, args.sizes, args.side
    ('radius', (64, 128), 's.png')
    >>> build_parser().parse_args(["fit-image", "tree.jpg", "--out", "o"]).side is None
    True
    """
    p = subparsers.add_parser(
        "fit-image",
        help="fit a tree to one picture, or to a front and a side picture (PNG/JPEG)",
        description="Fit a tree model to a picture of a tree (the front view; its side is "
        "left free), or to a front and a side picture. Each picture becomes a silhouette: "
        "by default the photo segmentation separates the tree from the sky and the ground "
        "(colour and connectivity), refusing pictures it cannot read (no plain sky, the tree "
        "cut off, no contrast, other objects); --segmentation threshold reads clean "
        "drawings by a grey threshold. The model is fitted coarse to fine (--sizes, default "
        "64,128,256: the GA at the first, a refinement at each next), with its leaves (a "
        "bare tree is fitted by a bare tree) and, for Honda, the arrangement of its branches "
        "(where the limbs go). Writes the run's results, fit.json (NCC and "
        "seconds per stage), tree.glb, the silhouettes used (silhouette_<view>.png, "
        "segmentation_<view>.png) and silhouettes.png (target against fit) into --out.",
    )
    p.add_argument("front", help="the picture (PNG, JPEG, ...; any size): the tree's front")
    p.add_argument("side", nargs="?", default=None, help="optional side picture (from the right)")
    p.add_argument(
        "--model",
        default="ifs3d",
        help="model to fit: " + ", ".join(FIT_SETUPS) + " (default ifs3d)",
    )
    p.add_argument("--out", required=True, help="results directory (must not hold a run)")
    p.add_argument(
        "--sizes",
        type=_sizes,
        default=SIZES,
        metavar="PX,PX,..",
        help="raster sizes, coarse to fine (default 64,128,256): the GA at the first, a "
        "local refinement at each next",
    )
    p.add_argument(
        "--size",
        type=int,
        default=None,
        metavar="PX",
        help="one raster size only, 8..1024 (no refinement; same as --sizes PX)",
    )
    p.add_argument(
        "--segmentation",
        choices=("photo", "threshold"),
        default="photo",
        help="photo (default): the tree apart from sky and ground, in colour; threshold: "
        "grey levels (--threshold, --polarity), for clean drawings and silhouettes",
    )
    p.add_argument(
        "--threshold",
        type=_threshold,
        default="otsu",
        metavar="otsu|LEVEL",
        help="with --segmentation threshold: 'otsu' (default) or a grey level strictly "
        "between 0 (black) and 1 (white), e.g. 0.4",
    )
    p.add_argument(
        "--polarity",
        choices=("auto", "dark", "light"),
        default="auto",
        help="with --segmentation threshold: dark tree on light, light on dark, or auto "
        "(the class covering less of the picture's border is the tree)",
    )
    p.add_argument(
        "--line-width",
        choices=("thin", "radius"),
        default=None,
        help="how the fitted tree is drawn: radius (default: branches as wide as their "
        "tubes, as photos show them) or thin (1-pixel lines: line drawings such as the "
        "paper's 64x64 silhouettes; ifs3d's fast path)",
    )
    p.add_argument(
        "--leaves",
        choices=LEAF_MODES,
        default="auto",
        help="auto (default): fit a bare and a leafy tree, keep the better (the leafy one "
        "only if clearly better); fit: fit the leaves; bare: no leaves; keep: the setup's "
        "leaves, fixed",
    )
    p.add_argument(
        "--no-leaves",
        dest="leaves",
        action="store_const",
        const="keep",
        help="same as --leaves keep",
    )
    for view in ("front", "side"):
        p.add_argument(
            f"--mask-{view}",
            default=None,
            metavar="PICTURE",
            help=f"mask picture for the {view} view (the picture's size; only its white part "
            "may be tree): for hard pictures",
        )
    p.add_argument(
        "--evaluations",
        type=int,
        default=None,
        metavar="N",
        help="fitness evaluations of the first stage, >= 100 (default: ifs3d 50,000, honda "
        "7,500); the setup's share for its polish is kept (ifs3d 70 %%, honda 20 %%)",
    )
    p.add_argument(
        "--refine",
        type=int,
        default=None,
        metavar="N",
        help="evaluations of the refinement at each finer size (default: the model's, "
        "honda 1,000, ifs3d 600)",
    )
    p.add_argument(
        "--arrange",
        type=int,
        default=None,
        metavar="N",
        help="evaluations of the search for the arrangement of the branches at each size "
        "(where the limbs go: the model's random draws fitted to the picture; default: the "
        "model's, honda 2,000; 0: the model's own random arrangement)",
    )
    p.add_argument(
        "--blur",
        type=float,
        default=None,
        metavar="SIGMA",
        help="search on views blurred by SIGMA pixels at the first size (scaled with the "
        "size; partial credit for a branch near its place: helps sparse trees of thin "
        "twigs), the binary NCC at the last size (default 0: the binary NCC throughout)",
    )
    p.add_argument(
        "--seed", type=int, default=0, metavar="N", help="random seed of the run (default 0)"
    )
    p.add_argument(
        "--restarts",
        type=int,
        default=None,
        metavar="N",
        help="independent fits (seeds SEED, SEED+1, ...) of each kind of tree, the best at "
        "the final size kept (default: the model's, honda 8, ifs3d 1)",
    )
    p.add_argument(
        "--carry",
        type=int,
        default=None,
        metavar="N",
        help="restarts of each kind of tree carried past the first size: the N that scored "
        "best at its end (default: the model's, honda 2; 0: all)",
    )
    p.add_argument(
        "--workers", type=int, default=None, metavar="N", help="evaluate in N local processes"
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_main)


def _write_masks(objective, out: Path, pictures: dict) -> list[str]:
    """The silhouettes used, at the pictures' size: ``silhouette_<view>.png`` (black tree
    on white) and ``segmentation_<view>.png`` (the picture, the tree tinted red)."""
    from PIL import Image

    from growsim.files import atomic_write
    from growsim.pictures.photo import load_rgb

    written = []
    for view, mask in objective.pictures.items():
        sil = Image.fromarray(np.where(mask, 0, 255).astype(np.uint8))
        path = out / f"silhouette_{view}.png"
        atomic_write(path, lambda fh, im=sil: im.save(fh, format="PNG"))
        rgb = load_rgb(pictures[view])
        over = 0.35 * rgb + 0.65  # washed out, the tree in red over it
        over[mask] = 0.4 * rgb[mask] + 0.6 * np.array([1.0, 0.0, 0.0])
        im = Image.fromarray(np.round(255 * over).astype(np.uint8))
        path2 = out / f"segmentation_{view}.png"
        atomic_write(path2, lambda fh, im=im: im.save(fh, format="PNG"))
        written += [str(path), str(path2)]
    return written


def _evolve(plan, size, args, blur, out) -> dict:
    """The first stage of one fit: the setup's GA on ``plan`` (compiled at the first
    size, ``size``), run into ``out``. Returns the fit's state for :func:`_size_stages`:
    its plan, the evolved parameters ``x``, the arrangement ``draws`` (``None``: the
    model's own), the stages so far (the GA's row: size, evaluations, seconds, binary NCC;
    with ``blur``, the blurred ``score`` searched too) and the run's directory."""
    from growsim.experiment import run

    t0 = time.perf_counter()
    result = run(plan, out=out, workers=args.workers, progress=not args.quiet)
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
    return {"plan": plan, "x": x, "draws": None, "stages": [row], "out": Path(result.out)}


def _size_stages(fit, k, config, sizes, setup, budgets, seed) -> None:
    """The searches of one fit's state ``fit`` (:func:`_evolve`) at ``sizes[k]``, in
    place: a refinement (at every size but the first, on the fit's config at that size,
    ``config(size, blur)``), the sweep of the discrete parameters
    (:func:`growsim.fitting.setups.sweep_discrete`) and the search for the branches' arrangement
    (:func:`growsim.fitting.setups.arrange`, for a model with random draws). ``budgets``
    ``(refine, arrange, blur)``: the evaluations of each refinement and of each
    arrangement search (0: none), and the blur at the first size (scaled with the size;
    the searches at the last size are on the binary NCC). Each search appends its row to
    ``fit["stages"]`` (size, evaluations, seconds, binary NCC)."""
    from growsim.experiment import load_plan

    refine_evaluations, arrange_evaluations, blur = budgets
    size = sizes[k]

    def stage(name, evaluations, search):
        plan, x, draws = fit["plan"], fit["x"], fit["draws"]
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
        fit["x"], fit["draws"] = x, draws
        row = {"size": size, "stage": name, "evaluations": evaluations}
        row["seconds"] = round(time.perf_counter() - t, 3)
        if getattr(plan.objectives[0], "blur", 0.0) > 0:
            row["score_start"], row["score"] = start, score
            row["ncc"] = exact_score(plan, x, draws)
        else:
            row["ncc_start"], row["ncc"] = start, score
        fit["stages"].append(row)

    # blurred at every size but the last, whose searches are on the score reported
    sigma = blur * size / sizes[0] if k < len(sizes) - 1 else 0.0
    if k > 0:
        fit["plan"] = load_plan(config(size, sigma))
        stage("refine", refine_evaluations, refine)
    elif blur > 0 and sigma == 0:  # one size: the GA's score was blurred
        fit["plan"] = load_plan(config(size, 0.0))
    # the discrete parameters (leaves per branch): every value tried at every size
    genome = fit["plan"].genome
    if np.any(genome.discrete & (genome.param_high - genome.param_low >= 1)):
        stage("discrete", 0, sweep_discrete)
    if arrange_evaluations > 0 and getattr(fit["plan"].model, "draws", None) is not None:
        stage("arrange", arrange_evaluations, arrange)


def _main(args) -> int:
    from growsim.experiment import load_plan
    from growsim.files import atomic_write, jsonable
    from growsim.objectives.silhouette import phenotype_views
    from growsim.phenotypes.plant.mesh import export
    from growsim.pictures.images import silhouette_image

    if args.evaluations is not None and args.evaluations < 100:
        raise UserInputError(f"--evaluations: at least 100, got {args.evaluations}")
    if args.refine is not None and args.refine < 0:
        raise UserInputError(f"--refine: at least 0, got {args.refine}")
    if args.size is not None and not 8 <= args.size <= 1024:
        raise UserInputError(f"--size: expected 8..1024, got {args.size}")
    setup = FIT_SETUPS.get(args.model)
    sizes = (args.size,) if args.size is not None else tuple(args.sizes)
    refine_evaluations = setup.refine if args.refine is None else args.refine
    arrange_evaluations = setup.arrange if args.arrange is None else args.arrange
    if arrange_evaluations < 0:
        raise UserInputError(f"--arrange: at least 0, got {arrange_evaluations}")
    blur = setup.blur if args.blur is None else args.blur
    widest = blur * (sizes[-2] if len(sizes) > 1 else sizes[0]) / sizes[0]
    if not (0.0 <= blur and widest <= 16.0):
        raise UserInputError(
            f"--blur: expected 0 or more pixels, at most 16 at the next-to-last size "
            f"(the blur grows with the size), got {blur:g} ({widest:g} at that size)"
        )
    options = ("model", "threshold", "polarity", "mask_front", "mask_side", "line_width")
    options += ("evaluations", "segmentation")
    kw = {k: getattr(args, k) for k in options}
    restarts = setup.restarts if args.restarts is None else args.restarts
    if restarts < 1:
        raise UserInputError(f"--restarts: at least 1, got {restarts}")
    carry = setup.carry if args.carry is None else args.carry
    if carry < 0:
        raise UserInputError(f"--carry: at least 0, got {carry}")
    mode = args.leaves
    if mode == "auto":
        # a bare and a leafy tree, when the model has leaves to choose
        modes = ("bare", "fit") if setup.leaves and setup.bare else ("keep",)
    else:
        modes = (mode,)
    label = {"fit": "leafy", "bare": "bare", "keep": "setup's"}
    runs = [(m, args.seed + r) for m in modes for r in range(restarts)]
    out_dir = Path(args.out)
    t0 = time.perf_counter()

    def config(size, m, seed, sigma=0.0):
        return fit_config(args.front, args.side, size=size, leaves=m, seed=seed, blur=sigma, **kw)

    # compiling builds the objective once: bad pictures fail here, before any evolution
    first = {run_: load_plan(config(sizes[0], *run_, blur)) for run_ in runs}
    budgets = (refine_evaluations, arrange_evaluations, blur)

    def ncc(fit):  # a fit's binary NCC at its last stage
        return fit["stages"][-1]["ncc"]

    fits = {}
    for m, seed in runs:
        name = label[m] if m != "keep" else "run"
        if restarts > 1:
            name += f"-{seed}"
        run_out = out_dir / name if len(runs) > 1 else out_dir
        fits[m, seed] = _evolve(first[m, seed], sizes[0], args, blur, run_out)
        _size_stages(fits[m, seed], 0, lambda size, sigma, m=m, seed=seed:
                     config(size, m, seed, sigma), sizes, setup, budgets, seed)  # fmt: skip
    # every restart's binary NCC at the end of the first size
    first_size = {f"{label[m]} seed {seed}": ncc(f) for (m, seed), f in fits.items()}
    # the restarts of each kind that scored best at the first size go on to the finer
    # sizes (the score there foretells the final one: docs/models/fitting.md)
    carried = []
    for m in modes:
        ranked = sorted((r for r in runs if r[0] == m), key=lambda r: -ncc(fits[r]))
        carried += ranked[: carry or len(ranked)]
    fits = {r: fits[r] for r in runs if r in carried}
    for (m, seed), f in fits.items():
        for k in range(1, len(sizes)):
            _size_stages(f, k, lambda size, sigma, m=m, seed=seed: config(size, m, seed, sigma),
                         sizes, setup, budgets, seed)  # fmt: skip
    # per kind of tree its best restart at the final size, then bare or leafy
    best = {}
    for (m, _), f in fits.items():
        if m not in best or ncc(f) > ncc(best[m]):
            best[m] = f
    chosen = modes[0]
    if len(modes) > 1:
        bare, leafy = ncc(best["bare"]), ncc(best["fit"])
        chosen = "fit" if leafy > bare + LEAF_MARGIN else "bare"
    plan, x, stages = best[chosen]["plan"], best[chosen]["x"], best[chosen]["stages"]
    draws = best[chosen]["draws"]
    objective = plan.objectives[0]
    out = Path(best[chosen]["out"]) if len(runs) == 1 else out_dir
    out.mkdir(parents=True, exist_ok=True)
    leaves_summary = {
        "mode": mode,
        "chosen": label[chosen],
        "ncc": {label[m]: ncc(f) for m, f in best.items()},
        "run": str(best[chosen]["out"]),
        "runs": {
            f"{label[m]} seed {seed}": {"ncc": ncc(f), "out": str(f["out"])}
            for (m, seed), f in fits.items()
        },
        # every restart's binary NCC at the end of the first size
        "first_size": first_size,
    }
    fitness = plan.fitness()
    row = fitness.full_params(x[None, :])[0]
    params = fitness.param_dict(row)
    for n in plan.int_names:
        params[n] = round(params[n])
    seed = int(fitness.model_seeds(row[None, :], None)[0])
    if draws is None:
        plant = fitness.develop(row, seed)
    else:  # the arrangement fitted to the picture
        plant = fitness.model.develop(
            fitness.param_dict(row), seed=seed, env=fitness.env, draws=draws
        )
    views = objective.view_scores(plant)
    # a 2D model (ifs2d) has no mesh: its picture instead
    shape = "tree.glb" if plant.phenotype == "plant" else "attractor.png"
    if plant.phenotype == "plant":
        export(plant, out / shape)
    else:
        plant.screenshot(out / shape, view="front")
    fitted = phenotype_views(plant, objective.size, objective.line_width, views=objective.n_views)
    titles = [
        f"{v} target" if i % 2 == 0 else f"{v} fit" for v in ("front", "side") for i in (0, 1)
    ]
    panels = [a for i in range(objective.n_views) for a in (objective.target[i], fitted[i])]
    silhouette_image(panels, out / "silhouettes.png", titles=titles[: len(panels)], scale=2)
    pictures = {"front": args.front, "side": args.side}
    written = _write_masks(objective, out, pictures)
    summary = {
        "model": args.model,
        "pictures": {k: str(v) for k, v in pictures.items() if v is not None},
        "views": ["front", "side"][: objective.n_views],
        "ncc": float(np.mean(views)),
        "ncc_views": dict(zip(("front", "side"), views)),
        "size": objective.size,
        "seconds": round(time.perf_counter() - t0, 3),
        "stages": stages,
        "leaves": leaves_summary,
        "params": params,
        # the arrangement of the branches fitted to the picture (None: the model's own):
        # model.develop(params, draws=np.array(draws)) grows the fitted tree
        "draws": None if draws is None else draws.tolist(),
        "files": [shape, "silhouettes.png", *[Path(w).name for w in written]],
    }
    text = json.dumps(jsonable(summary), indent=1)
    atomic_write(out / "fit.json", lambda fh: fh.write(text.encode()))
    shown = ", ".join(f"{k} {v:.4f}" for k, v in summary["ncc_views"].items())
    print(
        f"fitted {args.model}: mean NCC {summary['ncc']:.4f} ({shown}) at {objective.size} px "
        f"in {summary['seconds']:.1f} s"
    )
    if len(fits) > 1:
        shown = ", ".join(f"{k} {v['ncc']:.4f}" for k, v in leaves_summary["runs"].items())
        print(f"  kept: the {leaves_summary['chosen']} tree, {best[chosen]['out']} ({shown})")
    for st in stages:
        print(f"  {st['size']:4d} px {st['stage']:6s} {st['evaluations']:6d} evaluations "
              f"{st['seconds']:7.1f} s  NCC {st['ncc']:.4f}")  # fmt: skip
    print(f"  {'mesh' if shape == 'tree.glb' else 'picture'}: {out / shape}")
    print(f"  silhouettes: {out / 'silhouettes.png'} (used: {out_dir / 'silhouette_front.png'})")
    return 0
