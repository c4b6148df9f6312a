"""The environment: light, gravity, water and a tank, built from ``[environment]``.

- :mod:`growsim.env.environment`: :class:`Environment`, the whole table;
- :mod:`growsim.env.light`: :class:`Light`, orthographic projection and projected area
  of segment arrays (the shadow-map light grows here);
- :mod:`growsim.env.gravity`: :class:`Gravity` (loads, bending stress, breaking joints);
- :mod:`growsim.env.water`: :class:`Water` (transport by negative pressure: :func:`transport`);
- :mod:`growsim.env.ground`: :class:`Ground` (the soil surface);
- :mod:`growsim.env.stand`: :class:`Stand` (the neighbours: alone or an explicit stand);
- :mod:`growsim.env.tank`: :class:`Tank` and :class:`Obstacle`.

Examples
--------
>>> from growsim.env import Environment
>>> Environment().light.intensity
1.0
"""

from growsim.env.environment import Environment
from growsim.env.gravity import Gravity, Loads
from growsim.env.ground import Ground
from growsim.env.light import Light, projected_area, view_basis
from growsim.env.stand import Stand
from growsim.env.tank import Obstacle, Tank
from growsim.env.water import Water, WaterFlow, transport

__all__ = [
    "Environment",
    "Gravity",
    "Ground",
    "Light",
    "Loads",
    "Obstacle",
    "Stand",
    "Tank",
    "Water",
    "WaterFlow",
    "projected_area",
    "transport",
    "view_basis",
]
