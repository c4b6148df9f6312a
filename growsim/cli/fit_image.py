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

from growsim.cli.arguments import Later
from growsim.errors import UserInputError

__all__ = ["register"]


def _setups() -> tuple[str, ...]:
    from growsim.fitting.setups import FIT_SETUPS

    return tuple(FIT_SETUPS)


def _leaf_modes() -> tuple[str, ...]:
    from growsim.fitting.setups import LEAF_MODES

    return LEAF_MODES


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


def _numbers(n: int, form: str):
    """An argparse type: ``n`` numbers separated by commas (``form`` shows them), pixels
    of the picture as given; argparse names the flag in its error."""

    def parse(text: str) -> tuple[float, ...]:
        try:
            values = tuple(float(v) for v in text.replace(" ", "").split(","))
        except ValueError:
            values = ()
        if len(values) != n or not all(math.isfinite(v) for v in values):
            raise argparse.ArgumentTypeError(
                f"expected {form} (pixels of the picture, separated by commas), got {text!r}"
            )
        if n == 4 and not (values[0] < values[2] and values[1] < values[3]):
            raise argparse.ArgumentTypeError(
                f"expected {form} with x0 < x1 and y0 < y1 (left, top, right, bottom), got {text!r}"
            )
        return values

    parse.__name__ = form  # argparse's message for a failed type names it
    return parse


