"""Objectives: score a phenotype. Objectives combine by weights in an experiment.

An objective is a picklable class with ``name``, ``maximize`` (bool), construction from
keyword options (its config table), and ``__call__(plant) -> float``. It may also define
``batch(model, params, names, seeds) -> ndarray | None``: a fast path scoring a whole
``(n, p)`` parameter matrix of ``model`` at once (returning ``None`` when it cannot).

:func:`get_objective` finds one by name.
"""

from __future__ import annotations

import importlib

from growsim.errors import UserInputError

#: registry name -> "module:ClassName". One line per objective.
OBJECTIVES: dict[str, str] = {
    "silhouette": "growsim.objectives.silhouette:SilhouetteObjective",
    "light": "growsim.objectives.light:LightObjective",
}

__all__ = ["OBJECTIVES", "get_objective"]


def get_objective(name: str) -> type:
    """Return the objective class registered as ``name``.

    Examples
    --------
    >>> get_objective("silhouette").__name__
    'SilhouetteObjective'
    """
    try:
        target = OBJECTIVES[name]
    except KeyError:
        raise UserInputError(
            f"unknown objective {name!r}; available: {', '.join(sorted(OBJECTIVES))}"
        ) from None
    module, cls = target.split(":")
    return getattr(importlib.import_module(module), cls)
