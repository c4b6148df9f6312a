"""Light captured under a parallel light, for the least wood.

A simple light measure until the shadow-map light of the hormone model replaces it: the
light a plant catches is its leaves' orthographic shadow along the light direction
(leaves that overlap each other, seen from the light, count once: self-shading), and
wood is what it costs to hold them up::

    score = intensity * A_leaf(d) - wood_cost * V_wood

- ``A_leaf(d)``: :meth:`growsim.plant.Plant.projected_area` of the leaf segments along
  ``d`` (world units^2), rasterised at ``resolution`` pixels across the plant;
- ``V_wood``: :meth:`growsim.plant.Plant.wood_volume` (world units^3, the stem tubes);
- ``intensity`` and ``d`` default to ``environment.light`` and
  ``environment.light_direction`` of the experiment.

This follows the light-capture term of Ochoa's fitness (as used by Liu & Zhang, "IFS
plant populations evolved by a GA with a weighted fitness": the larger the lit area, the
better) with a wood cost in place of the paper's stability term, and Honda's model
("Tree branching by nutrient allocation") as the plant that grows it. ``wood_cost`` has
units of 1/length: at the default 0.02, a unit^3 of wood must catch 0.02 unit^2 more light to
pay for itself.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from growsim.errors import ConfigError

__all__ = ["LightObjective"]


class LightObjective:
    """Leaf area seen from a parallel light minus a cost per unit of wood (maximised).

    Parameters
    ----------
    direction : 3 floats, optional
        Direction the light travels (y up; ``(0, -1, 0)`` is light from above). Default:
        the experiment's ``environment.light_direction`` (else from above).
    intensity : float, optional
        Light intensity multiplying the area. Default: ``environment.light`` (else 1).
    wood_cost : float
        Cost per unit^3 of wood, >= 0 (default 0.02).
    resolution : int
        Raster size (pixels across the plant) of the projected area, 16..4096 (default 128).

    Examples
    --------
    >>> obj = LightObjective(wood_cost=0.0, resolution=64)
    >>> obj.name, obj.maximize
    ('light', True)
    >>> from growsim.models import get_model
    >>> plant = get_model("honda").develop(get_model("honda").PRESETS["zelkova"])
    >>> bool(obj(plant) > 0)
    True
    """

    name = "light"
    maximize = True

    def __init__(
        self,
        direction: Sequence[float] | None = None,
        intensity: float | None = None,
        wood_cost: float = 0.02,
        resolution: int = 128,
    ):
        if direction is not None:
            d = _vector(direction, "direction")
            direction = tuple(float(x) for x in d)
        if intensity is not None:
            intensity = _number(intensity, "intensity", 0.0, 1e6)
        self.direction = direction
        self.intensity = intensity
        self.wood_cost = _number(wood_cost, "wood_cost", 0.0, 1e9)
        if isinstance(resolution, bool) or not isinstance(resolution, (int, np.integer)):
            raise ConfigError(f"resolution: expected an integer, got {resolution!r}")
        if not 16 <= int(resolution) <= 4096:
            raise ConfigError(f"resolution: {resolution} is out of range [16, 4096]")
        self.resolution = int(resolution)

    def with_environment(self, env) -> LightObjective:
        """A copy taking direction and intensity from ``env`` where they were not given.

        ``env`` is an :class:`growsim.experiment.EnvironmentConfig` (``light``,
        ``light_direction``).
        """
        new = _copy(self)
        if new.direction is None and getattr(env, "light_direction", None) is not None:
            new.direction = tuple(float(x) for x in env.light_direction)
        if new.intensity is None and getattr(env, "light", None) is not None:
            new.intensity = float(env.light)
        return new

    def terms(self, plant) -> dict[str, float]:
        """The two terms of the score: ``{"leaf_area": A_leaf(d), "wood_volume": V}``."""
        from growsim.plant import LEAF

        d = self.direction if self.direction is not None else (0.0, -1.0, 0.0)
        area = float(plant.projected_area(d, kinds=(LEAF,), resolution=self.resolution))
        return {"leaf_area": area, "wood_volume": float(plant.wood_volume())}

    def __call__(self, plant) -> float:
        t = self.terms(plant)
        intensity = 1.0 if self.intensity is None else self.intensity
        return intensity * t["leaf_area"] - self.wood_cost * t["wood_volume"]

    def __repr__(self) -> str:
        return (
            f"LightObjective(direction={self.direction}, intensity={self.intensity}, "
            f"wood_cost={self.wood_cost}, resolution={self.resolution})"
        )


def _copy(obj):
    new = object.__new__(type(obj))
    new.__dict__.update(obj.__dict__)
    return new


def _number(v, name: str, lo: float, hi: float) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise ConfigError(f"{name}: expected a number, got {v!r}")
    v = float(v)
    if not math.isfinite(v) or not lo <= v <= hi:
        raise ConfigError(f"{name}: {v!r} is out of range [{lo:g}, {hi:g}]")
    return v


def _vector(v, name: str) -> np.ndarray:
    try:
        d = np.asarray(v, dtype=np.float64)
    except (TypeError, ValueError):
        raise ConfigError(f"{name}: expected 3 numbers, got {v!r}") from None
    if d.shape != (3,) or not np.all(np.isfinite(d)) or not np.any(d):
        raise ConfigError(f"{name}: expected a finite non-zero 3-vector, got {v!r}")
    return d
