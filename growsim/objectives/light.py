"""Light captured under a parallel light, for the least wood.

A simple light measure until the shadow-map light of the hormone model replaces it: the
light a plant catches is its leaves' orthographic shadow along the light direction
(leaves that overlap each other, seen from the light, count once: self-shading), and
wood is what it costs to hold them up::

    score = intensity * A_leaf(d) - wood_cost * V_wood

- ``A_leaf(d)``: :meth:`growsim.plant.Plant.leaf_area` along ``d`` (world units^2: the
  leaves' shadow, :func:`growsim.env.light.projected_area`), rasterised at ``resolution``
  pixels across the plant;
- ``V_wood``: :meth:`growsim.plant.Plant.wood_volume` (world units^3, the stem tubes);
- ``intensity`` and ``d`` default to ``environment.light.intensity`` and
  ``environment.light.direction`` of the experiment.

This follows the light-capture term of Ochoa's fitness (as used by Liu & Zhang, "IFS
plant populations evolved by a GA with a weighted fitness": the larger the lit area, the
better) with a wood cost in place of the paper's stability term, and Honda's model
("Tree branching by nutrient allocation") as the plant that grows it. ``wood_cost`` has
units of 1/length: at the default 0.02, a unit^3 of wood must catch 0.02 unit^2 more light to
pay for itself.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field

from growsim.env.light import Direction, Intensity
from growsim.objectives.base import Objective, ObjectiveOptions

__all__ = ["LightObjective", "LightOptions"]


class LightOptions(ObjectiveOptions):
    """Options of the ``light`` objective."""

    kind: Literal["light"] = Field("light", description="the objective: light")
    direction: Direction | None = Field(
        None, description="direction the light travels (y up); default environment.light.direction"
    )
    intensity: Intensity | None = Field(
        None, description="light intensity; default environment.light.intensity"
    )
    wood_cost: float = Field(0.02, ge=0.0, le=1e9, description="cost per unit^3 of wood")
    resolution: int = Field(
        128, ge=16, le=4096, description="raster size (pixels across the plant) of the leaf area"
    )


class LightObjective(Objective):
    """Leaf area seen from a parallel light minus a cost per unit of wood (maximised).

    Options (:class:`LightOptions`): ``direction`` (3 floats, the direction the light
    travels, y up; default the environment's), ``intensity`` (default the environment's),
    ``wood_cost`` (per unit^3 of wood, >= 0, default 0.02), ``resolution`` (raster size
    of the projected area, 16..4096, default 128).

    Examples
    --------
    >>> obj = LightObjective(wood_cost=0.0, resolution=64)
    >>> obj.name, obj.maximize
    ('light', True)
    >>> from growsim.models import get_model
    >>> plant = get_model("honda").develop(get_model("honda").preset("zelkova"))
    >>> bool(obj(plant) > 0), sorted(obj.terms(plant))
    (True, ['leaf_area', 'wood_volume'])
    """

    name = "light"
    maximize = True
    accepts = ("plant",)
    Options = LightOptions
    example: ClassVar[dict[str, Any]] = {"wood_cost": 0.5, "resolution": 64}

    def setup(self) -> None:
        o = self.options
        light = self.env.light
        self.direction = tuple(float(x) for x in (o.direction or light.direction))
        self.intensity = float(light.intensity if o.intensity is None else o.intensity)
        self.wood_cost = o.wood_cost
        self.resolution = o.resolution

    def terms(self, plant) -> dict[str, float]:
        """The two terms of the score: ``{"leaf_area": A_leaf(d), "wood_volume": V}``."""
        area = float(plant.leaf_area(self.direction, resolution=self.resolution))
        return {"leaf_area": area, "wood_volume": float(plant.wood_volume())}

    def __call__(self, plant) -> float:
        t = self.terms(plant)
        return self.intensity * t["leaf_area"] - self.wood_cost * t["wood_volume"]
