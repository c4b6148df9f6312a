"""The tank: ``[environment.tank]``, a box with obstacles for agents that swim (the fish).

A tank is an axis-aligned box ``[0, size]`` (x, y up, z) holding spheres and cubes.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, field_validator, model_validator

from growsim.options import Options

__all__ = ["Obstacle", "Tank"]


def _finite(v: list[float], positive: bool = False) -> list[float]:
    if not all(math.isfinite(x) and (x > 0 or not positive) for x in v):
        kind = "positive" if positive else "finite"
        raise ValueError(f"expected {kind} numbers, got {v!r}")
    return v


class Obstacle(Options):
    """One obstacle in the tank: a sphere or an axis-aligned cube.

    ``size`` is the sphere's radius or half the cube's edge; ``center`` its centre.

    Examples
    --------
    >>> Obstacle(shape="sphere", center=[10, 10, 10], size=5).shape
    'sphere'
    """

    shape: Literal["sphere", "cube"] = Field(description="obstacle shape")
    center: list[float] = Field(min_length=3, max_length=3, description="centre [x, y, z]")
    size: float = Field(gt=0.0, description="sphere radius, or half the cube's edge")

    @field_validator("center")
    @classmethod
    def _check_center(cls, v):
        return _finite(v)


class Tank(Options):
    """``[environment.tank]``: the box ``[0, size]`` and its obstacles.

    Examples
    --------
    >>> Tank(size=[300, 400, 300]).obstacles
    []
    """

    size: list[float] = Field(
        min_length=3, max_length=3, description="inner size [x, y, z] of the tank"
    )
    obstacles: list[Obstacle] = Field(default_factory=list, description="obstacles in the tank")

    @field_validator("size")
    @classmethod
    def _check_size(cls, v):
        return _finite(v, positive=True)

    @model_validator(mode="after")
    def _inside(self):
        for i, ob in enumerate(self.obstacles):
            if not all(0.0 <= c <= s for c, s in zip(ob.center, self.size)):
                raise ValueError(
                    f"obstacles[{i}]: centre {ob.center} is outside the tank [0, {self.size}]"
                )
        return self
