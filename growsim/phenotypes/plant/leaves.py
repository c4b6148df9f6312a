"""The light a plant's leaves receive from a shadow-map light (:func:`leaf_light`): the
one home of the sum ``Plant.measures(env)["light_captured"]`` and the light objective
(:mod:`growsim.objectives.light`) share.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from growsim.skeleton import LEAF

__all__ = ["LeafLight", "leaf_light"]


class LeafLight(NamedTuple):
    """What :func:`leaf_light` returns: the leaves' light and their blade area."""

    #: ``sum_i A_i R(L_i)`` over the LEAF segments (world units^2 x light)
    light: float
    #: ``sum_i A_i``: the leaves' blade area (world units^2)
    area: float


def leaf_light(plant, light, response=None, shifts=None, judged=None) -> LeafLight:
    """The light a plant's leaves (a :class:`~growsim.phenotypes.plant.Plant`) receive from
    a shadow-map light, weighted by blade area.

    ``light`` is a :class:`growsim.env.Light` (``environment.light``, or a copy with other
    fields); each segment's light ``L_i`` is :meth:`growsim.env.Light.segment_light` of the
    whole plant (stems and leaves cast shadows, leaves shade leaves). A LEAF segment is a
    blade of its length times twice its radius, ``A_i = 2 r_i len_i`` (as gravity's leaf
    mass). Returns :class:`LeafLight` ``(light, area)``::

        light = sum_leaves A_i R(L_i)        area = sum_leaves A_i

    with ``R`` the ``response`` (a function of an array of light values; default
    ``R(L) = L``). The one home of this sum: ``Plant.measures(env)["light_captured"]`` and
    the light objective (:mod:`growsim.objectives.light`) both use it. A plant without
    leaves gives ``(0.0, 0.0)``. ``shifts`` ``(k, 3)``: the plant is also shaded by its
    copies moved by these offsets (a periodic stand; :meth:`growsim.env.Light.segment_light`).
    ``judged`` ``(n,)`` bool: only these segments' leaves are summed, every segment casting
    shadows (a mixture's focal tree among its neighbours).

    Examples
    --------
    >>> from growsim.env import Light
    >>> from growsim.phenotypes.plant import STEM, Plant
    >>> leaves = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 1, 0]], [-1, 0], [-1, 0, 1],
    ...                            radius=0.25, kind=[STEM, LEAF])
    >>> leaf_light(leaves, Light())  # one level blade 1 x 0.5 in full light
    LeafLight(light=0.5, area=0.5)
    >>> leaf_light(leaves, Light(intensity=0.5), response=lambda L: 2 * L).light
    0.5
    """
    sel = plant.kind == LEAF
    if judged is not None:
        sel &= np.asarray(judged, dtype=bool)
    if not sel.any():
        return LeafLight(0.0, 0.0)
    extra = {} if shifts is None else {"shifts": shifts}
    lit = light.segment_light(plant, **extra)
    received = np.asarray(lit, dtype=np.float64)[sel]
    area = 2.0 * plant.radius[sel] * plant.lengths()[sel]
    if response is not None:
        received = np.asarray(response(received), dtype=np.float64)
    return LeafLight(float(area @ received), float(area.sum()))
