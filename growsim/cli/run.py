"""``growsim run CONFIG`` / ``growsim run --resume DIR``: run one experiment."""

from __future__ import annotations

import argparse
import sys

from growsim.cli.arguments import (
    add_evaluation_options,
    add_overrides,
    deprecation_notes,
    renamed_config,
)
from growsim.errors import UserInputError

__all__ = ["register"]

#: what ``growsim show`` opens, by phenotype kind (the end of ``growsim run``)
SHOW_WHAT = {
    "plant": "the best plant",
    "trajectory": "the best fish's swim",
    "points2d": "the best attractor",
}


def register(subparsers) -> None:
    """Add the ``run`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> args = build_parser().parse_args(["run", "exp.toml", "--seed", "3", "--set", "ga.elite=2"])
    >>> args.seed, args.overrides
    (3, ['ga.elite=2'])
    """
    p = subparsers.add_parser(
        "run",
        help="run an experiment config (or resume one)",
        description="Run an experiment config into a results directory: history.parquet, "
        "best.json, summary.json, config.toml, checkpoint.npz, the best plant's meshes and "
        "renders, fitness.png.",
    )
    p.add_argument("config", nargs="?", help="experiment TOML (e.g. experiments/quickstart.toml)")
    p.add_argument("--out", metavar="DIR", help="results directory (default runs/<name>-<time>)")
    p.add_argument(
        "--seed", type=int, metavar="N", help="seed of the run (overrides experiment.seed)"
    )
    add_overrides(p)
    add_evaluation_options(p)
    p.add_argument("--resume", metavar="DIR", help="continue the interrupted run in DIR")
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bar, no summary")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Run (or resume) and print where the results went. A config renamed in 0.2 is
    named (:func:`growsim.cli.arguments.renamed_config`), a preset renamed in 0.2 taken
    with a note."""
    renamed_config(args.config)
    with deprecation_notes():
        return _run(args)


def _run(args: argparse.Namespace) -> int:
    from growsim.experiment import run

    if args.resume is not None:
        if args.out is not None and args.out != args.resume:
            raise UserInputError("--out: not used with --resume (results stay in the DIR resumed)")
        if args.overrides:
            raise UserInputError("--set: a resumed run keeps its config; start a new run instead")
        from growsim.experiment.results import RunDir

        if RunDir(args.resume).is_complete() and args.config is None:
            # finished: nothing to resume; say so and leave its outputs as they are
            print(
                f"{args.resume}: this run is finished (summary.json); nothing to resume, "
                f"its results are unchanged; look at it with: growsim show {args.resume}"
            )
            return 0
    elif args.config is None:
        raise UserInputError("give a CONFIG to run, or --resume DIR")
    result = run(
        args.config,
        args.resume if args.resume is not None else args.out,
        seed=args.seed,
        overrides=args.overrides,
        workers=args.workers,
        scheduler=args.scheduler,
        resume=args.resume is not None,
        progress=not args.quiet,
    )
    if not args.quiet:
        s = result.summary
        out = result.out
        print(
            f"{s['experiment']}: best fitness {s['best_fitness']:.6g} "
            f"(generation {s['best_generation']}), {s['evaluations']} evaluations "
            f"in {s['wall_seconds']:.1f} s; stop: {s['stop_reason']}"
        )
        print(f"results in {out}/")
        pngs = sorted(p.name for p in out.glob("best_*.png"))
        if pngs:
            print(f"  renders: {', '.join(str(out / n) for n in pngs)}")
        kind = result.best.get("phenotype", "plant")
        what = SHOW_WHAT.get(kind, f"the best {kind}")
        print(f"  look at {what}: growsim show {out}")
        print(f"  compare runs: growsim compare {out} ...")
        for w in s.get("warnings", []):
            print(f"  warning: {w}", file=sys.stderr)
    return 0
