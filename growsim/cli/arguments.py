"""Command-line options shared by several subcommands: config overrides and where
evaluations run (``run``, ``sweep``), screenshot view and size, and the colouring of a
plant by its environment (``grow``, ``show``), :class:`Later` (what the library gives
a parser, read when first needed), and what the commands say of names renamed in 0.2
(:func:`deprecation_notes`, :func:`renamed_config`). Not a subcommand itself (no
``register``)."""

from __future__ import annotations

import argparse
import contextlib
import sys
import warnings
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

from growsim.errors import UserInputError

__all__ = [
    "DEFAULT_VIEW",
    "RENAMED",
    "Later",
    "add_color_options",
    "add_environment_options",
    "add_evaluation_options",
    "add_overrides",
    "add_screenshot_options",
    "deprecation_notes",
    "environment_table",
    "renamed_config",
]

#: the camera of ``grow`` and ``show`` when no ``--view`` is given (both the same). Front,
#: looking along -z: the view docs/plant.md's pictures are drawn in, and the one that
#: shows a 2D plant (hormone ``dims = 2``, in the x-y plane) face on, where iso would
#: show it edge-on at an angle.
DEFAULT_VIEW = "front"

#: parts of file names renamed in 0.2 (old, new): "seed" meant the source paper there,
#: and a seed in growsim is a random seed (``growsim run`` names the new file)
RENAMED = (("_seed_ga", "_paper_ga"),)


class Later:
    """Names the library gives a parser (a choice list, names for a help text), read the
    first time they are needed: when a value is checked or the help printed, not when
    the parser is built. ``growsim --help`` builds every subcommand's parser, so a
    subcommand's module imports no library module at its top (``docs/design.md``,
    "Imports"). As ``choices=`` it checks values; in a help text ``%(name)s`` of an
    attribute set on the action (or ``%(choices)s``) lists the names.

    Examples
    --------
    >>> modes = Later(lambda: ("auto", "fit"))
    >>> "fit" in modes, str(modes), list(modes)
    (True, 'auto, fit', ['auto', 'fit'])
    """

    def __init__(self, load: Callable[[], Sequence[str]]):
        self._load = load
        self._names: tuple[str, ...] | None = None

    def names(self) -> tuple[str, ...]:
        """The names, loaded once."""
        if self._names is None:
            self._names = tuple(self._load())
        return self._names

    def __iter__(self) -> Iterator[str]:
        return iter(self.names())

    def __contains__(self, value) -> bool:
        return value in self.names()

    def __len__(self) -> int:
        return len(self.names())

    def __str__(self) -> str:
        return ", ".join(self.names())


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


class _VizNames:
    """The names of a table (``growsim.render.VIEWS``, ``growsim.phenotypes.plant.colors.COLORS``)
    as argparse choices, read when first needed (building the parser imports neither NumPy
    nor pyvista)."""

    def __init__(self, module: str, table: str):
        self.module, self.table = module, table

    def _names(self) -> tuple[str, ...]:
        import importlib

        return tuple(vars(importlib.import_module(self.module))[self.table])

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


