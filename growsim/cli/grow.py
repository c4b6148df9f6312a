"""``growsim grow MODEL``: grow one plant from a preset and/or parameters; export it, render
it, print its counts and measures.

Works for every plant model in :data:`growsim.models.MODELS` (``--set`` over the model's
parameters, ``--preset`` over its presets); ``growsim grow --help`` lists every model's
parameters (range, default) and presets, ``growsim grow MODEL --help`` one model's
(:func:`models_help`). The screenshot options (``--view``, ``--size``) and the colouring
(``--color light|stress|water``, ``--light-arrow``) are shared with ``growsim show``
(:mod:`growsim.cli.arguments`); the environment the colours show is the default one with
``--light-direction``, ``--light-intensity`` and ``--water-supply``
(:func:`environment_from_args`).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import textwrap
from pathlib import Path

from growsim.cli.arguments import add_color_options, add_screenshot_options
from growsim.errors import UserInputError

__all__ = ["environment_from_args", "models_help", "parse_sets", "register", "run_grow"]

#: the environment options of ``grow``: option -> (table, key) of ``[environment]``
ENVIRONMENT_OPTIONS = {
    "--light-direction": ("light", "direction"),
    "--light-intensity": ("light", "intensity"),
    "--water-supply": ("water", "supply"),
}


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


def environment_from_args(args: argparse.Namespace):
    """The :class:`growsim.env.Environment` of ``grow``'s options: the default one with
    ``--light-direction X Y Z`` (the direction the light travels, y up), ``--light-intensity``
    and ``--water-supply`` where given; a bad value is a :class:`UserInputError` naming its
    option.

    Examples
    --------
    >>> a = argparse.Namespace(light_direction=[1, 0, 0], light_intensity=None,
    ...                        water_supply=0.5)
    >>> env = environment_from_args(a)
    >>> env.light.direction, env.light.intensity, env.water.supply
    ([1.0, 0.0, 0.0], 1.0, 0.5)
    >>> environment_from_args(argparse.Namespace(light_direction=[0, 0, 0]))
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --light-direction 0 0 0: expected a finite non-zero 3-vector...
    """
    from pydantic import ValidationError

    from growsim.env import Environment

    data: dict[str, dict] = {}
    given = {}
    for option, (table, key) in ENVIRONMENT_OPTIONS.items():
        value = getattr(args, option[2:].replace("-", "_"), None)
        if value is None:
            continue
        numbers = value if isinstance(value, list) else [value]
        shown = " ".join(_number(v) if math.isfinite(v) else str(v) for v in numbers)
        if not all(math.isfinite(v) for v in numbers):
            what = "finite numbers" if isinstance(value, list) else "a finite number"
            raise UserInputError(f"{option} {shown}: expected {what}")
        data.setdefault(table, {})[key] = value
        given[(table, key)] = option, shown
    try:
        return Environment.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        option, shown = given.get(tuple(err["loc"][:2]), (None, None))
        msg = err["msg"].removeprefix("Value error, ")
        if option is None:  # pragma: no cover - every option is mapped above
            raise UserInputError(f"environment: {msg}") from None
        raise UserInputError(f"{option} {shown}: {msg}") from None


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
        from growsim.render import check_size

        check_size(args.size, "--size")
    env = environment_from_args(args)
    if args.screenshot is None and (args.color is not None or args.light_arrow):
        option = f"--color {args.color}" if args.color is not None else "--light-arrow"
        raise UserInputError(f"{option}: grow draws it on the image; add --screenshot PATH.png")
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
    plant = model.develop(params, seed=args.seed, env=env)
    if model.phenotype != "plant":
        return _report_other(args, plant, params)

    from growsim.phenotypes.plant.mesh import mesh_arrays

    _, _, vkind = mesh_arrays(plant, sides=args.sides, segments=args.segments)
    if args.export is not None:
        from growsim.phenotypes.plant.mesh import export

        export(plant, args.export, sides=args.sides, segments=args.segments)
    if args.screenshot is not None:
        from growsim.phenotypes.plant.views import screenshot

        screenshot(
            plant, args.screenshot, view=args.view, size=args.size, color=args.color, env=env,
            light_arrow=args.light_arrow,
        )  # fmt: skip
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


def _report_other(args: argparse.Namespace, phenotype, params) -> int:
    """``grow``'s outputs for a phenotype that is not a plant (a fish's trajectory): its
    own render, save and measures; meshes and colouring are for plants."""
    kind = phenotype.phenotype
    for opt, given in (("--export", args.export), ("--color", args.color)):
        if given is not None:
            raise UserInputError(f"{opt}: {args.model} grows a {kind}, not a plant")
    if args.screenshot is not None:
        phenotype.screenshot(args.screenshot, view=args.view, size=args.size)
    if args.save is not None:
        phenotype.save(args.save)
    info = {
        "model": args.model,
        "preset": args.preset,
        "phenotype": kind,
        "params": {k: (int(v) if float(v).is_integer() else v) for k, v in params.items()},
        "measures": phenotype.measures(),
    }
    if args.json:
        json.dump(info, sys.stdout, indent=2, default=float)
        sys.stdout.write("\n")
    else:
        shown = ", ".join(f"{k} {v:.4g}" for k, v in list(info["measures"].items())[:4])
        print(f"{args.model}{' ' + args.preset if args.preset else ''}: a {kind}; {shown}")
        for opt, path in (("image", args.screenshot), (kind, args.save)):
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
            "--export tree.glb --screenshot tree.png --json. Colour it by its environment: "
            "growsim grow honda --preset zelkova --light-direction 1 0 0 --color light "
            "--screenshot lit.png. 'growsim grow MODEL --help' lists that model's parameters "
            "and presets."
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
    add_color_options(p)
    p.add_argument(
        "--light-direction",
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="direction the light travels, y up (default 0 -1 0: from above; 1 0 0: from -x)",
    )
    p.add_argument("--light-intensity", type=float, metavar="I", help="light intensity (default 1)")
    p.add_argument(
        "--water-supply", type=float, metavar="S", help="roots' water supply (default 1: ample)"
    )
    p.add_argument("--sides", type=int, default=6, help="tube polygon sides")
    p.add_argument("--segments", type=int, default=1, help="tube pieces per segment")
    p.add_argument("--json", action="store_true", help="print counts and measures as JSON")
    p.set_defaults(func=run_grow)
