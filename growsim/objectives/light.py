"""Light the leaves receive from the environment's light, for the least wood.

The default measure (``shading = "shadow-map"``) is the light each leaf receives from the
environment's shadow-map light, so leaves and stems above a leaf shade it (self-shading),
weighted by the leaf's area and passed through a light response, minus what the wood
costs::

    score = sum_leaves A_i R(L_i) - wood_cost * V_wood

- ``A_i = 2 r_i len_i``: the blade area of leaf ``i`` (a LEAF segment is a blade of its
  length times twice its radius, as gravity's leaf mass uses; world units^2);
- ``L_i``: the light leaf ``i`` receives, :meth:`growsim.env.Light.segment_light` of the
  environment's light (``[environment.light]``: direct light with hard or soft shadows
  plus the ``diffuse`` sky share, Lambert's cosine) over the whole plant, with the
  objective's ``direction``, ``intensity`` and ``resolution`` in place of the
  environment's where given. The map is an orthographic z-buffer along the light, as
  PlantGL's directional interception (*PlantGL: a Python-based geometric library for 3D
  plant modelling at different scales*) computes a shape's light from its visible pixels;
- ``R``: the light response. ``"linear"`` (default), ``R(L) = L``; ``"saturating"``, the
  rectangular hyperbola ``P = Pmax L / (L + K)`` scaled so that a leaf in full light
  counts its area, ``R(1) = 1``::

      R(L) = L (1 + K) / (L + K)        K = half_saturation > 0

  ``R(0) = 0``, ``R`` rises and is concave, ``R(L) >= L`` on ``[0, 1]`` (equal at 0 and
  1) and ``R(L) <= L`` above 1; the smaller ``K``, the sooner leaves saturate (at
  ``L = K`` a leaf gives ``(1 + K) / 2`` of its full-light value). With a linear
  response and binary shadows one flat layer of leaves is best at every light level;
  with saturation, upper leaves in full light give little more than half-lit ones, so a
  crown of several layers can pay (Horn, *The adaptive geometry of trees*;
  ``docs/references.md``);
- ``V_wood``: :meth:`growsim.phenotypes.plant.Plant.wood_volume` (world units^3, the stem tubes).

The sum ``sum_i A_i R(L_i)`` is :func:`growsim.phenotypes.plant.leaf_light` (its linear form is the
plant's ``light_captured`` measure). Terms: ``light`` (the sum), ``leaf_area``
(``sum_i A_i``) and ``wood_volume``.

In a stand (``[environment.stand]``, ``docs/models/stand.md``) the shadow-map score is
the plant's among its neighbours:

- ``mode = "periodic"``: the plant (the focal one) is shaded by its own copies at the
  lattice offsets :func:`growsim.kernels.stand.periodic_shifts` (``spacing``, ``rings``;
  on the x-z plane, or along x for a plant whose ``params`` say ``dims = 2``); the copies
  cast shadows, only the plant's own leaves are judged, and the wood is the plant's;
- ``mode = "explicit"``: the stand is scored, as the hormone model's explicit stand is (its
  nutrient is the stand's): a copy of the plant at every position of
  :meth:`growsim.env.stand.Stand.xz` (one genome; a model that does not grow plants
  together places them), all in one shadow map, every tree's leaves judged, shaded by
  all; ``light``, ``leaf_area`` and ``wood_volume`` are the stand's sums. A phenotype that
  is a stand already (``data["plant"]``, the hormone model's) is scored as it is;
- ``mode = "mixture"``: the phenotype is the focal tree carrying its neighbours (other
  genomes drawn from the population, ``meta["neighbours"]``:
  :func:`growsim.models.honda.mixture`); :func:`mixture_stand` joins them into one
  shadow map, only the focal tree's leaves are judged (shaded by itself and them) and
  the wood is its own. A phenotype carrying neighbours is scored among them whatever
  the stand; one without them in a mixture is refused (:class:`ConfigError`).

One shadow map per light spans the whole stand (the plant and its copies). So that each
crown keeps its ``resolution`` pixels across, as alone, the map gets
:func:`stand_resolution` pixels: ``resolution x (1 + lattice / crown)``, ``crown`` the
tree's width across the light and ``lattice`` what the copies add to it (about ``2 rings
spacing``, or the positions' spread), rounded up to 2^k or 1.5 x 2^k (few shadow-map
scratches are kept) and at most 4096. A map of ``resolution`` pixels over the whole stand
would leave a tree a few pixels at wide spacings, and coarse maps let more light through
(+56 % for a zelkova in a periodic stand 100 m apart at 64 pixels:
``benchmarks/log/stand.md``), a bias the GA could exploit. ``shading = "projection"`` has
no stand and is refused with one.

``shading = "projection"`` is the measure this objective used before the shadow-map
light, kept so old configs can reproduce old results (linear response only)::

    score = intensity * A_leaf(d) - wood_cost * V_wood

with ``A_leaf(d)`` the area of the leaves' orthographic shadow along ``d``
(:meth:`growsim.phenotypes.plant.Plant.leaf_area` at ``resolution``: overlapping leaves count once);
terms ``light`` (``intensity * A_leaf(d)``), ``leaf_area`` (``A_leaf(d)``) and
``wood_volume``. An old config gives its old results with ``shading = "projection"`` and
its old ``resolution`` (then 128 by default).

This follows the light-capture term of Ochoa's fitness (as used by Liu & Zhang, "IFS
plant populations evolved by a GA with a weighted fitness": the more light, the better)
with a wood cost in place of the paper's stability term, and Honda's model ("Tree
branching by nutrient allocation") as the plant that grows it. ``wood_cost`` has units of
light x area per volume: at the default 0.02, a unit^3 of wood must bring 0.02 unit^2 of
fully lit leaf more to pay for itself.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from growsim.env.light import Direction, Intensity, view_basis
from growsim.errors import ConfigError
from growsim.kernels.stand import periodic_shifts
from growsim.objectives.base import Objective, ObjectiveOptions
from growsim.phenotypes.plant import Plant, leaf_light
from growsim.phenotypes.stand import ground_offsets, place

__all__ = [
    "LightObjective", "LightOptions", "mixture_stand", "saturating_response", "stand_resolution",
]  # fmt: skip

#: the finest shadow map a stand gets (pixels across)
STAND_RESOLUTION_MAX = 4096


def stand_resolution(resolution: int, crown: float, lattice: float) -> int:
    """Pixels across a stand's shadow map that keep ``resolution`` pixels across a crown
    ``crown`` wide in a stand whose positions spread ``lattice`` (same units): ``resolution
    x (1 + lattice / crown)`` rounded up to the next ``2^k`` or ``1.5 x 2^k``, at least
    ``resolution`` and at most 4096 (``STAND_RESOLUTION_MAX``).

    Examples
    --------
    >>> stand_resolution(64, 40.0, 0.0), stand_resolution(64, 40.0, 80.0)
    (64, 192)
    >>> stand_resolution(64, 40.0, 100.0), stand_resolution(512, 1.0, 1e3)
    (256, 4096)
    """
    want = resolution * (1.0 + max(lattice, 0.0) / crown) if crown > 0 else resolution
    if want <= resolution:
        return int(resolution)
    step = 2 ** int(np.floor(np.log2(want)))
    for size in (step, 1.5 * step, 2 * step):
        if size >= want - 1e-9:
            return int(min(STAND_RESOLUTION_MAX, size))
    return STAND_RESOLUTION_MAX


def mixture_stand(plant):
    """The stand a mixture phenotype stands in: ``plant`` (the focal tree, at the origin)
    joined with the neighbours it carries (``meta["neighbours"]``, one plant's arrays
    placed at their positions with ``plant`` their position index, as
    :func:`growsim.models.honda.mixture` attaches them) into one
    :class:`growsim.phenotypes.plant.Plant` whose ``data["plant"]`` is 0 on the focal
    tree's segments; ``meta["stand"]`` the positions. The focal tree first, so its
    segments keep their indices.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.models import honda
    >>> env = Environment.parse({"stand": {"mode": "mixture", "neighbours": 2,
    ...                                    "spacing": 30.0}})
    >>> t = honda.mixture(honda.PRESETS["zelkova"], None, env=env)
    >>> s = mixture_stand(t)
    >>> s.n_segments == 3 * t.n_segments, np.bincount(s.data["plant"]).tolist()
    (True, [407, 407, 407])
    """

    nb = plant.meta["neighbours"]
    others = Plant(*(np.asarray(nb[k]) for k in ("start", "end", "radius", "parent")),
                   np.asarray(nb["order"]), np.asarray(nb["kind"]))  # fmt: skip
    joined = Plant.concat([plant.subset(np.ones(plant.n_segments, bool)), others])
    which = np.concatenate([np.zeros(plant.n_segments, np.int64), np.asarray(nb["plant"])])
    meta = {k: v for k, v in plant.meta.items() if k != "neighbours"}
    return Plant(joined.start, joined.end, joined.radius, joined.parent, joined.order,
                 joined.kind, {"plant": which}, meta)  # fmt: skip


def saturating_response(light, half_saturation: float):
    """The saturating light response ``R(L) = L (1 + K) / (L + K)``, ``K =
    half_saturation > 0``: a rectangular hyperbola with ``R(0) = 0`` and ``R(1) = 1``.
    ``light`` is a number or an array (``>= 0``); returns the same shape.

    Examples
    --------
    >>> import numpy as np
    >>> saturating_response(np.array([0.0, 0.5, 1.0, 2.0]), 0.5).round(3).tolist()
    [0.0, 0.75, 1.0, 1.2]
    """
    k = float(half_saturation)
    return light * (1.0 + k) / (light + k)


class LightOptions(ObjectiveOptions):
    """Options of the ``light`` objective."""

    kind: Literal["light"] = Field("light", description="the objective: light")
    shading: Literal["shadow-map", "projection"] = Field(
        "shadow-map",
        description="'shadow-map': sum of leaf blade area x response(light received), "
        "environment.light's shadow map; 'projection': intensity x area of the leaves' "
        "shadow (the measure before the shadow map)",
    )
    response: Literal["linear", "saturating"] = Field(
        "linear",
        description="light response R(L) of a leaf: 'linear' L, or 'saturating' "
        "L (1 + K) / (L + K) (R(1) = 1); shadow-map only",
    )
    half_saturation: float = Field(
        0.5,
        gt=0.0,
        le=1e6,
        description="K of the saturating response: the light at which a leaf gives "
        "(1 + K) / 2 of its full-light value",
    )
    direction: Direction | None = Field(
        None, description="direction the light travels (y up); default environment.light.direction"
    )
    intensity: Intensity | None = Field(
        None, description="light intensity; default environment.light.intensity"
    )
    wood_cost: float = Field(0.02, ge=0.0, le=1e9, description="cost per unit^3 of wood")
    resolution: int | None = Field(
        None,
        ge=16,
        le=4096,
        description="raster size (pixels across the plant) of the shadow map or projection; "
        "default environment.light.resolution",
    )

    @model_validator(mode="after")
    def _response_needs_shadow_map(self):
        if self.response != "linear" and self.shading == "projection":
            raise ValueError(
                f"response = {self.response!r} needs shading = 'shadow-map' (the projection "
                "has no light per leaf)"
            )
        return self


class LightObjective(Objective):
    """Light the leaves receive (shadow map, light response) minus a cost per unit of wood
    (maximised).

    Options (:class:`LightOptions`): ``shading`` (``"shadow-map"``, default, or
    ``"projection"``), ``response`` (``"linear"``, default, or ``"saturating"``),
    ``half_saturation`` (``K > 0``, default 0.5), ``direction`` (3 floats, the direction
    the light travels, y up), ``intensity`` and ``resolution`` (16..4096; each defaults to
    ``environment.light``'s), ``wood_cost`` (per unit^3 of wood, >= 0, default 0.02). The
    formulas: :mod:`growsim.objectives.light`. With ``[environment.stand]`` it scores the
    plant among its copies (``periodic``), the stand of copies (``explicit``) or the
    focal tree among the neighbours it carries (``mixture``): :meth:`scored`.

    Examples
    --------
    >>> obj = LightObjective(wood_cost=0.0)
    >>> obj.name, obj.maximize
    ('light', True)
    >>> from growsim.models import get_model
    >>> plant = get_model("honda").develop(get_model("honda").preset("zelkova"))
    >>> t = obj.terms(plant)
    >>> sorted(t), bool(0 < t["light"] < t["leaf_area"]), obj(plant) == t["light"]
    (['leaf_area', 'light', 'wood_volume'], True, True)
    >>> sat = LightObjective(wood_cost=0.0, response="saturating", half_saturation=0.2)
    >>> bool(sat(plant) >= obj(plant))  # every leaf's light is <= 1: R(L) >= L
    True

    In a periodic stand of its copies 20 m apart the tree gets less light:

    >>> from growsim.env import Environment
    >>> env = Environment.parse({"light": {"resolution": 512},
    ...                          "stand": {"mode": "periodic", "spacing": 20.0}})
    >>> bool(LightObjective(env=env, wood_cost=0.0)(plant) < obj(plant))
    True
    """

    name = "light"
    maximize = True
    accepts = ("plant",)
    Options = LightOptions
    example: ClassVar[dict[str, Any]] = {"wood_cost": 0.5, "resolution": 64}

    def setup(self) -> None:
        o = self.options
        env_light = self.env.light
        self.direction = tuple(float(x) for x in (o.direction or env_light.direction))
        self.intensity = float(env_light.intensity if o.intensity is None else o.intensity)
        self.resolution = int(env_light.resolution if o.resolution is None else o.resolution)
        self.wood_cost = o.wood_cost
        self.shading = o.shading
        self.half_saturation = float(o.half_saturation)
        update = {
            key: value
            for key, value in (
                ("direction", o.direction),
                ("intensity", o.intensity),
                ("resolution", o.resolution),
            )
            if value is not None
        }
        #: the light the leaves receive: the environment's, with this objective's overrides
        self.light = env_light.model_copy(update=update) if update else env_light
        stand = self.env.stand
        #: the stand the plant is scored in (None: alone)
        self.stand = None if stand.mode == "alone" else stand
        if self.stand is not None and self.shading == "projection":
            raise ConfigError(
                f"objective light: shading = 'projection' cannot score a plant in a stand "
                f"(environment.stand.mode = {stand.mode!r}); use shading = 'shadow-map'"
            )

    def scored(self, plant):
        """``(plant, shifts, light)``: what :meth:`terms` scores in the environment's
        stand, and the light it is lit by. Alone: the plant, ``None`` and :attr:`light`;
        ``"periodic"``: the plant and its copies' offsets ``(k, 3)``; ``"explicit"``: the
        stand of copies of the plant at the stand's positions (one
        :class:`growsim.phenotypes.plant.Plant`, ``data["plant"]`` each segment's tree)
        and ``None``; a mixture phenotype (``meta["neighbours"]``): the stand of the focal
        tree and its neighbours (:func:`mixture_stand`, the focal tree ``plant == 0``) and
        ``None``. In a stand the light has :func:`stand_resolution` pixels (the crown
        keeps its ``resolution``; in a mixture, the focal crown over the whole stand's
        extent); a stand phenotype (grown together) is scored as it is, by :attr:`light`.

        Examples
        --------
        >>> from growsim.env import Environment
        >>> from growsim.phenotypes.plant import Plant
        >>> one = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0], radius=0.5)
        >>> env = Environment.parse({"stand": {"mode": "periodic", "spacing": 2.0,
        ...                                    "rings": 1}})
        >>> _, shifts, light = LightObjective(env=env).scored(one)
        >>> shifts.shape, light.resolution  # a crown 1 wide, copies 4 across: 64 x 5 -> 384
        ((8, 3), 384)
        >>> env = Environment.parse({"stand": {"mode": "explicit", "layout": "row",
        ...                                    "count": 3}})
        >>> stand, _, _ = LightObjective(env=env).scored(one)
        >>> stand.n_segments, stand.data["plant"].tolist()
        (3, [0, 1, 2])
        >>> from growsim.models import honda
        >>> env = Environment.parse({"stand": {"mode": "mixture", "neighbours": 8,
        ...                                    "spacing": 20.0}})
        >>> tree = honda.mixture(honda.PRESETS["zelkova"], None, env=env)
        >>> stand, _, light = LightObjective(env=env).scored(tree)
        >>> stand.n_segments == 9 * tree.n_segments, light.resolution
        (True, 128)
        """
        if "neighbours" in plant.meta:  # a mixture: the focal tree among its neighbours
            stand = mixture_stand(plant)
            return stand, None, self._stand_light(plant, None, stand)
        if self.stand is None or "plant" in plant.data:  # alone, or a stand already
            return plant, None, self.light
        if self.stand.mode == "mixture":
            raise ConfigError(
                f"objective light: environment.stand.mode = 'mixture': the phenotype "
                f"(model {plant.meta.get('model', '?')!r}) carries no neighbours to be "
                "scored among (a model whose mixture attaches them: honda)"
            )
        if self.stand.mode == "periodic":
            dims = int(plant.meta.get("params", {}).get("dims", 3))
            shifts = periodic_shifts(self.stand.spacing, self.stand.rings, dims)
            return plant, shifts, self._stand_light(plant, shifts)

        xz = self.stand.xz()
        return place(plant, xz), None, self._stand_light(plant, ground_offsets(xz))

    def _stand_light(self, plant, moves, stand=None):
        """:attr:`light` with :func:`stand_resolution` pixels for ``plant`` (one crown)
        moved by each row of ``moves`` ``(k, 3)`` (or, given ``stand``, the plants of a
        mixture: ``plant`` keeps its pixels in the map spanning ``stand``): the crown's
        and the stand's widths as the map of the light's direction frames them (the
        larger of their extents across it, widened by the largest radius)."""

        if plant.n_segments == 0:
            return self.light
        ends = np.concatenate([plant.start, plant.end])
        rim = 2.0 * float(plant.radius.max())
        across = view_basis(self.light.direction)
        crown = max(float(np.ptp(ends @ a)) for a in across) + rim
        if stand is None:
            stand = max(float(np.ptp(ends @ a) + np.ptp(moves @ a)) for a in across) + rim
        else:
            every = np.concatenate([stand.start, stand.end])
            rim = max(rim, 2.0 * float(stand.radius.max()))
            stand = max(float(np.ptp(every @ a)) for a in across) + rim
        res = stand_resolution(self.light.resolution, crown, stand - crown)
        if res == self.light.resolution:
            return self.light
        return self.light.model_copy(update={"resolution": res})

    def respond(self, light: np.ndarray) -> np.ndarray:
        """The response ``R`` applied to an array of leaf light values (see the module).

        Examples
        --------
        >>> import numpy as np
        >>> L = np.array([0.0, 0.25, 1.0])
        >>> LightObjective().respond(L).tolist()
        [0.0, 0.25, 1.0]
        >>> LightObjective(response="saturating", half_saturation=0.25).respond(L).tolist()
        [0.0, 0.625, 1.0]
        """
        if self.options.response == "saturating":
            return saturating_response(light, self.half_saturation)
        return light

    def terms(self, plant) -> dict[str, float]:
        """The terms of the score: ``light`` (``sum A_i R(L_i)``, or ``intensity x A_leaf``
        for the projection), ``leaf_area`` (blade area, or the leaves' shadow for the
        projection) and ``wood_volume``; in a stand, of what :meth:`scored` gives (the
        plant among its copies, or the explicit stand's sums).

        Examples
        --------
        >>> from growsim.phenotypes.plant import LEAF, STEM, Plant
        >>> plant = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 1, 0]], [-1, 0], [-1, 0, 1],
        ...                           radius=0.25, kind=[STEM, LEAF])
        >>> LightObjective(intensity=0.5).terms(plant)["light"]  # a blade 1 x 0.5, lit
        0.25
        """
        if self.shading == "projection":
            area = float(plant.leaf_area(self.direction, resolution=self.resolution))
            light = self.intensity * area
        else:
            focal = plant
            plant, shifts, lit = self.scored(plant)
            if "neighbours" in focal.meta:  # a mixture: the focal tree's leaves and wood
                judged = plant.data["plant"] == 0
                light, area = leaf_light(plant, lit, self.respond, judged=judged)
                plant = focal
            elif shifts is None:
                light, area = leaf_light(plant, lit, self.respond)
            else:
                light, area = leaf_light(plant, lit, self.respond, shifts=shifts)
        return {"light": light, "leaf_area": area, "wood_volume": float(plant.wood_volume())}

    def __call__(self, plant) -> float:
        t = self.terms(plant)
        return t["light"] - self.wood_cost * t["wood_volume"]