def add_screenshot_options(p: argparse.ArgumentParser, view: str = DEFAULT_VIEW) -> None:
    """``--view`` (one of :data:`growsim.render.VIEWS`, default ``view``) and ``--size W H``
    (or ``N`` for a square; checked by :func:`growsim.render.check_size` before
    anything is
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
        choices=_VizNames("growsim.render", "VIEWS"),
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


def add_color_options(p: argparse.ArgumentParser) -> None:
    """``--color FIELD`` (one of :data:`growsim.phenotypes.plant.colors.COLORS`: paint each
    segment by the light
    it receives, the stress ratio at its joint or the share of its water demand met) and
    ``--light-arrow`` / ``--no-light-arrow`` (draw the light's direction; default: with
    ``--color light``): the colouring options of ``grow`` and ``show``.

    Examples
    --------
    >>> p = argparse.ArgumentParser()
    >>> add_color_options(p)
    >>> a = p.parse_args(["--color", "stress", "--light-arrow"])
    >>> a.color, a.light_arrow
    ('stress', True)
    >>> p.parse_args([]).light_arrow is None
    True
    """
    p.add_argument(
        "--color",
        choices=_VizNames("growsim.phenotypes.plant.colors", "COLORS"),
        metavar="FIELD",
        help="colour by the environment: %(choices)s (light received, stress: 1 breaks, water met)",
    )
    p.add_argument(
        "--light-arrow",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="draw the light's direction as an arrow from the light's side "
        "(default: with --color light)",
    )


def add_environment_options(p: argparse.ArgumentParser) -> None:
    """``--config FILE`` (an experiment config: its ``[environment]``, the whole file
    validated as ``growsim run`` does) or ``--environment FILE`` (a TOML file of the
    environment's tables, or any file with an ``[environment]`` table): the environment
    ``grow`` grows in and ``show`` colours by (:func:`environment_table` reads them).

    Examples
    --------
    >>> p = argparse.ArgumentParser()
    >>> add_environment_options(p)
    >>> p.parse_args(["--config", "experiments/hormone_3d.toml"]).config
    'experiments/hormone_3d.toml'
    """
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--config",
        metavar="FILE",
        help="take the environment of this experiment config (its [environment] table)",
    )
    g.add_argument(
        "--environment",
        metavar="FILE",
        help="take the environment of this TOML file ([light], [water], ... tables, or an "
        "[environment] table)",
    )


def environment_table(args: argparse.Namespace) -> tuple[dict, str] | None:
    """The ``[environment]`` table of ``--config FILE`` or ``--environment FILE`` (shorthands
    written as tables) and a label naming where it came from, or ``None`` if neither is
    given. A missing, unreadable or invalid file is a one-line error naming the option and
    the key; ``--config`` validates the whole config, as ``growsim run`` does.

    Examples
    --------
    >>> a = argparse.Namespace(config="experiments/hormone_2d.toml", environment=None)
    >>> table, label = environment_table(a)
    >>> table["light"]["diffuse"], label
    (0.5, '--config experiments/hormone_2d.toml')
    >>> environment_table(argparse.Namespace(config=None, environment=None)) is None
    True
    """
    from pathlib import Path

    from pydantic import ValidationError

    from growsim.env import Environment
    from growsim.env.environment import expand_shorthands
    from growsim.errors import ConfigError
    from growsim.experiment.load import read_config, read_toml
    from growsim.options import validation_message

    config, env_file = getattr(args, "config", None), getattr(args, "environment", None)
    if config is None and env_file is None:
        return None
    option, path = ("--config", config) if config is not None else ("--environment", env_file)
    label = f"{option} {path}"
    if config is not None:
        try:
            read_config(path)
        except ConfigError as exc:
            msg = str(exc)
            raise ConfigError(msg if msg.startswith(str(path)) else f"{label}: {msg}") from None
        data = read_toml(Path(path))
        table = data.get("environment", {})
    else:
        data = read_toml(Path(path))
        table = data["environment"] if "environment" in data else data
    if not isinstance(table, dict):
        raise ConfigError(f"{label}: environment: expected a table")
    try:
        table = expand_shorthands(table)
    except ValueError as exc:
        raise ConfigError(f"{label}: environment.{exc}") from None
    try:
        Environment.model_validate(table)
    except ValidationError as exc:
        msg = validation_message(exc, "environment.", Environment)
        raise ConfigError(f"{label}: {msg}") from None
    return table, label


@contextlib.contextmanager
def deprecation_notes(stream=None) -> Iterator[None]:
    """Within it, growsim's deprecations (a name renamed in 0.2 and taken until 0.3: a
    preset, a function) are printed once each as a one-line note on ``stream`` (default
    stderr), ``growsim: note: <what changed>``; other warnings show as usual.

    Examples
    --------
    >>> with deprecation_notes(stream=sys.stdout):
    ...     for _ in range(2):
    ...         warnings.warn("preset 'a' is now 'b'; the old name goes in 0.3", DeprecationWarning)
    growsim: note: preset 'a' is now 'b'; the old name goes in 0.3
    """
    shown: set[str] = set()
    with warnings.catch_warnings():
        previous = warnings.showwarning

        def show(message, category, filename, lineno, file=None, line=None):
            text = str(message)
            if not (issubclass(category, DeprecationWarning) and text.endswith("goes in 0.3")):
                previous(message, category, filename, lineno, file, line)
            elif text not in shown:
                shown.add(text)
                print(f"growsim: note: {text}", file=stream or sys.stderr)

        warnings.showwarning = show
        warnings.filterwarnings("always", r".*goes in 0\.3$", DeprecationWarning)
        yield


def renamed_config(path) -> None:
    """Refuse a config ``path`` that does not exist because its file was renamed in 0.2
    (:data:`RENAMED`), naming the new file; any other path passes (a missing one is
    refused where it is read).

    Examples
    --------
    >>> import growsim
    >>> exp = Path(growsim.__file__).parents[1] / "experiments"
    >>> try:
    ...     renamed_config(exp / "hormone_2d_seed_ga.toml")
    ... except UserInputError as e:
    ...     print(str(e).replace(str(exp), "experiments").replace("; ", ";\\n"))
    experiments/hormone_2d_seed_ga.toml: no such file;
    it was renamed experiments/hormone_2d_paper_ga.toml
    >>> renamed_config(exp / "quickstart.toml")
    """
    if path is None or Path(path).exists():
        return
    given = Path(path)
    for old, new in RENAMED:
        moved = given.with_name(given.name.replace(old, new))
        if old in given.name and moved.exists():
            raise UserInputError(f"{path}: no such file; it was renamed {moved}")
