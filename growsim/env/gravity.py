"""Gravity: ``[environment.gravity]``, the weight that loads branches, and breaking.

:class:`Gravity` holds the acceleration ``g`` and the materials (wood density, modulus of
rupture, leaf mass per area). :meth:`Gravity.loads` computes, at the joint at the base of
every segment, the mass above it, the moment of that mass's weight and the bending stress
against the wood's strength; :meth:`Gravity.breaks` and :meth:`Gravity.first_breaks` say
whether (and where) a plant breaks. Units are SI with world units read as metres (mass
kg, moment N m, stress Pa) unless a model says otherwise. See ``docs/environment.md``
("Gravity") for the equations and the sources of the defaults.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from pydantic import Field

from growsim.errors import UserInputError
from growsim.kernels.gravity import first_break_kernel, loads_kernel
from growsim.options import Options
from growsim.skeleton import checked_array, skeleton_arrays
from growsim.skeleton import radius_end as radius_end_of

__all__ = ["Gravity", "Loads"]

#: default wood density, kg/m^3: the middle of fresh (green) wood's 600-1000 kg/m^3
#: (USDA Forest Products Laboratory, *Wood Handbook*)
WOOD_DENSITY = 800.0
#: default modulus of rupture, Pa: green white fir, 40 MPa, at the low end of green
#: woods' 34-80 MPa (USDA Forest Products Laboratory, *Wood Handbook*)
MODULUS_OF_RUPTURE = 40e6
#: default fresh leaf mass per area, kg/m^2 (an assumption of ours: dry leaf mass per area
#: spans 0.014-1.5 kg/m^2, Wright et al. 2004, *The worldwide leaf economics spectrum*)
LEAF_MASS_PER_AREA = 0.1


@dataclass(frozen=True)
class Loads:
    """Gravity loads at the joint at the base of every segment (SI units).

    ``mass`` ``(n,)`` kg: each segment's own mass; ``mass_above`` ``(n,)`` kg: the segment
    and all its descendants; ``moment`` ``(n,)`` N m: the moment of their weight about the
    segment's base; ``stress_ratio`` ``(n,)``: the bending stress ``moment / (pi r^3 / 4)``
    over the strength (a joint breaks at 1; leaves are not judged: 0); ``strength``
    ``(n,)`` or ``(1,)`` Pa: the strength the joints were judged against (``(1,)``: one
    for all); ``first_break``: the segment whose joint breaks first (the largest ratio
    ``>= 1``, the lowest index on a tie), or ``-1``.
    """

    mass: np.ndarray
    mass_above: np.ndarray
    moment: np.ndarray
    stress_ratio: np.ndarray
    strength: np.ndarray
    first_break: int

    @property
    def stress(self) -> np.ndarray:
        """``(n,)`` Pa: the bending stress at each joint (0 for leaves)."""
        return self.stress_ratio * self.strength

    @property
    def broken(self) -> bool:
        """``True`` when some joint's stress reaches its strength."""
        return self.first_break >= 0


