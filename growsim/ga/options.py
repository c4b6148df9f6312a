"""The options of a :class:`growsim.ga.GA`, declared once: :class:`GAOptions`.

The experiment config's ``[ga]`` section extends :class:`GAOptions` with the genome's
coding and the run's budget, so a key, its default, its limits and its description are
written in one place. Values are checked strictly (a string ``"50"`` is not a
population), every default is validated too, and the rules between options (the elite is
smaller than the population, the steady model's children fewer than the population,
operator names registered) raise from a validator, so pydantic names the key.
"""

from __future__ import annotations

import dataclasses
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    ConfigDict,
    Field,
    Strict,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    ValidationError,
    field_validator,
    model_validator,
)
from pydantic.dataclasses import dataclass

from growsim.errors import UserInputError
from growsim.ga.crossover import CROSSOVER, Crossover
from growsim.ga.generation import GENERATION_MODELS, GenerationModel
from growsim.ga.mutation import MUTATION, Mutation
from growsim.ga.operator import Operators, make_operator
from growsim.ga.selection import SELECTION, Selection
from growsim.options import validation_message

__all__ = [
    "DEFAULT_MODEL",
    "DEFAULT_OPERATORS",
    "GA_OPTIONS_CONFIG",
    "PORTFOLIO_DEFAULTS",
    "GAOptions",
]

#: the reals' default portfolio options (issue 15, third round, benchmarks/log/ga.md): wider
#: polynomial steps (eta 10, not 20), a smaller first Gaussian step (0.005 of the ranges,
#: not 0.01) and more DE crossers at first (0.35, not 0.25)
PORTFOLIO_DEFAULTS = {"polynomial_eta": 10.0, "sigma": 0.005, "differential_share": 0.35}
#: default operators per genome kind, chosen by ``benchmarks/bbob.py`` (reals) and its bit
#: suite (bits); see benchmarks/log/ga.md. Before issue 15 the reals' were a tournament of 4, SBX
#: (eta 15) and polynomial mutation under the generational model: configs that relied on
#: them name them. The reals' first issue-15 defaults (SBX eta 15 + "self_adaptive") are
#: named the same way: ``crossover="sbx", mutation="self_adaptive"``; the second round's
#: (the portfolio with its own defaults) as ``mutation="portfolio"``.
DEFAULT_OPERATORS = {
    "bits": {
        "selection": ("tournament", {"size": 4}),
        "crossover": ("uniform", {"rate": 1.0}),
        "mutation": ("bitflip", {}),
    },
    "real": {
        "selection": ("tournament", {"size": 4}),
        "crossover": ("differential", {}),
        "mutation": ("portfolio", PORTFOLIO_DEFAULTS),
    },
}
#: default generation model per genome kind (``GAOptions(model=None)``)
DEFAULT_MODEL = {"bits": "generational", "real": "mu+lambda"}

_REGISTRIES = {"selection": SELECTION, "crossover": CROSSOVER, "mutation": MUTATION}

# Strict per field (Strict* types), not per class: a class-level ``strict=True`` would make
# pydantic accept only GAOptions instances, not dicts, where a GAOptions is itself a field
# (the config's ``[ga]`` section): error ``dataclass_exact_type``.
# defer_build: the validators are built on first use, not at import (a run validates its
# [ga] table through the config's subclass; measured: 35 ms less start-up)
GA_OPTIONS_CONFIG = ConfigDict(
    extra="forbid", validate_default=True, arbitrary_types_allowed=True, defer_build=True
)
StrictDict = Annotated[dict[str, Any], Strict()]


