"""The tank: ``[environment.tank]``, a box with obstacles for agents that swim (the fish).

A tank is an axis-aligned box ``[0, size]`` (x across, y up, z deep) holding spheres and
cubes. :data:`TANKS` holds the three tanks of Okusa's thesis ("GA-tuned path control of
a fish agent": small 300 x 400 x 300, medium 400 x 600 x 300, large 800 x 800 x 800, W x H
x D) with one obstacle layout, :data:`LAYOUT`, the same in all three as in the thesis (which
does not give its layout; ours is documented in ``docs/models/fish.md``). A preset fills
``size`` and ``obstacles`` unless they are given. ``margin`` is the distance from every
wall inside which a fish starts (40 px in the thesis): every side must exceed twice it.
"""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np
from pydantic import Field, field_validator, model_serializer, model_validator

from growsim.options import Options

__all__ = ["LAYOUT", "TANKS", "Obstacle", "Tank"]

#: the obstacle layout of the preset tanks (the same in all three, as in the thesis): a
#: sphere low in one corner and a cube high in the opposite one, placed to fit the small
#: tank; ``size`` is the radius or half the edge
LAYOUT: tuple[dict[str, Any], ...] = (
    {"shape": "sphere", "center": [90.0, 130.0, 90.0], "size": 20.0},
    {"shape": "cube", "center": [210.0, 270.0, 210.0], "size": 15.0},
)

#: the thesis's three tanks (inner size [x, y up, z] in pixels)
TANKS: dict[str, list[float]] = {
    "small": [300.0, 400.0, 300.0],
    "medium": [400.0, 600.0, 300.0],
    "large": [800.0, 800.0, 800.0],
}


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
    """``[environment.tank]``: the box ``[0, size]``, its obstacles and the start margin.

    Examples
    --------
    >>> Tank(size=[300, 400, 300]).obstacles
    []
    >>> t = Tank.model_validate({"preset": "medium"})
    >>> t.size, len(t.obstacles), t.margin
    ([400.0, 600.0, 300.0], 2, 40.0)
    >>> size, spheres, cubes = t.arrays()
    >>> spheres.shape, cubes.shape
    ((1, 4), (1, 4))
    """

    preset: Literal[tuple(TANKS)] | None = Field(  # type: ignore[valid-type]
        None,
        description="one of Okusa's tanks (small 300x400x300, medium 400x600x300, large "
        "800x800x800) with the documented obstacle layout; size and obstacles given "
        "replace the preset's",
    )
    size: list[float] = Field(
        min_length=3, max_length=3, description="inner size [x, y, z] of the tank (y is up)"
    )
    obstacles: list[Obstacle] = Field(default_factory=list, description="obstacles in the tank")
    margin: float = Field(
        40.0, ge=0.0, description="a fish starts at least this far from every wall (pixels)"
    )

    @model_validator(mode="before")
    @classmethod
    def _preset(cls, data: Any) -> Any:
        if isinstance(data, dict) and isinstance(data.get("preset"), str):
            name = data["preset"]
            if name in TANKS:
                data = dict(data)
                data.setdefault("size", list(TANKS[name]))
                data.setdefault("obstacles", [dict(o) for o in LAYOUT])
        return data

    @field_validator("size")
    @classmethod
    def _check_size(cls, v):
        return _finite(v, positive=True)

    @model_validator(mode="after")
    def _inside(self):
        if self.margin > 0 and not all(s > 2.0 * self.margin for s in self.size):
            raise ValueError(
                f"size: {self.size} is too small for the start margin of {self.margin:g} px "
                f"(every side must exceed {2.0 * self.margin:g})"
            )
        for i, ob in enumerate(self.obstacles):
            if not all(0.0 <= c <= s for c, s in zip(ob.center, self.size)):
                raise ValueError(
                    f"obstacles[{i}]: centre {ob.center} is outside the tank [0, {self.size}]"
                )
        return self

    @model_serializer(mode="wrap")
    def _as_preset(self, handler):
        """A tank that is its preset's is written as the preset alone, so a config saved
        with it (a run's ``config.toml``) still follows a later change of the preset (a
        sweep's ``--vary environment.tank.preset=...``)."""
        out = handler(self)
        if (
            self.preset is not None
            and list(self.size) == list(TANKS[self.preset])
            and [o.model_dump() for o in self.obstacles] == [dict(o) for o in LAYOUT]
        ):
            out.pop("size", None)
            out.pop("obstacles", None)
        return out

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The tank as the fish kernels take it: ``size (3,)``, spheres ``(k, 4)`` and cubes
        ``(m, 4)`` (``[cx, cy, cz, radius or half edge]``)."""
        rows = {"sphere": [], "cube": []}
        for ob in self.obstacles:
            rows[ob.shape].append([*ob.center, ob.size])
        return (
            np.asarray(self.size, dtype=np.float64),
            np.asarray(rows["sphere"], dtype=np.float64).reshape(-1, 4),
            np.asarray(rows["cube"], dtype=np.float64).reshape(-1, 4),
        )
