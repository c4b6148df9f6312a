"""The stand: ``[environment.stand]``, the neighbours a plant grows among.

``mode`` says what the neighbours are:

- ``"alone"`` (the default): the plant grows alone under its own shadow map, as before;
- ``"explicit"``: every position holds a plant; they grow together step by step, share one
  light (they shade each other every step) and each has its own water
  (:func:`growsim.models.hormone.grow_stand`);
- ``"periodic"``: one focal plant in an endless monoculture of its own copies at
  ``spacing`` (a square lattice; ``rings`` rings of copies around it shade it every
  step: :func:`growsim.models.hormone.grow_periodic`);
- ``"mixture"``: the focal plant grown with ``neighbours`` plants of other genomes on the
  lattice cells nearest it at ``spacing`` (a 3 x 3 block for 8 in 3D; a row in 2D), all
  grown together; in an experiment the neighbours are drawn from the population being
  evaluated, ``draws`` draws a generation, the same for every individual (common random
  numbers: :meth:`growsim.experiment.fitness.Fitness.prepare`), and the score is the mean
  over the draws (:func:`growsim.models.hormone.grow_mixture`).

Positions are on the ground, ``[x, z]`` pairs (in 2D ``z`` is 0): ``layout = "grid"``
(``rows`` x ``cols`` at ``spacing``), ``"row"`` (``count`` at ``spacing`` along x),
``"random"`` (``count`` plants uniformly in a square holding them at ``density`` plants per
m2, ``seed``) or ``positions = [[x, z], ...]`` given. Grids and rows are centred on the
origin. No two plants stand closer than ``min_distance``; none further than ``reach`` from
the origin (the shadow map spans the whole stand: too wide a stand leaves each plant a few
pixels).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from growsim.errors import ConfigError
from growsim.kernels.stand import nearest_shifts
from growsim.options import Options

__all__ = ["MODES", "Stand"]

#: the stand's modes
MODES = ("alone", "explicit", "periodic", "mixture")


class Stand(Options):
    """``[environment.stand]``: the plants' positions and what the neighbours are.

    Examples
    --------
    >>> Stand().mode, Stand().n_plants
    ('alone', 1)
    >>> s = Stand.parse({"mode": "explicit", "layout": "grid", "rows": 2, "cols": 2,
    ...                  "spacing": 1.0})
    >>> s.xz().tolist()
    [[-0.5, -0.5], [0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]]
    >>> s.ground_area()
    4.0
    >>> Stand.parse({"mode": "explicit", "spacing": 0.0}, "stand.")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.ConfigError: stand.spacing: Input should be greater than 0 (got 0.0)
    """

    mode: Literal["alone", "periodic", "mixture", "explicit"] = Field(
        "alone",
        description="alone (one plant, the default), explicit (every position a plant, "
        "grown together), periodic (the plant among its own copies at spacing), mixture "
        "(the plant among neighbours drawn from the population)",
    )
    layout: Literal["grid", "row", "random", "positions"] = Field(
        "grid", description="how the positions are laid out (positions: given)"
    )
    rows: int = Field(3, ge=1, le=100, description="grid: rows (along z)")
    cols: int = Field(3, ge=1, le=100, description="grid: columns (along x)")
    count: int = Field(5, ge=1, le=10000, description="row and random: number of plants")
    spacing: float = Field(1.0, gt=0.0, le=1e3, description="grid and row: distance (m)")
    density: float = Field(1.0, gt=0.0, le=1e4, description="random: plants per m2")
    seed: int = Field(0, ge=0, description="random: seed of the positions")
    positions: list[list[float]] | None = Field(
        None, description="given positions [[x, z], ...] (sets layout to positions)"
    )
    min_distance: float = Field(
        0.05, ge=0.0, le=1e3, description="closest two plants may stand (m)"
    )
    rings: int = Field(
        2, ge=1, le=5, description="periodic: rings of copies around the focal plant"
    )
    neighbours: int = Field(
        8, ge=1, le=48, description="mixture: neighbours around the focal plant"
    )
    draws: int = Field(
        2, ge=1, le=64, description="mixture: draws of neighbours a generation (scores averaged)"
    )
    reach: float = Field(
        1000.0, gt=0.0, le=1e5, description="furthest a plant may stand from the origin"
    )

    @model_validator(mode="after")
    def _check(self):

        if self.positions is not None:
            bad = [p for p in self.positions if len(p) != 2]
            if bad or not self.positions:
                raise ConfigError("positions: give [[x, z], ...], two numbers each")
            if self.layout not in ("grid", "positions"):
                raise ConfigError("positions: given with layout = "
                                  f"{self.layout!r}; drop one")  # fmt: skip
        xz = self.xz()
        far = np.hypot(xz[:, 0], xz[:, 1])
        if len(xz) and far.max() > self.reach:
            key = "positions" if self.positions is not None else "spacing"
            raise ConfigError(
                f"{key}: a plant at {far.max():.3g} m from the origin is beyond "
                f"reach = {self.reach:g} m (the shadow map's reach)"
            )
        if len(xz) > 1:
            d = np.hypot(*(xz[:, None, :] - xz[None, :, :]).transpose(2, 0, 1))
            d[np.diag_indices(len(xz))] = np.inf
            if d.min() < self.min_distance:
                key = {"positions": "positions", "random": "density"}.get(
                    "positions" if self.positions is not None else self.layout, "spacing"
                )
                raise ConfigError(
                    f"{key}: two plants {d.min():.3g} m apart, closer than "
                    f"min_distance = {self.min_distance:g} m (overlapping plants)"
                )
        return self

    @property
    def n_plants(self) -> int:
        """Plants in the stand (1 when ``mode = "alone"``).

        Examples
        --------
        >>> Stand.parse({"mode": "explicit", "layout": "row", "count": 4}).n_plants
        4
        """
        if self.mode == "mixture":
            return self.neighbours + 1
        return 1 if self.mode in ("alone", "periodic") else len(self.xz())

    def xz(self) -> np.ndarray:
        """``(N, 2)`` the plants' positions ``[x, z]`` on the ground (``[[0, 0]]`` when
        alone or periodic: one focal plant).

        Examples
        --------
        >>> Stand.parse({"mode": "explicit", "layout": "row", "count": 3,
        ...              "spacing": 2.0}).xz().tolist()
        [[-2.0, 0.0], [0.0, 0.0], [2.0, 0.0]]
        """
        if self.mode in ("alone", "periodic"):
            return np.zeros((1, 2))
        if self.mode == "mixture":  # the focal plant first, its neighbours nearest first
            return self.mixture_xz(3)
        if self.positions is not None:
            return np.asarray(self.positions, dtype=np.float64).reshape(-1, 2)
        s = self.spacing
        if self.layout == "row":
            x = (np.arange(self.count) - (self.count - 1) / 2) * s
            return np.stack([x, np.zeros(self.count)], axis=1)
        if self.layout == "random":
            side = math.sqrt(self.count / self.density)
            rng = np.random.default_rng(self.seed)
            return (rng.random((self.count, 2)) - 0.5) * side
        x = (np.arange(self.cols) - (self.cols - 1) / 2) * s
        z = (np.arange(self.rows) - (self.rows - 1) / 2) * s
        zz, xx = np.meshgrid(z, x, indexing="ij")
        return np.stack([xx.ravel(), zz.ravel()], axis=1)

    def mixture_xz(self, dims: int) -> np.ndarray:
        """``(neighbours + 1, 2)`` a mixture's positions ``[x, z]``: the focal plant at the
        origin, then its neighbours on the lattice cells of ``spacing`` nearest it (ring by
        ring; on the x axis in 2D, ``dims = 2``).

        Examples
        --------
        >>> Stand.parse({"mode": "mixture", "neighbours": 2, "spacing": 1.5}).mixture_xz(2).tolist()
        [[0.0, 0.0], [-1.5, 0.0], [1.5, 0.0]]
        """

        shifts = nearest_shifts(self.spacing, self.neighbours, dims)
        return np.vstack([np.zeros((1, 2)), shifts[:, [0, 2]]])

    def ground_area(self) -> float:
        """The ground the stand covers (m2), for the leaf area index: each plant's cell,
        ``spacing`` squared, in a grid; ``count / density`` at random; in a row or given
        positions the plants' bounding box widened by ``spacing`` (``min_distance`` at
        least).

        Examples
        --------
        >>> Stand.parse({"mode": "explicit", "layout": "random", "count": 8,
        ...              "density": 2.0}).ground_area()
        4.0
        """
        if self.positions is None and self.layout == "grid":
            return self.rows * self.cols * self.spacing**2
        if self.positions is None and self.layout == "random":
            return self.count / self.density
        xz = self.xz()
        pad = max(self.spacing, self.min_distance)
        return float(np.prod(xz.max(axis=0) - xz.min(axis=0) + pad))
