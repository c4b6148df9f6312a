"""Loading a config: read TOML, apply ``--set`` overrides, validate, compile.

- :func:`parse_overrides`: ``key.path=value`` strings into (path parts, value) pairs;
- :func:`load_plan`: the one way into a plan: read, override, validate and compile a
  config (a TOML path, a dict, a :class:`Config` or an
  :class:`~growsim.experiment.plan.ExperimentPlan`) into an ``ExperimentPlan`` (every
  objective built once); ``run``, ``sweep``, the species run, the report and
  ``fit-image`` all come in here;
- :func:`load_config`: the same, returning only the resolved :class:`Config`;
- :func:`build_fitness`: ``load_plan(source).fitness()``.

Every problem raises :class:`growsim.errors.ConfigError` (or ``UserInputError`` for an
unreadable file) with one line naming the key path.
"""

from __future__ import annotations

import copy
import re
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from pydantic import ValidationError

from growsim.env.environment import SHORTHANDS, expand_shorthands
from growsim.errors import ConfigError, UserInputError
from growsim.experiment.fitness import Fitness
from growsim.experiment.plan import ExperimentPlan, compile_plan
from growsim.experiment.schema import Config
from growsim.options import key_path, validation_message

__all__ = [
    "UNSET",
    "build_fitness",
    "config_difference",
    "flatten_config",
    "load_config",
    "load_plan",
    "parse_overrides",
    "parse_path",
    "parse_value",
    "read_config",
    "set_path",
    "validate",
]

#: Short aliases accepted at the start of a key path (``env.light`` = ``environment.light``).
ALIASES = {"env": "environment", "objectives": "objective", "exp": "experiment"}


def parse_path(path: str) -> list[str | int]:
    """Split ``objective[0].weight`` / ``objective.0.weight`` / ``env.light`` into parts.

    Examples
    --------
    >>> parse_path("env.light.intensity"), parse_path("objective[1].weight")
    (['environment', 'light', 'intensity'], ['objective', 1, 'weight'])
    """
    if not path or path.strip() != path:
        raise ConfigError(f"bad key path {path!r}")
    parts: list[str | int] = []
    for raw in path.split("."):
        m = re.fullmatch(r"([^\[\]]*)((?:\[\d+\])*)", raw)
        if m is None or (not m.group(1) and not m.group(2)):
            raise ConfigError(f"bad key path {path!r}")
        if m.group(1):
            parts.append(int(m.group(1)) if m.group(1).isdigit() else m.group(1))
        parts.extend(int(i) for i in re.findall(r"\[(\d+)\]", m.group(2)))
    if isinstance(parts[0], str):
        parts[0] = ALIASES.get(parts[0], parts[0])
    return parts


def flatten_config(data: Any, prefix: tuple[str, ...] = ()) -> dict[tuple[str, ...], Any]:
    """The leaves of config data by key path: ``{("environment", "light", "intensity"):
    0.5, ...}``. Lists of tables are indexed (``objective[0]``); other lists are values.

    Examples
    --------
    >>> flatten_config({"objective": [{"kind": "light"}], "ga": {"bounds": [0, 1]}})
    {('objective[0]', 'kind'): 'light', ('ga', 'bounds'): [0, 1]}
    """
    out: dict[tuple[str, ...], Any] = {}
    if isinstance(data, dict):
        for k, v in data.items():
            if isinstance(v, list) and v and all(isinstance(e, dict) for e in v):
                for i, e in enumerate(v):
                    out.update(flatten_config(e, (*prefix, f"{k}[{i}]")))
            else:
                out.update(flatten_config(v, (*prefix, str(k))))
    else:
        out[prefix] = data
    return out


#: the value of a key a config does not have (see :func:`config_difference`)
UNSET = "unset"


def config_difference(a: Any, b: Any) -> tuple[str, Any, Any] | None:
    """The first key path where two configs (as data) differ, with its value in each
    (:data:`UNSET` where one has no such key), or ``None`` when they are equal. Numbers
    compare by value (``1 == 1.0``).

    Examples
    --------
    >>> config_difference({"ga": {"population": 8, "elite": 1}}, {"ga": {"population": 6}})
    ('ga.population', 8, 6)
    >>> config_difference({"objective": [{"kind": "light", "wood_cost": 1.0}]},
    ...                   {"objective": [{"kind": "light", "wood_cost": 1}]}) is None
    True
    """

    def same(x, y):
        numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (x, y))
        return (numbers or type(x) is type(y)) and x == y

    fa, fb = flatten_config(a), flatten_config(b)
    for path in [*fa, *(p for p in fb if p not in fa)]:
        va, vb = fa.get(path, UNSET), fb.get(path, UNSET)
        if path not in fa or path not in fb or not same(va, vb):
            return ".".join(path), va, vb
    return None


