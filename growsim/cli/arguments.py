"""Command-line options shared by several subcommands (``run``, ``sweep``): config
overrides and where evaluations run. Not a subcommand itself (no ``register``)."""

from __future__ import annotations

import argparse

__all__ = ["add_evaluation_options", "add_overrides"]


def add_overrides(p: argparse.ArgumentParser, what: str = "") -> None:
    """``--set KEY=VALUE`` (repeatable) into ``args.overrides``.

    Examples
    --------
    >>> p = argparse.ArgumentParser()
    >>> add_overrides(p)
    >>> p.parse_args(["--set", "ga.population=8", "--set", "env.light=0.5"]).overrides
    ['ga.population=8', 'env.light=0.5']
    """
    p.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help=f"override a config key{what}, e.g. --set ga.population=50 (repeatable)",
    )


def add_evaluation_options(p: argparse.ArgumentParser) -> None:
    """``--workers N`` and ``--scheduler ADDR``: where evaluations run.

    Examples
    --------
    >>> p = argparse.ArgumentParser()
    >>> add_evaluation_options(p)
    >>> p.parse_args(["--workers", "2", "--scheduler", "local"]).workers
    2
    """
    p.add_argument("--workers", type=int, metavar="N", help="evaluate in N local processes")
    p.add_argument(
        "--scheduler",
        metavar="ADDR",
        help="evaluate on Dask: 'local' (a LocalCluster of --workers processes) or tcp://host:port",
    )
