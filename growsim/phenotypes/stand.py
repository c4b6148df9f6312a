"""A stand: several plants in one :class:`growsim.phenotypes.plant.Plant`; its placing
and its measures.

A stand (:func:`growsim.models.hormone.grow_stand`, or :func:`place`) is a ``Plant`` whose
``data["plant"]`` gives each segment's plant and whose ``meta["stand"]`` holds the
positions ``[x, z]``; it saves, loads and renders as any plant (all plants on one ground).
A model that grows the plants of a stand together (the ``"grow_stand"`` capability,
:meth:`growsim.models.base.Model.grow_stand`) yields it; plants grown each alone are put in
their places by :func:`place` (:func:`ground_offsets`). :func:`plant_table` measures each
plant, :func:`stand_measures` the stand.

Areas: a segment's leaf area is its silhouette ``2 r L`` weighted by its chlorophyll (green
tissue; wood counts nothing); the light it captures is its light (``data["light"]``, the
mean over its walls, 0 to the light's intensity) times its silhouette ``2 r L``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from growsim.errors import UserInputError
from growsim.phenotypes.plant import Plant

if TYPE_CHECKING:
    from collections.abc import Sequence

    import pandas as pd

    from growsim.phenotypes.plant import Plant

__all__ = ["PLANT_COLUMNS", "ground_offsets", "place", "plant_table", "stand_measures"]

#: the columns of :func:`plant_table`
PLANT_COLUMNS = (
    "x", "z", "segments", "height", "crown_width", "height_to_width", "branch_angle",
    "leaf_area", "light_captured", "light_per_leaf_area", "light_share",
)  # fmt: skip


def ground_offsets(xz) -> np.ndarray:
    """The ``(N, 3)`` moves ``(x, 0, z)`` that put a plant at each position ``[x, z]`` of
    ``xz`` ``(N, 2)`` on the ground.

    Examples
    --------
    >>> ground_offsets([[1.0, 2.0], [-0.5, 0.0]]).tolist()
    [[1.0, 0.0, 2.0], [-0.5, 0.0, 0.0]]
    """
    xz = np.asarray(xz, dtype=np.float64).reshape(-1, 2)
    return np.stack([xz[:, 0], np.zeros(len(xz)), xz[:, 1]], axis=1)


def place(plants: Plant | Sequence[Plant], xz, *, light=None) -> Plant:
    """A stand of plants each grown alone: copies of ``plants`` (one ``Plant``) at every
    position ``[x, z]`` of ``xz`` ``(N, 2)``, or the plants of the sequence ``plants``,
    one a position, in that order (:meth:`Plant.concat`, moved by
    :func:`ground_offsets`; the ``data`` keys all of them share). ``data["plant"]`` is
    each segment's position index, ``meta`` the first plant's with ``meta["stand"]`` the
    positions. Given ``light`` (a :class:`growsim.env.Light`, the environment's),
    ``data["light"]`` is each segment's light in the stand, one shadow map for all
    (:meth:`growsim.env.Light.segment_light`): what ``--color light`` paints and the
    per-plant measures (light captured, share) sum.

    A wrong number of plants for the positions raises
    :class:`growsim.errors.UserInputError`.

    Examples
    --------
    >>> from growsim.env import Environment
    >>> from growsim.phenotypes.plant import Plant
    >>> one = Plant.from_points([[0, 0, 0], [0, 1, 0]], [-1], [-1, 0])
    >>> s = place(one, [[-0.5, 0.0], [0.5, 0.0]], light=Environment().light)
    >>> s.data["plant"].tolist(), s.meta["stand"], s.data["light"].tolist()
    ([0, 1], [[-0.5, 0.0], [0.5, 0.0]], [0.0, 0.0])
    >>> s.start[:, 0].tolist()
    [-0.5, 0.5]
    """

    xz = np.asarray(xz, dtype=np.float64).reshape(-1, 2)
    trees = [plants] * len(xz) if isinstance(plants, Plant) else list(plants)
    if len(trees) != len(xz):
        raise UserInputError(f"place: {len(trees)} plants for {len(xz)} positions")
    joined = Plant.concat(trees, offsets=ground_offsets(xz))
    data = {**joined.data, "plant": np.repeat(np.arange(len(xz)), [t.n_segments for t in trees])}
    if light is not None:
        data["light"] = np.asarray(light.segment_light(joined), dtype=np.float64)
    meta = {**(trees[0].meta if trees else {}), "stand": xz.tolist()}
    return Plant(joined.start, joined.end, joined.radius, joined.parent, joined.order,
                 joined.kind, data, meta)  # fmt: skip


def _which(stand: Plant) -> np.ndarray:
    if "plant" in stand.data:
        return np.asarray(stand.data["plant"], dtype=np.int64)
    return np.zeros(stand.n_segments, np.int64)


def plant_table(stand: Plant) -> pd.DataFrame:
    """One row per plant of ``stand`` (index ``plant``), the columns of
    :data:`PLANT_COLUMNS`: its position, segments, height (top above the stand's ground,
    ``meta["ground"]``), crown width (the wider of its x and z extents), height-to-width
    ratio (inf for a zero width), branch angle (:meth:`Plant.branch_angle`, degrees; NaN for
    an unbranched plant), leaf area and light captured (see the module), light per leaf area
    and its share of the stand's light captured. A plain plant (no ``data["plant"]``) is a
    stand of one at its own position.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> a = Plant.from_points([[0, 0, 0], [0, 2, 0]], [-1], [-1, 0],
    ...                       data={"light": [1.0], "chlorophyll": [1.0]})
    >>> b = Plant.from_points([[1, 0, 0], [1, 1, 0]], [-1], [-1, 0],
    ...                       data={"light": [0.5], "chlorophyll": [1.0]})
    >>> s = Plant.concat([a, b])
    >>> s = Plant(s.start, s.end, s.radius, s.parent, s.order, s.kind,
    ...           {**s.data, "plant": [0, 1]}, {"stand": [[0, 0], [1, 0]]})
    >>> t = plant_table(s)
    >>> t.height.tolist(), t.light_share.round(3).tolist()
    ([2.0, 1.0], [0.8, 0.2])
    """

    which = _which(stand)
    xz = np.asarray(stand.meta.get("stand", [[0.0, 0.0]]), dtype=np.float64).reshape(-1, 2)
    N = max(len(xz), int(which.max()) + 1 if len(which) else 0)
    ground = float(stand.meta.get("ground", 0.0))
    n = stand.n_segments
    sil = 2.0 * stand.radius * stand.lengths()
    chl = np.asarray(stand.data.get("chlorophyll", np.ones(n)), dtype=np.float64)
    light = np.asarray(stand.data.get("light", np.zeros(n)), dtype=np.float64)
    leaf = np.bincount(which, weights=chl * sil, minlength=N)
    captured = np.bincount(which, weights=light * sil, minlength=N)
    rows = []
    for i in range(N):
        mask = which == i
        one = stand.subset(mask)
        if one.n_segments:
            b = one.bbox()
            height = float(b[1, 1] - ground)
            width = float(max(b[1, 0] - b[0, 0], b[1, 2] - b[0, 2]))
            angle = one.branch_angle()
        else:
            height = width = 0.0
            angle = float("nan")
        x, z = xz[i] if i < len(xz) else (np.nan, np.nan)
        rows.append({
            "x": float(x), "z": float(z), "segments": int(mask.sum()), "height": height,
            "crown_width": width, "height_to_width": height / width if width > 0 else np.inf,
            "branch_angle": angle, "leaf_area": float(leaf[i]),
            "light_captured": float(captured[i]),
            "light_per_leaf_area": float(captured[i] / leaf[i]) if leaf[i] > 0 else 0.0,
        })  # fmt: skip
    table = pd.DataFrame(rows, index=pd.RangeIndex(N, name="plant"))
    total = captured.sum()
    table["light_share"] = captured / total if total > 0 else np.zeros(N)
    return table[list(PLANT_COLUMNS)]


def stand_measures(stand: Plant, ground_area: float | None = None) -> dict[str, float]:
    """The stand's measures: ``plants``, ``leaf_area`` and ``light_captured`` (sums),
    ``leaf_area_index`` (leaf area over ``ground_area``, m2; default the positions'
    bounding box widened by the mean distance between neighbours, or 1 m2 for one plant),
    ``mean_height``, ``mean_crown_width``, ``mean_height_to_width`` and
    ``light_inequality`` (the Gini coefficient of the light captured: 0 when every plant
    takes the same share).

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> a = Plant.from_points([[0, 0, 0], [0, 2, 0]], [-1], [-1, 0],
    ...                       data={"light": [1.0], "chlorophyll": [1.0]})
    >>> m = stand_measures(a, ground_area=0.5)
    >>> m["plants"], round(m["leaf_area_index"], 6), m["light_inequality"]
    (1.0, 0.8, 0.0)
    """
    t = plant_table(stand)
    N = len(t)
    if ground_area is None:
        xz = t[["x", "z"]].to_numpy()
        if N > 1:
            d = np.hypot(*(xz[:, None, :] - xz[None, :, :]).transpose(2, 0, 1))
            d[np.diag_indices(N)] = np.inf
            pad = float(d.min(axis=1).mean())
            ground_area = float(np.prod(xz.max(0) - xz.min(0) + pad))
        else:
            ground_area = 1.0
    cap = np.sort(t.light_captured.to_numpy())
    gini = 0.0
    if N > 1 and cap.sum() > 0:
        i = np.arange(1, N + 1)
        gini = float((2 * i - N - 1) @ cap / (N * cap.sum()))
    finite = t.height_to_width[np.isfinite(t.height_to_width)]
    return {
        "plants": float(N),
        "leaf_area": float(t.leaf_area.sum()),
        "light_captured": float(t.light_captured.sum()),
        "leaf_area_index": float(t.leaf_area.sum() / ground_area),
        "mean_height": float(t.height.mean()),
        "mean_crown_width": float(t.crown_width.mean()),
        "mean_height_to_width": float(finite.mean()) if len(finite) else float("nan"),
        "light_inequality": gini,
    }
