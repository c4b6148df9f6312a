"""Collisions of a swimming agent with its tank's walls and obstacles (minimised): the
fitness of Okusa's thesis ("GA-tuned path control of a fish agent": the total of the 7
body points' collisions over 20,000 frames; 0 is a fish that never touches anything).

The score recounts the collisions of a :class:`growsim.phenotypes.trajectory.Trajectory` against the
objective's environment's tank (the default tank when it has none); the population fast
path (:meth:`CollisionsObjective.batch`) asks the model's ``collisions`` capability (the
fish's kernel over the whole population, no path kept), and gives the same numbers.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field

from growsim.kernels.fish import count_collisions
from growsim.models.fish import default_tank
from growsim.objectives.base import Objective, ObjectiveOptions

__all__ = ["CollisionsObjective", "CollisionsOptions"]


class CollisionsOptions(ObjectiveOptions):
    """``[[objective]] kind = "collisions"``: count collisions (the frames are the model's
    ``frames`` parameter: 20,000 for the fish)."""

    kind: Literal["collisions"] = Field("collisions", description="the objective: collisions")


class CollisionsObjective(Objective):
    """Total collisions along a trajectory (minimised; a GA stops at ``ga.target = 0.0``).

    Examples
    --------
    >>> from growsim.models.fish import develop
    >>> obj = CollisionsObjective()
    >>> t = develop({"frames": 2000, "view": 100, "speed": 5, "scale": 2})
    >>> obj(t) == t.collisions, obj.maximize
    (True, False)
    """

    name = "collisions"
    maximize = False
    accepts = ("trajectory",)
    Options = CollisionsOptions
    example: ClassVar[dict[str, Any]] = {}

    def setup(self) -> None:
        """The tank's arrays, once."""

        tank = self.env.tank if self.env.tank is not None else default_tank()
        self.tank = tank
        self._arrays = tank.arrays()

    def terms(self, trajectory) -> dict[str, float]:
        """``frames_with_collision``: frames where any body point collided."""

        hits, _ = count_collisions(
            trajectory.positions, trajectory.angles, trajectory.body, *self._arrays
        )
        return {"frames_with_collision": float(np.count_nonzero(hits))}

    def __call__(self, trajectory) -> float:

        _, total = count_collisions(
            trajectory.positions, trajectory.angles, trajectory.body, *self._arrays
        )
        return float(total)

    def batch(self, model, params, names, seeds=None):
        """The model's ``collisions`` capability over the whole population, or None."""
        if "collisions" not in model.capabilities:
            return None
        out = model.collisions(params, names, seeds, env=self.env)
        return None if out is None else np.asarray(out, dtype=np.float64)