def parse_value(text: str) -> Any:
    """A TOML value (``50``, ``0.5``, ``true``, ``[1, 2]``, ``"x"``), else the raw string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_overrides(overrides: Sequence[str]) -> list[tuple[list[str | int], Any]]:
    """Parse ``key.path=value`` strings into (path parts, value) pairs.

    Values are read as TOML values (``50`` is an int, ``[0.5, 1]`` a list, ``true`` a
    bool); anything that is not valid TOML is taken as a string (``model.preset=zelkova``).

    Examples
    --------
    >>> parse_overrides(["ga.population=50", "env.light=0.5", "objective[0].weight=2"])
    [(['ga', 'population'], 50), (['environment', 'light'], 0.5), (['objective', 0, 'weight'], 2)]
    """
    out = []
    for item in overrides:
        if not isinstance(item, str) or "=" not in item:
            raise ConfigError(f"override {item!r}: expected key.path=value")
        key, value = item.split("=", 1)
        out.append((parse_path(key.strip()), parse_value(value.strip())))
    return out


def set_path(data: dict, parts: list[str | int], value: Any, label: str) -> None:
    """Set ``value`` at the key path ``parts`` of nested config data, in place (tables
    and the ``objective`` list are created as needed); ``label`` names it in errors.

    Examples
    --------
    >>> d = {}
    >>> set_path(d, ["ga", "population"], 8, "--set")
    >>> d
    {'ga': {'population': 8}}
    >>> d = {"environment": {"light": {"direction": [1, -1, 0], "intensity": 1.0}}}
    >>> set_path(d, ["environment", "light"], 0.5, "--set")  # a shorthand keeps the table
    >>> d["environment"]["light"]
    {'direction': [1, -1, 0], 'intensity': 0.5}
    """
    if len(parts) == 2 and parts[0] == "environment" and parts[1] in SHORTHANDS:
        table, key = SHORTHANDS[parts[1]]
        if not isinstance(value, dict):
            parts = ["environment", table, key]
    node: Any = data
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        where = key_path(parts[: i + 1])
        if isinstance(part, int):
            if not isinstance(node, list):
                raise ConfigError(f"{label}: {key_path(parts[:i])} is not a list")
            if part > len(node):
                raise ConfigError(f"{label}: {where}: index out of range (have {len(node)})")
            if part == len(node):
                node.append({})
            if last:
                node[part] = value
            else:
                node = node[part]
            continue
        if not isinstance(node, dict):
            raise ConfigError(f"{label}: {key_path(parts[:i])} is not a table")
        if last:
            node[part] = value
        else:
            if part not in node:
                node[part] = [] if part == "objective" else {}
            node = node[part]


def read_toml(path: Path) -> dict:
    """The tables of a TOML file; a clear error for a missing, unreadable or bad file."""
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise UserInputError(f"{path}: no such config file") from None
    except IsADirectoryError:
        raise UserInputError(f"{path}: is a directory, expected a TOML config file") from None
    except OSError as exc:
        raise UserInputError(f"{path}: cannot read ({exc.strerror})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path}: not UTF-8 text (byte {exc.start})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: invalid TOML: {exc}") from None


def _absolute_paths(data: Any, bases: Sequence[Path]) -> None:
    """Make the file options of objectives absolute, in place.

    A relative path in an objective table (e.g. a target image ``front = "front.png"``)
    is looked up next to the config file first, then in the working directory; the first
    existing file wins and is written as an absolute path, so the ``config.toml`` saved
    with a run (and ``--resume``) works from any directory.
    """
    objectives = data.get("objective") if isinstance(data, dict) else None
    if not isinstance(objectives, list):
        return
    for table in objectives:
        if not isinstance(table, dict):
            continue
        for key, value in table.items():
            if key in ("kind", "weight") or not isinstance(value, str) or not value:
                continue
            try:
                p = Path(value)
                if p.is_absolute() or not (p.suffix or len(p.parts) > 1):
                    continue
                for base in bases:
                    if (base / p).is_file():
                        table[key] = str((base / p).resolve())
                        break
            except (OSError, ValueError):  # not a usable path: leave it to the objective
                continue


def validate(data: Mapping[str, Any], label: str = "config") -> Config:
    """Validate config data against the schema (no model or objective is built).

    Examples
    --------
    >>> validate({"model": {"kind": "honda"}, "objective": [{"kind": "light", "x": 1}]})
    ... # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.ConfigError: objective[0].x: unknown key; allowed: kind, weight, ...
    """
    try:
        return Config.model_validate(data)
    except ValidationError as exc:
        raise ConfigError(validation_message(exc, "", Config)) from None
    except (TypeError, ValueError) as exc:  # pragma: no cover - pydantic wraps these
        raise ConfigError(f"{label}: {exc}") from None


def read_config(source, overrides: Sequence[str] = ()) -> Config:
    """Read a path, dict, :class:`Config` or ``ExperimentPlan`` (its config), apply
    ``overrides``, make relative file names absolute and validate against the schema
    (nothing is compiled or built).

    Examples
    --------
    >>> read_config("experiments/quickstart.toml", ["env.light=0.5"]).environment.light.intensity
    0.5
    """
    if isinstance(source, ExperimentPlan):
        source = source.config
    if isinstance(source, Config):
        data, bases = source.to_dict(), [Path.cwd()]
    elif isinstance(source, Mapping):
        data, bases = copy.deepcopy(dict(source)), [Path.cwd()]
    else:
        data, bases = read_toml(Path(source)), [Path(source).resolve().parent, Path.cwd()]
    env = data.get("environment") if isinstance(data, dict) else None
    if isinstance(env, dict):  # shorthands as tables, so overrides of their keys apply
        try:
            data["environment"] = expand_shorthands(env)
        except ValueError as exc:
            raise ConfigError(f"environment.{exc}") from None
    for parts, value in parse_overrides(overrides):
        set_path(data, parts, value, "--set " + key_path(parts))
    _absolute_paths(data, bases)
    return validate(data)


def load_plan(source, overrides: Sequence[str] = ()) -> ExperimentPlan:
    """Read, override, validate and compile a config: an :class:`ExperimentPlan`. The
    one way into a plan.

    ``source`` is a TOML path, a dict of the same shape, a :class:`Config` or an
    ``ExperimentPlan``. ``overrides`` are ``key.path=value`` strings applied before
    validation. The model, its preset, fixed and evolved parameters, the objectives (built
    once, each checked to accept the model's phenotype) and the GA operators are all
    checked here, so a bad config fails before anything runs. Relative file paths in
    objective tables are looked up next to the config file, then in the working
    directory, and made absolute. A plan without overrides is returned as it is (its
    objectives are not built again); a :class:`Config` without overrides is compiled as
    it is (it was validated when made).

    Examples
    --------
    >>> plan = load_plan("experiments/quickstart.toml", ["ga.population=8"])
    >>> plan.model.name, plan.config.ga.population, len(plan.objectives)
    ('honda', 8, 1)
    >>> load_plan(plan) is plan, load_plan(plan, ["ga.population=6"]).config.ga.population
    (True, 6)
    >>> load_plan(plan.config).config == plan.config
    True
    """
    if not overrides:
        if isinstance(source, ExperimentPlan):
            return source
        if isinstance(source, Config):
            return compile_plan(source)
    return compile_plan(read_config(source, overrides))


def load_config(source, overrides: Sequence[str] = ()) -> Config:
    """Read, override, validate and resolve an experiment config (see :func:`load_plan`,
    which this compiles to check it; use that to run without compiling twice).

    Raises :class:`growsim.errors.ConfigError` with a one-line message naming the key path.

    Examples
    --------
    >>> cfg = load_config({"model": {"kind": "honda", "evolve": {"f": True}},
    ...                    "objective": [{"kind": "light"}]}, overrides=["ga.population=8"])
    >>> cfg.ga.population, cfg.ga.generations
    (8, 20)
    """
    return load_plan(source, overrides).config


def build_fitness(source, overrides: Sequence[str] = ()) -> Fitness:
    """The picklable :class:`Fitness` of anything :func:`load_plan` takes:
    ``load_plan(source, overrides).fitness()``.

    Examples
    --------
    >>> f = build_fitness("experiments/quickstart.toml")
    >>> f.model.name
    'honda'
    """
    return load_plan(source, overrides).fitness()
