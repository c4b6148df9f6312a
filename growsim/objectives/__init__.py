"""Objectives: score a phenotype. Objectives combine by weights in an experiment.

Every objective is an :class:`Objective` (name, maximize, the phenotype kinds it accepts,
its options' declaration, an :class:`ObjectiveOptions`, ``__call__``, optional ``terms``
and ``batch``; both from :mod:`growsim.objectives.base`), registered below by name.
:func:`get_objective` finds one. To add an objective, see ``docs/extending.md``.
"""

from __future__ import annotations

from growsim.objectives.base import Objective, ObjectiveOptions
from growsim.registry import Registry

#: registry name -> objective class (``"module:Class"``, imported on first use). One line
#: per objective.
OBJECTIVES: Registry[type[Objective]] = Registry(
    "objective",
    {
        "silhouette": "growsim.objectives.silhouette:SilhouetteObjective",
        "light": "growsim.objectives.light:LightObjective",
        "collisions": "growsim.objectives.collisions:CollisionsObjective",
        "nutrient": "growsim.objectives.nutrient:NutrientObjective",
        "ochoa": "growsim.objectives.ochoa:OchoaObjective",
        "collage": "growsim.objectives.collage:CollageObjective",
    },
)

__all__ = ["OBJECTIVES", "Objective", "ObjectiveOptions", "get_objective"]


def get_objective(name: str) -> type[Objective]:
    """Return the objective class registered as ``name``.

    Examples
    --------
    >>> get_objective("silhouette").__name__
    'SilhouetteObjective'
    """
    return OBJECTIVES.get(name)
