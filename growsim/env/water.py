"""Water: ``[environment.water]``, a fixed soil supply shared by path conductance.

The soil offers a plant a fixed amount of water a step, ``supply * soil`` (``supply`` 1 =
ample, ``soil`` the ample soil's water in kg a step), which its segments share by their
path conductance: water is a resource, and a plant with more leaves does not get more of
it. The equations (also in ``docs/environment.md``, "Water"):

- demand: ``d_i`` given per segment (the hormone model: the transpiration of its leaves,
  following the light they absorb and their area; :func:`segment_demand`: the light of a
  leaf, ``stem_demand * L_i`` of a stem), kg a step;
- path resistance from the soil to the far end of segment ``i`` (parent to child; the
  roots' own resistance is 1)::

      x_i = x_parent + resistance * L_i * (1 cm^2 / (pi r_i^2)) + lift * (g / 9.81) * max(0, dy_i)

  sapwood conducts by its cross-section (the pipe model's bundle of pipes: conductance
  ``~ pi r^2 / L``), so ``resistance`` is what a metre of stem of 1 cm^2 adds to the
  roots' resistance, and climbing costs ``lift`` a metre (the gravity potential); a stem of
  radius 0 passes nothing;
- path conductance ``k_i = 1 / (1 + x_i)``;
- sharing by water filling: ``w_i = d_i min(1, lam k_i)``, one level ``lam`` per plant such
  that the plant receives ``min(S, sum of d)`` (``S = supply * soil``): the most conductive
  segments are met first, and water a segment does not need goes to the others;
- share met ``m_i = w_i / d_i`` (1 where ``d_i = 0``).

So water received never exceeds the supply, doubling every demand (twice the leaf area)
brings no more water once the supply binds, and thin, long, high paths get less when the
plant is short of water. Sources: Shinozaki et al., *A quantitative analysis of plant
form: the pipe model theory* (sapwood as a bundle of pipes); Tyree and Ewers, *The
hydraulic architecture of trees and other woody plants* (conductance of a path of
segments, sapwood area per leaf area); the gravity term (0.0098 MPa per metre), as in
"Hormone-module growth: facts, formulas and a proposed design"
(``shared/research/hormone-model.md``, "Water"). Defaults :data:`SOIL`,
:data:`RESISTANCE`, :data:`LIFT`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydantic import Field

from growsim.errors import UserInputError
from growsim.kernels.water import transport_kernel  # numba only when water flows
from growsim.options import Options
from growsim.skeleton import LEAF, checked_array, skeleton_arrays

__all__ = ["LIFT", "RESISTANCE", "SOIL", "Water", "WaterFlow", "segment_demand", "transport"]

#: default water of the ample soil, kg a step (a week): about what 10 m^2 of leaves in
#: full light transpire (the hormone model's ``transpiration``, 10 kg per m^2 a week)
SOIL = 20.0
#: default path resistance a metre of stem of 1 cm^2 cross-section adds to the roots' (1)
RESISTANCE = 0.1
#: default path resistance a metre climbed adds (at g = 9.81): 0.0098 MPa of a soil-to-leaf
#: drop of about 1 MPa
LIFT = 0.01


@dataclass(frozen=True)
class WaterFlow:
    """What :func:`transport` returns.

    ``received`` ``(n,)`` water kept by each segment (the demand's units); ``met`` ``(n,)``
    share of each segment's demand met, in ``[0, 1]`` (1 where the demand is 0: the share
    to limit photosynthesis with); ``total`` the plant's total water received (at most
    the supply, per root).
    """

    received: np.ndarray
    met: np.ndarray
    total: float


def _arrays(plant) -> dict[str, np.ndarray]:
    """``start, end, radius, parent`` (and ``kind`` or ``None``) of a Plant or a mapping."""
    return skeleton_arrays(plant, "water")


def _nonneg(name: str, value: float) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise UserInputError(f"water: {name} must be a number, got {value!r}") from None
    if not np.isfinite(value) or value < 0:
        raise UserInputError(f"water: {name} must be finite and >= 0, got {value}")
    return value


def segment_demand(kind, light, length, stem_demand: float = 0.0) -> np.ndarray:
    """``(n,)`` demand: ``light`` for leaves, ``stem_demand * length`` for stems.

    ``kind`` ``(n,)`` (:data:`growsim.phenotypes.plant.STEM` /
    :data:`~growsim.phenotypes.plant.LEAF`) or ``None``
    (every segment demands by its light).

    Examples
    --------
    >>> segment_demand([0, 1, 1], [5.0, 1.0, 2.0], [2.0, 1.0, 1.0], stem_demand=0.1).tolist()
    [0.2, 1.0, 2.0]
    """
    light = np.asarray(light, dtype=np.float64)
    length = np.asarray(length, dtype=np.float64)
    if kind is None:
        return light.copy()

    return np.where(np.asarray(kind) == LEAF, light, float(stem_demand) * length)


def transport(
    plant,
    demand,
    supply: float = 1.0,
    *,
    soil: float = SOIL,
    stem_demand: float = 0.0,
    resistance: float = RESISTANCE,
    lift: float = LIFT,
    g: float = 9.81,
) -> WaterFlow:
    """Water received by each segment of ``plant`` (see the module docstring's equations).

    ``plant``: a :class:`growsim.phenotypes.plant.Plant` or a mapping with ``start``, ``end`` ``(n,
    3)``, ``radius``, ``parent`` ``(n,)`` and optionally ``kind`` (without it every segment
    demands ``demand``); parents must come before children. ``demand`` ``(n,)`` each leaf's
    demand, ``>= 0`` (e.g. its light, or its transpiration in kg a step). Each root draws
    ``supply * soil``. ``g`` scales the height term (pass ``env.gravity.g``).

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 2, 0], [-1, 2, 0]],
    ...                       [-1, 0, 0], [-1, 0, 1, 1], kind=[0, 1, 1])
    >>> w = transport(p, [0, 1, 1], 0.5, soil=1.0, resistance=0, lift=0)
    >>> w.received.tolist(), w.met.tolist(), w.total
    ([0.0, 0.25, 0.25], [1.0, 0.25, 0.25], 0.5)
    >>> w = transport(p, [0, 2, 2], 0.5, soil=1.0, resistance=0, lift=0)  # twice the demand
    >>> w.total                                                            # the same water
    0.5
    """

    arrs = _arrays(plant)
    n = arrs["start"].shape[0]
    demand = checked_array("water", "demand", demand, (), n)
    if n and demand.min() < 0:
        raise UserInputError(f"water: demand: segment {int(np.argmin(demand))} is negative")
    water = _nonneg("supply", supply) * _nonneg("soil", soil)
    stem_demand = _nonneg("stem_demand", stem_demand)
    resistance = _nonneg("resistance", resistance)
    lift = _nonneg("lift", lift) * _nonneg("g", g) / 9.81
    if arrs["kind"] is not None and stem_demand > 0:
        length = np.linalg.norm(arrs["end"] - arrs["start"], axis=1)
    else:
        length = np.zeros(n)  # stems demand nothing
    d = segment_demand(arrs["kind"], demand, length, stem_demand)
    received, met = transport_kernel(
        arrs["start"],
        arrs["end"],
        arrs["radius"],
        arrs["parent"],
        np.ascontiguousarray(d),
        water,
        resistance,
        lift,
    )
    return WaterFlow(received, met, float(received.sum()))


class Water(Options):
    """``[environment.water]``: the soil's water and the resistances on the way.

    ``supply`` is the soil's water as a share of the ample soil's (1 = ample, 0.5 = half
    the water); ``soil`` the ample soil's water in kg a step: a plant draws ``supply *
    soil`` a step, shared by its segments' path conductance (``resistance`` a metre of
    stem of 1 cm^2 adds, ``lift`` a metre climbed adds; see the module's equations);
    ``stem_demand`` the stems' own demand per metre. The hormone model's ``paper``
    physics reads ``supply`` alone, as the share of every module's pull met (the paper's
    negative pressure, ``docs/models/hormone.md``).

    Examples
    --------
    >>> Water(supply=0.5).supply
    0.5
    >>> Water(resistance=0.0, lift=0.0).lift
    0.0
    """

    supply: float = Field(
        1.0, ge=0.0, le=1e6,
        description="the soil's water as a share of the ample soil's (1 = ample)",
    )  # fmt: skip
    soil: float = Field(
        SOIL, ge=0.0, le=1e9,
        description="water the ample soil offers a plant, kg a step (a plant draws supply x soil)",
    )  # fmt: skip
    resistance: float = Field(
        RESISTANCE, ge=0.0, le=1e6,
        description="path resistance a metre of stem of 1 cm^2 cross-section adds (the roots': 1)",
    )  # fmt: skip
    lift: float = Field(
        LIFT, ge=0.0, le=1e6, description="path resistance a metre climbed adds (at g = 9.81)"
    )
    stem_demand: float = Field(
        0.0, ge=0.0, le=1e6, description="water a stem demands per metre (upkeep)"
    )

    def transport(self, plant, demand, **kwargs) -> WaterFlow:
        """:func:`transport` with this table's ``supply``, ``soil``, ``resistance``,
        ``lift`` and ``stem_demand`` (keyword arguments override them; pass
        ``g=env.gravity.g``).

        Examples
        --------
        >>> from growsim.phenotypes.plant import Plant
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0], kind=[1])
        >>> Water(supply=0.0).transport(p, [1.0]).met.tolist()
        [0.0]
        """
        options = {
            "soil": self.soil,
            "resistance": self.resistance,
            "lift": self.lift,
            "stem_demand": self.stem_demand,
            **kwargs,
        }
        supply = options.pop("supply", self.supply)
        return transport(plant, demand, supply, **options)
