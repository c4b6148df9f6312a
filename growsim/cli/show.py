"""``growsim show DIR``: open the best phenotype of a run (a plant in pyvista), or save a
screenshot."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(subparsers) -> None:
    """Add the ``show`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> build_parser().parse_args(["show", "runs/a", "--view", "top"]).view
    'top'
    """
    p = subparsers.add_parser(
        "show",
        help="show the best plant (phenotype) of a results directory",
        description="Open the best phenotype of a run (a plant: in an interactive pyvista "
        "window), or render it to a PNG with --screenshot (works without a display).",
    )
    p.add_argument("dir", metavar="DIR", help="results directory of a run")
    p.add_argument("--screenshot", metavar="PNG", help="write a PNG instead of opening a window")
    p.add_argument(
        "--view",
        default="iso",
        choices=["front", "side", "top", "iso"],
        help="camera for --screenshot (default iso)",
    )
    p.add_argument(
        "--size",
        type=int,
        nargs=2,
        default=(800, 800),
        metavar=("W", "H"),
        help="screenshot size in pixels",
    )
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Show or screenshot the best phenotype."""
    from pathlib import Path

    from growsim.errors import UserInputError
    from growsim.results import read_run

    phenotype = read_run(args.dir, finished=False, history=False).phenotype()
    if args.screenshot:
        w, h = args.size
        if not (16 <= w <= 8192 and 16 <= h <= 8192):
            raise UserInputError(f"--size: {w} x {h} is out of range [16, 8192]")
        out = Path(args.screenshot)
        if out.suffix.lower() != ".png":
            raise UserInputError(f"--screenshot {out}: expected a .png file name")
        phenotype.screenshot(out, view=args.view, size=(w, h))
        print(f"wrote {out}")
    else:
        phenotype.show(view=args.view)
    return 0