class Gravity(Options):
    """``[environment.gravity]``: gravity (along -y) and the materials that resist it.

    Examples
    --------
    >>> Gravity().g, Gravity().density, Gravity().strength
    (9.81, 800.0, 40000000.0)
    """

    g: float = Field(9.81, ge=0.0, le=1e3, description="gravitational acceleration, m/s^2")
    density: float = Field(
        WOOD_DENSITY,
        gt=0.0,
        le=1e5,
        description="fresh wood density, kg/m^3 (stems: truncated cones of this density)",
    )
    strength: float = Field(
        MODULUS_OF_RUPTURE,
        gt=0.0,
        le=1e12,
        description="modulus of rupture of green wood, Pa (a joint breaks when its bending "
        "stress reaches it; a model's per-segment data['strength'] overrides it)",
    )
    leaf_mass_per_area: float = Field(
        LEAF_MASS_PER_AREA,
        ge=0.0,
        le=1e3,
        description="fresh leaf mass per area, kg/m^2 (a leaf is a blade of its length "
        "times twice its radius)",
    )

    def loads(self, skeleton: Any, *, strength=None) -> Loads:
        """The loads at every joint of ``skeleton``: a :class:`growsim.phenotypes.plant.Plant`, or a
        mapping of arrays ``start``, ``end`` ``(n, 3)``, ``radius``, ``parent`` and
        optionally ``kind`` (default all stems), ``radius_end`` (default: as
        :meth:`growsim.phenotypes.plant.Plant.radius_end`) and ``strength``.

        The per-segment strength is ``strength`` ``(n,)`` if given, else
        ``data["strength"]`` of a plant (or the mapping's ``strength``), else
        :attr:`strength`. Segments must be stored parents first (``parent[s] < s``).
        Several roots (plants put together with :meth:`growsim.phenotypes.plant.Plant.concat`) are
        loaded independently; ``first_break`` is then the worst joint of them all.

        Raises :class:`growsim.errors.UserInputError` for a non-finite coordinate or
        radius (naming the segment), a child stored before its parent, or a bad strength.

        Examples
        --------
        >>> import numpy as np
        >>> from growsim.phenotypes.plant import Plant
        >>> branch = Plant.from_points([[0, 0, 0], [2, 0, 0]], [-1], [-1, 0], radius=0.05)
        >>> out = Gravity(g=10.0, density=500.0).loads(branch)
        >>> m = 500.0 * np.pi * 0.05**2 * 2  # a cylinder's mass
        >>> bool(np.isclose(out.moment[0], m * 10.0 * 1.0))  # weight x half its length
        True
        >>> out.first_break, bool(out.stress_ratio[0] < 1)
        (-1, True)
        """
        a = _arrays(skeleton, strength, self.strength)
        return _loads(a, self)

    def breaks(self, skeleton: Any, *, strength=None) -> bool:
        """``True`` when some joint of ``skeleton`` breaks under its own weight (see
        :meth:`loads`).

        Examples
        --------
        >>> from growsim.phenotypes.plant import Plant
        >>> twig = Plant.from_points([[0, 0, 0], [6, 0, 0]], [-1], [-1, 0], radius=0.01)
        >>> Gravity().breaks(twig), Gravity(g=0.0).breaks(twig)
        (True, False)
        """
        return self.loads(skeleton, strength=strength).broken

    def first_breaks(self, skeletons: Sequence[Any]) -> np.ndarray:
        """``(k,)`` int64: for each of ``k`` skeletons (plants or mappings, as
        :meth:`loads`), the segment whose joint breaks first, counted within that
        skeleton, or ``-1``. One kernel call for them all (a population's plants).

        Examples
        --------
        >>> from growsim.phenotypes.plant import Plant
        >>> thin = Plant.from_points([[0, 0, 0], [6, 0, 0]], [-1], [-1, 0], radius=0.01)
        >>> thick = Plant.from_points([[0, 0, 0], [6, 0, 0]], [-1], [-1, 0], radius=0.1)
        >>> Gravity().first_breaks([thin, thick]).tolist()
        [0, -1]
        """
        parts = [_arrays(s, None, self.strength) for s in skeletons]
        if not parts:
            return np.zeros(0, np.int64)
        sizes = np.array([p["start"].shape[0] for p in parts], np.int64)
        offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        parents = [np.where(p["parent"] >= 0, p["parent"] + o, -1) for p, o in zip(parts, offsets)]
        merged = {
            k: np.concatenate([p[k] for p in parts])
            for k in parts[0]
            if k not in ("parent", "strength")
        }
        merged["parent"] = np.concatenate(parents)
        merged["strength"] = np.concatenate(
            [np.broadcast_to(p["strength"], (m,)) for p, m in zip(parts, sizes)]
        )
        ratio = _kernel(merged, self)[3]
        first = first_break_kernel(ratio, offsets)
        return np.where(first >= 0, first - offsets[:-1], -1)

    def first_break_step(self, steps: Iterable[Any]) -> tuple[int, int]:
        """``(step, segment)`` of the first joint to break while a plant grows step-wise:
        ``steps`` yields the plant after each step (a model's ``grow(...)``), and the first
        step whose plant breaks gives its :attr:`Loads.first_break`; ``(-1, -1)`` when the
        plant never breaks. Growth is read only up to the break.

        Examples
        --------
        >>> from growsim.phenotypes.plant import Plant
        >>> def grow():  # a branch that lengthens by 1 each step
        ...     for k in range(1, 9):
        ...         yield Plant.from_points([[0, 0, 0], [k, 0, 0]], [-1], [-1, 0], radius=0.01)
        >>> Gravity().first_break_step(grow())
        (5, 0)
        """
        for step, skeleton in enumerate(steps):
            first = self.loads(skeleton).first_break
            if first >= 0:
                return step, first
        return -1, -1


def _kernel(a: dict, gravity: Gravity) -> np.ndarray:
    """``(4, n)``: mass, mass above, moment, stress ratio (see ``loads_kernel``)."""
    return loads_kernel(
        a["start"],
        a["end"],
        a["radius"],
        a["radius_end"],
        a["parent"],
        a["kind"],
        a["strength"],
        (float(gravity.density), float(gravity.leaf_mass_per_area), float(gravity.g)),
        np.empty((4, a["start"].shape[0])),
    )


def _loads(a: dict, gravity: Gravity) -> Loads:
    out = _kernel(a, gravity)
    n = out.shape[1]
    first = int(first_break_kernel(out[3], np.array([0, n], np.int64))[0])
    return Loads(out[0], out[1], out[2], out[3], a["strength"], first)


def _arrays(skeleton: Any, strength, default_strength: float) -> dict[str, np.ndarray]:
    """Validated kernel inputs from a Plant or a mapping of arrays."""
    a = skeleton_arrays(skeleton, "gravity")
    start, end, radius, parent, data = a["start"], a["end"], a["radius"], a["parent"], a["data"]
    n = start.shape[0]
    kind = np.zeros(n, np.int8) if a["kind"] is None else a["kind"]
    if "radius_end" in data:
        radius_end = checked_array("gravity", "radius_end", data["radius_end"], (), n)
    else:
        radius_end = radius_end_of(parent, kind, radius)
    if strength is None:
        strength = data.get("strength")
    if strength is None:
        strength_arr = np.array([float(default_strength)])
    else:
        strength_arr = checked_array("gravity", "strength", strength, (), n)
        if n and not np.all(strength_arr > 0):
            i = int(np.flatnonzero(~(strength_arr > 0))[0])
            raise UserInputError(f"gravity: strength: segment {i} is not positive")
        if n == 0:
            strength_arr = np.array([float(default_strength)])
    return {
        "start": start,
        "end": end,
        "radius": radius,
        "radius_end": radius_end,
        "parent": parent,
        "kind": kind,
        "strength": strength_arr,
    }
