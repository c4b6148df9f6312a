"""``growsim sweep CONFIG --vary KEY=V1,V2 ... --repeats N``: a grid of runs, one table."""

from __future__ import annotations

import argparse

from growsim.cli.arguments import (
    add_evaluation_options,
    add_overrides,
    deprecation_notes,
    renamed_config,
)

__all__ = ["register"]


def register(subparsers) -> None:
    """Add the ``sweep`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> build_parser().parse_args(["sweep", "exp.toml", "--vary", "env.light=1,0.5"]).vary
    ['env.light=1,0.5']
    """
    p = subparsers.add_parser(
        "sweep",
        help="run a grid of config variants x repeats",
        description="Run every combination of the --vary values, each with --repeats seeds "
        "(experiment.seed + 0..N-1; --block K: the K-th block of N seeds), into "
        "OUT/<variant>/seed-<seed>/, and write one table "
        "OUT/sweep.csv (and .parquet). Re-running the same sweep reuses finished runs.",
    )
    p.add_argument("config", help="experiment TOML")
    p.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="KEY=V1,V2",
        help="a key and its values, e.g. --vary env.light=1.0,0.5 (repeatable: a grid)",
    )
    p.add_argument(
        "--repeats", type=int, metavar="N", help="seeds per variant (default experiment.repeats)"
    )
    p.add_argument(
        "--block",
        type=int,
        default=1,
        metavar="K",
        help="run the K-th block of seeds: experiment.seed + (K-1)*N + 0..N-1 with N the "
        "repeats (default 1); a fresh block confirms a first one: growsim compare DIR1 "
        "--confirm DIR2",
    )
    p.add_argument(
        "--out", metavar="DIR", help="sweep directory (default runs/<name>-sweep-<time>)"
    )
    add_overrides(p, " for every variant")
    add_evaluation_options(p)
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bars, no table")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Run the sweep and print the combined table (names renamed in 0.2: as ``run``)."""
    renamed_config(args.config)
    with deprecation_notes():
        return _sweep(args)


def _sweep(args: argparse.Namespace) -> int:
    from growsim.experiment import sweep

    df = sweep(
        args.config,
        args.vary,
        repeats=args.repeats,
        out=args.out,
        overrides=args.overrides,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=not args.quiet,
        block=args.block,
    )
    if not args.quiet:
        import pandas as pd

        cols = [
            c
            for c in df.columns
            if (c != "out" and not c.startswith("best_")) or c == "best_fitness"
        ]
        with pd.option_context("display.width", 160, "display.max_columns", 20):
            print(df[cols].to_string(index=False))
        root = __import__("pathlib").Path(df["out"].iloc[0]).parent.parent
        print(f"table: {root / 'sweep.csv'}")
        print(f"compare the variants: growsim compare {root}")
        from growsim.experiment.load import read_config

        declared = read_config(args.config, args.overrides).compare
        if args.block == 1 and declared is not None and declared.primary:
            print(
                f"confirm on fresh seeds: growsim sweep {args.config} --block 2 --out DIR2, "
                f"then growsim compare {root} --confirm DIR2"
            )
    return 0
