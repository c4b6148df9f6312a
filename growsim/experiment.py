"""Experiment configs, runs and sweeps: the user's way into growsim.

An experiment is a TOML file (see ``docs/configs.md``, generated from the schema below by
``python -m growsim.experiment --docs``) with the sections ``[experiment]``, ``[model]``
(+ ``[model.evolve]``), ``[environment]``, ``[[objective]]``, ``[ga]`` and ``[output]``.

- :func:`load_config` validates a file or dict (unknown keys, wrong types and values out
  of range raise :class:`growsim.errors.ConfigError` naming the key path and the allowed
  values), fills defaults and applies ``key.path=value`` overrides.
- :func:`run` runs one experiment into a results directory (:mod:`growsim.results`) and
  returns a :class:`RunResult`; ``resume=True`` continues a killed run to the same result.
- :func:`sweep` runs a grid of variants x repeats and returns one combined DataFrame.

Randomness: one seed per run (``experiment.seed``, or ``--seed``). The GA spawns its own
generator and one seed per evaluation (by the evaluation's global index) from it, so the
history does not depend on ``--workers`` or ``--scheduler``. Models are developed with
``model.noise = "fixed"`` (default): every evaluation of a genome grows the same plant (a
model's own ``seed`` parameter is used when it has one, fixed or evolved, else the run
seed), so a genome's fitness is a function of the genome; or ``"per-evaluation"``: each
evaluation grows with its own seed, so the GA selects for shapes that are good whatever
the random draws (a noisy fitness).
"""

from __future__ import annotations

import dataclasses
import itertools
import logging
import math
import re
import sys
import time
import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from growsim.errors import ConfigError, GrowsimError, UserInputError

__all__ = [
    "Config",
    "Fitness",
    "RunResult",
    "build_fitness",
    "config_docs",
    "load_config",
    "parse_overrides",
    "run",
    "sweep",
]

log = logging.getLogger(__name__)

#: Short aliases accepted at the start of a key path (``env.light`` = ``environment.light``).
ALIASES = {"env": "environment", "objectives": "objective", "exp": "experiment"}

VIEWS = ("front", "side", "top", "iso")
MESH_FORMATS = ("vtp", "ply", "obj", "glb")


# --------------------------------------------------------------------------------------
# schema
# --------------------------------------------------------------------------------------


class _Section(BaseModel):
    # strict: a TOML string "50" is not silently a population of 50; ints are accepted
    # for floats (pydantic's strict float does that), lists are used instead of tuples
    # because strict tuples reject TOML arrays.
    model_config = ConfigDict(extra="forbid", strict=True, validate_default=True)


class ExperimentConfig(_Section):
    """``[experiment]``: what this experiment is called and how it is seeded."""

    name: str = Field(
        "experiment",
        pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$",
        description="name of the experiment; used in the default results directory "
        "runs/<name>-<timestamp> (letters, digits, _ . -; at most 64)",
    )
    description: str = Field("", description="free text, copied to summary.json")
    seed: int = Field(0, ge=0, le=2**63 - 1, description="seed of the run (--seed overrides)")
    repeats: int = Field(
        1, ge=1, le=1000, description="default number of seeds per variant in growsim sweep"
    )


class ModelConfig(_Section):
    """``[model]``: which model, its fixed parameters and the parameters the GA evolves."""

    kind: str = Field(description="registered model name (growsim.models.MODELS)")
    preset: str | None = Field(None, description="named parameter set of the model to start from")
    params: dict[str, int | float] = Field(
        default_factory=dict,
        description="fixed parameter values (over the preset, over the model's defaults)",
    )
    evolve: dict[str, Any] = Field(
        default_factory=dict,
        description="parameters the GA evolves: name = true (the model's range) or "
        "[low, high] (a range inside the model's range); at least one",
    )
    noise: Literal["fixed", "per-evaluation"] = Field(
        "fixed",
        description="'fixed': a genome always grows the same plant (the model's seed "
        "parameter, else the run seed); 'per-evaluation': every evaluation grows with its "
        "own seed (noisy fitness, selects robust shapes)",
    )

    @field_validator("evolve")
    @classmethod
    def _check_evolve(cls, v):
        for name, spec in v.items():
            if spec is False:
                raise ValueError(f"{name} = false: leave it out instead (or set true)")
            if spec is True:
                continue
            ok = (
                isinstance(spec, list)
                and len(spec) == 2
                and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in spec)
            )
            if not ok:
                raise ValueError(f"{name}: expected true or [low, high], got {spec!r}")
            if not all(math.isfinite(x) for x in spec) or not spec[0] < spec[1]:
                raise ValueError(f"{name}: expected finite low < high, got {spec!r}")
        return {k: (True if x is True else [float(x[0]), float(x[1])]) for k, x in v.items()}

    @field_validator("params")
    @classmethod
    def _check_params(cls, v):
        for name, x in v.items():
            if not math.isfinite(x):
                raise ValueError(f"{name}: {x!r} is not a finite number")
        return v


class EnvironmentConfig(_Section):
    """``[environment]``: the world the plants grow in (models and objectives read it)."""

    light: float = Field(1.0, ge=0.0, le=1e6, description="light intensity (1 = full light)")
    light_direction: list[float] = Field(
        default_factory=lambda: [0.0, -1.0, 0.0],
        min_length=3,
        max_length=3,
        description="direction the parallel light travels (y up: [0, -1, 0] is from above)",
    )
    water: float = Field(1.0, ge=0.0, le=1e6, description="water supply (1 = ample)")
    gravity: float = Field(9.81, ge=0.0, le=1e3, description="gravity, m/s^2")

    @field_validator("light_direction")
    @classmethod
    def _check_direction(cls, v):
        if not all(math.isfinite(x) for x in v) or math.hypot(*v) == 0.0:
            raise ValueError(f"expected a finite non-zero 3-vector, got {v!r}")
        return v


class ObjectiveConfig(BaseModel):
    """``[[objective]]``: one scored term; other keys are options of the objective class."""

    model_config = ConfigDict(extra="allow", strict=True)

    kind: str = Field(description="registered objective name (growsim.objectives.OBJECTIVES)")
    weight: float = Field(
        1.0,
        description="weight in the sum of objectives (objectives that minimise count "
        "negatively: the GA maximises sum(weight * sign * score))",
    )

    @field_validator("weight")
    @classmethod
    def _finite(cls, v):
        if not math.isfinite(v) or v == 0.0:
            raise ValueError(f"expected a finite non-zero number, got {v!r}")
        return v

    def options(self) -> dict[str, Any]:
        """The keyword options passed to the objective class."""
        return dict(self.model_extra or {})


