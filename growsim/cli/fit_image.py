"""``growsim fit-image FRONT SIDE``: fit a tree to a front and a side picture.

Builds the experiment config in memory (see :func:`fit_config`): for ifs3d the best setup,
read from the package's ``growsim/data/ifs_tree_best.toml`` (:func:`best_setup`; the file
``experiments/ifs_tree_best.toml`` links to, so the command and the experiment are one
setup) with the pictures as the target; compiles and runs it
(:func:`growsim.experiment.run`), then writes into ``--out``: the run's results,
``tree.glb`` (the fitted tree's mesh) and ``silhouettes.png`` (target and fitted
silhouettes, front and side, side by side).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from growsim.errors import UserInputError

__all__ = ["BEST_SETUP", "HONDA_EVOLVE", "best_setup", "fit_config", "register"]

#: The package data file holding the best ifs3d setup (see docs/models/ifs3d.md for how it
#: was chosen): its ``[model]``, ``[ga]`` and ``[output]`` tables are what ``fit-image
#: --model ifs3d`` runs; ``experiments/ifs_tree_best.toml`` is a link to it.
BEST_SETUP = "ifs_tree_best.toml"

#: Honda parameters fitted to pictures (the rest come from the ``cherry`` preset).
HONDA_EVOLVE: dict = {
    "f": [0.5, 1.0],
    "theta0": True,
    "theta_max": True,
    "thq": True,
    "thr": True,
    "bd": [5.0, 40.0],
    "b0": [1.0, 12.0],
    "b_max": [0.0, 6.0],
}

#: Honda's GA: 60 generations of 100, then 1,500 evaluations of polish (7,500 in all).
HONDA_GA: dict = {"population": 100, "generations": 60, "polish": {"evaluations": 1500}}

#: The line width each model's fit draws its trees with, unless ``--line-width`` says.
LINE_WIDTH = {"ifs3d": "thin", "honda": "radius"}


def best_setup() -> dict:
    """The tables of the best ifs3d setup, ``growsim/data/ifs_tree_best.toml`` (a fresh
    dict on every call).

    Examples
    --------
    >>> setup = best_setup()
    >>> setup["ga"]["evaluations"], setup["ga"]["polish"]["evaluations"]
    (50000, 35000)
    """
    import tomllib
    from importlib.resources import files

    return tomllib.loads((files("growsim") / "data" / BEST_SETUP).read_text(encoding="utf-8"))


def __getattr__(name: str):
    # ``BEST_GA`` (used by benchmarks/ifs_fit.py): the best setup's [ga] table, read from
    # the data file when asked
    if name == "BEST_GA":
        return best_setup()["ga"]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def fit_config(
    front,
    side,
    *,
    model: str = "ifs3d",
    size: int = 64,
    threshold="otsu",
    polarity: str = "auto",
    mask_front=None,
    mask_side=None,
    line_width: str | None = None,
    evaluations: int | None = None,
    seed: int = 0,
) -> dict:
    """The experiment config (a dict for :func:`growsim.experiment.load_config`) of a fit.

    ifs3d: the ``[model]``, ``[ga]`` and ``[output]`` tables of :func:`best_setup`, as they
    are; honda: the ``cherry`` preset with :data:`HONDA_EVOLVE` evolved, :data:`HONDA_GA`.
    ``evaluations`` replaces the budget and keeps the polish's share of it (ifs3d: 70 %,
    honda: 20 %), with enough generations for the GA's share. ``line_width``: ``"thin"`` or
    ``"radius"``; ``None``, the model's :data:`LINE_WIDTH`. Picture paths are made absolute,
    so the config runs from any directory.

    Examples
    --------
    >>> cfg = fit_config("front.png", "side.png")
    >>> cfg["model"]["kind"], cfg["ga"]["coding"], cfg["objective"][0]["kind"]
    ('ifs3d', 'real', 'silhouette')
    >>> ga = fit_config("front.png", "side.png", evaluations=10_000)["ga"]
    >>> ga["evaluations"], ga["polish"]["evaluations"]
    (10000, 7000)
    """
    if model not in LINE_WIDTH:
        raise UserInputError(f"--model: expected ifs3d or honda, got {model!r}")
    if line_width is None:
        # photos show trunks and leaves with their thickness: the Honda tree's tubes are
        # drawn at their radius (measured on a rendered zelkova photographed front and
        # side: NCC 0.926 against 0.848 with thin lines). ifs3d keeps thin lines, its fast
        # path (docs/models/ifs3d.md: when to choose "radius").
        line_width = LINE_WIDTH[model]
    if line_width not in ("thin", "radius"):
        raise UserInputError(f"--line-width: expected thin or radius, got {line_width!r}")
    objective = {
        "kind": "silhouette",
        "front": str(Path(front).absolute()),
        "side": str(Path(side).absolute()),
        "size": int(size),
        "threshold": threshold,
        "polarity": polarity,
        "line_width": line_width,
    }
    if mask_front is not None:
        objective["mask_front"] = str(Path(mask_front).absolute())
    if mask_side is not None:
        objective["mask_side"] = str(Path(mask_side).absolute())
    if model == "ifs3d":
        setup = best_setup()
        model_cfg, ga, output = setup["model"], setup["ga"], setup["output"]
    else:
        model_cfg = {"kind": "honda", "preset": "cherry", "evolve": dict(HONDA_EVOLVE)}
        ga = {**HONDA_GA, "polish": dict(HONDA_GA["polish"])}
        output = {"mesh": ["vtp"], "screenshots": ["front", "side"]}
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


def register(subparsers) -> None:
    """Add the ``fit-image`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> args = build_parser().parse_args(["fit-image", "f.png", "s.png", "--out", "o",
    ...                                   "--line-width", "radius", "--threshold", "0.4"])
    >>> args.line_width, args.threshold
    ('radius', 0.4)
    """
    p = subparsers.add_parser(
        "fit-image",
        help="fit a tree to front and side pictures (PNG/JPEG)",
        description="Fit a tree model to a front and a side picture of a tree: the pictures "
        "become silhouettes (Otsu threshold, dark-on-light or light-on-dark detected), a GA "
        "fits the model's front/side projections to them, and the fitted tree's mesh and a "
        "target-vs-fitted silhouette image are written to --out. ifs3d runs the best setup "
        "of experiments/ifs_tree_best.toml (50,000 evaluations: 30 % GA, 70 % CMA-ES). "
        "Pictures whose silhouette is too small, too noisy or fills the frame are refused "
        "(growsim/images.py).",
    )
    p.add_argument("front", help="front picture (PNG, JPEG, ...; any size)")
    p.add_argument("side", help="side picture (the tree seen from its right)")
    p.add_argument(
        "--model",
        choices=("ifs3d", "honda"),
        default="ifs3d",
        help="tree model to fit: ifs3d (3D fractal tree, default) or honda (branching tree "
        "from the cherry preset)",
    )
    p.add_argument("--out", required=True, help="results directory (must not hold a run)")
    p.add_argument(
        "--size",
        type=int,
        default=64,
        metavar="PX",
        help="silhouette raster size in pixels, 8..1024 (default 64; larger pictures need "
        "more --evaluations)",
    )
    p.add_argument(
        "--threshold",
        type=_threshold,
        default="otsu",
        metavar="otsu|LEVEL",
        help="'otsu' (default: Otsu's threshold of each picture) or a grey level strictly "
        "between 0 (black) and 1 (white), e.g. 0.4",
    )
    p.add_argument(
        "--polarity",
        choices=("auto", "dark", "light"),
        default="auto",
        help="dark: a dark tree on a light background; light: the reverse; auto (default): "
        "the class covering less of the picture's border is the tree",
    )
    p.add_argument(
        "--line-width",
        choices=("thin", "radius"),
        default=None,
        help="how the fitted tree is drawn: thin (1-pixel lines, the paper's drawing; "
        "ifs3d's default and fast path) or radius (tubes as wide as the branches: pictures "
        "with thick trunks and branches, e.g. renders or photos; honda's default)",
    )
    for view in ("front", "side"):
        p.add_argument(
            f"--mask-{view}",
            default=None,
            metavar="PICTURE",
            help=f"mask picture for the {view} view (the picture's size; only its white part "
            "is looked at)",
        )
    p.add_argument(
        "--evaluations",
        type=int,
        default=None,
        metavar="N",
        help="fitness evaluations budget, >= 100 (default: ifs3d 50,000, honda 7,500); the "
        "setup's share for the final polish is kept (ifs3d 70 %%, honda 20 %%)",
    )
    p.add_argument(
        "--seed", type=int, default=0, metavar="N", help="random seed of the run (default 0)"
    )
    p.add_argument(
        "--workers", type=int, default=None, metavar="N", help="evaluate in N local processes"
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_main)


def _main(args) -> int:
    from growsim.experiment import load_plan, run
    from growsim.images import silhouette_image
    from growsim.mesh import export
    from growsim.objectives.silhouette import plant_views

    if args.evaluations is not None and args.evaluations < 100:
        raise UserInputError(f"--evaluations: at least 100, got {args.evaluations}")
    # compiling builds the objective once: bad pictures fail here, before any evolution
    options = ("model", "size", "threshold", "polarity", "mask_front", "mask_side")
    options += ("line_width", "evaluations", "seed")
    plan = load_plan(fit_config(args.front, args.side, **{k: getattr(args, k) for k in options}))
    objective = plan.objectives[0]
    result = run(plan, out=args.out, workers=args.workers, progress=not args.quiet)
    out = Path(result.out)
    plant = result.best_plant
    export(plant, out / "tree.glb")
    fitted = plant_views(plant, objective.size, objective.line_width)
    silhouette_image(
        [objective.target[0], fitted[0], objective.target[1], fitted[1]],
        out / "silhouettes.png",
        titles=["front target", "front fit", "side target", "side fit"],
    )
    print(f"fitted {args.model}: mean NCC {objective(plant):.4f}")
    print(f"  mesh: {out / 'tree.glb'}")
    print(f"  silhouettes: {out / 'silhouettes.png'}")
    return 0
