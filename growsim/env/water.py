"""Water: ``[environment.water]`` and transport by negative pressure (the seed's model).

Each segment pulls water in proportion to the light it receives (the seed's "negative
pressure"); the pull of a segment's whole subtree is the sum of its children's; the
roots' water is shared down the tree in proportion to those sums, and each segment passes
on less than enters it: the pressure falls along thin, long paths that carry the pull of
many leaves, and with height. The equations (also in ``docs/environment.md``, "Water"):

- demand: ``d_i = light_i`` for leaves, ``d_i = stem_demand * L_i`` for stems (an upkeep
  per unit length, default 0); ``L_i`` the segment's length;
- subtree demand (child-to-parent pass): ``D_i = d_i + sum_{c child of i} D_c``;
- root inflow: ``F_r = supply * D_r`` (``supply`` is a share of the demand: 1 = as much as
  the plant pulls, before the losses on the way);
- a child ``c`` of ``i`` receives ``F_c = a_i D_c / D_i`` (parent-to-child pass), where
  ``a_i = F_i exp(-x_i)`` is what reaches ``i``'s far end;
- pressure drop along segment ``i`` (Hagen-Poiseuille flow through the pipe model's bundle
  of unit pipes: conductance ``~ r^2 / L``, driven by the subtree's pull ``D``; plus the
  gravity potential ``rho g dh``)::

      x_i = resistance * L_i * (D_i / r_i^2) / (D_r / r_r^2)
            + lift * (g / 9.81) * max(0, dy_i)

  the first term is ``L_i`` times the segment's demand per cross-section relative to its
  root's (``r`` the segment's radius, ``r_r`` the root segment's), so a tree that obeys
  the pipe model (cross-section proportional to the leaves above) loses ``resistance`` per
  unit length everywhere and a thin branch bearing many leaves loses more; a segment of
  radius 0 with demand beyond it passes nothing; going down costs nothing;
- received: ``w_i = min(d_i, a_i d_i / D_i)``; share met ``m_i = w_i / d_i`` (1 where
  ``d_i = 0``); water a segment cannot use (supply above 1) is lost, never passed on.

In closed form ``m_i = min(1, supply * exp(-s_i))`` with ``s_i`` the sum of ``x`` from
the root to ``i``: without losses (``resistance = lift = 0``) every segment gets
``min(1, supply)`` of its demand and the plant's total is ``min(1, supply) * sum(d)``;
with losses the total is less. Sources: the pipe model (Shinozaki et al. 1964), HydroShoot's
flux ``F = -K dH / L`` and the gravity term (0.0098 MPa per metre), and a two-pass tree
transport built on them (``docs/references.md``). ``resistance`` and ``lift`` are
per unit of the plant's own length (models' units are not metres): defaults
:data:`RESISTANCE` and :data:`LIFT`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pydantic import Field

from growsim.errors import UserInputError
from growsim.kernels.water import transport_kernel  # numba only when water flows
from growsim.options import Options
from growsim.skeleton import LEAF, checked_array, skeleton_arrays

__all__ = ["LIFT", "RESISTANCE", "Water", "WaterFlow", "segment_demand", "transport"]

#: default loss per unit length where the demand per cross-section is the root's (``x_i``).
RESISTANCE = 0.005
#: default loss per unit of height climbed at g = 9.81 (the gravity term of ``x_i``).
LIFT = 0.005


@dataclass(frozen=True)
class WaterFlow:
    """What :func:`transport` returns.

    ``received`` ``(n,)`` water kept by each segment (the demand's units); ``met`` ``(n,)``
    share of each segment's demand met, in ``[0, 1]`` (1 where the demand is 0: the share
    to limit photosynthesis with); ``total`` the plant's total water received.
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
    light,
    supply: float = 1.0,
    *,
    stem_demand: float = 0.0,
    resistance: float = RESISTANCE,
    lift: float = LIFT,
    g: float = 9.81,
) -> WaterFlow:
    """Water received by each segment of ``plant`` (see the module docstring's equations).

    ``plant``: a :class:`growsim.phenotypes.plant.Plant` or a mapping with ``start``, ``end`` ``(n,
    3)``, ``radius``, ``parent`` ``(n,)`` and optionally ``kind`` (without it every segment
    demands by its light); parents must come before children. ``light`` ``(n,)`` the light
    each segment receives (e.g. leaf areas, or ones), ``>= 0``. ``supply`` the roots'
    water as a share of the demand. ``g`` scales the height term (pass
    ``env.gravity.g``).

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 2, 0], [-1, 2, 0]],
    ...                       [-1, 0, 0], [-1, 0, 1, 1], kind=[0, 1, 1])
    >>> w = transport(p, [0, 1, 1], 0.5, resistance=0, lift=0)
    >>> w.received.tolist(), w.met.tolist(), w.total
    ([0.0, 0.5, 0.5], [1.0, 0.5, 0.5], 1.0)
    >>> w = transport(p, [0, 1, 1], 1.0, lift=0.1)  # climbing costs water
    >>> w.met.round(3).tolist()
    [1.0, 0.812, 0.812]
    """

    arrs = _arrays(plant)
    n = arrs["start"].shape[0]
    light = checked_array("water", "light", light, (), n)
    if n and light.min() < 0:
        raise UserInputError(f"water: light: segment {int(np.argmin(light))} is negative")
    supply = _nonneg("supply", supply)
    stem_demand = _nonneg("stem_demand", stem_demand)
    resistance = _nonneg("resistance", resistance)
    lift = _nonneg("lift", lift) * _nonneg("g", g) / 9.81
    if arrs["kind"] is not None and stem_demand > 0:
        length = np.linalg.norm(arrs["end"] - arrs["start"], axis=1)
    else:
        length = np.zeros(n)  # stems demand nothing
    demand = segment_demand(arrs["kind"], light, length, stem_demand)
    received, met = transport_kernel(
        arrs["start"],
        arrs["end"],
        arrs["radius"],
        arrs["parent"],
        np.ascontiguousarray(demand),
        supply,
        resistance,
        lift,
    )
    return WaterFlow(received, met, float(received.sum()))


