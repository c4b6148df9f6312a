"""``growsim show DIR``: open the best phenotype of a run (a plant in pyvista), or save a
screenshot; ``--color light|stress|water`` paints a plant by the run's ``[environment]``."""

from __future__ import annotations

import argparse

from growsim.cli.arguments import (
    add_color_options,
    add_environment_options,
    add_screenshot_options,
)

__all__ = ["register", "window_title"]


def register(subparsers) -> None:
    """Add the ``show`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> args = build_parser().parse_args(["show", "runs/a", "--view", "back", "--size", "400"])
    >>> args.view, args.size
    ('back', (400, 400))
    >>> build_parser().parse_args(["show", "runs/a", "--color", "water"]).color
    'water'
    """
    p = subparsers.add_parser(
        "show",
        help="show the best plant (phenotype) of a results directory",
        description="Open the best phenotype of a run (a plant: in an interactive pyvista "
        "window), or render it to a PNG with --screenshot (works without a display). "
        "--color light|stress|water paints the plant by the run's [environment] (or that of "
        "--config FILE / --environment FILE).",
    )
    p.add_argument("dir", metavar="DIR", help="results directory of a run")
    p.add_argument("--screenshot", metavar="PNG", help="write a PNG instead of opening a window")
    # the same --view (growsim.render.VIEWS, the same default) and --size (W H, or N) as
    # ``growsim grow``
    add_screenshot_options(p)
    # the same --color and --light-arrow as ``growsim grow``; the environment is the run's
    add_color_options(p)
    # --config / --environment: colour by another experiment's environment than the run's
    add_environment_options(p)
    p.set_defaults(func=main)


def window_title(run_dir, kind: str, fitness=None) -> str:
    """The title of ``show``'s window: the run, what is shown and its fitness.

    Examples
    --------
    >>> window_title("runs/a", "plant", 12.5)
    'growsim show runs/a: the best plant (fitness 12.5)'
    """
    shown = f" (fitness {fitness:.6g})" if isinstance(fitness, (int, float)) else ""
    return f"growsim show {run_dir}: the best {kind}{shown}"


def main(args: argparse.Namespace) -> int:
    """Show or screenshot the best phenotype."""
    from pathlib import Path

    from growsim.cli.arguments import environment_table
    from growsim.errors import UserInputError
    from growsim.experiment.results import read_run

    if args.screenshot:
        from growsim.render import check_size

        size = check_size(args.size, "--size")
        out = Path(args.screenshot)
        if out.suffix.lower() != ".png":
            raise UserInputError(f"--screenshot {out}: expected a .png file name")
    record = read_run(args.dir, finished=False, history=False)
    phenotype = record.phenotype()
    title = window_title(args.dir, phenotype.phenotype, record.best.get("fitness"))
    if args.color is None and not args.light_arrow:  # the phenotype's own render
        if args.screenshot:
            phenotype.screenshot(out, view=args.view, size=size)
            print(f"wrote {out}")
        else:
            phenotype.show(view=args.view, title=title)
        return 0
    from growsim.experiment.load import validate
    from growsim.phenotypes.plant import Plant
    from growsim.phenotypes.plant import views as viz

    option = f"--color {args.color}" if args.color is not None else "--light-arrow"
    if not isinstance(phenotype, Plant):
        raise UserInputError(
            f"{option}: the best phenotype of {args.dir} is a {phenotype.phenotype}, "
            "not a plant: only plants are coloured by their environment"
        )
    found = environment_table(args)
    if found is not None:
        from growsim.env import Environment

        env = Environment.model_validate(found[0])
    else:
        env = validate(record.config, str(Path(args.dir) / "config.toml")).environment
    options = {"view": args.view, "color": args.color, "env": env, "light_arrow": args.light_arrow}
    if args.screenshot:
        viz.screenshot(phenotype, out, size=size, **options)
        print(f"wrote {out}")
    else:
        viz.show(phenotype, title=title, **options)
    return 0
