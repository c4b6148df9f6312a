"""Command-line options shared by several subcommands: config overrides and where
evaluations run (``run``, ``sweep``), screenshot view and size (``grow``, ``show``). Not a
subcommand itself (no ``register``)."""

from __future__ import annotations

import argparse

__all__ = ["add_evaluation_options", "add_overrides", "add_screenshot_options"]


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


class _ViewNames:
    """The names of :data:`growsim.viz.VIEWS` as argparse choices, read when first needed
    (building the parser imports neither NumPy nor pyvista)."""

    def _names(self) -> tuple[str, ...]:
        from growsim.viz import VIEWS

        return tuple(VIEWS)

    def __contains__(self, item) -> bool:
        return item in self._names()

    def __iter__(self):
        return iter(self._names())


class _Size(argparse.Action):
    """``--size W H`` or ``--size N`` (``N x N``) into a ``(W, H)`` tuple."""

    def __call__(self, parser, namespace, values, option_string=None):
        if len(values) > 2:
            parser.error(f"argument {option_string}: expected W H or N, got {len(values)} numbers")
        setattr(namespace, self.dest, (values[0], values[-1]))


def add_screenshot_options(p: argparse.ArgumentParser, view: str = "front") -> None:
    """``--view`` (one of :data:`growsim.viz.VIEWS`, default ``view``) and ``--size W H``
    (or ``N`` for a square; checked by :func:`growsim.viz.check_size` before anything is
    grown or read): the screenshot options of ``grow`` and ``show``.

    Examples
    --------
    >>> p = argparse.ArgumentParser()
    >>> add_screenshot_options(p)
    >>> a = p.parse_args(["--view", "back", "--size", "300"])
    >>> a.view, a.size
    ('back', (300, 300))
    """
    p.add_argument(
        "--view",
        default=view,
        choices=_ViewNames(),
        metavar="VIEW",
        help=f"screenshot camera: %(choices)s (default {view})",
    )
    p.add_argument(
        "--size",
        type=int,
        nargs="+",
        action=_Size,
        default=(800, 800),
        metavar=("W", "H"),
        help="screenshot size in pixels: W H, or N for N x N (each 16..4096; default 800 800)",
    )
