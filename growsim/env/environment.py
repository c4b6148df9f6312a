"""The environment a phenotype grows (or swims) in: ``[environment]`` of a config.

:class:`Environment` gathers the parts, each a frozen table with its own module: light
(:mod:`growsim.env.light`), gravity (:mod:`growsim.env.gravity`), water
(:mod:`growsim.env.water`), the ground (:mod:`growsim.env.ground`), the stand
(:mod:`growsim.env.stand`) and an optional tank
(:mod:`growsim.env.tank`). Models and objectives receive it as built; nothing copies it.

Shorthands kept from the first configs: ``light = 0.5`` is
``light.intensity = 0.5``, ``light_direction = [...]`` is ``light.direction``,
``water = 0.5`` is ``water.supply`` and ``gravity = 9.81`` is ``gravity.g``.

:meth:`Environment.segment_table` puts the passes side by side, one row per segment: the
light a segment receives, the load on its joint and the water it gets (what
``growsim grow --color`` and ``growsim show --color`` paint on a plant).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from pydantic import Field, model_validator

from growsim.env.gravity import Gravity
from growsim.env.ground import Ground
from growsim.env.light import Light
from growsim.env.stand import Stand
from growsim.env.tank import Tank
from growsim.env.water import Water
from growsim.options import Options
from growsim.skeleton import skeleton_arrays

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["SEGMENT_COLUMNS", "SHORTHANDS", "Environment", "expand_shorthands"]

#: shorthand key -> (table, key in the table)
SHORTHANDS = {
    "light": ("light", "intensity"),
    "light_direction": ("light", "direction"),
    "water": ("water", "supply"),
    "gravity": ("gravity", "g"),
}

#: the columns of :meth:`Environment.segment_table`, in order
SEGMENT_COLUMNS = ("kind", "light", "moment", "stress_ratio", "water", "water_met")


class Environment(Options):
    """``[environment]``: the world the phenotypes live in (light, gravity, water, ground,
    tank).

    Examples
    --------
    >>> env = Environment.model_validate({"light": 0.5, "water": {"supply": 0.25}})
    >>> env.light.intensity, env.light.direction, env.water.supply, env.gravity.g
    (0.5, [0.0, -1.0, 0.0], 0.25, 9.81)
    >>> env.tank is None
    True
    """

    light: Light = Field(default_factory=Light, description="the parallel light")
    gravity: Gravity = Field(default_factory=Gravity, description="gravity")
    water: Water = Field(default_factory=Water, description="water supply")
    ground: Ground = Field(default_factory=Ground, description="the soil surface")
    stand: Stand = Field(default_factory=Stand, description="the neighbours (default: alone)")
    tank: Tank | None = Field(None, description="a tank with obstacles (agents that swim)")

    @model_validator(mode="before")
    @classmethod
    def _shorthands(cls, data: Any) -> Any:
        return expand_shorthands(data)

    def segment_table(self, plant) -> pd.DataFrame:
        """The environment on each segment of ``plant``: a DataFrame, one row per segment
        (index ``segment``), with the columns of :data:`SEGMENT_COLUMNS`:

        - ``kind``: ``"stem"`` or ``"leaf"`` (a categorical; every segment is a stem when
          ``plant`` is a mapping without ``kind``);
        - ``light``: the light it receives, ``self.light.segment_light(plant)`` (the
          shadow map: 0 in the shade, up to ``light.intensity``);
        - ``moment`` (N m) and ``stress_ratio`` (bending stress over strength, ``>= 1``
          breaks; 0 for leaves) at its joint, from ``self.gravity.loads(plant)``;
        - ``water`` (received) and ``water_met`` (share of its demand met, 1 where it
          demands nothing) from ``self.water.transport(plant, light, g=self.gravity.g)``:
          the light above is the demand.

        ``plant`` is a :class:`growsim.phenotypes.plant.Plant` or a mapping of segment arrays
        (``start``, ``end``, ``radius``, ``parent``, optional ``kind``), parents first. One
        shadow map serves all its segments: plants put together with ``Plant.concat`` shade
        each other here (gravity and water still treat each root on its own). Bad arrays
        raise :class:`growsim.errors.UserInputError` from the pass that meets them.

        Examples
        --------
        >>> from growsim.models import honda
        >>> tree = honda.develop(honda.PRESETS["zelkova"])
        >>> side = Environment.model_validate({"light": {"direction": [1, 0, 0]}})
        >>> table = side.segment_table(tree)
        >>> list(table.columns) == list(SEGMENT_COLUMNS), len(table) == tree.n_segments
        (True, True)
        >>> leaves = table[table.kind == "leaf"]
        >>> bool(leaves.stress_ratio.eq(0).all()), bool(leaves.water_met.between(0, 1).all())
        (True, True)
        >>> x = (tree.start[:, 0] + tree.end[:, 0]) / 2   # light from -x: that side is brighter
        >>> bool(table.light[x < 0].mean() > table.light[x > 0].mean())
        True
        """

        arrays = skeleton_arrays(plant, "segment_table")
        n = arrays["start"].shape[0]
        kind = np.zeros(n, np.int8) if arrays["kind"] is None else arrays["kind"]
        light = np.asarray(self.light.segment_light(plant), dtype=np.float64)
        loads = self.gravity.loads(plant)
        flow = self.water.transport(plant, light, g=self.gravity.g)
        return pd.DataFrame(
            {
                "kind": pd.Categorical.from_codes(kind.astype(np.int64), ["stem", "leaf"]),
                "light": light,
                "moment": np.asarray(loads.moment, dtype=np.float64),
                "stress_ratio": np.asarray(loads.stress_ratio, dtype=np.float64),
                "water": np.asarray(flow.received, dtype=np.float64),
                "water_met": np.asarray(flow.met, dtype=np.float64),
            },
            index=pd.RangeIndex(n, name="segment"),
        )


def expand_shorthands(data: Any) -> Any:
    """``[environment]`` data with its shorthands written as tables (a new dict).

    Examples
    --------
    >>> expand_shorthands({"light": 0.5, "light_direction": [1, -1, 0], "water": 2})
    {'light': {'intensity': 0.5, 'direction': [1, -1, 0]}, 'water': {'supply': 2}}
    """
    if not isinstance(data, dict) or not any(k in data for k in SHORTHANDS):
        return data
    data = dict(data)
    for short, (table, key) in SHORTHANDS.items():
        if short not in data or (short == table and isinstance(data[short], dict)):
            continue
        value = data.pop(short)
        sub = data.get(table, {})
        if not isinstance(sub, dict):
            raise ValueError(f"{short}: shorthand for {table}.{key}, but {table} is set too")
        if key in sub:
            raise ValueError(f"{short}: given twice (also as {table}.{key})")
        data[table] = {**sub, key: value}
    return data