def _sizes(text: str) -> tuple[int, ...]:
    from growsim.fitting.choices import raster_sizes

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
        usage="growsim fit-image PICTURE [SIDE] --out DIR [options] | --resume DIR",
        description="Fit a tree model to a picture of a tree, or to a front and a side "
        "picture. Drawings (grey, two levels) take the fast exact path (threshold, thin "
        "lines, 64 px), photos the photo one (sky and ground apart, 64,128,256 px); each "
        "model and a bare and a leafy tree are fitted at the first size and the best kept; "
        "the choices are printed and kept in DIR/fit.json with the fit "
        "(fit_<view>.png, framed as silhouette_<view>.png).",
    )
    p.add_argument("front", nargs="?", default=None, metavar="PICTURE",
                   help="the tree's front (PNG, JPEG, ...)")  # fmt: skip
    p.add_argument("side", nargs="?", default=None, metavar="SIDE", help="its side (optional)")
    p.add_argument("--out", default=None, metavar="DIR", help="results directory (new)")
    p.add_argument("--resume", default=None, metavar="DIR",
                   help="continue the interrupted fit in DIR")  # fmt: skip
    model = p.add_argument(
        "--model",
        default="auto",
        metavar="NAME",
        help="auto (each model that fits the picture's kind, the best kept), %(setups)s",
    )
    model.setups = Later(_setups)
    p.add_argument(
        "--budget",
        type=float,
        default=1.0,
        metavar="X",
        help="every search's evaluations times X (default 1: a photo in about 90 s)",
    )
    p.add_argument("--seed", type=int, default=0, metavar="N", help="random seed (default 0)")
    p.add_argument(
        "--workers", type=int, default=None, metavar="N", help="processes (default: the cores)"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    x = p.add_argument_group("expert options (default: chosen from the picture)")
    x.add_argument("--segmentation", choices=("auto", "photo", "threshold"), default="auto",
                   metavar="KIND", help="auto, photo or threshold")  # fmt: skip
    x.add_argument("--threshold", type=_threshold, default="otsu", metavar="otsu|LEVEL",
                   help="otsu or a grey level between 0 (black) and 1 (white)")  # fmt: skip
    x.add_argument("--polarity", choices=("auto", "dark", "light"), default="auto",
                   metavar="P", help="the tree auto, dark or light")  # fmt: skip
    x.add_argument("--line-width", choices=("thin", "radius"), default=None, metavar="W",
                   help="thin (1-pixel lines) or radius (tubes)")  # fmt: skip
    x.add_argument("--sizes", type=_sizes, default=None, metavar="PX,PX,..",
                   help="raster sizes, coarse to fine")  # fmt: skip
    x.add_argument("--size", type=int, default=None, metavar="PX",
                   help="one raster size (same as --sizes PX)")  # fmt: skip
    x.add_argument("--leaves", choices=Later(_leaf_modes), default=None, metavar="MODE",
                   help="%(choices)s (keep: the setup's)")  # fmt: skip
    for view in ("front", "side"):
        x.add_argument(f"--mask-{view}", default=None, metavar="PIC",
                       help="only its white part may be tree")  # fmt: skip
    for flag, dest in (("--box", "box"), ("--box-side", "box_side")):
        p.add_argument(flag, dest=dest, type=_numbers(4, "x0,y0,x1,y1"), default=None,
                       metavar="X0,Y0,X1,Y1",
                       help="a photo: the tree is in this box (pixels; where several trees "
                       "stand, or a tree in front of a wood)" if dest == "box"
                       else "the same for the side picture")  # fmt: skip
    for flag, dest in (("--point", "point"), ("--point-side", "point_side")):
        p.add_argument(flag, dest=dest, type=_numbers(2, "x,y"), default=None, metavar="X,Y",
                       help="a photo: a pixel on the tree (instead of --box)" if dest == "point"
                       else "the same for the side picture")  # fmt: skip
    x.add_argument("--evaluations", type=int, default=None, metavar="N",
                   help="evaluations of the first stage")  # fmt: skip
    x.add_argument("--refine", type=int, default=None, metavar="N",
                   help="evaluations of each finer size's refinement")  # fmt: skip
    x.add_argument("--arrange", type=int, default=None, metavar="N",
                   help="evaluations of the arrangement search")  # fmt: skip
    x.add_argument("--blur", type=float, default=None, metavar="SIGMA",
                   help="blur of the first size's search (pixels)")  # fmt: skip
    x.add_argument("--restarts", type=int, default=None, metavar="N",
                   help="fits of each kind of tree, the best kept")  # fmt: skip
    x.add_argument("--carry", type=int, default=None, metavar="N",
                   help="restarts carried past the first size (0: all)")  # fmt: skip
    p.set_defaults(func=_main)


#: the options passed on to :func:`growsim.fitting.fit.fit_image` as they are
_OPTIONS = ("model", "budget", "sizes", "size", "segmentation", "threshold", "polarity",
            "line_width", "leaves", "mask_front", "mask_side", "box", "point", "box_side",
            "point_side", "evaluations", "refine", "arrange", "blur", "seed", "restarts",
            "carry", "workers")  # fmt: skip


#: the parser's defaults of :data:`_OPTIONS` (an option given beside --resume is refused)
_DEFAULTS = {k: None for k in _OPTIONS} | {
    "model": "auto",
    "budget": 1.0,
    "segmentation": "auto",
    "threshold": "otsu",
    "polarity": "auto",
    "seed": 0,
}


def _main(args) -> int:
    from growsim.fitting.fit import fit_image

    progress = not args.quiet
    if args.resume is not None:
        given = [f"--{k.replace('_', '-')}" for k in _OPTIONS
                 if k != "workers" and getattr(args, k) != _DEFAULTS[k]]  # fmt: skip
        if args.out is not None or given:
            raise UserInputError(
                f"--resume: give the fit's directory alone (not {', '.join(given) or '--out'}); "
                "it goes on with the options it was started with"
            )
        result = fit_image(args.front, args.side, out=args.resume, resume=True,
                           workers=args.workers, progress=progress)  # fmt: skip
    else:
        if args.front is None or args.out is None:
            raise UserInputError("give a PICTURE and --out DIR (or --resume DIR)")
        options = {k: getattr(args, k) for k in _OPTIONS}
        result = fit_image(args.front, args.side, out=args.out, progress=progress, **options)
    summary, leaves = result.summary, result.summary["leaves"]
    shown = ", ".join(f"{k} {v:.4f}" for k, v in result.ncc_views.items())
    print(
        f"fitted {result.model}: mean NCC {result.ncc:.4f} ({shown}) at {result.size} px "
        f"in {summary['seconds']:.1f} s"
    )
    areas = ", ".join(f"{k} {v:.2f}" for k, v in summary["area_ratio"].items())
    print(f"  area of the fit over the picture's tree: {areas}")
    if len(leaves["first_size"]) > 1:
        shown = ", ".join(f"{k} {v['score']:.4f}" for k, v in leaves["first_size"].items())
        print(f"  first size: {shown}")
        print(f"  kept: {result.model}, the {leaves['chosen']} tree, {result.run}")
    for st in result.stages:
        print(f"  {st['size']:4d} px {st['stage']:6s} {st['evaluations']:6d} evaluations "
              f"{st['seconds']:7.1f} s  NCC {st['ncc']:.4f}")  # fmt: skip
    for view, found in summary.get("segmentation", {}).items():
        hint = found["hint"]
        hint = (
            ""
            if not hint
            else ", "
            + ", ".join(f"--{k} {','.join(f'{v:g}' for v in vs)}" for k, vs in hint.items())
        )
        ground = "no ground" if found["horizon"] is None else f"horizon at row {found['horizon']}"
        print(f"  {view} picture: the tree found by {found['method']}{hint}, {ground}, "
              f"contrast {found['contrast']:.0f} Delta E, confidence {found['confidence']:.2f} "
              f"(segmentation_{view}.png)")  # fmt: skip
    for name, choice in summary["choices"].items():
        value = choice["value"]
        value = ",".join(map(str, value)) if isinstance(value, list) else value
        print(f"  {name}: {value} ({choice['why']})")
    kind = "picture" if result.shape.suffix == ".png" else "mesh"
    print(f"  {kind}: {result.shape}")
    used = result.out / "silhouette_front.png"
    fits = ", ".join(p.name for p in result.files if p.name.startswith("fit_"))
    print(f"  silhouettes: {result.out / 'silhouettes.png'} (used: {used}; fit: {fits})")
    return 0
