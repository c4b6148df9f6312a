"""The collage score of an IFS code against a picture (Barnsley's collage theorem).

The collage theorem (M. Barnsley, *Fractals Everywhere*, 1988): if the union of the
images of a set ``G`` under the maps, ``W(G) = W_1(G) u ... u W_N(G)``, is close to ``G``,
then the attractor ``A`` of the maps is close to ``G``:
``h(G, A) <= h(G, W(G)) / (1 - s)`` (``h`` the Hausdorff distance, ``s`` the largest
contraction). So a code can be judged on the target itself, map by map, without drawing
its attractor: each map must send the picture into the picture, and together they must
cover it. This is the usual fitness of evolutionary solutions to the inverse IFS problem
(e.g. Nettleton & Garigliano, *Evolutionary algorithms and a fractal inverse problem*,
BioSystems 1994), and it is smooth where the silhouette NCC of the attractor is flat.

Score: ``NCC(W(G), G)`` on binary rasters (:func:`growsim.kernels.views.ncc`), ``G`` the
target's 2D view (as the silhouette objective reads it, ``views = "front"``). The world
coordinates of ``G``'s pixels are those of the candidate's own 2D view (its framing:
:meth:`growsim.phenotypes.attractor.Attractor.framing`), so ``W(G)`` is ``G`` moved by the code
as the
code's attractor would be; each target pixel is sampled at ``samples x samples`` points.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field

from growsim.kernels.ifs2d import points_raster
from growsim.kernels.views import MARGIN, frame_view, ncc
from growsim.objectives.base import Objective, ObjectiveOptions
from growsim.objectives.silhouette import SilhouetteObjective

__all__ = ["CollageObjective", "CollageOptions", "collage"]


def collage(target, maps, framing, samples: int = 3) -> np.ndarray:
    """``W(G)``: the union of the maps' images of the binary view ``target`` ``(S, S)``,
    as a binary ``(S, S)`` view.

    ``maps`` ``(N, 6)`` rows ``a b c d e f``; ``framing`` ``(base_x, y_min, scale)`` of the
    view (:meth:`growsim.phenotypes.attractor.Attractor.framing`): pixel ``(col, row)`` is the world
    point ``x = base_x + (col - S/2) / scale``, ``y = y_min + (S - 0.5 - row) / scale``.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.zeros((8, 8), np.uint8); g[:, 4] = 1  # a stick of height 8 / scale
    >>> w = collage(g, [[0, 0, 0, 0.5, 0, 0]], (0.0, 0.0, 1.0), samples=1)  # the lower half
    >>> w[:, 4].tolist()
    [0, 0, 0, 0, 1, 1, 1, 1]
    """

    target = np.asarray(target) != 0
    S = target.shape[0]
    bx, y0, k = (float(v) for v in framing)
    rows, cols = np.nonzero(target)
    off = (np.arange(samples) + 0.5) / samples
    du, dv = np.meshgrid(off, off)
    col = (cols[:, None] + du.reshape(1, -1)).reshape(-1)
    row = (rows[:, None] + dv.reshape(1, -1)).reshape(-1)
    x = bx + (col - 0.5 * S) / k
    y = y0 + ((S - MARGIN) - row) / k
    maps = np.asarray(maps, dtype=np.float64).reshape(-1, 6)
    xs = (maps[:, 0:1] * x + maps[:, 1:2] * y + maps[:, 4:5]).reshape(-1)
    ys = (maps[:, 2:3] * x + maps[:, 3:4] * y + maps[:, 5:6]).reshape(-1)
    c, r = frame_view(xs, ys, bx, y0, k, S)
    return points_raster(c, r, (S, S))


class CollageOptions(ObjectiveOptions):
    """Options of the ``collage`` objective: the target (as the silhouette objective's,
    one view) and the sampling."""

    kind: Literal["collage"] = Field("collage", description="the objective: collage")
    front: str | None = Field(None, description="the picture (path)")
    segmentation: Literal["threshold", "photo"] = Field(
        "threshold", description="picture to silhouette: 'threshold' or 'photo'"
    )
    target_model: str | None = Field(None, description="render the target from this model")
    target_preset: str | None = Field(None, description="preset of target_model")
    target_params: dict[str, float] | None = Field(
        None, description="parameters of target_model (over the preset)"
    )
    size: int = Field(64, ge=8, le=1024, description="raster size in pixels")
    samples: int = Field(3, ge=1, le=8, description="samples per target pixel, per axis")


class CollageObjective(Objective):
    """The collage score of a 2D IFS code against a picture (maximised, in [0, 1]).

    ``NCC(W(G), G)``: see the module docstring.

    Examples
    --------
    >>> from growsim.models import ifs2d
    >>> obj = CollageObjective(target_model="ifs2d", target_preset="fern")
    >>> round(obj(ifs2d.develop(ifs2d.PRESETS["fern"])), 2) > 0.9
    True
    """

    name = "collage"
    maximize = True
    accepts = ("points2d",)
    Options = CollageOptions
    example: ClassVar[dict[str, Any]] = {"target_model": "ifs2d", "target_preset": "fern"}

    def setup(self) -> None:

        o = self.options
        keys = {"front", "target_model", "target_preset", "target_params", "size"}
        values = o.model_dump(include=keys, exclude_none=True)
        if o.front is not None:
            values["segmentation"] = o.segmentation
        # the target as the silhouette objective reads it (one view), one home for that
        self.target = SilhouetteObjective(views="front", env=self.env, **values).target[0]

    def __call__(self, phenotype) -> float:
        w = collage(self.target, phenotype.maps, phenotype.framing(self.target.shape[0]),
                    self.options.samples)  # fmt: skip
        return ncc(w[None], self.target[None])
