"""Water: ``[environment.water]``, the supply the roots draw from.

Transport by negative pressure grows from here (the environment issue).
"""

from __future__ import annotations

from pydantic import Field

from growsim.options import Options

__all__ = ["Water"]


class Water(Options):
    """``[environment.water]``: water supply (1 = ample).

    Examples
    --------
    >>> Water(supply=0.5).supply
    0.5
    """

    supply: float = Field(1.0, ge=0.0, le=1e6, description="water supply (1 = ample)")
