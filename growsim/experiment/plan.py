"""The :class:`ExperimentPlan`: a validated config compiled once into what a run needs.

Compiling resolves the model and its parameters (preset, fixed values, evolved ranges),
builds the genome, builds every objective once (with the run's environment) and checks
that each accepts the model's phenotype, and checks the GA set-up. ``run``, ``sweep``,
``fit-image``, ``show`` and the report take the plan; a seed override is a copy of it.
Plans are made by :func:`growsim.experiment.load.load_plan` (from a path, dict, Config or
plan); :func:`compile_plan` is its last step.
"""

from __future__ import annotations

import dataclasses
import fnmatch
import math
from typing import Any

import numpy as np

from growsim.env import Environment
from growsim.errors import ConfigError, GrowsimError, UserInputError
from growsim.experiment.fitness import Fitness
from growsim.experiment.schema import Config
from growsim.ga import GA, genome_from_params
from growsim.models import get_model
from growsim.models.base import Model, Param, resolve_params
from growsim.objectives import get_objective

__all__ = ["ExperimentPlan", "ModelPlan", "compile_plan", "plan_model"]


@dataclasses.dataclass(frozen=True)
class ModelPlan:
    """The model part of a plan: enough to grow a phenotype from parameters (``show``
    and the report need no more: no objective, no target picture).

    Attributes
    ----------
    model : the :class:`growsim.models.base.Model`
    spec : every parameter (:class:`Param`), in spec order
    fixed : values of the parameters that are not evolved
    evolved : the evolved parameters (ranges narrowed by ``model.evolve``), in spec order
    environment : the :class:`growsim.env.Environment`
    noise : ``"fixed"`` or ``"per-evaluation"``
    seed : the run seed
    """

    model: Model
    spec: tuple[Param, ...]
    fixed: dict[str, float]
    evolved: tuple[Param, ...]
    environment: Environment
    noise: str
    seed: int

    @property
    def names(self) -> tuple[str, ...]:
        """Every model parameter's name, in spec order."""
        return tuple(p.name for p in self.spec)

    @property
    def int_names(self) -> frozenset[str]:
        """Names of the integer parameters."""
        return frozenset(p.name for p in self.spec if p.kind == "int")

    def fitness(self) -> Fitness:
        """The :class:`~growsim.experiment.fitness.Fitness` of the model part, without
        objectives: its :meth:`~growsim.experiment.fitness.Fitness.phenotype_of` grows an
        individual as the run did."""
        return Fitness(self, (), ())


@dataclasses.dataclass(frozen=True)
class ExperimentPlan(ModelPlan):
    """A config compiled once: the model plan, the objectives (built), the genome, and
    the resolved config (GA options, outputs).

    Examples
    --------
    >>> from growsim.experiment import load_plan
    >>> plan = load_plan("experiments/quickstart.toml")
    >>> [p.name for p in plan.evolved][:3], plan.genome.n_params
    (['f', 'theta0', 'theta_max'], 6)
    >>> plan.with_seed(5).seed, plan.with_seed(5).objectives is plan.objectives
    (5, True)
    """

    config: Config = None  # type: ignore[assignment]
    objectives: tuple[Any, ...] = ()

    @property
    def weights(self) -> tuple[float, ...]:
        """The objectives' weights."""
        return tuple(o.options.weight for o in self.objectives)

    @property
    def genome(self):
        """The :class:`growsim.ga.Genome` of the evolved parameters (``[ga]`` coding)."""

        g = self.config.ga
        return genome_from_params(
            self.evolved, coding=g.coding, bits=g.bits, bit_coding=g.bit_coding
        )

    def with_seed(self, seed: int) -> ExperimentPlan:
        """The same plan with another run seed (objectives are shared, not rebuilt)."""
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise UserInputError(f"--seed: expected an integer >= 0, got {seed!r}")
        return dataclasses.replace(self, config=self.config.with_seed(int(seed)), seed=int(seed))

    def fitness(self) -> Fitness:
        """The picklable :class:`~growsim.experiment.fitness.Fitness` of the plan."""
        return Fitness(self)

    def build_ga(self, fitness, batch_size: int | None = None):
        """The :class:`growsim.ga.GA` of the plan evolving ``fitness``."""

        overrides = {} if batch_size is None else {"batch_size": batch_size}
        return GA(self.genome, fitness, self.config.ga, maximize=True, seed=self.seed, **overrides)


