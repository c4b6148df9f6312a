"""The ``growsim`` command line.

Each subcommand lives in its own module in this package and defines
``register(subparsers)``, which adds its parser and sets ``func`` (a callable taking the
parsed ``argparse.Namespace`` and returning an exit code). :func:`main` discovers them.

Errors derived from :class:`growsim.errors.GrowsimError` are printed as
``growsim: error: ...`` with exit code 2 and no traceback. Ctrl-C (SIGINT) stops a command
with exit code 130, SIGTERM (a batch system's time limit, ``kill``) the same way with 143:
both wait for what must not be cut (a checkpoint being written) and end the command's
worker processes.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import signal
import sys
import threading
from collections.abc import Callable

from growsim import __version__
from growsim.errors import GrowsimError

__all__ = ["build_parser", "command", "main"]


class _Parser(argparse.ArgumentParser):
    """An ``ArgumentParser`` whose usage errors are one line (``growsim: error: ...``),
    exit code 2, like every other growsim error."""

    #: what adds the parser's options when they are first needed (:meth:`fill_later`)
    _fill: Callable[[argparse.ArgumentParser], None] | None = None

    def error(self, message: str):
        self.exit(2, f"growsim: error: {self.prog}: {message} (see '{self.prog} --help')\n")

    def fill_later(self, fill: Callable[[argparse.ArgumentParser], None]) -> None:
        """Add this parser's options with ``fill(parser)`` the first time it parses or
        prints its help, not when ``growsim --help`` builds every subcommand: options
        made from a library's schema then cost nothing to the other commands."""
        self._fill = fill

    def fill_now(self) -> None:
        """Add the options :meth:`fill_later` was given, now (once)."""
        fill, self._fill = self._fill, None
        if fill is not None:
            fill(self)

    def parse_known_args(self, args=None, namespace=None):
        self.fill_now()
        return super().parse_known_args(args, namespace)

    def format_help(self) -> str:
        self.fill_now()
        return super().format_help()

    def format_usage(self) -> str:
        self.fill_now()
        return super().format_usage()


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


#: set when SIGTERM stopped the command
_terminated: list[int] = []


def _on_sigterm(signum, frame) -> None:
    """SIGTERM: stop as Ctrl-C does (its handler, deferred where a run holds it)."""
    _terminated.append(signum)
    if signal.getsignal(signal.SIGINT) in (signal.SIG_IGN, signal.SIG_DFL, None):
        raise KeyboardInterrupt  # no Python handler of Ctrl-C to defer it: stop here
    signal.raise_signal(signal.SIGINT)


def main(argv: list[str] | None = None, *, process: bool = False) -> int:
    """Run the command line; returns the exit code (0 ok, 2 bad input, 130 interrupted by
    Ctrl-C, 143 by SIGTERM).

    Once interrupted, further Ctrl-Cs are ignored while it reports; ``process`` (the
    ``growsim`` command, :func:`command`: the process exits next) keeps them ignored while
    the interpreter shuts down, else (called from Python) Ctrl-C's handler is put back as
    it was, so the caller and the processes it starts later can still be interrupted.

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
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.getsignal(signal.SIGTERM) if main_thread else None
    previous_int = signal.getsignal(signal.SIGINT) if main_thread else None
    if previous == signal.SIG_DFL:
        signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        return int(args.func(args) or 0)
    except GrowsimError as exc:
        print(f"growsim: error: {exc}", file=sys.stderr)
        return exc.exit_code
    except KeyboardInterrupt:
        # a second Ctrl-C while it reports (and, for the command, while the interpreter
        # shuts down) must not interrupt it again or kill it by the signal
        if main_thread:
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        if _terminated:
            _terminated.clear()
            print("growsim: terminated", file=sys.stderr)
            return 143
        print("growsim: interrupted", file=sys.stderr)
        return 130
    finally:
        if previous == signal.SIG_DFL:
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
        if main_thread and not process and previous_int is not None:
            signal.signal(signal.SIGINT, previous_int)


def command() -> None:
    """The ``growsim`` command (and ``python -m growsim``): :func:`main` as its own
    process, which then exits with its code.

    Examples
    --------
    >>> import subprocess, sys
    >>> subprocess.run([sys.executable, "-m", "growsim", "--version"]).returncode  # doctest: +SKIP
    0
    """
    sys.exit(main(process=True))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