class GAConfig(_Section):
    """``[ga]``: the genetic algorithm (see docs/ga.md for the operators)."""

    population: int = Field(50, ge=2, le=10_000_000, description="individuals per generation")
    generations: int | None = Field(20, ge=0, le=10_000_000, description="stop after this many")
    evaluations: int | None = Field(None, ge=1, description="stop after this many evaluations")
    target: float | None = Field(None, description="stop when the best fitness reaches it")
    stagnation: int | None = Field(
        None, ge=1, description="stop after this many generations without improvement"
    )
    wall_time: float | None = Field(None, gt=0.0, description="stop after this many seconds")
    coding: Literal["real", "bits"] = Field("real", description="genome coding")
    bits: int = Field(8, ge=1, le=32, description="bits per parameter when coding = 'bits'")
    bit_coding: Literal["binary", "gray", "weighted", "fraction"] = Field(
        "binary", description="how bits map to a value when coding = 'bits'"
    )
    selection: str | None = Field(None, description="selection operator (default per coding)")
    crossover: str | None = Field(None, description="crossover operator (default per coding)")
    mutation: str | None = Field(None, description="mutation operator (default per coding)")
    selection_options: dict[str, Any] = Field(default_factory=dict, description="its options")
    crossover_options: dict[str, Any] = Field(default_factory=dict, description="its options")
    mutation_options: dict[str, Any] = Field(default_factory=dict, description="its options")
    model: Literal["generational", "steady", "mu+lambda"] = Field(
        "generational", description="generation model"
    )
    elite: int = Field(1, ge=0, description="best individuals copied unchanged")
    elite_rate: float | None = Field(
        None, ge=0.0, le=1.0, description="elite as a share of the population (over elite)"
    )
    islands: int = Field(1, ge=1, le=10_000, description="sub-populations")
    migration_rate: float = Field(0.1, ge=0.0, le=1.0, description="share migrating")
    migration_interval: int = Field(5, ge=1, description="generations between migrations")
    extinction: bool = Field(True, description="re-create a population that stops reproducing")
    batch_size: int | None = Field(None, ge=1, description="individuals per evaluation task")
    polish: dict[str, Any] | None = Field(
        None,
        description="local refinement of the best: evaluations, sigma, batch, min_sigma, "
        'method ("es" or "cmaes"), e.g. {evaluations = 500, sigma = 0.02}',
    )

    @model_validator(mode="after")
    def _check(self):
        if self.generations is None and self.evaluations is None and self.wall_time is None:
            raise ValueError("no budget: set at least one of generations, evaluations or wall_time")
        if self.elite >= self.population:
            raise ValueError(f"elite ({self.elite}) must be below population ({self.population})")
        return self


class OutputConfig(_Section):
    """``[output]``: which artefacts a run writes besides history, best and summary."""

    mesh: list[Literal["vtp", "ply", "obj", "glb"]] = Field(
        default_factory=lambda: ["vtp", "glb"], description="mesh formats of the best plant"
    )
    screenshots: list[Literal["front", "side", "top", "iso"]] = Field(
        default_factory=lambda: ["front", "iso"], description="views rendered to best_<view>.png"
    )
    size: list[int] = Field(
        default_factory=lambda: [800, 800],
        min_length=2,
        max_length=2,
        description="screenshot size [width, height] in pixels (16..4096)",
    )
    plot: bool = Field(True, description="write fitness.png")
    plant: bool = Field(True, description="write best_plant.npz (the best Plant)")

    @field_validator("size")
    @classmethod
    def _check_size(cls, v):
        if not all(16 <= s <= 4096 for s in v):
            raise ValueError(f"each of width, height must be in [16, 4096], got {v!r}")
        return v


class Config(BaseModel):
    """A whole, validated experiment config (the TOML file as objects).

    Examples
    --------
    >>> cfg = Config.model_validate({"model": {"kind": "honda", "evolve": {"f": True}},
    ...                              "objective": [{"kind": "light"}]})
    >>> cfg.ga.population
    50
    """

    model_config = ConfigDict(extra="forbid", strict=True)

    experiment: ExperimentConfig = Field(default_factory=ExperimentConfig)
    model: ModelConfig
    environment: EnvironmentConfig = Field(default_factory=EnvironmentConfig)
    objective: list[ObjectiveConfig] = Field(min_length=1, max_length=64)
    ga: GAConfig = Field(default_factory=GAConfig)
    output: OutputConfig = Field(default_factory=OutputConfig)

    def to_dict(self) -> dict[str, Any]:
        """The config as plain TOML-able data (``None`` values left out: TOML has no null).

        Examples
        --------
        >>> load_config("experiments/quickstart.toml").to_dict()["model"]["kind"]
        'honda'
        """
        return self.model_dump(mode="json", exclude_none=True)

    def to_toml(self) -> str:
        """The config as TOML text (what ``config.toml`` of a run holds)."""
        import tomli_w

        return tomli_w.dumps(self.to_dict())


SECTIONS: dict[str, type[BaseModel]] = {
    "experiment": ExperimentConfig,
    "model": ModelConfig,
    "environment": EnvironmentConfig,
    "objective": ObjectiveConfig,
    "ga": GAConfig,
    "output": OutputConfig,
}


# --------------------------------------------------------------------------------------
# loading, overrides, error messages
# --------------------------------------------------------------------------------------


def _loc_path(loc: Sequence[Any]) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out or "(top level)"


def _fields_at(loc: Sequence[Any]) -> list[str] | None:
    """Field names of the schema section at ``loc`` (for 'unknown key' messages)."""
    cls: type[BaseModel] = Config
    for part in loc:
        if isinstance(part, int):
            continue
        field = cls.model_fields.get(str(part))
        if field is None:
            return None
        ann = field.annotation
        nxt = None
        for cand in (ann, *getattr(ann, "__args__", ())):
            if isinstance(cand, type) and issubclass(cand, BaseModel):
                nxt = cand
        if nxt is None:
            return None
        cls = nxt
    return list(cls.model_fields)


_UNION_TAGS = {"bool", "int", "float", "str", "list", "dict"}


def _strip_union(loc: Sequence[Any]) -> list[Any]:
    """Drop the union branch pydantic appends to a location (``...f.int``)."""
    loc = list(loc)
    while loc and isinstance(loc[-1], str) and ("[" in loc[-1] or loc[-1] in _UNION_TAGS):
        loc.pop()
    return loc


def _validation_message(exc: ValidationError) -> str:
    """One line naming the key path of the first problem (and how many more there are)."""
    errors = exc.errors(include_url=False)
    first = errors[0]
    loc = _strip_union(first["loc"])
    kind = first["type"]
    path = _loc_path(loc)
    if kind == "extra_forbidden":
        allowed = _fields_at(loc[:-1])
        msg = f"{path}: unknown key" + (f"; allowed: {', '.join(allowed)}" if allowed else "")
    elif kind == "missing":
        msg = f"{path}: required key missing"
    else:
        text = re.sub(r" or instance of \w+", "", first["msg"].removeprefix("Value error, "))
        same = [e for e in errors if _strip_union(e["loc"]) == loc]
        tags = {e["loc"][-1] for e in same if len(e["loc"]) > len(loc)}
        if len(same) > 1 and tags == {"int", "float"}:  # the int | float of model.params
            text = "expected a number"
        got = first.get("input")
        got_s = repr(got)
        if len(got_s) > 60:
            got_s = got_s[:57] + "..."
        msg = f"{path}: {text}" + ("" if isinstance(got, dict) else f" (got {got_s})")
    n_more = len({tuple(_strip_union(e["loc"])) for e in errors} - {tuple(loc)})
    if n_more:
        msg += f" (and {n_more} more problem{'s' if n_more > 1 else ''})"
    return msg


def _canonical(path: str) -> list[str | int]:
    """Split ``objective[0].weight`` / ``objective.0.weight`` / ``env.light`` into parts."""
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


