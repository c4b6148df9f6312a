"""The objective contract: what scores a phenotype, with which options.

An objective is a :class:`Objective` subclass registered by name in
:data:`growsim.objectives.OBJECTIVES`. It declares

- :attr:`~Objective.name`, :attr:`~Objective.maximize`;
- :attr:`~Objective.accepts`: the phenotype kinds it can score (see
  :mod:`growsim.phenotypes`); a config pairing it with a model whose phenotype is not
  among them is refused at load time;
- :attr:`~Objective.Options`: its options, an :class:`ObjectiveOptions` subclass: the one
  declaration of its ``[[objective]]`` table (types, defaults, limits, descriptions),
  from which the config schema and ``docs/configs.md`` are built;

and implements ``__call__(phenotype) -> float``, optionally :meth:`~Objective.terms`
(named parts of the score, reported for the best individual) and
:meth:`~Objective.batch` (a fast path scoring a whole population's parameters). The
base declares both with their defaults (no terms; no fast path: ``None``), so the
fitness (:class:`growsim.experiment.fitness.Fitness`) reads :attr:`~Objective.maximize`
and calls ``terms`` and ``batch`` on every objective, never probing for them.
An objective is built once per run, with the run's environment, and is picklable.
"""

from __future__ import annotations

import abc
import math
from typing import Any, ClassVar

import numpy as np
from pydantic import Field, field_validator

from growsim.env import Environment
from growsim.options import Options

__all__ = ["Objective", "ObjectiveOptions"]


class ObjectiveOptions(Options):
    """``[[objective]]``: the keys every objective table has. Subclasses add the
    objective's own options and narrow ``kind`` to its name (a ``Literal``)."""

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


class Objective(abc.ABC):
    """Base of every objective (see the module docstring for the contract).

    ``Objective(options=None, *, env=None, **values)``: ``options`` an instance of
    :attr:`Options`, or the option values as keywords (validated; a bad one raises
    :class:`growsim.errors.ConfigError` naming it); ``env`` the run's
    :class:`growsim.env.Environment` (default: the default environment). Subclasses
    prepare what they need in :meth:`setup` (e.g. read target pictures), once.

    Examples
    --------
    >>> from growsim.objectives import get_objective
    >>> obj = get_objective("light")(wood_cost=0.5)
    >>> obj.options.wood_cost, obj.options.weight, obj.accepts
    (0.5, 1.0, ('plant',))
    """

    name: ClassVar[str] = ""
    maximize: ClassVar[bool] = True
    #: phenotype kinds the objective scores
    accepts: ClassVar[tuple[str, ...]] = ("plant",)
    #: the options' declaration
    Options: ClassVar[type[ObjectiveOptions]] = ObjectiveOptions
    #: option values of a typical use (docs and the conformance tests build it)
    example: ClassVar[dict[str, Any]] = {}

    def __init__(self, options: ObjectiveOptions | None = None, *, env=None, **values: Any):

        if options is None:
            options = self.Options.parse({"kind": self.name, **values}, where=f"{self.name}.")
        elif values or not isinstance(options, self.Options):
            raise TypeError(f"{type(self).__name__}: give options or keyword values, not both")
        self.options = options
        self.env = Environment() if env is None else env
        self.setup()

    def setup(self) -> None:  # noqa: B027 - optional hook, empty by default
        """Prepare what scoring needs, once (default: nothing)."""

    @abc.abstractmethod
    def __call__(self, phenotype) -> float:
        """The score of one phenotype."""

    def terms(self, phenotype) -> dict[str, float]:
        """Named parts of the score (e.g. leaf area and wood volume); default none."""
        return {}

    def exact(self, phenotype) -> float:
        """The score reported for a phenotype, where the search scores something smoother
        (the silhouette's binary NCC whatever its ``blur``); default: the score itself."""
        return float(self(phenotype))

    def batch(self, model, params: np.ndarray, names, seeds=None) -> np.ndarray | None:
        """Score a whole ``(n, p)`` matrix of ``model`` parameters (columns ``names``) at
        once, or return None when there is no fast path (the default)."""
        return None

    def __repr__(self) -> str:
        opts = self.options.model_dump(exclude={"kind", "weight"}, exclude_none=True)
        return f"{type(self).__name__}({', '.join(f'{k}={v!r}' for k, v in opts.items())})"
