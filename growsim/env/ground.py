"""The ground: ``[environment.ground]``, the soil surface a plant stands on.

The soil is the horizontal plane ``y = height`` (y up); the default, 0, is the plant's
base (a plant grows from the origin). A model that knows the ground grows nothing below
it: the hormone model turns a module whose end would go under the soil up until the end
touches it (``docs/models/hormone.md``, "The ground"), so every measure of its plants
counts only what stands above. Renders of such plants draw the soil as a slab under them.
"""

from __future__ import annotations

from pydantic import Field

from growsim.options import Options

__all__ = ["Ground"]


class Ground(Options):
    """``[environment.ground]``: the soil surface, the plane ``y = height``.

    ``height`` is at most 0: the plant's base (the origin) stands on the soil or above
    it, never buried.

    Examples
    --------
    >>> Ground().height
    0.0
    >>> Ground.parse({"height": 1.0}, "ground.")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.ConfigError: ground.height: Input should be less than or equal to 0 (got 1.0)
    """

    height: float = Field(
        0.0,
        ge=-1e6,
        le=0.0,
        description="height of the soil surface (y up; 0 = the plant's base, which may not be "
        "buried); models with a ground (hormone) grow nothing below it",
    )