def _parse_value(text: str) -> Any:
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
        out.append((_canonical(key.strip()), _parse_value(value.strip())))
    return out


def _set_path(data: dict, parts: list[str | int], value: Any, label: str) -> None:
    node: Any = data
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        where = _loc_path(parts[: i + 1])
        if isinstance(part, int):
            if not isinstance(node, list):
                raise ConfigError(f"{label}: {_loc_path(parts[:i])} is not a list")
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
            raise ConfigError(f"{label}: {_loc_path(parts[:i])} is not a table")
        if last:
            node[part] = value
        else:
            if part not in node:
                node[part] = [] if part == "objective" else {}
            node = node[part]


def _read_toml(path: Path) -> dict:
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


def load_config(
    source: str | Path | Mapping[str, Any] | Config, overrides: Sequence[str] = ()
) -> Config:
    """Read, override, validate and resolve an experiment config.

    ``source`` is a TOML path, a dict of the same shape or a :class:`Config`. ``overrides``
    are ``key.path=value`` strings applied before validation. The model, its preset,
    fixed and evolved parameters, the objectives (built once from their options) and the
    GA operator names are all checked here, so a bad config fails before anything runs.
    Relative file paths in objective tables are looked up next to the config file, then in
    the working directory, and made absolute.

    Raises :class:`growsim.errors.ConfigError` with a one-line message naming the key path.

    Examples
    --------
    >>> cfg = load_config({"model": {"kind": "honda", "evolve": {"f": True}},
    ...                    "objective": [{"kind": "light"}]}, overrides=["ga.population=8"])
    >>> cfg.ga.population, cfg.ga.generations
    (8, 20)
    """
    if isinstance(source, Config):
        data = source.to_dict()
        label = "config"
    elif isinstance(source, Mapping):
        import copy

        data = copy.deepcopy(dict(source))
        label = "config"
    else:
        path = Path(source)
        data = _read_toml(path)
        label = str(path)
    for parts, value in parse_overrides(overrides):
        _set_path(data, parts, value, "--set " + _loc_path(parts))
    bases = [Path.cwd()]
    if not isinstance(source, (Mapping, Config)):
        bases.insert(0, Path(source).resolve().parent)
    _absolute_paths(data, bases)
    try:
        cfg = Config.model_validate(data)
    except ValidationError as exc:
        raise ConfigError(_validation_message(exc)) from None
    except (TypeError, ValueError) as exc:  # pragma: no cover - pydantic wraps these
        raise ConfigError(f"{label}: {exc}") from None
    _check_semantics(cfg)
    return _resolved(cfg)


# --------------------------------------------------------------------------------------
# semantic checks: model, parameters, objectives, operators
# --------------------------------------------------------------------------------------


def _model_module(cfg: Config):
    from growsim.models import get_model

    try:
        return get_model(cfg.model.kind)
    except UserInputError as exc:
        raise ConfigError(f"model.kind: {exc}") from None


def _param_spec(module, user_params: Mapping[str, float]):
    spec_fn = getattr(module, "param_spec", None)
    if spec_fn is not None:
        try:
            return tuple(spec_fn(dict(user_params)))
        except UserInputError as exc:
            raise ConfigError(f"model.params: {exc}") from None
    return tuple(module.PARAMS)


def _user_params(cfg: Config, module) -> dict[str, float]:
    presets = getattr(module, "PRESETS", {}) or {}
    base: dict[str, float] = {}
    if cfg.model.preset is not None:
        if cfg.model.preset not in presets:
            raise ConfigError(
                f"model.preset: unknown preset {cfg.model.preset!r} of model "
                f"{cfg.model.kind!r}; available: {', '.join(sorted(presets)) or '(none)'}"
            )
        base.update(presets[cfg.model.preset])
    base.update(cfg.model.params)
    return base


@dataclasses.dataclass(frozen=True)
class _Plan:
    """What the runner needs, derived from a checked config."""

    names: tuple[str, ...]  # every model parameter, in spec order
    fixed: dict[str, float]  # values of the parameters that are not evolved
    evolved: tuple  # Params (ranges possibly narrowed) the GA evolves, in spec order
    int_names: frozenset[str]


def _plan(cfg: Config) -> _Plan:
    from growsim.models.base import resolve_params

    module = _model_module(cfg)
    user = _user_params(cfg, module)
    spec = _param_spec(module, user)
    by_name = {p.name: p for p in spec}
    unknown = sorted(set(cfg.model.evolve) - set(by_name))
    if unknown:
        raise ConfigError(
            f"model.evolve.{unknown[0]}: unknown parameter of model {cfg.model.kind!r}; "
            f"allowed: {', '.join(by_name)}"
        )
    if not cfg.model.evolve:
        raise ConfigError(
            "model.evolve: nothing to evolve; name at least one parameter "
            f"(allowed: {', '.join(by_name)})"
        )
    unknown = [k for k in user if k not in by_name]
    if unknown:
        raise ConfigError(
            f"model.params.{unknown[0]}: unknown parameter of model {cfg.model.kind!r}; "
            f"allowed: {', '.join(by_name)}"
        )
    try:
        resolved = resolve_params(spec, user, where="model.params.")
    except UserInputError as exc:
        raise ConfigError(str(exc)) from None
    evolved = []
    for p in spec:
        rng = cfg.model.evolve.get(p.name)
        if rng is None:
            continue
        if isinstance(rng, list):
            lo, hi = rng
            if lo < p.low or hi > p.high:
                raise ConfigError(
                    f"model.evolve.{p.name}: [{lo:g}, {hi:g}] is outside the model's range "
                    f"[{p.low:g}, {p.high:g}]"
                )
            if p.kind == "int" and math.floor(hi) < math.ceil(lo):
                raise ConfigError(f"model.evolve.{p.name}: no integer in [{lo:g}, {hi:g}]")
            p = dataclasses.replace(p, low=float(lo), high=float(hi))
        evolved.append(p)
    fixed = {k: v for k, v in resolved.items() if k not in cfg.model.evolve}
    return _Plan(
        names=tuple(p.name for p in spec),
        fixed=fixed,
        evolved=tuple(evolved),
        int_names=frozenset(p.name for p in spec if p.kind == "int"),
    )


def _build_objective(cfg: Config, i: int):
    from growsim.objectives import get_objective

    oc = cfg.objective[i]
    where = f"objective[{i}]"
    try:
        cls = get_objective(oc.kind)
    except UserInputError as exc:
        raise ConfigError(f"{where}.kind: {exc}") from None
    opts = oc.options()
    try:
        obj = cls(**opts)
    except GrowsimError as exc:
        raise ConfigError(f"{where}: {exc}") from None
    except TypeError as exc:
        bad = re.search(r"unexpected keyword argument '([^']+)'", str(exc))
        if bad:
            import inspect

            accepted = [n for n in inspect.signature(cls).parameters if n not in ("self", "kwargs")]
            raise ConfigError(
                f"{where}.{bad.group(1)}: unknown option of objective {oc.kind!r}; "
                f"allowed: kind, weight, {', '.join(accepted)}"
            ) from None
        raise ConfigError(f"{where}: {exc}") from None
    except (ValueError, KeyError, OSError) as exc:
        raise ConfigError(f"{where}: {exc}") from None
    hook = getattr(obj, "with_environment", None)
    if hook is not None:
        obj = hook(cfg.environment)
    return obj


