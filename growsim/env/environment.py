"""The environment a phenotype grows (or swims) in: ``[environment]`` of a config.

:class:`Environment` gathers the parts, each a frozen table with its own module: light
(:mod:`growsim.env.light`), gravity (:mod:`growsim.env.gravity`), water
(:mod:`growsim.env.water`) and an optional tank (:mod:`growsim.env.tank`). Models and
objectives receive it as built; nothing copies it.

Shorthands kept from the first configs: ``light = 0.5`` is
``light.intensity = 0.5``, ``light_direction = [...]`` is ``light.direction``,
``water = 0.5`` is ``water.supply`` and ``gravity = 9.81`` is ``gravity.g``.
"""

from __future__ import annotations

from typing import Any

from pydantic import Field, model_validator

from growsim.env.gravity import Gravity
from growsim.env.light import Light
from growsim.env.tank import Tank
from growsim.env.water import Water
from growsim.options import Options

__all__ = ["SHORTHANDS", "Environment", "expand_shorthands"]

#: shorthand key -> (table, key in the table)
SHORTHANDS = {
    "light": ("light", "intensity"),
    "light_direction": ("light", "direction"),
    "water": ("water", "supply"),
    "gravity": ("gravity", "g"),
}


class Environment(Options):
    """``[environment]``: the world the phenotypes live in (light, gravity, water, tank).

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
    tank: Tank | None = Field(None, description="a tank with obstacles (agents that swim)")

    @model_validator(mode="before")
    @classmethod
    def _shorthands(cls, data: Any) -> Any:
        return expand_shorthands(data)


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