@dataclass(frozen=True, config=GA_OPTIONS_CONFIG)
class GAOptions:
    """The options of :class:`growsim.ga.GA` (``GA(genome, fitness, GAOptions(...))``, or
    the same names as keywords: ``GA(genome, fitness, population=20)``).

    Operators are registry names (:data:`~growsim.ga.SELECTION`,
    :data:`~growsim.ga.CROSSOVER`, :data:`~growsim.ga.MUTATION`) with their options, or
    operator instances (without options); None takes the defaults of the genome's kind
    (:data:`DEFAULT_OPERATORS`: bits: tournament of 4, uniform crossover, bit-flip 1/L;
    reals: tournament of 4, the differential crossover (DE trials or SBX) and the
    self-adaptive portfolio mutation), and options
    given with None override the defaults' options. ``model=None`` likewise takes the
    coding's default (:data:`DEFAULT_MODEL`: bits generational, reals mu+lambda).

    Every field is strict (a string ``"50"`` is not a population; ints are accepted for
    floats); a subclass (the config's ``[ga]`` section) declares its fields the same way,
    with pydantic's ``Strict*`` types.

    Examples
    --------
    >>> o = GAOptions(population=40, elite_rate=0.05, model="mu+lambda")
    >>> o.n_elite, o.generation_model().offspring
    (2, 40)
    >>> GAOptions(population=4, elite=4)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    pydantic_core._pydantic_core.ValidationError: 1 validation error for GAOptions
      Value error, elite (4) must be smaller than population (4) ...
    """

    population: StrictInt = Field(50, ge=2, le=10_000_000, description="individuals per generation")
    selection: StrictStr | Selection | None = Field(
        None, description="selection operator (default per coding)"
    )
    crossover: StrictStr | Crossover | None = Field(
        None, description="crossover operator (default per coding)"
    )
    mutation: StrictStr | Mutation | None = Field(
        None, description="mutation operator (default per coding)"
    )
    selection_options: StrictDict = Field(default_factory=dict, description="its options")
    crossover_options: StrictDict = Field(default_factory=dict, description="its options")
    mutation_options: StrictDict = Field(default_factory=dict, description="its options")
    model: Literal["generational", "steady", "mu+lambda"] | None = Field(
        None, description="generation model (default per coding)"
    )
    elite: StrictInt = Field(1, ge=0, description="best individuals copied unchanged")
    elite_rate: StrictFloat | None = Field(
        None, ge=0.0, le=1.0, description="elite as a share of the population (over elite)"
    )
    offspring: StrictInt | None = Field(
        None,
        ge=1,
        description="children per generation of the steady (default 2) and mu+lambda "
        "(default population) models",
    )
    islands: StrictInt = Field(1, ge=1, le=10_000, description="sub-populations")
    migration_rate: StrictFloat = Field(0.1, ge=0.0, le=1.0, description="share migrating")
    migration_interval: StrictInt = Field(5, ge=1, description="generations between migrations")
    extinction: StrictBool = Field(
        True, description="re-create a population that stops reproducing"
    )
    batch_size: StrictInt | None = Field(None, ge=1, description="individuals per evaluation task")

    @field_validator(
        "population",
        "elite",
        "offspring",
        "islands",
        "migration_interval",
        "batch_size",
        mode="before",
    )
    @classmethod
    def _numpy_int(cls, v):
        # a NumPy integer counts as an int (strict mode would refuse it)
        return int(v) if isinstance(v, np.integer) else v

    @field_validator("selection_options", "crossover_options", "mutation_options", mode="before")
    @classmethod
    def _no_options(cls, v):
        return {} if v is None else v

    @field_validator("selection", "crossover", "mutation")
    @classmethod
    def _registered(cls, v, info):
        if isinstance(v, str):
            try:
                _REGISTRIES[info.field_name].get(v)
            except UserInputError as e:
                raise ValueError(str(e)) from None
        return v

    @model_validator(mode="after")
    def _check(self):
        for role in _REGISTRIES:
            spec = getattr(self, role)
            if spec is not None and not isinstance(spec, str) and getattr(self, f"{role}_options"):
                raise ValueError(f"{role}_options: given with an operator instance {spec!r}")
        if self.n_elite >= self.population:
            what = "elite" if self.elite_rate is None else f"elite_rate ({self.elite_rate}): elite"
            raise ValueError(
                f"{what} ({self.n_elite}) must be smaller than population ({self.population})"
            )
        if self.model is not None:  # None: checked when the genome's kind is known
            self.generation_model()  # raises ValueError for an offspring the model cannot use
        return self

    @property
    def n_elite(self) -> int:
        """The elite's size: ``round(elite_rate * population)`` if ``elite_rate`` is set,
        else ``elite``."""
        if self.elite_rate is None:
            return self.elite
        return round(float(self.elite_rate) * self.population)

    def model_name(self, kind: str | None = None) -> str:
        """``model``, or when None the default of a genome of ``kind``
        (:data:`DEFAULT_MODEL`).

        Examples
        --------
        >>> GAOptions().model_name("real"), GAOptions(model="steady").model_name("real")
        ('mu+lambda', 'steady')
        """
        if self.model is not None:
            return self.model
        if kind not in DEFAULT_MODEL:
            raise UserInputError(
                f"model: None takes the default of the genome's kind ({', '.join(DEFAULT_MODEL)}); "
                f"got kind {kind!r}"
            )
        return DEFAULT_MODEL[kind]

    def generation_model(self, kind: str | None = None) -> GenerationModel:
        """The :class:`~growsim.ga.generation.GenerationModel` named by ``model`` (None:
        the default for a genome of ``kind``, see :meth:`model_name`)."""
        name = self.model_name(kind)
        return GENERATION_MODELS.get(name)(self.population, self.n_elite, self.offspring)

    def operator(self, role: str, kind: str) -> tuple[str | Any, dict[str, Any]]:
        """``(spec, options)`` of the ``role`` operator (``"selection"``, ``"crossover"``,
        ``"mutation"``) for a genome of ``kind``, defaults filled in.

        Examples
        --------
        >>> GAOptions(crossover_options={"eta": 5}).operator("crossover", "real")
        ('differential', {'eta': 5})
        """
        spec, options = getattr(self, role), getattr(self, f"{role}_options")
        if spec is None:
            spec, default = DEFAULT_OPERATORS[kind][role]
            options = {**default, **options}
        return spec, dict(options)

    def operators(self, kind: str) -> Operators:
        """The selection, crossover and mutation for a genome of ``kind``: the instances
        given, or built from their registry with the options (see :meth:`operator`).

        Examples
        --------
        >>> GAOptions(selection="rank").operators("bits").selection
        LinearRank(pressure=2.0)
        """
        return Operators(
            *(make_operator(_REGISTRIES[role], *self.operator(role, kind)) for role in _REGISTRIES)
        )

    @classmethod
    def build(cls, options: GAOptions | None = None, **overrides) -> GAOptions:
        """``options`` (default: the defaults) with ``overrides`` (field names) replaced,
        validated; :class:`UserInputError` names an unknown or bad option.

        Examples
        --------
        >>> GAOptions.build(GAOptions(population=10), islands=2).islands
        2
        >>> GAOptions.build(populaton=10)  # doctest: +ELLIPSIS
        Traceback (most recent call last):
        ...
        growsim.errors.UserInputError: unknown GA option(s) populaton; allowed: population, ...
        >>> GAOptions.build(population=1.5)
        Traceback (most recent call last):
        ...
        growsim.errors.UserInputError: population: Input should be a valid integer (got 1.5)
        """
        allowed = [f.name for f in dataclasses.fields(GAOptions)]
        bad = [k for k in overrides if k not in allowed]
        if bad:
            raise UserInputError(
                f"unknown GA option(s) {', '.join(bad)}; allowed: {', '.join(allowed)}"
            )
        if options is not None and not isinstance(options, GAOptions):
            raise UserInputError(f"options must be a GAOptions, got {options!r}")
        try:
            if options is None:
                return cls(**overrides)
            return dataclasses.replace(options, **overrides) if overrides else options
        except ValidationError as e:
            raise UserInputError(validation_message(e)) from None