def _check_semantics(cfg: Config) -> None:
    _plan(cfg)
    for i in range(len(cfg.objective)):
        _build_objective(cfg, i)
    # Build the GA once with a stand-in fitness: the GA checks operator names, their
    # options and the generation model itself, so a typo fails before anything is written.
    from growsim.ga import PolishOptions

    try:
        _build_ga(cfg, _no_fitness, _plan(cfg))
        if cfg.ga.polish is not None:
            PolishOptions.from_dict(dict(cfg.ga.polish))
    except GrowsimError as exc:
        raise ConfigError(f"ga.{exc}") from None
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"ga: {exc}") from None


def _no_fitness(x):  # pragma: no cover - never called: only lets the GA be built
    raise AssertionError("not a real fitness")


def _resolved(cfg: Config) -> Config:
    """The config with the model's parameters and ranges written out in full.

    ``model.params`` holds every fixed parameter (preset and defaults filled) and
    ``model.evolve`` every evolved range, so ``config.toml`` of a run does not depend on a
    later change of a preset or a default.
    """
    plan = _plan(cfg)
    data = cfg.to_dict()
    data["model"]["params"] = {
        k: (int(v) if k in plan.int_names else float(v)) for k, v in plan.fixed.items()
    }
    data["model"]["evolve"] = {p.name: [float(p.low), float(p.high)] for p in plan.evolved}
    # int params are written as TOML ints; strict float fields accept ints.
    return Config.model_validate(data)


# --------------------------------------------------------------------------------------
# the fitness: model + objectives, picklable
# --------------------------------------------------------------------------------------


class Fitness:
    """The fitness of an experiment: develop each individual, score it, weight and sum.

    A module-level class holding only picklable pieces (model *name*, fixed values,
    objective instances, environment), so process pools and Dask workers can run it.
    ``__call__`` takes the GA's ``(n, k)`` matrix of evolved parameters (columns in
    ``evolved`` order) and returns ``(n,)`` float64 fitness values to maximise:
    ``sum_i weight_i * sign_i * score_i`` with ``sign_i = -1`` for objectives that
    minimise. An objective with ``batch(model, params, names, seeds)`` scores the whole
    ``(n, p)`` matrix of every model parameter at once when it returns an array.

    Examples
    --------
    >>> f = build_fitness(load_config("experiments/quickstart.toml"))
    >>> f.evolved
    ('f', 'theta0', 'theta_max', 'thq', 'b0', 'b_max')
    >>> f(np.array([[0.8, 80.0, 5.0, 0.2, 8.0, 4.0]])).shape
    (1,)
    """

    def __init__(
        self,
        model: str,
        names: Sequence[str],
        fixed: Mapping[str, float],
        evolved: Sequence[str],
        objectives: Sequence[Any],
        weights: Sequence[float],
        env: Any = None,
        noise: str = "fixed",
        seed: int = 0,
        int_names: Sequence[str] = (),
    ):
        self.model = model
        self.names = tuple(names)
        self.fixed = dict(fixed)
        self.evolved = tuple(evolved)
        self.objectives = list(objectives)
        self.weights = np.asarray(weights, dtype=np.float64)
        self.signs = np.array([1.0 if getattr(o, "maximize", True) else -1.0 for o in objectives])
        self.env = env
        self.noise = noise
        self.seed = int(seed)
        self.int_names = frozenset(int_names)
        col = {n: i for i, n in enumerate(self.names)}
        self._evolved_cols = np.array([col[n] for n in self.evolved], dtype=np.int64)
        self._base = np.array([self.fixed.get(n, np.nan) for n in self.names], dtype=np.float64)

    def full_params(self, x: np.ndarray) -> np.ndarray:
        """``(n, k)`` evolved values -> ``(n, p)`` values of every model parameter."""
        x = np.atleast_2d(np.asarray(x, dtype=np.float64))
        full = np.repeat(self._base[None, :], len(x), axis=0)
        full[:, self._evolved_cols] = x
        if self.int_names:
            for j, n in enumerate(self.names):
                if n in self.int_names:
                    full[:, j] = np.round(full[:, j])
        return full

    def param_dict(self, row: np.ndarray) -> dict[str, float]:
        """One row of :meth:`full_params` as the ``{name: value}`` dict a model develops."""
        return {n: float(v) for n, v in zip(self.names, row)}

    def model_seeds(self, full: np.ndarray, seeds: np.ndarray | None) -> np.ndarray:
        """``(n,)`` uint64 seeds the model develops each individual with."""
        n = len(full)
        if self.noise == "per-evaluation" and seeds is not None:
            # the GA's seeds use all 64 bits; models take seeds as int parameters, often
            # up to 2**31 - 1 (Honda's ``seed``): keep the top 31 bits
            return np.asarray(seeds, dtype=np.uint64) >> np.uint64(33)
        if "seed" in self.names:
            return full[:, self.names.index("seed")].astype(np.uint64)
        return np.full(n, self.seed, dtype=np.uint64)

    def develop(self, row: np.ndarray, seed: int):
        """Grow the plant of one full parameter row."""
        from growsim.models import get_model

        return get_model(self.model).develop(self.param_dict(row), seed=int(seed), env=self.env)

    def __call__(self, x: np.ndarray, seeds: np.ndarray | None = None) -> np.ndarray:
        full = self.full_params(x)
        n = len(full)
        mseeds = self.model_seeds(full, seeds)
        total = np.zeros(n, dtype=np.float64)
        pending = []
        for obj, w, s in zip(self.objectives, self.weights, self.signs):
            batch = getattr(obj, "batch", None)
            vals = None
            if batch is not None:
                from growsim.models import get_model

                vals = batch(get_model(self.model), full, self.names, mseeds)
            if vals is None:
                pending.append((obj, w * s))
            else:
                total += w * s * np.asarray(vals, dtype=np.float64).reshape(n)
        if pending:
            for i in range(n):
                plant = self.develop(full[i], mseeds[i])
                for obj, ws in pending:
                    total[i] += ws * float(obj(plant))
        return total


def build_fitness(cfg: Config) -> Fitness:
    """The picklable :class:`Fitness` of a checked config.

    Examples
    --------
    >>> f = build_fitness(load_config("experiments/quickstart.toml"))
    >>> f.model
    'honda'
    """
    plan = _plan(cfg)
    objectives = [_build_objective(cfg, i) for i in range(len(cfg.objective))]
    return Fitness(
        model=cfg.model.kind,
        names=plan.names,
        fixed=plan.fixed,
        evolved=[p.name for p in plan.evolved],
        objectives=objectives,
        weights=[o.weight for o in cfg.objective],
        env=cfg.environment,
        noise=cfg.model.noise,
        seed=cfg.experiment.seed,
        int_names=plan.int_names,
    )


# --------------------------------------------------------------------------------------
# run
# --------------------------------------------------------------------------------------