def _user_params(cfg: Config, model: Model) -> dict[str, float]:
    base: dict[str, float] = {}
    if cfg.model.preset is not None:
        try:
            base.update(model.preset(cfg.model.preset))
        except UserInputError as exc:
            raise ConfigError(f"model.preset: {exc}") from None
    base.update(cfg.model.params)
    return base


def plan_model(cfg: Config) -> ModelPlan:
    """The model part of a config: model, parameter spec, fixed and evolved parameters.

    Examples
    --------
    >>> from growsim.experiment import load_config
    >>> plan_model(load_config("experiments/quickstart.toml")).fixed["generations"]
    10.0
    """

    try:
        model = get_model(cfg.model.kind)
    except UserInputError as exc:
        raise ConfigError(f"model.kind: {exc}") from None
    user = _user_params(cfg, model)
    try:
        spec = model.param_spec(user)
    except UserInputError as exc:
        raise ConfigError(f"model.params: {exc}") from None
    by_name = {p.name: p for p in spec}
    allowed = ", ".join(by_name)
    evolve = _expand_patterns(cfg.model.evolve, by_name, cfg.model.kind)
    unknown = sorted(set(evolve) - set(by_name))
    if unknown:
        raise ConfigError(
            f"model.evolve.{unknown[0]}: unknown parameter of model {cfg.model.kind!r}; "
            f"allowed: {allowed}"
        )
    if not evolve:
        raise ConfigError(
            f"model.evolve: nothing to evolve; name at least one parameter (allowed: {allowed})"
        )
    unknown = [k for k in user if k not in by_name]
    if unknown:
        raise ConfigError(
            f"model.params.{unknown[0]}: unknown parameter of model {cfg.model.kind!r}; "
            f"allowed: {allowed}"
        )
    try:
        resolved = resolve_params(spec, user, where="model.params.")
    except UserInputError as exc:
        raise ConfigError(str(exc)) from None
    evolved = []
    for p in spec:
        rng = evolve.get(p.name)
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
    _check_mixture(cfg, model)
    return ModelPlan(
        model=model,
        spec=tuple(spec),
        fixed={k: v for k, v in resolved.items() if k not in evolve},
        evolved=tuple(evolved),
        environment=cfg.environment,
        noise=cfg.model.noise,
        seed=cfg.experiment.seed,
    )


def _check_mixture(cfg: Config, model) -> None:
    """A mixture (``environment.stand.mode = "mixture"``) needs a model that grows among
    neighbours and a population that holds them: else a :class:`ConfigError` naming the
    key."""
    stand = cfg.environment.stand
    if stand.mode != "mixture":
        return
    if "mixture" not in model.capabilities:
        raise ConfigError(
            f"environment.stand.mode: 'mixture' needs a model that grows among neighbours "
            f"(hormone, honda); model {model.name!r} does not"
        )
    population = cfg.ga.population
    if stand.neighbours > population - 1:
        raise ConfigError(
            f"environment.stand.neighbours: {stand.neighbours} neighbours drawn from a "
            f"population of {population}: at most {population - 1}"
        )


def _expand_patterns(evolve: dict, by_name: dict, kind: str) -> dict:
    """``[model.evolve]`` with its shell-style patterns (``"h*_w?" = true``: names with
    ``*``, ``?`` or ``[...]``) replaced by the parameters they match, in spec order; a name
    given in full wins over a pattern. A pattern that matches nothing is a
    :class:`ConfigError` naming it.

    Examples
    --------
    >>> _expand_patterns({"a*": True, "ab": [0, 1]}, {"ab": 0, "ac": 0, "b": 0}, "m")
    {'ac': True, 'ab': [0, 1]}
    """
    out: dict = {}
    for key, value in evolve.items():
        if not any(ch in key for ch in "*?["):
            continue
        hits = [name for name in by_name if fnmatch.fnmatchcase(name, key)]
        if not hits:
            raise ConfigError(
                f"model.evolve.{key}: the pattern matches no parameter of model {kind!r}"
            )
        for name in hits:
            if name not in evolve:
                out[name] = value
    out.update({k: v for k, v in evolve.items() if not any(ch in k for ch in "*?[")})
    return out


