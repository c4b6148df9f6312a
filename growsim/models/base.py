"""What every model publishes: its parameter spec, so the GA can evolve any parameter."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from growsim.errors import UserInputError


@dataclass(frozen=True)
class Param:
    """One model parameter: its name, range ``[low, high]``, kind and default.

    ``kind`` is ``"real"`` or ``"int"``. A GA-codable field: :func:`growsim.ga.genome_from_params`
    turns a list of them into a :class:`growsim.ga.Genome`.

    Examples
    --------
    >>> p = Param("f", 0.0, 1.0, default=0.95, doc="lateral nutrient ratio")
    >>> p.check(0.5)
    0.5
    """

    name: str
    low: float
    high: float
    default: float
    kind: Literal["real", "int"] = "real"
    doc: str = ""
    unit: str = ""

    def check(self, value, where: str = "") -> float:
        """Return ``value`` as a float (int-valued for ``kind="int"``) or raise
        :class:`UserInputError` naming the parameter and its range."""
        label = f"{where}{self.name}"
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise UserInputError(f"{label}: expected a number, got {value!r}")
        v = float(value)
        if not np.isfinite(v):
            raise UserInputError(f"{label}: {value!r} is not a finite number")
        if v < self.low or v > self.high:
            raise UserInputError(
                f"{label}: {value!r} is out of range [{self.low:g}, {self.high:g}]"
            )
        if self.kind == "int":
            if v != round(v):
                raise UserInputError(f"{label}: expected an integer, got {value!r}")
            v = float(round(v))
        return v


def resolve_params(
    spec: Sequence[Param], values: Mapping[str, float] | None = None, where: str = ""
) -> dict[str, float]:
    """Fill defaults from ``spec``, check every value, reject unknown names.

    Examples
    --------
    >>> spec = (Param("a", 0, 1, 0.5), Param("n", 1, 9, 3, kind="int"))
    >>> resolve_params(spec, {"n": 4})
    {'a': 0.5, 'n': 4.0}
    """
    by_name = {p.name: p for p in spec}
    values = dict(values or {})
    unknown = sorted(set(values) - set(by_name))
    if unknown:
        raise UserInputError(
            f"{where}unknown parameter(s) {', '.join(unknown)}; allowed: {', '.join(by_name)}"
        )
    return {p.name: p.check(values.get(p.name, p.default), where) for p in spec}