@dataclasses.dataclass
class RunResult:
    """What :func:`run` returns.

    ``history``: DataFrame, one row per generation (and island): generation, evaluations,
    best, mean, std, worst, best_so_far, diversity, seconds; ``best_params``: every model
    parameter of the best individual; ``best_fitness``; ``best_plant``: its
    :class:`growsim.plant.Plant`; ``out``: the results directory; ``summary``: the dict
    of summary.json.

    Examples
    --------
    >>> r = run("experiments/quickstart.toml", out="runs/doc")  # doctest: +SKIP
    >>> r.best_fitness > 0  # doctest: +SKIP
    True
    """

    history: Any
    best_params: dict[str, float]
    best_fitness: float
    best_plant: Any
    out: Path
    summary: dict[str, Any]
    stop_reason: str = ""


def default_out(cfg: Config, root: str | Path = "runs", kind: str = "") -> Path:
    """``runs/<name>[-<kind>]-<YYYYmmdd-HHMMSS>`` (with ``-2``, ``-3``... if it exists).

    Examples
    --------
    >>> cfg = load_config({"model": {"kind": "honda", "evolve": {"f": True}},
    ...                    "objective": [{"kind": "light"}]})
    >>> default_out(cfg).name.startswith("experiment-")
    True
    """
    stamp = time.strftime("%Y%m%d-%H%M%S")
    base = Path(root) / "-".join(x for x in (cfg.experiment.name, kind, stamp) if x)
    out, k = base, 2
    while out.exists():
        out = base.with_name(f"{base.name}-{k}")
        k += 1
    return out


class _Progress:
    """Per-generation callback: tqdm bar on stderr, a live history.parquet (at most every
    ``every`` seconds, so a long run can be watched; the checkpoint is what resumes), and
    the user's callback."""

    def __init__(
        self, total: int | None, enabled: bool, user_callback=None, rd=None, every: float = 5.0
    ):
        self.user_callback = user_callback
        self.rd = rd
        self.every = every
        self.last_write = time.perf_counter()
        self.bar = None
        self.t0 = time.perf_counter()
        self.evals0: int | None = None
        if enabled:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=total, unit="gen", file=sys.stderr, dynamic_ncols=True)

    def __call__(self, ga, row: Mapping[str, Any]):
        if self.bar is not None:
            evals = int(row.get("evaluations", 0))
            if self.evals0 is None:
                self.evals0 = evals
                self.t0 = time.perf_counter()
            dt = max(time.perf_counter() - self.t0, 1e-9)
            rate = (evals - self.evals0) / dt
            gen = int(row.get("generation", self.bar.n))
            self.bar.update(max(gen + 1 - self.bar.n, 0))
            self.bar.set_postfix(
                best=f"{row.get('best_so_far', row.get('best', float('nan'))):.4g}",
                mean=f"{row.get('mean', float('nan')):.4g}",
                evals_s=f"{rate:.0f}",
                refresh=False,
            )
        if self.rd is not None and time.perf_counter() - self.last_write > self.every:
            try:
                self.rd.write_parquet("history.parquet", ga.history)
            except Exception as exc:  # only a live view: never stop a run for it
                log.warning("live history.parquet not written: %s", exc)
            self.last_write = time.perf_counter()
        if self.user_callback is not None:
            return self.user_callback(ga, row)
        return None

    def close(self):
        if self.bar is not None:
            self.bar.close()


def _check_executor_args(workers, scheduler) -> None:
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1
    ):
        raise UserInputError(f"--workers: expected an integer >= 1, got {workers!r}")
    if scheduler is not None and not (
        scheduler == "local" or re.match(r"^(tcp|tls|ws|wss|inproc)://\S+$", str(scheduler))
    ):
        raise UserInputError(
            f"--scheduler: {scheduler!r} is not 'local' or an address like tcp://host:8786"
        )


def _executor(workers: int | None, scheduler: str | None):
    """(executor for GA.run, cleanup callable)."""
    if scheduler is None:
        if workers is None or workers <= 1:
            return None, lambda: None
        return int(workers), lambda: None
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise UserInputError(
            "--scheduler needs dask.distributed: pip install 'growsim[dask]'"
        ) from None
    if scheduler == "local":
        cluster = LocalCluster(
            n_workers=workers or 2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
        )
        client = Client(cluster)

        def close():
            client.close()
            cluster.close()

    else:
        if not re.match(r"^(tcp|tls|ws|wss|inproc)://", scheduler):
            raise UserInputError(
                f"--scheduler: {scheduler!r} is not 'local' or an address like tcp://host:8786"
            )
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise UserInputError(f"--scheduler: cannot reach {scheduler}: {exc}") from None
        close = client.close
    return client.get_executor(pure=False), close


def _executor_workers(executor) -> int | None:
    """How many evaluations an executor runs at once (Dask: the cluster's threads)."""
    client = getattr(executor, "_client", None)
    if client is not None:
        try:
            workers = client.scheduler_info()["workers"].values()
            return max(1, sum(int(w.get("nthreads", 1)) for w in workers))
        except Exception:  # an unreachable or odd scheduler: fall back to the GA's default
            return None
    n = getattr(executor, "_max_workers", None)
    return int(n) if n else None


def _build_ga(cfg: Config, fitness: Fitness, plan: _Plan, batch_size: int | None = None):
    from growsim.ga import GA, genome_from_params

    g = cfg.ga
    genome = genome_from_params(plan.evolved, coding=g.coding, bits=g.bits, bit_coding=g.bit_coding)
    return GA(
        genome,
        fitness,
        population=g.population,
        maximize=True,
        seed=cfg.experiment.seed,
        selection=g.selection,
        crossover=g.crossover,
        mutation=g.mutation,
        selection_options=dict(g.selection_options) or None,
        crossover_options=dict(g.crossover_options) or None,
        mutation_options=dict(g.mutation_options) or None,
        model=g.model,
        elite=g.elite,
        elite_rate=g.elite_rate,
        islands=g.islands,
        migration_rate=g.migration_rate,
        migration_interval=g.migration_interval,
        extinction=g.extinction,
        batch_size=g.batch_size if batch_size is None else batch_size,
    )


