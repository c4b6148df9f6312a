"""``growsim grow MODEL``: grow one plant from a preset and/or parameters; export it, render
it, print its counts and measures.

Works for every plant model in :data:`growsim.models.MODELS` (``--set`` over the model's
parameters, ``--preset`` over its presets); ``growsim grow --help`` lists every model's
parameters (range, default) and presets, ``growsim grow MODEL --help`` one model's
(:func:`models_help`). The screenshot options (``--view``, ``--size``) are shared with
``growsim show`` (:func:`growsim.cli.arguments.add_screenshot_options`).
"""

from __future__ import annotations

import argparse
import json
import sys
import textwrap
from pathlib import Path

from growsim.cli.arguments import add_screenshot_options
from growsim.errors import UserInputError

__all__ = ["models_help", "parse_sets", "register", "run_grow"]


def parse_sets(items: list[str] | None) -> dict[str, float]:
    """Parse ``["f=0.8", "generations=12"]`` into ``{"f": 0.8, "generations": 12.0}``.

    Examples
    --------
    >>> parse_sets(["f=0.8", "seed=4"])
    {'f': 0.8, 'seed': 4.0}
    """
    out: dict[str, float] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise UserInputError(f"--set {item!r}: expected NAME=VALUE")
        try:
            out[name] = float(value)
        except ValueError:
            raise UserInputError(f"--set {item!r}: {value!r} is not a number") from None
    return out


