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

from growsim.cli.arguments import Later
from growsim.errors import UserInputError

__all__ = ["register"]


def _setups() -> tuple[str, ...]:
    from growsim.fitting.setups import FIT_SETUPS

    return tuple(FIT_SETUPS)


def _text(name: str, how: str):
    """An argparse type reading option ``name``'s text (``how``: ``"threshold"``,
    ``"sizes"`` or ``"hint"``) as :mod:`growsim.fitting.options` does; argparse names the
    flag in its error."""
    from growsim.fitting import options

    read = {"threshold": options.parse_threshold, "sizes": options.raster_sizes,
            "hint": lambda text: tuple(options.parse_hint(name, text))}[how]  # fmt: skip

    def parse(text: str):
        try:
            return read(text)
        except UserInputError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    parse.__name__ = name  # argparse's message for a failed type names it
    return parse


def _add_option(parser, name: str, form: dict, annotation) -> argparse.Action:
    """Add option ``name`` of :class:`~growsim.fitting.options.FitOptions` (``form``: its
    :meth:`~growsim.fitting.options.FitOptions.cli` form) to ``parser``: its flag, default,
    metavar, help, choices and type from the schema."""
    kw = {"default": form["default"], "metavar": form["metavar"], "help": form["help"]}
    if form["flag"] is None:
        return parser.add_argument(name, nargs="?", **kw)
    if form.get("text"):
        kw["type"] = _text(name, form["text"])
    elif form["choices"] is not None:
        kw["choices"] = form["choices"]
    elif int in (annotation, *getattr(annotation, "__args__", ())):
        kw["type"] = int
    elif float in (annotation, *getattr(annotation, "__args__", ())):
        kw["type"] = float
    return parser.add_argument(form["flag"], dest=name, **kw)


def register(subparsers) -> None:
    """Add the ``fit-image`` subcommand: its options are the fields of
    :class:`~growsim.fitting.options.FitOptions` (flags, defaults, help and choices from
    the schema), and how the fit runs (``--out``, ``--resume``, ``--workers``, ``-q``).

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
        description="Fit a tree to a picture of a tree, or to a front and a side picture. "
        "Drawings (grey, two levels) take the fast exact path: the models' parameters "
        "searched (threshold, thin lines, 64 px). Photographs (the tree told apart from sky "
        "and ground) are reconstructed: the tree they show, its visible skeleton lifted into "
        "3D, twigs grown into its crown, Honda's parameters inferred from it (DIR/model.json); "
        "--method search (or any option of the search) searches the models instead "
        "(64,128,256 px, bare and leafy, the best kept). The choices are printed and kept in "
        "DIR/fit.json with the fit (fit_<view>.png, framed as silhouette_<view>.png).",
    )
    p.set_defaults(func=_main)
    p.fill_later(_options)  # the schema's options: only when fit-image parses or helps


def _options(p) -> None:
    """Add fit-image's options to its parser ``p``: the fields of
    :class:`~growsim.fitting.options.FitOptions`, then how the fit runs."""
    from growsim.fitting.options import FitOptions

    forms = FitOptions.cli()
    fields = FitOptions.model_fields
    groups = {
        "positional": p,
        "main": p,
        "expert": p.add_argument_group("expert options (default: chosen from the picture)"),
    }
    for name in ("front", "side"):
        _add_option(p, name, forms[name], fields[name].annotation)
    p.add_argument("--out", default=None, metavar="DIR", help="results directory (new)")
    p.add_argument("--resume", default=None, metavar="DIR",
                   help="continue the interrupted fit in DIR")  # fmt: skip
    for name, form in forms.items():
        if form["group"] != "positional":
            action = _add_option(groups[form["group"]], name, form, fields[name].annotation)
            if name == "model":
                action.setups = Later(_setups)
    p.add_argument(
        "--workers", type=int, default=None, metavar="N", help="processes (default: the cores)"
    )
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def _main(args) -> int:
    from growsim.fitting.fit import fit_image
    from growsim.fitting.options import FitOptions, flag
    from growsim.pictures.record import ENDS_AT_HORIZON

    progress = not args.quiet
    forms = FitOptions.cli()
    names = [k for k, form in forms.items() if form["flag"] is not None]
    if args.resume is not None:
        given = [flag(k) for k in names if getattr(args, k) != forms[k]["default"]]
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
        options = {k: getattr(args, k) for k in names}
        result = fit_image(args.front, args.side, out=args.out, workers=args.workers,
                           progress=progress, **options)  # fmt: skip
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
        if found.get("ends_at_horizon", 0.0) >= ENDS_AT_HORIZON:
            print(f"  {view} picture: its outline ends along the horizon over "
                  f"{100 * found['ends_at_horizon']:.0f} % of its width: the crown below the "
                  f"horizon or the trunk may be missing (segmentation_{view}.png)")  # fmt: skip
    choices = summary["choices"]
    if "method" not in choices and result.method:  # a drawing's fit.json does not hold it
        choices = {"method": result.method, **choices}
    for name, choice in choices.items():
        value = choice["value"]
        value = ",".join(map(str, value)) if isinstance(value, list) else value
        print(f"  {name}: {value} ({choice['why']})")
    kind = "picture" if result.shape.suffix == ".png" else "mesh"
    print(f"  {kind}: {result.shape}")
    if "reconstruction" in summary:
        rec = summary["reconstruction"]
        print(f"  reconstructed by {rec['method']}: {rec['visible_branches']} visible branches, "
              f"{'leafy' if rec['leafy'] else 'bare'} (assumptions in fit.json; "
              f"skeleton: {result.out / 'skeleton_front.png'})")  # fmt: skip
        print(
            f"  a tree of this kind: growsim grow honda --params {result.out / 'model.json'} "
            f"(statistics beside the photo's tree's: {result.out / 'stats.csv'})"
        )
    used = result.out / "silhouette_front.png"
    fits = ", ".join(p.name for p in result.files if p.name.startswith("fit_"))
    print(f"  silhouettes: {result.out / 'silhouettes.png'} (used: {used}; fit: {fits})")
    return 0
