"""Total nutrient held by a plant's modules: the fitness of Uehara, Akamine
and Endo ("Plants that acquire a 3D structure by adapting to the environment").

``score = sum_m nutrient_m`` over the modules of a plant grown by a model that keeps a
per-module ``data["nutrient"]`` (the hormone model, :mod:`growsim.models.hormone`; a
plant of a model that keeps none holds none: 0). A plant that stopped on a NaN
(``meta["stopped"] == "nan"``) scores NaN, which the GA counts as a failure and scores
worst. Terms: ``nutrient`` (the score), ``modules`` (the count).

Population fast path (:meth:`NutrientObjective.batch`): a model with a ``population``
capability (the hormone model, :func:`growsim.models.hormone.population`) grows the whole
population in one kernel call, keeping no plant, and gives the same numbers.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field

from growsim.kernels.hormone import total
from growsim.objectives.base import Objective, ObjectiveOptions

__all__ = ["NutrientObjective", "NutrientOptions"]


class NutrientOptions(ObjectiveOptions):
    """Options of the ``nutrient`` objective (none of its own)."""

    kind: Literal["nutrient"] = Field("nutrient", description="the objective: nutrient")


class NutrientObjective(Objective):
    """Total nutrient held by all modules (maximised).

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models import get_model
    >>> env = Environment.model_validate({"light": {"diffuse": 0.5}})
    >>> model = get_model("hormone")
    >>> plant = model.develop({**model.preset("demo_2d"), "steps": 8}, env=env)
    >>> obj = NutrientObjective(env=env)
    >>> bool(obj(plant) == plant.data["nutrient"].sum()), sorted(obj.terms(plant))
    (True, ['modules', 'nutrient'])
    """

    name = "nutrient"
    maximize = True
    accepts = ("plant",)
    Options = NutrientOptions
    example: ClassVar[dict[str, Any]] = {}

    def setup(self) -> None:
        """Nothing to prepare."""

    def terms(self, plant) -> dict[str, float]:
        """``{"nutrient": total, "modules": count}``."""
        if "nutrient" not in plant.data:  # a model that keeps no nutrient holds none
            return {"nutrient": 0.0, "modules": float(plant.n_segments)}
        if plant.meta.get("stopped") == "nan":
            return {"nutrient": float("nan"), "modules": float(plant.n_segments)}

        nutrient = np.ascontiguousarray(plant.data["nutrient"], dtype=np.float64)
        held = float(total(nutrient, len(nutrient)))
        return {"nutrient": held, "modules": float(plant.n_segments)}

    def __call__(self, plant) -> float:
        return self.terms(plant)["nutrient"]

    def batch(self, model, params, names, seeds=None):
        """The model's ``population`` capability over the whole population (its
        ``total_nutrient`` column), or None."""
        if "population" not in model.capabilities:
            return None
        table = model.population(params, names, seeds, env=self.env)
        return None if table is None else table["total_nutrient"].to_numpy(np.float64)