def _number(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else f"{x:g}"


def models_help(name: str | None = None) -> str:
    """The parameters (range, default, unit, meaning) and presets of the registered models
    (:data:`growsim.models.MODELS`), or of model ``name`` only if it is one of them: the
    epilog of ``growsim grow --help``.

    Examples
    --------
    >>> text = models_help("honda")
    >>> "zelkova" in text and "  f " in text and "ifs3d" not in text
    True
    """
    from growsim.models import MODELS
    from growsim.models.base import Model

    names = [name] if name in MODELS else list(MODELS)
    lines = ["models: their parameters (--set NAME=VALUE; range, default) and presets (--preset):"]
    for model_name in names:
        model = MODELS.get(model_name)
        rows = []
        for p in model.params:
            unit = f" {p.unit}" if p.unit else ""
            rng = f"{_number(p.low)} .. {_number(p.high)}{unit}, default {_number(p.default)}"
            rows.append((p.name, p.kind, rng, p.doc))
        lines += ["", f"{model_name} (phenotype: {model.phenotype})"]
        presets = ", ".join(sorted(model.presets)) or "(none)"
        lines += textwrap.wrap(
            f"presets: {presets}", 88, initial_indent="  ", subsequent_indent="    "
        )
        if rows:
            w0, w2 = (max(len(r[i]) for r in rows) for i in (0, 2))
            lines += [f"  {a:<{w0}}  {b:<4}  {c:<{w2}}  {d}".rstrip() for a, b, c, d in rows]
        if type(model).param_spec is not Model.param_spec:
            lines.append("  (shown for the default fixed values: the list depends on them)")
    return "\n".join(lines) + "\n"


class _ModelsHelp(argparse.Action):
    """``-h/--help`` of ``grow``: the usual help, then :func:`models_help` (of the model
    given before ``--help``, if any). Built on demand: building the parser imports no model."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help=None):  # fmt: skip
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        parser.epilog = models_help(getattr(namespace, "model", None))
        parser.print_help()
        parser.exit()


def run_grow(args: argparse.Namespace) -> int:
    """Body of ``growsim grow`` (see ``growsim grow --help``)."""
    from growsim.models import get_model

    model = get_model(args.model)
    if args.screenshot is not None:
        from growsim.viz import check_size

        check_size(args.size, "--size")
    params: dict[str, float] = {}
    if args.preset is not None:
        params.update(model.preset(args.preset))
    params.update(parse_sets(args.set))
    params = model.resolve(params, where=f"{args.model}.")
    # check every output path before the (possibly long) growth, so nothing is grown
    # for an output that cannot be written
    for opt, path in (("--export", args.export), ("--screenshot", args.screenshot)):
        if path is not None and not Path(path).resolve().parent.is_dir():
            raise UserInputError(f"{opt} {path}: directory {Path(path).parent} does not exist")
    if args.screenshot is not None and Path(args.screenshot).suffix.lower() != ".png":
        raise UserInputError(f"--screenshot {args.screenshot}: must end in .png")
    if args.export is not None and Path(args.export).suffix.lower() not in (
        ".vtp",
        ".ply",
        ".obj",
        ".glb",
    ):
        raise UserInputError(f"--export {args.export}: use .vtp, .ply, .obj or .glb")
    # models default their own seed (honda: its ``seed`` parameter); pass one only if given
    plant = model.develop(params, seed=args.seed)

    from growsim.mesh import mesh_arrays

    _, _, vkind = mesh_arrays(plant, sides=args.sides, segments=args.segments)
    if args.export is not None:
        from growsim.mesh import export

        export(plant, args.export, sides=args.sides, segments=args.segments)
    if args.screenshot is not None:
        from growsim.viz import screenshot

        screenshot(plant, args.screenshot, view=args.view, size=args.size)
    if args.save is not None:
        plant.save(args.save)
    generations = plant.data.get("generation")
    info = {
        "model": args.model,
        "preset": args.preset,
        "params": {k: (int(v) if float(v).is_integer() else v) for k, v in params.items()},
        "seed": plant.meta.get("seed", params.get("seed")),
        "counts": {
            "segments": plant.n_segments,
            "stems": plant.n_stems,
            "leaves": plant.n_leaves,
            "tips": plant.n_tips,
            "branch_points": plant.n_branch_points,
            "generations": int(generations.max())
            if generations is not None and generations.size
            else 0,
            "mesh_vertices": int(vkind.size),
            "leaf_vertices": int((vkind == 1).sum()),
        },
        "measures": plant.measures(),
    }
    if args.json:
        json.dump(info, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        c = info["counts"]
        print(
            f"{args.model}{' ' + args.preset if args.preset else ''}: {c['stems']} stems, "
            f"{c['leaves']} leaves, {c['tips']} tips, {c['mesh_vertices']} mesh vertices, "
            f"height {info['measures']['height']:.3g}"
        )
        for opt, path in (("mesh", args.export), ("image", args.screenshot), ("plant", args.save)):
            if path is not None:
                print(f"  {opt}: {path}")
    return 0


def register(subparsers) -> None:
    """Add the ``grow`` subcommand to ``subparsers``.

    Examples
    --------
    >>> import argparse
    >>> p = argparse.ArgumentParser(); sub = p.add_subparsers()
    >>> register(sub)
    >>> p.parse_args(["grow", "honda", "--preset", "zelkova"]).preset
    'zelkova'
    """
    p = subparsers.add_parser(
        "grow",
        help="grow one plant from a preset/parameters; export, render, print measures",
        description=(
            "Grow one plant. Example: growsim grow honda --preset zelkova --set f=0.8 "
            "--export tree.glb --screenshot tree.png --json. 'growsim grow MODEL --help' "
            "lists that model's parameters and presets."
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        add_help=False,
    )
    p.description = textwrap.fill(p.description, 88)
    p.add_argument(
        "-h",
        "--help",
        action=_ModelsHelp,
        help="show this help, the models' parameters and presets",
    )
    p.add_argument("model", help="model name (growsim.models.MODELS: honda, ifs3d, ...)")
    p.add_argument("--preset", help="named parameter set of the model (listed below)")
    p.add_argument("--seed", type=int, help="random seed (overrides the preset's)")
    p.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="set a parameter (repeatable; names and ranges below)",
    )
    p.add_argument("--export", metavar="PATH", help="mesh file: .vtp, .ply, .obj or .glb")
    p.add_argument("--screenshot", metavar="PATH", help="PNG render")
    p.add_argument("--save", metavar="PATH", help="the Plant skeleton as .npz")
    add_screenshot_options(p, view="front")
    p.add_argument("--sides", type=int, default=6, help="tube polygon sides")
    p.add_argument("--segments", type=int, default=1, help="tube pieces per segment")
    p.add_argument("--json", action="store_true", help="print counts and measures as JSON")
    p.set_defaults(func=run_grow)
