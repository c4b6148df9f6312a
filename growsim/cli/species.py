"""``growsim species CONFIG``: evolve a species with Ochoa's weighted fitness and record
the best plant of every generation (:func:`growsim.experiment.species.evolve_species`)."""

from __future__ import annotations

import argparse

from growsim.cli.arguments import add_overrides

__all__ = ["register"]


def register(subparsers) -> None:
    """Add the ``species`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> args = build_parser().parse_args(["species", "experiments/ifs_species.toml", "-q"])
    >>> args.config, args.quiet
    ('experiments/ifs_species.toml', True)
    """
    p = subparsers.add_parser(
        "species",
        help="evolve a species (ochoa objective), recording every generation's best",
        description="Run an experiment whose objective is 'ochoa' and write, besides the "
        "run's files, generations.parquet (each generation's best and its four terms), "
        "generations.png (the first, middle and last generation's best) and terms.png.",
    )
    p.add_argument("config", help="experiment TOML (e.g. experiments/ifs_species.toml)")
    p.add_argument("--out", metavar="DIR", help="results directory (default runs/<name>-<time>)")
    p.add_argument(
        "--seed", type=int, metavar="N", help="seed of the run (overrides experiment.seed)"
    )
    add_overrides(p)
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bar, no table")
    p.set_defaults(func=main)


def main(args: argparse.Namespace) -> int:
    """Evolve, then print each generation's best and its terms."""
    from growsim.experiment.species import evolve_species
    from growsim.objectives.ochoa import TERMS

    result, table = evolve_species(
        args.config, out=args.out, seed=args.seed, overrides=args.overrides,
        progress=not args.quiet,
    )  # fmt: skip
    if not args.quiet:
        print(table[["generation", "fitness", *TERMS]].round(4).to_string(index=False))
        print(f"results: {result.out}")
    return 0
