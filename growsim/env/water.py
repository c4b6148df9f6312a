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
flux ``F = -K dH / L`` and the gravity term (0.0098 MPa per metre), and the proposed
two-pass tree transport, all from "Hormone-module growth: facts, formulas and a proposed
design" (``shared/research/hormone-model.md``, "Water"). ``resistance`` and ``lift`` are
per unit of the plant's own length (models' units are not metres): defaults
:data:`RESISTANCE` and :data:`LIFT`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from pydantic import Field

from growsim.errors import UserInputError
from growsim.options import Options

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


def _finite(name: str, arr: np.ndarray) -> None:
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.flatnonzero(bad.reshape(arr.shape[0], -1).any(1))[0])
        raise UserInputError(f"water: {name} of segment {i} is not finite")


def _arrays(plant) -> dict[str, np.ndarray]:
    """``start, end, radius, parent`` (and ``kind`` or ``None``) of a Plant or a mapping."""
    if isinstance(plant, Mapping):
        need = ("start", "end", "radius", "parent")
        missing = [k for k in need if k not in plant]
        if missing:
            raise UserInputError(f"water: segment arrays miss {missing} (need {list(need)})")
        get = plant.get
    else:
        get = lambda k: getattr(plant, k, None)  # noqa: E731
    shapes = {"start": (3,), "end": (3,), "radius": (), "parent": ()}
    out = {}
    for key in shapes:
        dtype = np.int64 if key == "parent" else np.float64
        try:
            out[key] = np.ascontiguousarray(get(key), dtype=dtype)
        except (TypeError, ValueError) as exc:
            msg = f"water: {key}: cannot convert to {np.dtype(dtype)} ({exc})"
            raise UserInputError(msg) from None
    n = out["start"].shape[0] if out["start"].ndim == 2 else -1
    for key, tail in shapes.items():
        if out[key].shape != (n, *tail):
            want = "(n" + "".join(f", {s}" for s in tail) + ")"
            raise UserInputError(f"water: {key}: expected shape {want}, got {out[key].shape}")
    kind = get("kind")
    out["kind"] = None if kind is None else np.asarray(kind)
    if out["kind"] is not None and out["kind"].shape != (n,):
        raise UserInputError(f"water: kind: expected shape (n,), got {out['kind'].shape}")
    for key in ("start", "end", "radius"):
        _finite(key, out[key])
    if n and out["radius"].min() < 0:
        raise UserInputError(
            f"water: radius of segment {int(np.argmin(out['radius']))} is negative"
        )
    bad = (out["parent"] < -1) | (out["parent"] >= np.arange(n))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise UserInputError(
            f"water: segment {i} has parent {int(out['parent'][i])}: parents must come "
            "before their children (parent[i] < i, -1 for a root)"
        )
    return out


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

    ``kind`` ``(n,)`` (:data:`growsim.plant.STEM` / :data:`~growsim.plant.LEAF`) or ``None``
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
    from growsim.plant import LEAF

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

    ``plant``: a :class:`growsim.plant.Plant` or a mapping with ``start``, ``end`` ``(n,
    3)``, ``radius``, ``parent`` ``(n,)`` and optionally ``kind`` (without it every segment
    demands by its light); parents must come before children. ``light`` ``(n,)`` the light
    each segment receives (e.g. leaf areas, or ones), ``>= 0``. ``supply`` the roots'
    water as a share of the demand. ``g`` scales the height term (pass
    ``env.gravity.g``).

    Examples
    --------
    >>> from growsim.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 2, 0], [-1, 2, 0]],
    ...                       [-1, 0, 0], [-1, 0, 1, 1], kind=[0, 1, 1])
    >>> w = transport(p, [0, 1, 1], 0.5, resistance=0, lift=0)
    >>> w.received.tolist(), w.met.tolist(), w.total
    ([0.0, 0.5, 0.5], [1.0, 0.5, 0.5], 1.0)
    >>> w = transport(p, [0, 1, 1], 1.0, lift=0.1)  # climbing costs water
    >>> w.met.round(3).tolist()
    [1.0, 0.812, 0.812]
    """
    from growsim.kernels.water import transport_kernel  # numba only when water flows

    arrs = _arrays(plant)
    n = arrs["start"].shape[0]
    light = np.ascontiguousarray(light, dtype=np.float64)
    if light.shape != (n,):
        raise UserInputError(f"water: light: expected shape ({n},), got {light.shape}")
    _finite("light", light)
    if n and light.min() < 0:
        raise UserInputError(f"water: light of segment {int(np.argmin(light))} is negative")
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
    """``[environment.water]``: water supply (1 = ample).

    ``supply`` is the water the roots offer as a share of what the plant pulls (1 = all of
    its demand, before the losses along the way); :meth:`transport` shares it out.

    Examples
    --------
    >>> Water(supply=0.5).supply
    0.5
    """

    supply: float = Field(1.0, ge=0.0, le=1e6, description="water supply (1 = ample)")

    def transport(self, plant, light, **kwargs) -> WaterFlow:
        """:func:`transport` with this table's ``supply``.

        Examples
        --------
        >>> from growsim.plant import Plant
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0], kind=[1])
        >>> Water(supply=0.0).transport(p, [1.0]).met.tolist()
        [0.0]
        """
        return transport(plant, light, self.supply, **kwargs)