class Water(Options):
    """``[environment.water]``: water supply (1 = ample) and the losses on the way.

    ``supply`` is the water the roots offer as a share of what the plant pulls (1 = all of
    its demand, before the losses along the way); ``resistance`` and ``lift`` are the
    pressure drops per unit length and per unit of height climbed, ``stem_demand`` the
    stems' upkeep per unit length (see the module's equations); :meth:`transport` shares
    the water out with them.

    Examples
    --------
    >>> Water(supply=0.5).supply
    0.5
    >>> Water(resistance=0.0, lift=0.0).lift
    0.0
    """

    supply: float = Field(1.0, ge=0.0, le=1e6, description="water supply (1 = ample)")
    resistance: float = Field(
        RESISTANCE, ge=0.0, le=1e6,
        description="pressure drop per unit length where the pull per cross-section is the root's",
    )  # fmt: skip
    lift: float = Field(
        LIFT, ge=0.0, le=1e6, description="pressure drop per unit of height climbed (at g = 9.81)"
    )
    stem_demand: float = Field(
        0.0, ge=0.0, le=1e6, description="water a stem demands per unit length (upkeep)"
    )

    def transport(self, plant, light, **kwargs) -> WaterFlow:
        """:func:`transport` with this table's ``supply``, ``resistance``, ``lift`` and
        ``stem_demand`` (keyword arguments override them; pass ``g=env.gravity.g``).

        Examples
        --------
        >>> from growsim.phenotypes.plant import Plant
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0], kind=[1])
        >>> Water(supply=0.0).transport(p, [1.0]).met.tolist()
        [0.0]
        """
        options = {
            "resistance": self.resistance,
            "lift": self.lift,
            "stem_demand": self.stem_demand,
            **kwargs,
        }
        return transport(plant, light, self.supply, **options)