def _resolved(cfg: Config, mp: ModelPlan) -> Config:
    """The config with the model's parameters and ranges written out in full.

    ``model.params`` holds every fixed parameter (preset and defaults filled) and
    ``model.evolve`` every evolved range, so ``config.toml`` of a run does not depend on a
    later change of a preset or a default.
    """
    data = cfg.to_dict()
    ints = mp.int_names
    data["model"]["params"] = {k: (int(v) if k in ints else float(v)) for k, v in mp.fixed.items()}
    data["model"]["evolve"] = {p.name: [float(p.low), float(p.high)] for p in mp.evolved}
    return Config.model_validate(data)


def _build_objective(cfg: Config, i: int, mp: ModelPlan):

    options = cfg.objective[i]
    where = f"objective[{i}]"
    cls = get_objective(options.kind)
    if mp.model.phenotype not in cls.accepts:
        raise ConfigError(
            f"{where}: objective {options.kind!r} scores {', '.join(cls.accepts)} phenotypes; "
            f"model {mp.model.name!r} grows a {mp.model.phenotype!r}"
        )
    try:
        return cls(options, env=mp.environment)
    except (GrowsimError, ValueError, KeyError, OSError) as exc:
        raise ConfigError(_objective_message(cfg, i, str(exc))) from None


def _objective_message(cfg: Config, i: int, text: str) -> str:
    """``text`` (an objective's refusal) prefixed with the key the user wrote: ``objective``
    (the one ``[[objective]]`` table; ``objective[i]`` and which table, among several) and
    the option whose value or name the text starts with (e.g. ``objective.front``).

    Examples
    --------
    >>> from growsim.experiment.load import validate
    >>> cfg = validate({"model": {"kind": "ifs3d"},
    ...                 "objective": [{"kind": "silhouette", "front": "a.png", "side": "b.png"}]})
    >>> _objective_message(cfg, 0, "a.png: image file not found")
    'objective.front: a.png: image file not found'
    >>> _objective_message(cfg, 0, "side: the side view is missing")
    'objective.side: the side view is missing'
    """
    options = cfg.objective[i]
    n = len(cfg.objective)
    where = "objective" if n == 1 else f"objective[{i}]"
    tail = "" if n == 1 else f" (the {_ordinal(i + 1)} [[objective]], {options.kind})"
    for key, value in options.model_dump().items():
        if key in ("kind", "weight"):
            continue
        if text.startswith(f"{key}: "):
            return f"{where}.{key}{tail}: {text[len(key) + 2 :]}"
        if isinstance(value, str) and value and text.startswith(value):
            return f"{where}.{key}{tail}: {text}"
    return f"{where}{tail}: {text}"


def _ordinal(k: int) -> str:
    return f"{k}{'th' if 10 <= k % 100 <= 20 else {1: 'st', 2: 'nd', 3: 'rd'}.get(k % 10, 'th')}"


def compile_plan(cfg: Config) -> ExperimentPlan:
    """Compile a schema-valid config: resolve the model, build each objective once,
    check the GA. Raises :class:`~growsim.errors.ConfigError` naming the key path.

    Examples
    --------
    >>> from growsim.experiment.load import validate
    >>> cfg = validate({"model": {"kind": "honda", "evolve": {"f": True}},
    ...                 "objective": [{"kind": "light"}]})
    >>> compile_plan(cfg).config.model.evolve
    {'f': [0.0, 1.0]}
    """
    mp = plan_model(cfg)
    objectives = tuple(_build_objective(cfg, i, mp) for i in range(len(cfg.objective)))
    plan = ExperimentPlan(
        **{f.name: getattr(mp, f.name) for f in dataclasses.fields(ModelPlan)},
        config=_resolved(cfg, mp),
        objectives=objectives,
    )
    # The schema checked the GA's options (operator names among them); the operators
    # check their own options and that they can handle the genome's coding: build them
    # once here, so a typo fails before anything is written.
    try:
        genome = plan.genome
        plan.config.ga.operators(genome.kind).check(genome)
    except GrowsimError as exc:
        raise ConfigError(f"ga.{exc}") from None
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"ga: {exc}") from None
    return plan