def _jsonable(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    return x


def run(
    config: str | Path | Mapping[str, Any] | Config | None = None,
    out: str | Path | None = None,
    *,
    seed: int | None = None,
    overrides: Sequence[str] = (),
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    progress: bool = True,
    callback=None,
    executor=None,
) -> RunResult:
    """Run one experiment into a results directory; return its :class:`RunResult`.

    ``config``: a TOML path, dict or :class:`Config` (``None`` with ``resume=True``: the
    ``config.toml`` saved in ``out``). ``out``: the results directory (default
    ``runs/<name>-<timestamp>``); a fresh run refuses a directory that already holds a
    run, and a second run on a directory in use refuses at once. ``seed`` overrides
    ``experiment.seed``. ``workers``: local process pool size; ``scheduler``: ``"local"``
    (a Dask LocalCluster of ``workers`` processes) or a Dask scheduler address.
    ``resume=True`` continues from ``out/checkpoint.npz`` to the same history and best as
    an uninterrupted run. ``progress``: a tqdm bar on stderr (only when stderr is a TTY).
    ``callback(ga, row)`` is called after every generation (return True to stop).
    ``executor``: any ``concurrent.futures.Executor`` to evaluate on (instead of
    ``workers``/``scheduler``; not shut down here), e.g. ``Client.get_executor(pure=False)``.

    Examples
    --------
    >>> r = run("experiments/quickstart.toml", out="runs/doc", progress=False)  # doctest: +SKIP
    >>> sorted(p.name for p in r.out.iterdir())[:3]  # doctest: +SKIP
    ['best.json', 'best.vtp', 'best_front.png']
    """
    from growsim.results import RunDir

    _check_executor_args(workers, scheduler)
    if resume:
        if out is None:
            raise UserInputError("resume: give the results directory to resume (--resume DIR)")
        rd = RunDir(out)
        if not rd.config_path.is_file():
            raise UserInputError(f"{rd.path}: no config.toml here; nothing to resume")
        saved = load_config(rd.config_path)
        if config is not None:
            given = load_config(config, overrides)
            if seed is not None:
                given = load_config(given, [f"experiment.seed={int(seed)}"])
            if given.to_dict() != saved.to_dict():
                raise ConfigError(
                    f"{rd.path}: the config given differs from the run's config.toml; "
                    "resume with the directory alone (growsim run --resume DIR)"
                )
        elif seed is not None and seed != saved.experiment.seed:
            raise ConfigError(
                f"--seed {seed}: the run in {rd.path} has seed {saved.experiment.seed}"
            )
        cfg = saved
    else:
        if config is None:
            raise UserInputError("no config given")
        cfg = load_config(config, overrides)
        if seed is not None:
            if not isinstance(seed, (int, np.integer)) or isinstance(seed, bool) or seed < 0:
                raise UserInputError(f"--seed: expected an integer >= 0, got {seed!r}")
            cfg = load_config(cfg, [f"experiment.seed={int(seed)}"])
        rd = RunDir(out if out is not None else default_out(cfg))

    # connect to the evaluators first: an unreachable scheduler writes nothing
    ext, close = (executor, lambda: None) if executor is not None else _executor(workers, scheduler)
    try:
        with rd.lock():
            if not resume:
                rd.create_fresh()
                rd.write_text("config.toml", cfg.to_toml())
            try:
                return _run_locked(cfg, rd, workers, scheduler, resume, progress, callback, ext)
            except KeyboardInterrupt:
                print(f"growsim: to continue: growsim run --resume {rd.path}", file=sys.stderr)
                raise
    finally:
        close()


def _run_locked(cfg, rd, workers, scheduler, resume, progress, callback, ext) -> RunResult:
    from growsim import __version__

    plan = _plan(cfg)
    fitness = build_fitness(cfg)
    g = cfg.ga
    executor = ext
    # Tasks per generation: the GA splits a population into 4 tasks per worker, counting
    # local CPUs when it cannot see the executor's size; give it the Dask cluster's size.
    # (Batching never changes results: seeds follow the evaluation index.)
    batch = None
    n_exec = _executor_workers(executor) if executor is not None else None
    if g.batch_size is None and n_exec is not None:
        batch = max(1, math.ceil(g.population / (4 * n_exec)))
    ga = _build_ga(cfg, fitness, plan, batch_size=batch)
    show_bar = bool(progress) and sys.stderr.isatty()
    bar = _Progress(g.generations, show_bar, callback, rd=rd)
    t0 = time.perf_counter()
    started = time.strftime("%Y-%m-%dT%H:%M:%S%z")
    try:
        result = ga.run(
            generations=g.generations,
            evaluations=g.evaluations,
            target=g.target,
            stagnation=g.stagnation,
            wall_time=g.wall_time,
            executor=executor,
            callback=bar,
            checkpoint=rd.checkpoint_path,
            resume=resume,
            polish=dict(g.polish) if g.polish else None,
        )
    finally:
        bar.close()
    t_ga = time.perf_counter()
    # the GA's own clock covers every session of a resumed run
    ga_seconds = float(getattr(result, "seconds", t_ga - t0))

    best_row = fitness.full_params(np.asarray(result.best.params, dtype=np.float64)[None, :])[0]
    best_params = fitness.param_dict(best_row)
    for n in plan.int_names:
        best_params[n] = round(best_params[n])
    plant_seed = int(fitness.model_seeds(best_row[None, :], None)[0])
    history = result.history
    rd.write_parquet("history.parquet", history)
    best = {
        "fitness": float(result.best.fitness),
        "generation": int(result.best.generation),
        "evolved": {n: best_params[n] for n in fitness.evolved},
        "params": best_params,
        "model": cfg.model.kind,
        "plant_seed": plant_seed,
    }
    raw = getattr(result.best, "raw", None)
    if raw is not None:
        best["genome"] = np.asarray(raw).tolist()
    rd.write_json("best.json", _jsonable(best))

    warnings: list[str] = []
    plant = None
    try:
        plant = fitness.develop(best_row, plant_seed)
    except Exception as exc:  # the best genome scored, so this is a model bug: report it
        warnings.append(f"developing the best plant failed: {exc}")
        log.warning("developing the best plant failed: %s", exc)
    if plant is not None:
        warnings += _artefacts(cfg, rd, plant, history)
    elif cfg.output.plot:
        warnings += _artefacts(cfg, rd, None, history)

    summary = {
        "experiment": cfg.experiment.name,
        "description": cfg.experiment.description,
        "model": cfg.model.kind,
        "objectives": [o.kind for o in cfg.objective],
        "seed": cfg.experiment.seed,
        "best_fitness": float(result.best.fitness),
        "best_generation": int(result.best.generation),
        "generations": int(history["generation"].max()) + 1 if len(history) else 0,
        "evaluations": int(result.evaluations),
        "wall_seconds": round(ga_seconds + time.perf_counter() - t_ga, 3),
        "ga_seconds": round(ga_seconds, 3),
        "history_seconds": float(history["seconds"].max()) if "seconds" in history else None,
        "stop_reason": str(result.stop_reason),
        "resumed": bool(resume),
        "started": started,
        "finished": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "growsim_version": __version__,
        "workers": workers,
        "scheduler": scheduler,
        "measures": _measures(plant, cfg) if plant is not None else {},
        "warnings": warnings,
    }
    summary = _jsonable(summary)
    rd.write_json("summary.json", summary)  # last: its presence marks a complete run
    return RunResult(
        history=history,
        best_params=best_params,
        best_fitness=float(result.best.fitness),
        best_plant=plant,
        out=rd.path,
        summary=summary,
        stop_reason=str(result.stop_reason),
    )


def _measures(plant, cfg: Config) -> dict[str, float]:
    """Shape measures of the best plant for summaries and comparisons."""
    out: dict[str, float] = {}
    try:
        out.update({k: float(v) for k, v in plant.measures().items() if np.isscalar(v)})
    except Exception as exc:  # measures are informative; never lose a run for them
        log.warning("plant.measures() failed: %s", exc)
    try:
        from growsim.plant import LEAF

        d = np.asarray(cfg.environment.light_direction, dtype=np.float64)
        out["light_captured"] = float(
            cfg.environment.light * plant.projected_area(tuple(d), kinds=(LEAF,))
        )
        out["wood_volume"] = float(plant.wood_volume())
    except Exception as exc:
        log.warning("light measure failed: %s", exc)
    out["segments"] = float(plant.n_segments)
    return out


def _artefacts(cfg: Config, rd, plant, history) -> list[str]:
    """Best plant npz, meshes, screenshots, fitness plot. Returns warnings."""
    warnings = []
    o = cfg.output

    def attempt(what, fn):
        try:
            fn()
        except Exception as exc:  # an artefact must not lose the run's results
            warnings.append(f"{what}: {exc}")
            log.warning("writing %s failed: %s", what, exc)

    def mesh_files():
        from growsim import mesh as gmesh

        m = gmesh.plant_mesh(plant)
        for fmt in o.mesh:
            attempt(f"best.{fmt}", lambda fmt=fmt: gmesh.export(m, rd.path / f"best.{fmt}"))

    def screenshot(view):
        from growsim import viz

        rd.write_with(
            f"best_{view}.png",
            lambda tmp: viz.screenshot(plant, tmp, view=view, size=tuple(o.size)),
        )

    def plot():
        from growsim import viz

        rd.write_with("fitness.png", lambda tmp: viz.plot_fitness(history, tmp))

    if plant is not None:
        if o.plant:
            attempt("best_plant.npz", lambda: plant.save(rd.path / "best_plant.npz"))
        if o.mesh:
            attempt("mesh", mesh_files)
        for view in o.screenshots:
            attempt(f"best_{view}.png", lambda view=view: screenshot(view))
    if o.plot and len(history):
        attempt("fitness.png", plot)
    return warnings


def load_run(path: str | Path) -> RunResult:
    """Read a finished results directory back into a :class:`RunResult`.

    Examples
    --------
    >>> r = load_run("runs/quickstart-20261122-101500")  # doctest: +SKIP
    >>> r.best_plant.height()  # doctest: +SKIP
    41.2
    """
    import json

    import pandas as pd

    from growsim.results import RunDir

    rd = RunDir(path)
    if not rd.summary_path.is_file():
        raise UserInputError(f"{rd.path}: not a finished growsim run (no summary.json)")
    summary = json.loads(rd.summary_path.read_text())
    best = json.loads(rd.best_path.read_text())
    history = pd.read_parquet(rd.history_path)
    plant = None
    if (rd.path / "best_plant.npz").is_file():
        from growsim.plant import Plant

        plant = Plant.load(rd.path / "best_plant.npz")
    return RunResult(
        history=history,
        best_params=best["params"],
        best_fitness=float(best["fitness"]),
        best_plant=plant,
        out=rd.path,
        summary=summary,
        stop_reason=summary.get("stop_reason", ""),
    )


def best_plant(path: str | Path):
    """The best plant of a results directory: ``best_plant.npz``, or re-grown from
    ``best.json`` and ``config.toml`` when that file was not saved.

    Examples
    --------
    >>> best_plant("runs/quickstart-20261122-101500").n_segments  # doctest: +SKIP
    1023
    """
    import json

    from growsim.results import RunDir

    rd = RunDir(path)
    npz = rd.path / "best_plant.npz"
    if npz.is_file():
        from growsim.plant import Plant

        return Plant.load(npz)
    if not rd.best_path.is_file() or not rd.config_path.is_file():
        raise UserInputError(f"{rd.path}: not a growsim results directory (no best.json)")
    cfg = load_config(rd.config_path)
    best = json.loads(rd.best_path.read_text())
    fitness = build_fitness(cfg)
    row = np.array([float(best["params"][n]) for n in fitness.names])
    return fitness.develop(row, int(best.get("plant_seed", cfg.experiment.seed)))


# --------------------------------------------------------------------------------------
# sweep
# --------------------------------------------------------------------------------------


def parse_vary(items: Sequence[str] | Mapping[str, Sequence[Any]]) -> dict[str, list[Any]]:
    """``["env.light=1.0,0.5", "ga.population=[10, 20]"]`` -> ``{path: [values]}``.

    A value list is comma-separated TOML values, or one TOML array.

    Examples
    --------
    >>> parse_vary(["env.light=1.0,0.5", "model.preset=zelkova,cherry"])
    {'environment.light': [1.0, 0.5], 'model.preset': ['zelkova', 'cherry']}
    """
    if isinstance(items, Mapping):
        out = {}
        for k, v in items.items():
            vals = list(v) if isinstance(v, (list, tuple)) else [v]
            if not vals:
                raise UserInputError(f"--vary {k}: no values")
            out[_loc_path(_canonical(k))] = vals
        return out
    out = {}
    for item in items:
        if "=" not in item:
            raise UserInputError(f"--vary {item!r}: expected key.path=v1,v2,...")
        key, text = item.split("=", 1)
        key = _loc_path(_canonical(key.strip()))
        text = text.strip()
        parsed = _parse_value(text) if text.startswith("[") else None
        if isinstance(parsed, list):
            vals = parsed
        else:
            vals = [_parse_value(t.strip()) for t in text.split(",") if t.strip()]
        if not vals:
            raise UserInputError(f"--vary {key}: no values")
        if key in out:
            raise UserInputError(f"--vary {key}: given twice")
        out[key] = vals
    return out


def _label(assign: Mapping[str, Any]) -> str:
    """A directory-safe name of one variant: ``light=0.5_light_direction=0,-1,0``."""
    if not assign:
        return "base"

    def text(v):
        if isinstance(v, (list, tuple)):
            return ",".join(text(x) for x in v)
        if isinstance(v, bool):
            return str(v).lower()
        return str(v)

    parts = [f"{k.split('.')[-1]}={text(v)}" for k, v in assign.items()]
    return re.sub(r"[^A-Za-z0-9_.=,+-]", "-", "_".join(parts))[:120]


def sweep(
    config: str | Path | Mapping[str, Any] | Config,
    vary: Sequence[str] | Mapping[str, Sequence[Any]] = (),
    *,
    repeats: int | None = None,
    out: str | Path | None = None,
    overrides: Sequence[str] = (),
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
):
    """Run the grid of variants x repeats; return one row per run as a DataFrame.

    ``vary`` maps key paths to value lists (or ``"path=v1,v2"`` strings). Every variant
    runs ``repeats`` seeds (``experiment.seed + r``, the same seeds for every variant, so
    variants are compared on common random numbers) into
    ``out/<variant label>/seed-<seed>/``. A finished run found there is reused and a
    killed one resumed, so re-running a sweep completes it. The table (also written to
    ``out/sweep.csv`` and ``out/sweep.parquet``) has one column per varied key, then
    ``repeat``, ``seed``, ``best_fitness``, ``generations``, ``evaluations``,
    ``wall_seconds``, the best plant's measures and ``out``.

    Examples
    --------
    >>> df = sweep("experiments/quickstart.toml", ["env.light=1.0,0.5"], repeats=2,
    ...            out="runs/sw", overrides=["ga.generations=2"])  # doctest: +SKIP
    >>> len(df)  # doctest: +SKIP
    4
    """

    import pandas as pd

    from growsim.files import atomic_write

    _check_executor_args(workers, scheduler)
    base = load_config(config, overrides)
    grid = parse_vary(vary)
    n_rep = base.experiment.repeats if repeats is None else repeats
    if not isinstance(n_rep, int) or n_rep < 1:
        raise UserInputError(f"--repeats: expected an integer >= 1, got {n_rep!r}")
    # validate every variant before running any, so a typo fails at once
    variants = []
    keys = list(grid)
    for combo in itertools.product(*(grid[k] for k in keys)):
        assign = dict(zip(keys, combo))
        data = base.to_dict()
        for k, v in assign.items():
            _set_path(data, _canonical(k), v, f"--vary {k}")
        variants.append((assign, load_config(data)))
    labels = [_label(a) for a, _ in variants]
    if len(set(labels)) != len(labels):
        labels = [f"v{i}-{lab}" for i, lab in enumerate(labels)]
    root = Path(out) if out is not None else default_out(base, kind="sweep")
    root.mkdir(parents=True, exist_ok=True)
    executor, close = _executor(workers, scheduler)  # one pool/cluster for every run
    try:
        rows = _sweep_runs(variants, labels, n_rep, root, executor, workers, scheduler, progress)
    finally:
        close()
    df = pd.DataFrame(rows)
    atomic_write(root / "sweep.csv", df.to_csv(index=False))
    from growsim.results import write_parquet

    write_parquet(root / "sweep.parquet", df)
    return df


def _sweep_runs(variants, labels, n_rep, root, executor, workers, scheduler, progress):
    import json

    from growsim.results import RunDir

    rows = []
    if isinstance(executor, int):  # a process-pool size: let each run make its pool
        executor = None
    total, k = len(variants) * n_rep, 0
    for (assign, cfg), label in zip(variants, labels):
        for r in range(n_rep):
            seed = cfg.experiment.seed + r
            run_dir = root / label / f"seed-{seed}"
            rd = RunDir(run_dir)
            k += 1
            if progress and sys.stderr.isatty():
                print(f"sweep: run {k}/{total}: {label}/seed-{seed}", file=sys.stderr)
            if rd.summary_path.is_file():
                summary = json.loads(rd.summary_path.read_text())
            elif rd.config_path.is_file():
                summary = run(
                    None,
                    run_dir,
                    resume=True,
                    workers=workers,
                    scheduler=scheduler,
                    progress=progress,
                    executor=executor,
                ).summary
            else:
                summary = run(
                    cfg,
                    run_dir,
                    seed=seed,
                    workers=workers,
                    scheduler=scheduler,
                    progress=progress,
                    executor=executor,
                ).summary
            row = {k: v for k, v in assign.items()}
            row.update(
                variant=label,
                repeat=r,
                seed=seed,
                best_fitness=summary["best_fitness"],
                generations=summary["generations"],
                evaluations=summary["evaluations"],
                wall_seconds=summary["wall_seconds"],
            )
            row.update({f"best_{k}": v for k, v in summary.get("measures", {}).items()})
            row["out"] = str(run_dir)
            rows.append(row)
    return rows


# --------------------------------------------------------------------------------------
# docs
# --------------------------------------------------------------------------------------


def _type_name(ann: Any) -> str:
    text = repr(ann) if not isinstance(ann, type) else ann.__name__
    text = text.replace("typing.", "").replace("NoneType", "None")
    return text.replace("Literal", "one of ")


def _range_text(field) -> str:
    parts = []
    for m in field.metadata:
        for attr, sym in (("ge", ">="), ("gt", ">"), ("le", "<="), ("lt", "<")):
            v = getattr(m, attr, None)
            if v is not None:
                parts.append(f"{sym} {v}")
        for attr, sym in (("min_length", "length >="), ("max_length", "length <=")):
            v = getattr(m, attr, None)
            if v is not None:
                parts.append(f"{sym} {v}")
        pat = getattr(m, "pattern", None)
        if pat:
            parts.append(f"matches `{pat}`")
    return ", ".join(parts)


def _default_text(field) -> str:
    if field.is_required():
        return "**required**"
    if field.default_factory is not None:
        v = field.default_factory()
    else:
        v = field.default
    if v is None:
        return "unset"
    if isinstance(v, str):
        return f'`"{v}"`'
    if isinstance(v, bool):
        return f"`{str(v).lower()}`"
    return f"`{v}`"


def config_docs() -> str:
    """Markdown reference of every config key: type, default, range (docs/configs.md).

    Examples
    --------
    >>> "ga.population" in config_docs()
    True
    """
    lines = [
        "# Experiment configs: every key",
        "",
        "<!-- generated by `python -m growsim.experiment --docs > docs/configs.md`;",
        "     tests/test_config.py fails when it is out of date -->",
        "",
        "An experiment is a TOML file with the sections below. Unknown keys, wrong types and",
        "values out of range are rejected with a message naming the key path (exit code 2);",
        "defaults are filled in and the resolved config is saved as `config.toml` in the",
        "results directory. Override any key on the command line with",
        "`--set key.path=value` (values are TOML: `--set ga.population=50`,",
        "`--set model.preset=zelkova`, `--set 'objective[0].weight=2'`; `env.` is short",
        "for `environment.`).",
        "",
        "Model parameters: `model.params` and `model.evolve` take the parameter names of the",
        "chosen model (see `docs/models/<model>.md`, or `growsim grow MODEL --help`);",
        "their ranges come from the model's parameter spec. Objective tables take the",
        "options of the objective class (`kind` and `weight` are common to all; see the",
        "objective's docstring, e.g. `growsim.objectives.light.LightObjective`). A relative",
        "file path in an objective table (a target image) is looked up next to the config",
        "file first, then in the working directory, and saved as an absolute path.",
        "",
        "Randomness: `experiment.seed` seeds the run; the GA derives one seed per evaluation",
        "from it by the evaluation's index, so results do not depend on `--workers` or",
        '`--scheduler`. With `model.noise = "fixed"` a genome always grows the same plant',
        "(the model's own `seed` parameter, fixed or evolved, else the run seed); with",
        '`"per-evaluation"` each evaluation grows with its own seed.',
        "",
    ]
    for section, cls in SECTIONS.items():
        header = f"[[{section}]]" if section == "objective" else f"[{section}]"
        first = (cls.__doc__ or "").strip().split("\n")[0]
        first = re.sub(r"^``\[+\w+\]+``: ", "", first)
        lines += [f"## `{header}`", "", first[:1].upper() + first[1:], ""]
        lines += ["| key | type | default | range | meaning |", "|---|---|---|---|---|"]
        for name, field in cls.model_fields.items():
            typ = _type_name(field.annotation).replace("|", "or")
            lines.append(
                f"| `{section}.{name}` | {typ} | {_default_text(field)} | "
                f"{_range_text(field) or '-'} | {(field.description or '').replace('|', '/')} |"
            )
        if section == "objective":
            lines.append(
                "| `objective.<option>` | any | - | - | every other key is a keyword option "
                "of the objective class, which validates it |"
            )
        lines.append("")
    lines += [
        "## Cross-key rules",
        "",
        "- `ga`: at least one of `generations`, `evaluations`, `wall_time` is set;",
        "  `elite` < `population`; operator names must be registered in `growsim.ga`.",
        "- `model.evolve`: at least one parameter; a `[low, high]` range must lie inside",
        "  the model's own range; evolved parameters override `model.params`.",
        "- `model.preset` must be one of the model's `PRESETS`.",
        "",
    ]
    return "\n".join(lines)


def _main(argv: Sequence[str] | None = None) -> int:
    import argparse

    p = argparse.ArgumentParser(prog="python -m growsim.experiment")
    p.add_argument("--docs", action="store_true", help="print docs/configs.md (Markdown)")
    args = p.parse_args(argv)
    if args.docs:
        sys.stdout.write(config_docs())
        return 0
    p.print_help()
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(_main())
