"""Gravity: ``[environment.gravity]``, the acceleration that loads branches.

Torque at joints and breaking grow from here (the environment issue).
"""

from __future__ import annotations

from pydantic import Field

from growsim.options import Options

__all__ = ["Gravity"]


class Gravity(Options):
    """``[environment.gravity]``: gravitational acceleration (along -y).

    Examples
    --------
    >>> Gravity().g
    9.81
    """

    g: float = Field(9.81, ge=0.0, le=1e3, description="gravitational acceleration, m/s^2")
