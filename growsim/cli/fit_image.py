"""``growsim fit-image PICTURE [SIDE]``: fit a tree model to one picture, or to a front and
a side picture.

The command parses its arguments, calls :func:`growsim.fitting.fit.fit_image` (the fit:
silhouettes from the pictures, the coarse-to-fine stages, bare and leafy trees, restarts,
the arrangement search, the files written into ``--out``; see that module) and prints
what it returns (:class:`growsim.fitting.fit.FitResult`): the final NCC per view, the kept
fit and every stage.
"""

from __future__ import annotations

import argparse
import math

from growsim.errors import UserInputError
from growsim.fitting.fit import fit_image, raster_sizes
from growsim.fitting.setups import FIT_SETUPS, LEAF_MODES, SIZES

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
        return raster_sizes(text)
    except UserInputError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


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


#: the options passed on to :func:`growsim.fitting.fit.fit_image` as they are
_OPTIONS = ("model", "sizes", "size", "segmentation", "threshold", "polarity", "line_width",
            "leaves", "mask_front", "mask_side", "evaluations", "refine", "arrange", "blur",
            "seed", "restarts", "carry", "workers")  # fmt: skip


def _main(args) -> int:
    options = {k: getattr(args, k) for k in _OPTIONS}
    result = fit_image(args.front, args.side, out=args.out, progress=not args.quiet, **options)
    summary, leaves = result.summary, result.summary["leaves"]
    shown = ", ".join(f"{k} {v:.4f}" for k, v in result.ncc_views.items())
    print(
        f"fitted {result.model}: mean NCC {result.ncc:.4f} ({shown}) at {result.size} px "
        f"in {summary['seconds']:.1f} s"
    )
    if len(leaves["runs"]) > 1:
        shown = ", ".join(f"{k} {v['ncc']:.4f}" for k, v in leaves["runs"].items())
        print(f"  kept: the {leaves['chosen']} tree, {result.run} ({shown})")
    for st in result.stages:
        print(f"  {st['size']:4d} px {st['stage']:6s} {st['evaluations']:6d} evaluations "
              f"{st['seconds']:7.1f} s  NCC {st['ncc']:.4f}")  # fmt: skip
    kind = "picture" if result.shape.suffix == ".png" else "mesh"
    print(f"  {kind}: {result.shape}")
    used = result.out / "silhouette_front.png"
    print(f"  silhouettes: {result.out / 'silhouettes.png'} (used: {used})")
    return 0
