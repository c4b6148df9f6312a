"""The Plant: one skeleton of segments shared by every plant model, and its measures.

A :class:`Plant` is a set of per-segment arrays (y is up):

========== ================= ===========================================================
field      dtype, shape      meaning
========== ================= ===========================================================
``start``  float64 ``(n, 3)`` first end point of each segment
``end``    float64 ``(n, 3)`` second end point (towards the tip)
``radius`` float64 ``(n,)``   radius at the segment's base (leaves: half the blade width)
``parent`` int64 ``(n,)``     index of the parent segment, ``-1`` for a root
``order``  int32 ``(n,)``     branching order (0 = trunk)
``kind``   int8 ``(n,)``      :data:`STEM` (0) or :data:`LEAF` (1)
``data``   ``dict``           extra per-segment arrays (first axis ``n``): light, age, ...
``meta``   ``dict``           model name, parameters, seed (JSON-able values)
========== ================= ===========================================================

A model may store ``data["radius_end"]`` (the radius at each segment's far end) so meshes
taper exactly as the model means; otherwise meshes derive it from the children.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from growsim.env.light import projected_area
from growsim.errors import UserInputError
from growsim.files import atomic_write, json_default
from growsim.phenotypes.base import Phenotype
from growsim.phenotypes.plant import mesh as gmesh
from growsim.phenotypes.plant import views as viz
from growsim.phenotypes.plant.leaves import leaf_light
from growsim.skeleton import LEAF, STEM, checked_array, radius_end

__all__ = ["LEAF", "STEM", "Plant", "cluster_leaves"]


def _as_array(name: str, value, dtype, shape_tail: tuple[int, ...], n: int | None) -> np.ndarray:
    return checked_array("Plant", name, value, shape_tail, n, dtype=dtype, finite=False)


@dataclass
class Plant(Phenotype):
    """A plant skeleton: per-segment arrays (see the module docstring for the fields).

    The phenotype of every plant model (kind ``"plant"`` under the contract of
    :mod:`growsim.phenotypes`).

    Arrays are converted to their dtypes and checked on construction: shapes agree, points
    and radii are finite, radii are non-negative, parents are ``-1`` or a valid other index,
    kinds are :data:`STEM` or :data:`LEAF`. Any violation raises
    :class:`growsim.errors.UserInputError` naming the field.

    Examples
    --------
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [0.5, 1.5, 0]], parent=[-1, 0],
    ...                       point_parent=[-1, 0, 1])
    >>> p.n_segments, p.n_tips, round(p.height(), 3)
    (2, 1, 1.5)
    """

    phenotype: ClassVar[str] = "plant"

    start: np.ndarray
    end: np.ndarray
    radius: np.ndarray
    parent: np.ndarray
    order: np.ndarray
    kind: np.ndarray
    data: dict[str, np.ndarray] = field(default_factory=dict)
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.start = _as_array("start", self.start, np.float64, (3,), None)
        n = self.start.shape[0]
        self.end = _as_array("end", self.end, np.float64, (3,), n)
        self.radius = _as_array("radius", self.radius, np.float64, (), n)
        self.parent = _as_array("parent", self.parent, np.int64, (), n)
        self.order = _as_array("order", self.order, np.int32, (), n)
        self.kind = _as_array("kind", self.kind, np.int8, (), n)
        for name in ("start", "end", "radius"):
            if not np.all(np.isfinite(getattr(self, name))):
                bad = int(
                    np.flatnonzero(~np.isfinite(getattr(self, name)).reshape(n, -1).all(1))[0]
                )
                raise UserInputError(f"Plant.{name}: segment {bad} is not finite")
        if n and self.radius.min() < 0:
            raise UserInputError(
                f"Plant.radius: segment {int(np.argmin(self.radius))} has a negative radius"
            )
        if n:
            bad = (self.parent < -1) | (self.parent >= n) | (self.parent == np.arange(n))
            if bad.any():
                i = int(np.flatnonzero(bad)[0])
                raise UserInputError(
                    f"Plant.parent: segment {i} has parent {int(self.parent[i])} "
                    f"(must be -1 or another index in [0, {n}))"
                )
            badk = (self.kind != STEM) & (self.kind != LEAF)
            if badk.any():
                i = int(np.flatnonzero(badk)[0])
                raise UserInputError(f"Plant.kind: segment {i} has kind {int(self.kind[i])}")
        data = {}
        for key, value in dict(self.data or {}).items():
            arr = np.asarray(value)
            if arr.ndim == 0 or arr.shape[0] != n:
                raise UserInputError(
                    f"Plant.data[{key!r}]: first axis must have {n} rows, got shape {arr.shape}"
                )
            data[str(key)] = arr
        self.data = data
        self.meta = dict(self.meta or {})

    # ------------------------------------------------------------------ construction
    @classmethod
    def _unchecked(cls, start, end, radius, parent, order, kind, data, meta) -> Plant:
        """Build without the checks of ``__post_init__``, for arrays a kernel produced with
        the right dtypes and shapes (saves ~20 us per plant; models' tests re-validate)."""
        self = object.__new__(cls)
        self.start, self.end, self.radius = start, end, radius
        self.parent, self.order, self.kind = parent, order, kind
        self.data, self.meta = data, meta
        return self

    @classmethod
    def empty(cls, meta: Mapping | None = None) -> Plant:
        """A plant with no segments.

        Examples
        --------
        >>> Plant.empty().n_segments
        0
        """
        z = np.zeros((0, 3))
        return cls(
            z,
            z,
            np.zeros(0),
            np.zeros(0, np.int64),
            np.zeros(0, np.int32),
            np.zeros(0, np.int8),
            meta=dict(meta or {}),
        )

    @classmethod
    def from_points(
        cls,
        points,
        parent,
        point_parent,
        *,
        radius=0.1,
        order=None,
        kind=None,
        data: Mapping | None = None,
        meta: Mapping | None = None,
    ) -> Plant:
        """Build from a tree of points: segment ``i`` joins ``points[point_parent[j]]`` to
        ``points[j]`` for every point ``j`` with ``point_parent[j] >= 0``.

        ``points`` ``(m, 3)``; ``point_parent`` ``(m,)`` int (-1 for roots); ``parent``
        ``(n,)`` parent *segment* of each of the ``n`` segments, in the order of the points
        that end them. ``radius`` scalar or ``(n,)``; ``order`` and ``kind`` default to 0.

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 2, 0]], parent=[-1], point_parent=[-1, 0])
        >>> p.end.tolist()
        [[0.0, 2.0, 0.0]]
        """
        pts = np.asarray(points, dtype=np.float64)
        pp = np.asarray(point_parent, dtype=np.int64)
        if pts.ndim != 2 or pts.shape[1] != 3 or pp.shape != (pts.shape[0],):
            raise UserInputError("Plant.from_points: points must be (m, 3) and point_parent (m,)")
        j = np.flatnonzero(pp >= 0)
        n = j.size
        rad = np.broadcast_to(np.asarray(radius, dtype=np.float64), (n,)).copy()
        return cls(
            pts[pp[j]],
            pts[j],
            rad,
            parent,
            np.zeros(n, np.int32) if order is None else order,
            np.zeros(n, np.int8) if kind is None else kind,
            data=dict(data or {}),
            meta=dict(meta or {}),
        )

    @classmethod
    def concat(cls, plants: Sequence[Plant], offsets=None, meta: Mapping | None = None) -> Plant:
        """Join plants into one (e.g. a stand of trees); parents are re-indexed.

        ``offsets`` optional ``(k, 3)`` translation of each plant. Only ``data`` keys that all
        plants share are kept.

        Examples
        --------
        >>> a = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
        >>> Plant.concat([a, a], offsets=[[0, 0, 0], [5, 0, 0]]).crown_width()
        5.0
        """
        plants = list(plants)
        if not plants:
            return cls.empty(meta)
        if offsets is None:
            off = np.zeros((len(plants), 3))
        else:
            off = np.asarray(offsets, dtype=np.float64)
            if off.shape != (len(plants), 3):
                raise UserInputError(f"Plant.concat: offsets must be ({len(plants)}, 3)")
        base = np.cumsum([0] + [p.n_segments for p in plants])[:-1]
        parents = [np.where(p.parent >= 0, p.parent + b, -1) for p, b in zip(plants, base)]
        keys = set(plants[0].data)
        for p in plants[1:]:
            keys &= set(p.data)
        return cls(
            np.concatenate([p.start + o for p, o in zip(plants, off)]),
            np.concatenate([p.end + o for p, o in zip(plants, off)]),
            np.concatenate([p.radius for p in plants]),
            np.concatenate(parents),
            np.concatenate([p.order for p in plants]),
            np.concatenate([p.kind for p in plants]),
            data={k: np.concatenate([p.data[k] for p in plants]) for k in sorted(keys)},
            meta=dict(meta or {"parts": [p.meta for p in plants]}),
        )

    def subset(self, mask) -> Plant:
        """The plant restricted to the segments where ``mask`` ``(n,)`` bool is true
        (parents outside the subset become ``-1``).

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0], [-1, 0, 1])
        >>> p.subset([False, True]).parent.tolist()
        [-1]
        """
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != (self.n_segments,):
            raise UserInputError(f"Plant.subset: mask must have shape ({self.n_segments},)")
        new_index = np.full(self.n_segments, -1, np.int64)
        new_index[mask] = np.arange(int(mask.sum()))
        par = self.parent[mask]
        par = np.where(par >= 0, new_index[np.maximum(par, 0)], -1)
        return Plant(
            self.start[mask],
            self.end[mask],
            self.radius[mask],
            par,
            self.order[mask],
            self.kind[mask],
            data={k: v[mask] for k, v in self.data.items()},
            meta=dict(self.meta),
        )

    def cluster_leaves(self) -> Plant:
        """The plant with each branch's leaves merged into one: :func:`cluster_leaves`
        (what :func:`growsim.phenotypes.plant.mesh.lod_meshes` asks of a plant)."""
        return cluster_leaves(self)

    # ------------------------------------------------------------------ topology
    @property
    def n_segments(self) -> int:
        """Number of segments, stems and leaves (``int``)."""
        return int(self.start.shape[0])

    @property
    def n_stems(self) -> int:
        """Number of :data:`STEM` segments."""
        return int(np.count_nonzero(self.kind == STEM))

    @property
    def n_leaves(self) -> int:
        """Number of :data:`LEAF` segments."""
        return int(np.count_nonzero(self.kind == LEAF))

    def stem_children_count(self) -> np.ndarray:
        """``(n,)`` int64: number of STEM children of each segment.

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 2, 0], [-1, 2, 0]],
        ...                       [-1, 0, 0], [-1, 0, 1, 1])
        >>> p.stem_children_count().tolist()
        [2, 0, 0]
        """
        stem = (self.kind == STEM) & (self.parent >= 0)
        return np.bincount(self.parent[stem], minlength=self.n_segments).astype(np.int64)

    @property
    def n_tips(self) -> int:
        """Number of STEM segments without a STEM child (branch tips)."""
        c = self.stem_children_count()
        return int(np.count_nonzero((self.kind == STEM) & (c == 0)))

    @property
    def n_branch_points(self) -> int:
        """Number of STEM segments from whose end two or more STEM segments grow."""
        c = self.stem_children_count()
        return int(np.count_nonzero((self.kind == STEM) & (c >= 2)))

    def branch_angle(self) -> float:
        """Mean over the branch points (:attr:`n_branch_points`) of the widest angle, in
        degrees, between a STEM child's axis and its parent's: how far laterals diverge
        (NaN when there are no branch points: an unbranched plant has no branch angle, and
        comparisons leave it out rather than count it as 0 degrees).

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [0, 2, 0], [1, 2, 0]],
        ...                       [-1, 0, 0], [-1, 0, 1, 1])  # a stem forks: up and 45 deg
        >>> round(p.branch_angle(), 6)
        45.0
        >>> Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0]).branch_angle()
        nan
        """
        c = self.stem_children_count()
        axis = self.end - self.start
        norm = np.linalg.norm(axis, axis=1)
        unit = axis / np.where(norm > 0, norm, 1.0)[:, None]
        kids = np.flatnonzero((self.parent >= 0) & (self.kind == STEM))
        kids = kids[(self.kind[self.parent[kids]] == STEM) & (c[self.parent[kids]] >= 2)]
        if not len(kids):
            return float("nan")
        cos = np.clip(np.einsum("ij,ij->i", unit[kids], unit[self.parent[kids]]), -1.0, 1.0)
        widest = np.full(self.n_segments, -1.0)
        np.maximum.at(widest, self.parent[kids], np.degrees(np.arccos(cos)))
        return float(widest[widest >= 0].mean())

    def lengths(self) -> np.ndarray:
        """``(n,)`` float64 segment lengths."""
        return np.linalg.norm(self.end - self.start, axis=1)

    # ------------------------------------------------------------------ measures
    def _points(self) -> np.ndarray:
        return np.concatenate([self.start, self.end])

    def bbox(self) -> np.ndarray:
        """``(2, 3)`` float64 ``[min, max]`` corners of all segment end points (zeros when
        empty).

        Examples
        --------
        >>> Plant.from_points([[0, 0, 0], [1, 2, 3]], [-1], [-1, 0]).bbox().tolist()
        [[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]]
        """
        if self.n_segments == 0:
            return np.zeros((2, 3))
        pts = self._points()
        return np.stack([pts.min(0), pts.max(0)])

    def height(self) -> float:
        """Vertical extent (y max minus y min) of the skeleton."""
        b = self.bbox()
        return float(b[1, 1] - b[0, 1])

    def crown_width(self) -> float:
        """Extent along x (the front view's width) of the skeleton."""
        b = self.bbox()
        return float(b[1, 0] - b[0, 0])

    def crown_depth(self) -> float:
        """Extent along z (the side view's width) of the skeleton."""
        b = self.bbox()
        return float(b[1, 2] - b[0, 2])

    def height_to_width(self) -> float:
        """:meth:`height` over the plant's width: the widest of :meth:`crown_width`,
        :meth:`crown_depth` and its thickest segment's diameter (a bare stem is as wide as
        it is thick). Slenderness: plants in dense stands grow tall and narrow. 0 for a
        plant of no segments.

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 2, 0], [1, 3, 0]], [-1, 0], [-1, 0, 1])
        >>> p.height_to_width()  # 3 tall, 1 wide
        3.0
        """
        if self.n_segments == 0:
            return 0.0
        width = max(self.crown_width(), self.crown_depth(), 2.0 * float(self.radius.max()))
        return self.height() / width if width > 0 else 0.0

    def total_length(self, kinds: Iterable[int] | None = (STEM,)) -> float:
        """Sum of segment lengths of the given kinds (default stems only; ``None`` = all).

        Examples
        --------
        >>> Plant.from_points([[0, 0, 0], [0, 2, 0]], [-1], [-1, 0]).total_length()
        2.0
        """
        sel = self._select(kinds)
        return float(self.lengths()[sel].sum())

    def radius_end(self) -> np.ndarray:
        """``(n,)`` radius at each segment's far end: ``data["radius_end"]`` if the model
        gave it, else the largest radius of the segment's children of the same kind, else
        the segment's own radius (a tip does not narrow).

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0], [-1, 0, 1],
        ...                       radius=[0.2, 0.1])
        >>> p.radius_end().tolist()
        [0.1, 0.1]
        """
        if "radius_end" in self.data:
            return np.asarray(self.data["radius_end"], dtype=np.float64)
        return radius_end(self.parent, self.kind, self.radius)

    def wood_volume(self) -> float:
        """Volume of the STEM segments as truncated cones (radius to :meth:`radius_end`).

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0], radius=1.0)
        >>> round(p.wood_volume(), 4)  # a cylinder of radius 1, height 1
        3.1416
        """
        sel = self.kind == STEM
        r0 = self.radius[sel]
        r1 = self.radius_end()[sel]
        L = self.lengths()[sel]
        return float(np.sum(np.pi * L * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0))

    def _select(self, kinds) -> np.ndarray:
        if kinds is None:
            return np.ones(self.n_segments, bool)
        kinds = [int(k) for k in kinds]
        for k in kinds:
            if k not in (STEM, LEAF):
                raise UserInputError(f"kinds: unknown segment kind {k} (use STEM=0, LEAF=1)")
        return np.isin(self.kind, kinds)

    def leaf_area(self, direction=(0.0, -1.0, 0.0), resolution: int = 256) -> float:
        """Area of the leaves' orthographic shadow along ``direction`` (leaves that overlap
        seen from there count once): :func:`growsim.env.light.projected_area` of the LEAF
        segments.

        Examples
        --------
        >>> Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0]).leaf_area()
        0.0
        """

        sel = self.kind == LEAF
        return projected_area(
            self.start[sel], self.end[sel], self.radius[sel], direction, resolution
        )

    def measures(self, env=None, resolution: int = 256) -> dict[str, float]:
        """All measures as a JSON-able dict: counts, extents, lengths, volume, the shadow
        areas from above (all segments and leaves only, at ``resolution``), the mean
        :meth:`branch_angle`, and for a plant whose model keeps each segment's light
        (``data["light"]``, the hormone model) ``light_per_area``, the light per unit of
        side area ``sum_i A_i l_i / sum_i A_i`` (``A_i = 2 pi r_i L_i``: light-interception
        efficiency). With an
        environment (:class:`growsim.env.Environment`), also ``light_captured``: the light
        the leaves receive from its shadow-map light, ``sum_i A_i L_i`` over the leaves
        (:func:`leaf_light`; the light objective's linear ``light`` term).

        Examples
        --------
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
        >>> sorted(p.measures())[:3]
        ['branch_angle', 'crown_depth', 'crown_width']
        """

        out = {
            "n_segments": self.n_segments,
            "n_stems": self.n_stems,
            "n_leaves": self.n_leaves,
            "n_tips": self.n_tips,
            "n_branch_points": self.n_branch_points,
            "height": self.height(),
            "crown_width": self.crown_width(),
            "crown_depth": self.crown_depth(),
            "height_to_width": self.height_to_width(),
            "total_length": self.total_length(),
            "wood_volume": self.wood_volume(),
            "projected_area_top": projected_area(
                self.start, self.end, self.radius, resolution=resolution
            ),
            "leaf_area_top": self.leaf_area(resolution=resolution),
            "branch_angle": self.branch_angle(),
        }
        if "light" in self.data and self.n_segments:
            # light interception efficiency: the light per unit of side area, area-weighted
            area = 2.0 * np.pi * self.radius * self.lengths()
            light = np.asarray(self.data["light"], dtype=np.float64)
            out["light_per_area"] = float(area @ light / area.sum()) if area.sum() > 0 else 0.0
        if "leaf_area" in self.data and self.n_segments:
            # foliage carried on the segments (the hormone model): its area, and the leaf
            # area index over the plant's shadow from above with the foliage drawn (each
            # segment widened to the radius r = A / (2 L) of a blade of its leaf area)
            leaf = np.asarray(self.data["leaf_area"], dtype=np.float64)
            length = self.lengths()
            blade = np.divide(leaf, 2.0 * length, out=np.zeros_like(leaf), where=length > 0)
            shade = projected_area(
                self.start, self.end, np.maximum(self.radius, blade), resolution=resolution
            )
            out["leaf_area"] = float(leaf.sum())
            out["leaf_area_index"] = float(leaf.sum() / shade) if shade > 0 else 0.0
        if env is not None:
            out["light_captured"] = leaf_light(self, env.light).light
        return out

    def artefacts(self, output) -> dict[str, Any]:
        """Meshes (``best.<format>`` for each of ``output.mesh``, one mesh shared) and
        renders (``best_<view>.png`` for each of ``output.screenshots``)."""

        shared: dict[str, Any] = {}

        def mesh_writer(path):
            if "mesh" not in shared:
                shared["mesh"] = gmesh.plant_mesh(self)
            return gmesh.export(shared["mesh"], path)

        files = {f"best.{fmt}": mesh_writer for fmt in output.mesh}
        files.update(super().artefacts(output))
        return files

    def render_image(self, *, view: str = "iso", size=(800, 800)) -> np.ndarray:
        """An ``(H, W, 3)`` render (pyvista, off-screen):
        :func:`growsim.phenotypes.plant.views.render_image`."""

        return viz.render_image(self, view=view, size=size)

    def screenshot(self, path, *, view: str = "iso", size=(800, 800)) -> Path:
        """A PNG render: :func:`growsim.phenotypes.plant.views.screenshot`."""

        return viz.screenshot(self, path, view=view, size=size)

    def show(self, *, view: str = "iso", title: str | None = None) -> None:
        """An interactive pyvista window: :func:`growsim.phenotypes.plant.views.show`."""

        viz.show(self, view=view, title=title)

    # ------------------------------------------------------------------ persistence
    def save(self, path: str | os.PathLike) -> Path:
        """Write the plant to ``path`` (``.npz``) atomically. ``meta`` must be JSON-able.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "p.npz"
        >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0], meta={"model": "x"})
        >>> Plant.load(p.save(f)).meta
        {'model': 'x'}
        """
        path = Path(path)
        if path.suffix != ".npz":
            raise UserInputError(f"{path}: a Plant is saved as .npz")
        try:
            meta = json.dumps(self.meta, default=json_default)
        except (TypeError, ValueError) as exc:
            raise UserInputError(f"Plant.meta is not JSON-able: {exc}") from None
        arrays = {
            "start": self.start,
            "end": self.end,
            "radius": self.radius,
            "parent": self.parent,
            "order": self.order,
            "kind": self.kind,
            "meta": np.array(meta),
            "phenotype": np.array(self.phenotype),
        }
        arrays.update({f"data__{k}": v for k, v in self.data.items()})
        return atomic_write(path, lambda fh: np.savez_compressed(fh, **arrays))

    @classmethod
    def load(cls, path: str | os.PathLike) -> Plant:
        """Read a plant written by :meth:`save`.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> f = pathlib.Path(tempfile.mkdtemp()) / "p.npz"
        >>> Plant.load(Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0]).save(f)).n_segments
        1
        """
        path = Path(path)
        try:
            with np.load(path, allow_pickle=False) as z:
                files = set(z.files)
                need = {"start", "end", "radius", "parent", "order", "kind", "meta"}
                if not need <= files:
                    raise UserInputError(
                        f"{path}: not a growsim Plant (missing {sorted(need - files)})"
                    )
                return cls(
                    z["start"],
                    z["end"],
                    z["radius"],
                    z["parent"],
                    z["order"],
                    z["kind"],
                    data={k[6:]: z[k] for k in files if k.startswith("data__")},
                    meta=json.loads(str(z["meta"])),
                )
        except (OSError, ValueError) as exc:
            if isinstance(exc, UserInputError):
                raise
            raise UserInputError(f"{path}: cannot read a Plant ({exc})") from None

    def __repr__(self) -> str:
        model = self.meta.get("model", "?")
        return f"Plant(model={model!r}, segments={self.n_segments}, leaves={self.n_leaves})"


def cluster_leaves(plant: Plant) -> Plant:
    """The plant with the leaves of each branch merged into one leaf of the same total
    blade area (radius and length scaled by ``sqrt(k)`` for ``k`` leaves), centred on
    their mean centre and pointing their mean direction. Stems are unchanged.

    Examples
    --------
    >>> from growsim.models import honda
    >>> t = honda.develop(honda.PRESETS["zelkova"])
    >>> c = cluster_leaves(t)
    >>> c.n_leaves * 3 == t.n_leaves, c.n_stems == t.n_stems
    (True, True)
    """
    if not isinstance(plant, Plant):
        raise UserInputError(f"expected a growsim Plant, got {type(plant).__name__}")
    leaf = plant.kind == LEAF
    if not leaf.any():
        return plant
    idx = np.flatnonzero(leaf)
    groups, inv, counts = np.unique(plant.parent[idx], return_inverse=True, return_counts=True)
    g = groups.size
    mid = 0.5 * (plant.start[idx] + plant.end[idx])
    d = plant.end[idx] - plant.start[idx]
    c = np.zeros((g, 3))
    dd = np.zeros((g, 3))
    for ax in range(3):
        c[:, ax] = np.bincount(inv, mid[:, ax], g) / counts
        dd[:, ax] = np.bincount(inv, d[:, ax], g)
    L = np.linalg.norm(d, axis=1)
    lsum = np.bincount(inv, L, g) / counts
    rsum = np.bincount(inv, plant.radius[idx], g) / counts
    unit = dd / np.maximum(np.linalg.norm(dd, axis=1, keepdims=True), 1e-12)
    scale = np.sqrt(counts)
    half = 0.5 * lsum * scale
    stems = plant.subset(~leaf)
    remap = np.full(plant.n_segments, -1, np.int64)
    remap[~leaf] = np.arange(stems.n_segments)
    pick = np.zeros(g, np.int64)
    pick[inv[::-1]] = idx[::-1]  # the first leaf of each group lends its order and data
    data = {k: np.concatenate([stems.data[k], v[pick]]) for k, v in plant.data.items()}
    if "radius_end" in data:
        data["radius_end"][stems.n_segments :] = rsum * scale
    return Plant(
        np.concatenate([stems.start, c - half[:, None] * unit]),
        np.concatenate([stems.end, c + half[:, None] * unit]),
        np.concatenate([stems.radius, rsum * scale]),
        np.concatenate([stems.parent, remap[groups]]),
        np.concatenate([stems.order, plant.order[pick]]),
        np.concatenate([stems.kind, np.full(g, LEAF, np.int8)]),
        data=data,
        meta=dict(plant.meta),
    )
