"""``growsim grow MODEL``: grow one plant from a preset and/or parameters; export it, render
it, print its counts and measures.

Works for every plant model in :data:`growsim.models.MODELS` (``--set`` over the model's
parameters, ``--preset`` over its presets); ``growsim grow --help`` lists the models and
their presets, ``growsim grow MODEL --help`` one model's parameters (range, default) and
presets (:func:`models_help`). The screenshot options (``--view``, ``--size``) and the
colouring (``--color light|stress|water``, ``--light-arrow``) are shared with ``growsim
show`` (:mod:`growsim.cli.arguments`). The environment the plant grows in (and the colours
show) is that of ``--config FILE`` (an experiment's ``[environment]``) or ``--environment
FILE``, else the one the preset carries (hormone's demo genomes: the sun a little from the
side, a sky), else the default one; ``--light-direction``, ``--light-intensity`` and
``--water-supply`` set keys over it (:func:`environment_base`,
:func:`environment_from_args`).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import textwrap
from pathlib import Path

from growsim.cli.arguments import (
    add_color_options,
    add_environment_options,
    add_screenshot_options,
    deprecation_notes,
)
from growsim.errors import UserInputError

#: what ``--export`` writes, by suffix: meshes (growsim.phenotypes.plant.mesh.export) and
#: the architecture (growsim.phenotypes.plant.to_mtg, to_qsm_table)
MESH_SUFFIXES = (".vtp", ".ply", ".obj", ".glb")
ARCHITECTURE_SUFFIXES = (".mtg", ".csv")

__all__ = [
    "ARCHITECTURE_SUFFIXES",
    "MESH_SUFFIXES",
    "environment_base",
    "environment_from_args",
    "models_help",
    "parse_sets",
    "register",
    "run_grow",
]

#: the environment options of ``grow``: option -> (table, key) of ``[environment]``
ENVIRONMENT_OPTIONS = {
    "--light-direction": ("light", "direction"),
    "--light-intensity": ("light", "intensity"),
    "--water-supply": ("water", "supply"),
}


def parse_sets(items: list[str] | None) -> dict[str, float | str]:
    """Parse ``["f=0.8", "generations=12"]`` into ``{"f": 0.8, "generations": 12.0}``; a
    value that is not a number stays a name, for a parameter with named values.

    Examples
    --------
    >>> parse_sets(["f=0.8", "seed=4", "physics=paper"])
    {'f': 0.8, 'seed': 4.0, 'physics': 'paper'}
    """
    out: dict[str, float | str] = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise UserInputError(f"--set {item!r}: expected NAME=VALUE")
        try:
            out[name] = float(value)
        except ValueError:  # a named value (hormone's physics=paper); the model checks it
            out[name] = value.strip()
    return out


def _number(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else f"{x:g}"


def models_help(name: str | None = None) -> str:
    """The epilog of ``growsim grow --help``: with ``name`` one of the registered models
    (:data:`growsim.models.MODELS`), that model's parameters (range, default, unit, meaning)
    and presets; otherwise one line a model (its phenotype, how many parameters, its
    presets) and how to see a model's parameters.

    Examples
    --------
    >>> text = models_help("honda")
    >>> "zelkova" in text and "  f " in text and "ifs3d" not in text
    True
    >>> short = models_help()
    >>> "growsim grow MODEL --help" in short and "h0_bias" not in short
    True
    """
    from growsim.models import MODELS

    if name not in MODELS:
        lines = [
            "models ('growsim grow MODEL --help' lists a model's parameters, their ranges",
            "and defaults, for --set NAME=VALUE):",
        ]
        for model_name in MODELS:
            model = MODELS.get(model_name)
            presets = ", ".join(sorted(model.presets)) or "(none)"
            lines += textwrap.wrap(
                f"{model_name} ({model.phenotype}, {len(model.param_spec())} parameters); "
                f"presets: {presets}",
                88,
                initial_indent="  ",
                subsequent_indent="      ",
            )
        return "\n".join(lines) + "\n"
    return _model_help(name)


def _model_help(model_name: str) -> str:
    """The parameters and presets of one model (see :func:`models_help`)."""
    from growsim.models import MODELS
    from growsim.models.base import Model

    model = MODELS.get(model_name)
    lines = [f"{model_name}: its parameters (--set NAME=VALUE; range, default) and presets:"]
    rows = []
    for p in model.params:
        unit = f" {p.unit}" if p.unit else ""
        rng = f"{_number(p.low)} .. {_number(p.high)}{unit}, default {_number(p.default)}"
        rows.append((p.name, p.kind, rng, p.doc))
    lines += ["", f"{model_name} (phenotype: {model.phenotype})"]
    presets = ", ".join(sorted(model.presets)) or "(none)"
    lines += textwrap.wrap(f"presets: {presets}", 88, initial_indent="  ", subsequent_indent="    ")
    if model.preset_environments:
        lines += textwrap.wrap(
            f"(presets {', '.join(sorted(model.preset_environments))} grow in their own "
            "environment unless --config or --environment is given)",
            88,
            initial_indent="  ",
            subsequent_indent="   ",
        )
    if rows:
        w0, w2 = (max(len(r[i]) for r in rows) for i in (0, 2))
        lines += [f"  {a:<{w0}}  {b:<4}  {c:<{w2}}  {d}".rstrip() for a, b, c, d in rows]
    if type(model).param_spec is not Model.param_spec:
        lines.append("  (shown for the default fixed values: the list depends on them)")
    return "\n".join(lines) + "\n"


def environment_from_args(args: argparse.Namespace, base=None):
    """The :class:`growsim.env.Environment` of ``grow``'s options: the ``[environment]``
    table ``base`` (a ``(table, label)`` pair: that of ``--config``/``--environment`` or of
    the preset; ``None``: the default environment) with ``--light-direction X Y Z`` (the
    direction the light travels, y up), ``--light-intensity`` and ``--water-supply`` over it
    where given; a bad value is a :class:`UserInputError` naming its option.

    Examples
    --------
    >>> a = argparse.Namespace(light_direction=[1, 0, 0], light_intensity=None,
    ...                        water_supply=0.5)
    >>> env = environment_from_args(a)
    >>> env.light.direction, env.light.intensity, env.water.supply
    ([1.0, 0.0, 0.0], 1.0, 0.5)
    >>> env = environment_from_args(a, ({"light": {"diffuse": 0.5}}, "preset demo_3d"))
    >>> env.light.direction, env.light.diffuse
    ([1.0, 0.0, 0.0], 0.5)
    >>> environment_from_args(argparse.Namespace(light_direction=[0, 0, 0]))
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --light-direction 0 0 0: expected a finite non-zero 3-vector...
    """
    import copy

    from pydantic import ValidationError

    from growsim.env import Environment

    table, label = base if base is not None else ({}, "environment")
    data: dict[str, dict] = copy.deepcopy(dict(table))
    given = {}
    for option, (key_table, key) in ENVIRONMENT_OPTIONS.items():
        value = getattr(args, option[2:].replace("-", "_"), None)
        if value is None:
            continue
        numbers = value if isinstance(value, list) else [value]
        shown = " ".join(_number(v) if math.isfinite(v) else str(v) for v in numbers)
        if not all(math.isfinite(v) for v in numbers):
            what = "finite numbers" if isinstance(value, list) else "a finite number"
            raise UserInputError(f"{option} {shown}: expected {what}")
        sub = data.get(key_table)
        data[key_table] = {**(sub if isinstance(sub, dict) else {}), key: value}
        given[(key_table, key)] = option, shown
    try:
        return Environment.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        option, shown = given.get(tuple(err["loc"][:2]), (None, None))
        msg = err["msg"].removeprefix("Value error, ")
        if option is None:
            raise UserInputError(f"{label}: environment: {msg}") from None
        raise UserInputError(f"{option} {shown}: {msg}") from None


def environment_base(args: argparse.Namespace, model) -> tuple[dict, str] | None:
    """Where ``grow``'s environment starts: the ``[environment]`` of ``--config`` or
    ``--environment`` (:func:`growsim.cli.arguments.environment_table`), else the one the
    preset carries (:meth:`growsim.models.base.Model.preset_environment`), else ``None``
    (the default environment); with the label ``grow`` reports.

    Examples
    --------
    >>> from growsim.models import get_model
    >>> a = argparse.Namespace(config=None, environment=None, preset="demo_3d")
    >>> table, label = environment_base(a, get_model("hormone"))
    >>> table["light"]["direction"], label
    ([0.3, -1.0, 0.2], 'preset demo_3d')
    >>> environment_base(argparse.Namespace(preset="zelkova"), get_model("honda")) is None
    True
    """
    from growsim.cli.arguments import environment_table

    found = environment_table(args)
    if found is not None:
        return found
    preset = getattr(args, "preset", None)
    if preset is not None and model.preset_environment(preset):
        return model.preset_environment(preset), f"preset {preset}"
    return None


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


def _stand_env(args: argparse.Namespace, model, env):
    """``env`` with the explicit stand of ``--stand``/``--spacing`` (``None`` without
    ``--stand``); bad values raise :class:`growsim.errors.UserInputError` naming the option.

    Examples
    --------
    >>> import argparse
    >>> from growsim.env import Environment
    >>> from growsim.models import get_model
    >>> a = argparse.Namespace(stand="2x3", spacing=0.5)
    >>> _stand_env(a, get_model("hormone"), Environment()).stand.n_plants
    6
    """
    from growsim.env.stand import Stand
    from growsim.errors import ConfigError

    spacing = getattr(args, "spacing", None)
    if getattr(args, "stand", None) is None:
        if spacing is not None:
            raise UserInputError("--spacing: only with --stand")
        return None
    if model.phenotype != "plant":
        raise UserInputError(f"--stand: {model.name} grows no plants")
    text = args.stand.lower()
    try:
        parts = [int(v) for v in text.split("x")]
    except ValueError:
        parts = []
    if len(parts) not in (1, 2) or min(parts) < 1:
        raise UserInputError(f"--stand {args.stand}: give RxC (e.g. 5x5) or a count N")
    table = {"mode": "explicit", "spacing": 1.0 if spacing is None else spacing}
    if len(parts) == 2:
        table.update(layout="grid", rows=parts[0], cols=parts[1])
    else:
        table.update(layout="row", count=parts[0])
    try:
        stand = Stand.parse(table)
    except ConfigError as exc:
        raise UserInputError(f"--stand/--spacing: {exc}") from None
    return env.model_copy(update={"stand": stand})


def _stand_plants(args: argparse.Namespace, model, params, n: int) -> list[dict] | None:
    """The parameters of each of a stand's ``n`` plants from ``--plants A,B,...`` (None
    without it): each item a preset name of ``model`` or a JSON file (a run's
    ``best.json``, whose ``params`` are used, or a ``{name: value}`` mapping) over the
    preset's values ``params``, ``--set`` over them all, given to the positions in turn.
    A model with the ``"grow_stand"`` capability grows them together, others each alone (then
    placed: :func:`growsim.phenotypes.stand.place`); bad items raise
    :class:`growsim.errors.UserInputError` naming ``--plants``.

    Examples
    --------
    >>> import argparse
    >>> from growsim.models import get_model
    >>> m = get_model("hormone")
    >>> a = argparse.Namespace(plants="demo_2d,demo_3d", stand="3", set=None)
    >>> [p["dims"] for p in _stand_plants(a, m, m.resolve({}), 3)]
    [2.0, 3.0, 2.0]
    """
    import json

    text = getattr(args, "plants", None)
    if text is None:
        return None
    if getattr(args, "stand", None) is None:
        raise UserInputError("--plants: only with --stand")
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise UserInputError("--plants: give presets or JSON files, separated by commas")
    each = []
    for item in items:
        if item in model.presets:
            values = model.preset(item)
        else:
            path = Path(item)
            try:
                data = json.loads(path.read_text())
            except (OSError, ValueError) as exc:
                raise UserInputError(
                    f"--plants {item}: not a preset of {model.name} "
                    f"({', '.join(model.presets)}) nor a readable JSON file ({exc})"
                ) from None
            values = data.get("params", data) if isinstance(data, dict) else None
            if not isinstance(values, dict):
                raise UserInputError(f"--plants {item}: expected a JSON object of parameters")
        sets = parse_sets(getattr(args, "set", None))
        each.append(model.resolve({**params, **values, **sets}, where=f"--plants {item}: "))
    return [each[i % len(each)] for i in range(n)]


def params_file(path: str, model_name: str) -> dict:
    """The parameters in the JSON file ``path`` of ``--params``: its ``params`` (a
    ``fit-image`` reconstruction's ``model.json``, a run's ``best.json``) or the file's
    own ``{name: value}`` mapping; a file naming another ``model`` than ``model_name``, or
    one that cannot be read, raises :class:`~growsim.errors.UserInputError` naming
    ``--params``.

    Examples
    --------
    >>> import json, tempfile
    >>> f = Path(tempfile.mkdtemp()) / "model.json"
    >>> _ = f.write_text(json.dumps({"model": "honda", "params": {"f": 0.7}}))
    >>> params_file(str(f), "honda")
    {'f': 0.7}
    >>> params_file(str(f), "ifs3d")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --params ...model.json: parameters of honda, not of ifs3d
    """
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, ValueError) as exc:
        raise UserInputError(f"--params {path}: not a readable JSON file ({exc})") from None
    values = data.get("params", data) if isinstance(data, dict) else None
    if not isinstance(values, dict):
        raise UserInputError(f"--params {path}: expected a JSON object of parameters")
    named = data.get("model")
    if isinstance(named, str) and "params" in data and named != model_name:
        raise UserInputError(f"--params {path}: parameters of {named}, not of {model_name}")
    return dict(values)


def run_grow(args: argparse.Namespace) -> int:
    """Body of ``growsim grow`` (see ``growsim grow --help``); a preset renamed in 0.2 is
    taken with a one-line note (:func:`growsim.cli.arguments.deprecation_notes`)."""
    with deprecation_notes():
        return _grow(args)


def _grow(args: argparse.Namespace) -> int:
    from growsim.models import get_model

    model = get_model(args.model)
    if args.screenshot is not None:
        from growsim.render import check_size

        check_size(args.size, "--size")
    if args.preset is not None:
        model.preset(args.preset)  # an unknown preset first, before any file is read
    base = environment_base(args, model)
    env = environment_from_args(args, base)
    if args.screenshot is None and (args.color is not None or args.light_arrow):
        option = f"--color {args.color}" if args.color is not None else "--light-arrow"
        raise UserInputError(f"{option}: grow draws it on the image; add --screenshot PATH.png")
    params: dict[str, float] = {}
    if args.preset is not None:
        params.update(model.preset(args.preset))
    if getattr(args, "params", None) is not None:
        params.update(params_file(args.params, model.name))
    params.update(parse_sets(args.set))
    params = model.resolve(params, where=f"{args.model}.")
    # check every output path before the (possibly long) growth, so nothing is grown
    # for an output that cannot be written
    outputs = (("--export", args.export), ("--screenshot", args.screenshot), ("--gif", args.gif))
    for opt, path in outputs:
        if path is not None and not Path(path).resolve().parent.is_dir():
            raise UserInputError(f"{opt} {path}: directory {Path(path).parent} does not exist")
    if args.screenshot is not None and Path(args.screenshot).suffix.lower() != ".png":
        raise UserInputError(f"--screenshot {args.screenshot}: must end in .png")
    exported = None if args.export is None else Path(args.export).suffix.lower()
    if exported is not None and exported not in MESH_SUFFIXES + ARCHITECTURE_SUFFIXES:
        raise UserInputError(
            f"--export {args.export}: use .vtp, .ply, .obj or .glb (a mesh), .mtg or .csv "
            "(the architecture: an MTG, a QSM cylinder table)"
        )
    if args.gif is not None and Path(args.gif).suffix.lower() not in (".gif", ".mp4"):
        raise UserInputError(
            f"--gif {args.gif}: must end in .gif (or .mp4, with the video extra: "
            'pip install "growsim[video]")'
        )
    if args.gif is not None and model.phenotype != "plant":
        raise UserInputError(f"--gif: {model.name} grows no plant (its own view: growsim show)")
    # models default their own seed (honda: its ``seed`` parameter); pass one only if given
    stand = _stand_env(args, model, env)

    plants = _stand_plants(args, model, params, stand.stand.n_plants if stand else 0)
    every_step = args.gif is not None  # every step's phenotype for --gif, else the last
    if stand is not None:
        env = stand
        which = params if plants is None else plants
        frames = list(model.grow_in_stand(which, seed=args.seed, env=env, every_step=every_step))
    elif every_step:
        frames = list(model.grow(params, seed=args.seed, env=env))
    else:
        frames = [model.develop(params, seed=args.seed, env=env)]
    plant = frames[-1]
    args.environment_label = base[1] if base is not None else "default"
    if model.phenotype != "plant":
        return _report_other(args, plant, params)

    from growsim.phenotypes.plant.mesh import leaf_modules, mesh_arrays

    _, _, vkind = mesh_arrays(plant, sides=args.sides, segments=args.segments)
    if exported == ".mtg":
        from growsim.phenotypes.plant import to_mtg

        to_mtg(plant, args.export)
    elif exported == ".csv":
        from growsim.phenotypes.plant import to_qsm_table

        to_qsm_table(plant, args.export)
    elif exported is not None:
        from growsim.phenotypes.plant.mesh import export

        export(plant, args.export, sides=args.sides, segments=args.segments)
    if args.screenshot is not None:
        from growsim.phenotypes.plant.views import screenshot

        screenshot(
            plant, args.screenshot, view=args.view, size=args.size, color=args.color, env=env,
            light_arrow=args.light_arrow,
        )  # fmt: skip
    if args.gif is not None:
        from growsim.phenotypes.plant.views import growth_animation

        growth_animation(frames, args.gif, view=args.view, size=args.size)
    if args.save is not None:
        plant.save(args.save)
    generations = plant.data.get("generation")
    # leaves: what is drawn as a leaf, the LEAF segments and the modules (hormone) drawn
    # with a leaf blade (leaf_modules: those modules, counted among the stems too)
    blades = int(leaf_modules(plant).sum())
    info = {
        "model": args.model,
        "preset": args.preset,
        "params": {k: (int(v) if float(v).is_integer() else v) for k, v in params.items()},
        "seed": plant.meta.get("seed", params.get("seed")),
        "environment": args.environment_label,
        "counts": {
            "segments": plant.n_segments,
            "stems": plant.n_stems,
            "leaves": plant.n_leaves + blades,
            "leaf_modules": blades,
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
    if stand is not None:
        from growsim.phenotypes.stand import plant_table, stand_measures

        info["stand"] = stand_measures(plant, env.stand.ground_area())
        info["plants"] = plant_table(plant).to_dict(orient="records")
    if args.json:
        json.dump(info, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        c = info["counts"]
        blade = f" (modules with a leaf blade: {c['leaf_modules']})" if c["leaf_modules"] else ""
        print(
            f"{args.model}{' ' + args.preset if args.preset else ''}: {c['stems']} stems, "
            f"{c['leaves']} leaves{blade}, {c['tips']} tips, "
            f"{c['mesh_vertices']} mesh vertices, "
            f"height {info['measures']['height']:.3g}"
            + ("" if base is None else f" (environment: {base[1]})")
        )
        shown = (("mesh", args.export), ("image", args.screenshot), ("animation", args.gif),
                 ("plant", args.save))  # fmt: skip
        for opt, path in shown:
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
        "environment": getattr(args, "environment_label", "default"),
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
            "--screenshot lit.png. Grow it in an experiment's environment: growsim grow "
            "hormone --preset demo_3d --config experiments/hormone_3d.toml. 'growsim grow "
            "MODEL --help' lists that model's parameters and presets."
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
        add_help=False,
    )
    p.description = textwrap.fill(p.description, 88)
    p.add_argument(
        "-h",
        "--help",
        action=_ModelsHelp,
        help="show this help and the models; with MODEL before it, that model's parameters",
    )
    p.add_argument("model", help="model name (growsim.models.MODELS: honda, ifs3d, ...)")
    p.add_argument(
        "--preset",
        help="named parameter set of the model (listed below), with its environment if it has one",
    )
    p.add_argument(
        "--params",
        metavar="FILE",
        help="parameters from a JSON file (model.json, best.json)",
    )
    p.add_argument("--seed", type=int, help="random seed (overrides the preset's)")
    p.add_argument(
        "--set",
        action="append",
        metavar="NAME=VALUE",
        help="set a parameter (repeatable; names and ranges: growsim grow MODEL --help)",
    )
    p.add_argument(
        "--export",
        metavar="PATH",
        help="a mesh: .vtp, .ply, .obj or .glb; the architecture: .mtg (MTG) or .csv (QSM)",
    )
    p.add_argument("--screenshot", metavar="PATH", help="PNG render")
    p.add_argument("--save", metavar="PATH", help="the Plant skeleton as .npz")
    p.add_argument(
        "--gif",
        metavar="PATH",
        help="growth, a frame a step: .gif (.mp4: growsim[video])",
    )
    add_screenshot_options(p)
    add_color_options(p)
    add_environment_options(p)
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
    p.add_argument("--sides", type=int, default=6, help="tube polygon sides (default 6)")
    p.add_argument("--segments", type=int, default=1, help="tube pieces per segment (default 1)")
    p.add_argument(
        "--stand",
        metavar="RxC|N",
        help="a stand: a grid RxC (e.g. 5x5) or a row of N; hormone plants grow together, "
        "other models' copies are placed; per plant in --json",
    )
    p.add_argument("--spacing", type=float, metavar="S", help="--stand: distance (m, default 1)")
    p.add_argument(
        "--plants",
        metavar="A,B,...",
        help="--stand of different plants (presets, best.json files)",
    )
    p.add_argument("--json", action="store_true", help="print counts and measures as JSON")
    p.set_defaults(func=run_grow)
