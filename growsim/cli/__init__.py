"""The ``growsim`` command line.

Each subcommand lives in its own module in this package and defines
``register(subparsers)``, which adds its parser and sets ``func`` (a callable taking the
parsed ``argparse.Namespace`` and returning an exit code). :func:`main` discovers them.

Errors derived from :class:`growsim.errors.GrowsimError` are printed as
``growsim: error: ...`` with exit code 2 and no traceback.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import signal
import sys

from growsim import __version__
from growsim.errors import GrowsimError

__all__ = ["build_parser", "main"]


class _Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors are one line (``growsim: error: ...``),
    exit code 2, like every other growsim error."""

    def error(self, message: str):
        self.exit(2, f"growsim: error: {self.prog}: {message} (see '{self.prog} --help')\n")


def build_parser() -> argparse.ArgumentParser:
    """The top-level parser with every discovered subcommand.

    Examples
    --------
    >>> p = build_parser()
    >>> p.prog
    'growsim'
    """
    parser = _Parser(
        prog="growsim",
        description="growsim: evolutionary plant-growth simulator (one GA, many plant models).",
    )
    parser.add_argument("--version", action="version", version=f"growsim {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        register = getattr(module, "register", None)
        if register is not None:
            register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit code (0 ok, 2 bad input, 130 interrupted).

    Examples
    --------
    >>> main(["--version"])  # doctest: +SKIP
    growsim 0.1.0
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if getattr(args, "func", None) is None:
        parser.print_help()
        return 0
    try:
        return int(args.func(args) or 0)
    except GrowsimError as exc:
        print(f"growsim: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        # a second Ctrl-C while the interpreter shuts down must not kill it by the signal
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        print("growsim: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
