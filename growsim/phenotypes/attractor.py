"""An attractor: the 2D point cloud an IFSP code draws (Liu & Zhang), as a phenotype
(:mod:`growsim.phenotypes`, kind ``"points2d"``).

It holds the chaos game's points ``(n, 2)`` (x right, y up), the repaired code that drew
them (maps ``(N, 6)`` rows ``a b c d e f`` and probabilities ``(N,)``), the model's
parameters and meta data. Its 2D view (:meth:`Attractor.front_view`) is the raster every
2D score reads (the Ochoa terms of :mod:`growsim.objectives.ochoa`, the silhouette NCC),
framed as plant views are (:mod:`growsim.kernels.views`): the stem base (the lowest
point) at the horizontal centre and on the bottom row, one scale fitting the height or
the half-width about the base. Pictures: the front (and mirrored back) view is the point
density drawn directly; other views are pyvista renders of the points in the ``z = 0``
plane.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.files import atomic_write, json_default
from growsim.kernels.ifs2d import bounds, points_raster
from growsim.kernels.views import frame_scale, frame_view
from growsim.phenotypes.base import Phenotype
from growsim.render import aim_camera, check_size, scene_image, show_scene

__all__ = ["Attractor", "singular_values"]

#: colour of dense ink (the fern's green) and of the background
_INK = np.array([22.0, 110.0, 40.0])
_PAPER = np.array([255.0, 255.0, 255.0])


class Attractor(Phenotype):
    """A 2D IFS attractor (see the module docstring).

    Examples
    --------
    >>> from growsim.models.ifs2d import PRESETS, develop
    >>> a = develop(PRESETS["fern"])
    >>> a.phenotype, a.n_points, a.front_view(64).shape
    ('points2d', 100000, (64, 64))
    """

    phenotype = "points2d"
    capabilities = frozenset({"front_view"})

    def __init__(self, points, maps, p, params=None, meta=None):
        self.points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
        self.maps = np.asarray(maps, dtype=np.float64).reshape(-1, 6)
        self.p = np.asarray(p, dtype=np.float64).reshape(-1)
        if self.p.shape[0] != self.maps.shape[0]:
            raise UserInputError(
                f"Attractor: {self.maps.shape[0]} maps but {self.p.shape[0]} probabilities"
            )
        if not np.isfinite(self.points).all():
            raise UserInputError("Attractor: points must be finite")
        self.params = {k: float(v) for k, v in (params or {}).items()}
        self.meta = dict(meta or {})

    def __repr__(self) -> str:
        return f"Attractor(maps={self.maps.shape[0]}, points={self.n_points})"

    # ------------------------------------------------------------------ geometry
    @property
    def n_points(self) -> int:
        """Number of points."""
        return int(self.points.shape[0])

    def _bounds(self) -> tuple[float, float, float, float, float]:
        """``(x_min, x_max, y_min, y_max, x_low)``, computed once (points do not change)."""
        if getattr(self, "_cached_bounds", None) is None:
            self._cached_bounds = bounds(self.points)
        return self._cached_bounds

    def bbox(self) -> np.ndarray:
        """``(2, 2)`` ``[min, max]`` corners (zeros when empty)."""
        x0, x1, y0, y1, _ = self._bounds()
        return np.array([[x0, y0], [x1, y1]])

    def base(self) -> tuple[float, float]:
        """The stem base: the lowest point ``(x, y)`` (the first of equals; ``(0, 0)``
        when empty). The main stem is the vertical line through it.

        Examples
        --------
        >>> Attractor([[1.0, 2.0], [3.0, 0.5]], [[0] * 6], [1.0]).base()
        (3.0, 0.5)
        """
        _, _, y0, _, xl = self._bounds()
        return xl, y0

    def height(self) -> float:
        """Vertical extent (world units)."""
        b = self.bbox()
        return float(b[1, 1] - b[0, 1])

    def width(self) -> float:
        """Horizontal extent (world units)."""
        b = self.bbox()
        return float(b[1, 0] - b[0, 0])

    def framing(self, size: int) -> tuple[float, float, float]:
        """``(base_x, y_min, scale)`` of the ``size`` raster of :meth:`front_view`: the
        scale (pixels per unit) fits the height into ``size - 1`` pixels or the larger
        half-width about the base into ``size / 2 - 0.5``
        (:func:`growsim.kernels.views.frame_scale`)."""

        x0, x1, y0, y1, bx = self._bounds()
        if self.n_points == 0:
            return bx, y0, 1.0
        return bx, y0, frame_scale(y1 - y0, max(x1 - bx, bx - x0), size)

    def front_view(self, size: int = 64) -> np.ndarray:
        """The 2D view ``(size, size)`` uint8: 1 where a point falls, framed (see
        :meth:`framing`; the base on the centre column and the bottom row).

        Examples
        --------
        >>> a = Attractor([[0.0, 0.0], [0.0, 1.0]], [[0] * 6], [1.0])
        >>> v = a.front_view(8)
        >>> int(v[7, 4]), int(v[0, 4]), int(v.sum())
        (1, 1, 2)
        """

        size = int(size)
        bx, by, k = self.framing(size)
        col, row = frame_view(self.points[:, 0], self.points[:, 1], bx, by, k, size)
        return points_raster(col, row, (size, size))

    def views(self, size: int = 64) -> np.ndarray:
        """``(1, size, size)`` uint8: :meth:`front_view` as the one view of a silhouette
        comparison (:mod:`growsim.kernels.views` compares ``(V, S, S)`` stacks)."""
        return self.front_view(size)[None]

    # ------------------------------------------------------------------ measures
    def measures(self, env=None) -> dict[str, float]:
        """``n_points``, ``n_maps``, ``maps_used`` (probability > 0), ``height``,
        ``width``, ``left`` and ``right`` (extents either side of the main stem),
        ``max_singular_value`` (of the maps' linear parts), ``coverage`` (share of
        the 128 x 128 view that is ink), and the parameters.

        Examples
        --------
        >>> from growsim.models.ifs2d import PRESETS, develop
        >>> m = develop(PRESETS["fern"]).measures()
        >>> m["maps_used"], round(m["height"]), round(m["left"], 2), round(m["right"], 2)
        (4.0, 10, 2.18, 2.66)
        """

        bx, _ = self.base()
        b = self.bbox()
        out = {
            "n_points": float(self.n_points),
            "n_maps": float(self.maps.shape[0]),
            "maps_used": float(np.count_nonzero(self.p > 0)),
            "height": self.height(),
            "width": self.width(),
            "left": float(bx - b[0, 0]),
            "right": float(b[1, 0] - bx),
            "max_singular_value": float(singular_values(self.maps).max(initial=0.0)),
            "coverage": float(self.front_view(128).mean()),
        }
        out.update(self.params)
        return out

    # ------------------------------------------------------------------ persistence
    def save(self, path: str | os.PathLike) -> Path:
        """Write to ``path`` (``.npz``, compressed) atomically.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "a.npz"
        >>> a = Attractor([[0.0, 1.0]], [[0.5, 0, 0, 0.5, 0, 0]], [1.0], meta={"seed": 3})
        >>> Attractor.load(a.save(f)).meta
        {'seed': 3}
        """
        path = Path(path)
        if path.suffix != ".npz":
            raise UserInputError(f"{path}: an attractor is saved as .npz")
        arrays = {
            "phenotype": np.array(self.phenotype),
            "points": self.points,
            "maps": self.maps,
            "p": self.p,
            "params": np.array(json.dumps(self.params, sort_keys=True)),
            "meta": np.array(json.dumps(self.meta, sort_keys=True, default=json_default)),
        }
        return atomic_write(path, lambda fh: np.savez_compressed(fh, **arrays))

    @classmethod
    def load(cls, path: str | os.PathLike) -> Attractor:
        """Read an attractor written by :meth:`save`."""
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                if "phenotype" not in z.files or str(z["phenotype"]) != cls.phenotype:
                    raise UserInputError(f"{path}: not an attractor (points2d) file")
                a = {k: z[k] for k in z.files}
        except (OSError, ValueError, KeyError) as exc:
            raise UserInputError(f"{path}: cannot read an attractor ({exc})") from None
        return cls(
            a["points"],
            a["maps"],
            a["p"],
            params=json.loads(str(a["params"])),
            meta=json.loads(str(a["meta"])),
        )

    # ------------------------------------------------------------------ pictures
    def density_image(self, size=(800, 800), *, mirror: bool = False) -> np.ndarray:
        """The front view as a picture ``(H, W, 3)`` uint8 (``size`` is ``(W, H)``): the
        whole attractor fitted with a 3 % margin, each pixel shaded from white to green by
        ``log(1 + count) / log(1 + c95)`` (``c95`` the 95th percentile of the non-empty
        pixels' counts). ``mirror``: seen from the back.

        Examples
        --------
        >>> from growsim.models.ifs2d import PRESETS, develop
        >>> img = develop(PRESETS["fern"]).density_image((40, 60))
        >>> img.shape, bool(img.min() < 100)
        ((60, 40, 3), True)
        """

        w, h = check_size(size)
        img = np.empty((h, w, 3), np.uint8)
        img[:] = _PAPER.astype(np.uint8)
        if self.n_points == 0:
            return img
        b = self.bbox()
        ext = np.maximum(b[1] - b[0], 1e-12)
        m = 0.03 * min(w, h)
        k = min((w - 2 * m) / ext[0], (h - 2 * m) / ext[1])
        x = self.points[:, 0]
        if mirror:
            x = b[1, 0] + b[0, 0] - x
        col = 0.5 * w + k * (x - 0.5 * (b[0, 0] + b[1, 0]))
        row = 0.5 * h - k * (self.points[:, 1] - 0.5 * (b[0, 1] + b[1, 1]))
        counts = points_raster(col, row, (h, w), count=True)
        nz = counts[counts > 0]
        c95 = max(float(np.percentile(nz, 95)), 1.0) if nz.size else 1.0
        t = np.clip(np.log1p(counts) / np.log1p(c95), 0.0, 1.0)[..., None]
        t = np.where(counts[..., None] > 0, 0.35 + 0.65 * t, 0.0)
        return np.round(_PAPER * (1 - t) + _INK * t).astype(np.uint8)

    def _plotter_scene(self, pl, view) -> None:
        import pyvista as pv

        pts = np.column_stack([self.points, np.zeros(self.n_points)])
        if self.n_points:
            pl.add_mesh(pv.PolyData(pts), color=tuple(_INK / 255), point_size=2.0)
        b = self.bbox()
        centre = np.array([*(0.5 * (b[0] + b[1])), 0.0])
        radius = max(float(np.linalg.norm(b[1] - b[0])) / 2.0, 1e-6)
        aim_camera(pl, centre, radius, view)
        pl.enable_parallel_projection()
        pl.camera.parallel_scale = radius * 1.05
        pl.reset_camera_clipping_range()

    def render_image(self, *, view: str = "iso", size=(800, 800)) -> np.ndarray:
        """An ``(H, W, 3)`` picture: ``front`` / ``back`` the point density
        (:meth:`density_image`); other views a pyvista render of the points in the
        ``z = 0`` plane.

        Examples
        --------
        >>> from growsim.models.ifs2d import PRESETS, develop
        >>> develop(PRESETS["tree"]).render_image(view="side", size=(32, 24)).shape
        (24, 32, 3)
        """
        if view in ("front", "back"):
            return self.density_image(size, mirror=view == "back")

        return scene_image(lambda pl: self._plotter_scene(pl, view), size)

    def show(self, *, view: str = "front", title: str | None = None) -> None:
        """An interactive pyvista window of the points (needs a display), titled ``title``."""

        show_scene(lambda pl: self._plotter_scene(pl, view), title=title)

    def to_json(self) -> dict[str, Any]:
        """The code as JSON-able rows ``{"maps": [[a, b, c, d, e, f], ...], "p": [...]}``."""
        return {"maps": self.maps.tolist(), "p": self.p.tolist()}


def singular_values(maps) -> np.ndarray:
    """``(N,)`` largest singular value of each map's linear part (rows ``a b c d ...``).

    Examples
    --------
    >>> singular_values([[0.0, -0.5, 0.5, 0.0, 0, 0]]).tolist()
    [0.5]
    """
    m = np.asarray(maps, dtype=np.float64).reshape(-1, np.shape(maps)[-1])
    a, b, c, d = m[:, 0], m[:, 1], m[:, 2], m[:, 3]
    s = a * a + b * b + c * c + d * d
    det = a * d - b * c
    return np.sqrt(0.5 * (s + np.sqrt(np.maximum(s * s - 4.0 * det * det, 0.0))))
