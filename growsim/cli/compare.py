"""``growsim compare DIR...``: table, statistics, curves, renders and an HTML report."""

from __future__ import annotations

import argparse

__all__ = ["register"]


def register(subparsers) -> None:
    """Add the ``compare`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> build_parser().parse_args(["compare", "runs/a", "runs/b", "--no-renders"]).dirs
    ['runs/a', 'runs/b']
    """
    p = subparsers.add_parser(
        "compare",
        help="compare results directories (runs or sweeps)",
        description="Group the runs found in the DIRs (repeats = same config up to the seed) "
        "and write compare.csv, stats.csv, runs.csv, curves.png, renders.png and a "
        "self-contained report.html to --out.",
    )
    p.add_argument("dirs", nargs="+", metavar="DIR", help="run or sweep directories")
    p.add_argument("--out", metavar="DIR", help="report directory (default runs/compare-<time>)")
    p.add_argument("--no-renders", action="store_true", help="skip rendering the best plants")
    p.add_argument("--quiet", "-q", action="store_true", help="print nothing")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Compare and print the table."""
    import pandas as pd

    from growsim.report import compare

    c = compare(args.dirs, args.out, renders=not args.no_renders)
    if not args.quiet:
        cols = [
            "group",
            "runs",
            "best",
            "mean",
            "ci95",
            "generations",
            "evaluations",
            "seconds",
            "height",
            "width",
            "segments",
            "light_captured",
        ]
        with pd.option_context(
            "display.width", 200, "display.max_columns", 20, "display.float_format", "{:.4g}".format
        ):
            print(c.table[cols].to_string(index=False))
            if len(c.stats):
                print()
                print(c.stats.to_string(index=False))
        print(f"report: {c.files.get('html', c.files['table'])}")
    return 0
