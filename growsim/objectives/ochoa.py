"""Ochoa's weighted fitness of a plant's 2D picture (Liu & Zhang, after G. Ochoa, "On genetic
algorithms and Lindenmayer systems", PPSN V, LNCS 1498, 1998).

Four terms, each in ``[0, 1]``, read off the plant's 2D view (:func:`plane_view`: an
attractor's raster, or a plant skeleton's front view, x right and y up), and their
weighted mean

    F = (a w_a + b w_b + c w_c + d w_d) / (w_a + w_b + w_c + w_d)

- ``a``, **phototropism**: ``min(1, H / height)``: the plant's height ``H`` (world units)
  over the option ``height`` (the height that scores 1);
- ``b``, **light capture**: the share of the light crossing the view that the plant
  intercepts, with ``[environment.light]``: ``min(1, I sum_k w_k n_k / L_k)`` over the
  light's directions ``(d_k, w_k)`` (:meth:`growsim.env.light.Light.directions`: the
  beam, and the sky's when ``diffuse > 0``) taken in the view's plane, ``n_k`` the plant's
  shadow across ``d_k`` in one-pixel bins and ``L_k = S |u_y| + S |u_x|`` the raster's
  (:func:`growsim.kernels.ochoa.shadow_bins`). From straight above it is the share of the
  raster's columns the plant occupies: the 2D form of :meth:`Light.captured` (intensity x
  projected area), divided by the frame's;
- ``c``, **structural stability**: ``1 - m / n``: ``n`` branching points of the view's
  skeleton, ``m`` of them with at least ``many_branches`` branches (1 when ``n = 0``);
  the skeleton is ``skimage.morphology.skeletonize`` of the view with spurs shorter than
  ``prune`` pixels removed (:mod:`growsim.kernels.ochoa`);
- ``d``, **symmetry**: ``min(L, R) / max(L, R)``: ``L``, ``R`` the distances from the
  main stem (the vertical through the stem base, the view's centre column) to the
  leftmost and rightmost ink (1 when both are 0).

The view is framed without regard to size (the stem base on the centre column and the
bottom row, one scale fitting the height or the half-width about the base: as the
silhouette objective's views), so only ``a`` depends on the plant's absolute size.
A species is a named set of the four weights (:data:`SPECIES`, option ``species``);
``weights`` overrides some of them.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field, field_validator, model_validator

from growsim.env.light import Light
from growsim.errors import UserInputError
from growsim.kernels.ochoa import junctions, prune_kernel, shadow_bins
from growsim.objectives.base import Objective, ObjectiveOptions
from growsim.objectives.silhouette import plant_views

__all__ = [
    "SPECIES",
    "TERMS",
    "OchoaObjective",
    "OchoaOptions",
    "ochoa_terms",
    "plane_view",
]

#: the four terms, in the paper's order (a, b, c, d)
TERMS = ("phototropism", "light", "stability", "symmetry")

#: Named species: weights of the four terms. ``tree_one`` and ``tree_two`` are growsim's
#: weights for the paper's two fractal trees (its text gives none): the first values
#: stability and light most, the second light and height.
SPECIES: dict[str, dict[str, float]] = {
    "balanced": {"phototropism": 1.0, "light": 1.0, "stability": 1.0, "symmetry": 1.0},
    "tree_one": {"phototropism": 1.0, "light": 2.0, "stability": 2.0, "symmetry": 1.0},
    "tree_two": {"phototropism": 2.0, "light": 2.0, "stability": 1.0, "symmetry": 1.0},
    "tall": {"phototropism": 3.0, "light": 1.0, "stability": 1.0, "symmetry": 0.5},
    "spreading": {"phototropism": 0.5, "light": 3.0, "stability": 1.0, "symmetry": 1.0},
}


def plane_view(phenotype, size: int = 128) -> tuple[np.ndarray, float]:
    """The 2D view ``(size, size)`` uint8 of a phenotype and its height (world units).

    A phenotype with the ``"front_view"`` capability (an
    :class:`growsim.phenotypes.attractor.Attractor`) gives its own; a
    :class:`growsim.phenotypes.plant.Plant` gives its skeleton's front view (the x-y plane,
    thin lines: :func:`growsim.objectives.silhouette.plant_views`). Both are framed alike:
    the stem base on the centre column and the bottom row.

    Examples
    --------
    >>> from growsim.models import honda
    >>> img, h = plane_view(honda.develop(honda.PRESETS["zelkova"]), 64)
    >>> img.shape, int(img[63, 32]), h > 0
    ((64, 64), 1, True)
    """
    if "front_view" in phenotype.capabilities:
        view = phenotype.front_view(int(size))
        return np.asarray(view, dtype=np.uint8), float(phenotype.height())
    if phenotype.phenotype == "plant":
        return plant_views(phenotype, int(size))[0], float(phenotype.height())
    raise UserInputError(
        f"ochoa: a {type(phenotype).__name__} has no 2D view (an attractor or a plant has)"
    )


def _plane_directions(light) -> list[tuple[float, float, float]]:
    """``(ux, uy, weight)`` of the light's directions in the view's plane (x, y); a
    direction along z (none in the plane) counts as from above."""
    dirs, weights = light.directions()
    out = []
    for d, w in zip(dirs, weights):
        if w == 0.0:
            continue
        n = float(np.hypot(d[0], d[1]))
        ux, uy = (0.0, -1.0) if n < 1e-9 else (float(d[0] / n), float(d[1] / n))
        out.append((ux, uy, float(w)))
    return out


def ochoa_terms(
    img, height: float, *, light=None, height_ref: float = 10.0, many: int = 4, prune: int = 2
) -> dict[str, float]:
    """The four terms of a 2D view ``img`` ``(S, S)`` (stem base on column ``S // 2``)
    and the counts behind them (see the module docstring for the formulas).

    ``height``: the plant's height (world units); ``light``: a
    :class:`growsim.env.light.Light` (default: from above, intensity 1). Returns
    ``phototropism``, ``light``, ``stability``, ``symmetry`` and ``branch_points``,
    ``many_branch_points``, ``shadow_bins``, ``left``, ``right`` (pixels).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((9, 9), np.uint8); img[:, 4] = 1; img[2, 1:8] = 1  # a cross
    >>> t = ochoa_terms(img, 5.0, prune=0)
    >>> t["phototropism"], round(t["light"], 3), t["stability"], t["symmetry"]
    (0.5, 0.778, 0.0, 1.0)
    """
    from skimage.morphology import skeletonize

    img = np.ascontiguousarray(np.asarray(img) != 0, dtype=np.uint8)
    if img.ndim != 2 or img.shape[0] != img.shape[1]:
        raise UserInputError(f"ochoa: a view is a square raster, got shape {img.shape}")
    S = img.shape[0]
    light = Light() if light is None else light
    a = min(1.0, max(float(height), 0.0) / float(height_ref))
    b = 0.0
    bins_main = 0
    for k, (ux, uy, w) in enumerate(_plane_directions(light)):
        n, frame = shadow_bins(img, (ux, uy))
        bins_main = n if k == 0 else bins_main
        b += w * n / frame
    b = min(1.0, float(light.intensity) * b)
    skel = np.ascontiguousarray(skeletonize(img.astype(bool)), dtype=np.uint8)
    if prune > 0:
        prune_kernel(skel, int(prune))
    n_points, n_many = junctions(skel, int(many))
    c = 1.0 if n_points == 0 else 1.0 - n_many / n_points
    cols = np.flatnonzero(img.any(axis=0))
    centre = S // 2 + 0.5
    left = right = 0.0
    if cols.size:
        left = max(0.0, centre - (cols[0] + 0.5))
        right = max(0.0, (cols[-1] + 0.5) - centre)
    hi = max(left, right)
    d = 1.0 if hi == 0.0 else min(left, right) / hi
    return {
        "phototropism": float(a),
        "light": float(b),
        "stability": float(c),
        "symmetry": float(d),
        "branch_points": float(n_points),
        "many_branch_points": float(n_many),
        "shadow_bins": float(bins_main),
        "left": float(left),
        "right": float(right),
    }


class OchoaOptions(ObjectiveOptions):
    """Options of the ``ochoa`` objective: the species' weights and how the terms are read."""

    kind: Literal["ochoa"] = Field("ochoa", description="the objective: ochoa")
    species: str = Field(
        "balanced", description=f"named weights of the four terms: {', '.join(SPECIES)}"
    )
    weights: dict[str, float] | None = Field(
        None,
        description="weights over the species' (keys phototropism, light, stability, "
        "symmetry; >= 0, not all 0)",
    )
    height: float = Field(
        10.0, gt=0.0, le=1e9, description="phototropism: the height (world units) scoring 1"
    )
    size: int = Field(128, ge=16, le=1024, description="raster size of the 2D view, pixels")
    many_branches: int = Field(
        4, ge=3, le=8, description="stability: a branching point with at least this many "
        "branches (the one it grows from counts) is unstable",
    )  # fmt: skip
    prune: int = Field(
        2, ge=0, le=64, description="stability: skeleton spurs up to this many pixels are "
        "ignored",
    )  # fmt: skip

    @field_validator("species")
    @classmethod
    def _known_species(cls, v):
        if v not in SPECIES:
            raise ValueError(f"unknown species {v!r}; available: {', '.join(SPECIES)}")
        return v

    @field_validator("weights")
    @classmethod
    def _check_weights(cls, v):
        if v is None:
            return v
        unknown = sorted(set(v) - set(TERMS))
        if unknown:
            raise ValueError(f"unknown term(s) {', '.join(unknown)}; allowed: {', '.join(TERMS)}")
        if any(not np.isfinite(w) or w < 0 for w in v.values()):
            raise ValueError(f"weights must be finite and >= 0, got {v}")
        return v

    @model_validator(mode="after")
    def _some_weight(self):
        if sum(self.term_weights().values()) <= 0.0:
            raise ValueError("weights: at least one term needs a weight > 0")
        return self

    def term_weights(self) -> dict[str, float]:
        """The four weights: the species', then ``weights`` over them."""
        return {**SPECIES[self.species], **(self.weights or {})}


class OchoaObjective(Objective):
    """Ochoa's weighted fitness of a plant's 2D picture (maximised, in [0, 1]).

    See the module docstring for the four terms; :meth:`terms` reports them (and the
    counts behind them) for the best individual. Scores attractors (``points2d``) and
    plants (their front view).

    Examples
    --------
    >>> from growsim.models import ifs2d
    >>> obj = OchoaObjective(species="tree_one", height=2.0)
    >>> plant = ifs2d.develop(ifs2d.PRESETS["tree"])
    >>> t = obj.terms(plant)
    >>> sorted(k for k in t if k in TERMS), 0.0 <= obj(plant) <= 1.0
    (['light', 'phototropism', 'stability', 'symmetry'], True)
    """

    name = "ochoa"
    maximize = True
    accepts = ("points2d", "plant")
    Options = OchoaOptions
    example: ClassVar[dict[str, Any]] = {"species": "tree_one", "height": 2.0, "size": 64}

    def setup(self) -> None:
        w = self.options.term_weights()
        self.weights = np.array([w[t] for t in TERMS], dtype=np.float64)

    def terms(self, phenotype) -> dict[str, float]:
        """The four terms and their counts (see :func:`ochoa_terms`)."""
        o = self.options
        img, height = plane_view(phenotype, o.size)
        return ochoa_terms(
            img, height, light=self.env.light, height_ref=o.height, many=o.many_branches,
            prune=o.prune,
        )  # fmt: skip

    def score(self, terms: dict[str, float]) -> float:
        """``F``: the weighted mean of the four terms of ``terms``."""
        v = np.array([terms[t] for t in TERMS])
        return float(v @ self.weights / self.weights.sum())

    def __call__(self, phenotype) -> float:
        return self.score(self.terms(phenotype))
