"""Branch statistics of any Plant, as users of tree-structure models tabulate them: each
branch (an axis: a chain of stem segments of one order, the continuation of its parent
keeping the order, as Honda's model and the reconstruction number them) with its order,
length, branching angle and its length and radius over its parent's (the measures of
Godin and Caraglio's multiscale tree graphs, *A multiscale model of plant topological
structures*, 1998, and of Honda, Tomlinson and Fisher, *Two geometrical models of
branching of botanical trees*, 1981); a summary per order.

Directions are chords: a branch leaves in the direction of its chord over the first
:data:`DIRECTION_SHARE` of the tree's height (at least one segment); its parent's
direction there is the parent axis's chord over the same length up to the branching
point. So a tree drawn as pixel polylines and a tree of long model segments are measured
alike.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from growsim.phenotypes.plant import STEM

__all__ = ["DIRECTION_SHARE", "axes_of", "branch_table", "order_summary", "tree_summary"]

#: a branch's direction: its chord over this share of the tree's height
DIRECTION_SHARE = 0.05


def axes_of(plant) -> tuple[np.ndarray, np.ndarray]:
    """``(axis (n,), first)``: each stem segment's axis (``-1`` for a leaf) and each
    axis's first segment. A segment continues its parent's axis when it has the parent's
    order and is the first such child.

    Examples
    --------
    >>> from growsim.phenotypes.plant import Plant
    >>> p = Plant.from_points([[0, 0, 0], [0, 1, 0], [0, 2, 0], [1, 2, 0]],
    ...                       parent=[-1, 0, 0], point_parent=[-1, 0, 1, 1], order=[0, 0, 1])
    >>> axes_of(p)[0].tolist()
    [0, 0, 1]
    """
    n = plant.n_segments
    stem = plant.kind == STEM
    axis = np.full(n, -1, np.int64)
    first: list[int] = []
    taken = np.zeros(n, bool)
    for s in range(n):
        if not stem[s]:
            continue
        p = int(plant.parent[s])
        if p >= 0 and axis[p] >= 0 and plant.order[s] == plant.order[p] and not taken[p]:
            axis[s] = axis[p]
            taken[p] = True
        else:
            axis[s] = len(first)
            first.append(s)
    return axis, np.asarray(first, np.int64)


def _chord_forward(segs: list[int], plant, length: float) -> np.ndarray:
    """The direction from the first segment's start over ``length`` along ``segs``."""
    a = plant.start[segs[0]]
    acc = 0.0
    b = plant.end[segs[0]]
    for s in segs:
        b = plant.end[s]
        acc += float(np.linalg.norm(plant.end[s] - plant.start[s]))
        if acc >= length:
            break
    d = b - a
    return d / max(float(np.linalg.norm(d)), 1e-12)


def _chord_back(seg: int, plant, axis: np.ndarray, length: float) -> np.ndarray:
    """The direction of the axis of ``seg`` arriving at ``seg``'s end, over ``length``."""
    b = plant.end[seg]
    s = seg
    acc = 0.0
    a = plant.start[seg]
    while s >= 0 and axis[s] == axis[seg]:
        a = plant.start[s]
        acc += float(np.linalg.norm(plant.end[s] - plant.start[s]))
        if acc >= length:
            break
        s = int(plant.parent[s])
    d = b - a
    return d / max(float(np.linalg.norm(d)), 1e-12)


def branch_table(plant) -> pd.DataFrame:
    """One row per branch (axis) of ``plant``'s stems: ``branch``, ``parent`` (its parent
    branch, ``-1`` for the trunk), ``order``, ``segments``, ``length``, ``radius`` (at its
    base), ``height`` (of its base), ``angle`` (degrees from its parent's direction at the
    branching point; NaN for the trunk), ``length_ratio`` (its length over its parent's),
    ``radius_ratio`` (its base radius over its parent's segment's there).

    Examples
    --------
    >>> from growsim.models import honda
    >>> t = branch_table(honda.develop(honda.PRESETS["zelkova"]))
    >>> list(t.columns)[:4], int(t.order.max()) >= 2
    (['branch', 'parent', 'order', 'segments'], True)
    """
    axis, first = axes_of(plant)
    cols = ["branch", "parent", "order", "segments", "length", "radius", "height", "angle",
            "length_ratio", "radius_ratio"]  # fmt: skip
    if first.size == 0:
        return pd.DataFrame(columns=cols)
    stem = np.flatnonzero(axis >= 0)
    seg_len = np.linalg.norm(plant.end - plant.start, axis=1)
    members: list[list[int]] = [[] for _ in range(first.size)]
    for s in stem:
        members[axis[s]].append(int(s))
    lengths = np.array([seg_len[m].sum() for m in members])
    pts = np.concatenate([plant.start[stem], plant.end[stem]])
    height = float(np.ptp(pts[:, 1])) if pts.size else 0.0
    chord = max(DIRECTION_SHARE * height, 1e-12)
    rows = []
    for k, s0 in enumerate(first):
        p = int(plant.parent[s0])
        pa = int(axis[p]) if p >= 0 and axis[p] >= 0 else -1
        if pa >= 0:
            d_child = _chord_forward(members[k], plant, chord)
            d_par = _chord_back(p, plant, axis, chord)
            angle = float(np.degrees(np.arccos(np.clip(np.dot(d_child, d_par), -1.0, 1.0))))
            lr = lengths[k] / max(lengths[pa], 1e-12)
            rr = float(plant.radius[s0]) / max(float(plant.radius[p]), 1e-12)
        else:
            angle, lr, rr = np.nan, np.nan, np.nan
        base = (float(plant.radius[s0]), float(plant.start[s0][1]))
        rows.append((k, pa, int(plant.order[s0]), len(members[k]), float(lengths[k]), *base,
                     angle, lr, rr))  # fmt: skip
    return pd.DataFrame(rows, columns=cols)


def order_summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per order of a :func:`branch_table`: ``branches``, median ``length``, ``angle``,
    ``length_ratio`` and ``radius_ratio``.

    Examples
    --------
    >>> from growsim.models import honda
    >>> s = order_summary(branch_table(honda.develop(honda.PRESETS["zelkova"])))
    >>> list(s.columns)
    ['order', 'branches', 'length', 'angle', 'length_ratio', 'radius_ratio']
    """
    g = table.groupby("order")
    out = pd.DataFrame({
        "branches": g.size(),
        "length": g["length"].median(),
        "angle": g["angle"].median(),
        "length_ratio": g["length_ratio"].median(),
        "radius_ratio": g["radius_ratio"].median(),
    }).reset_index()  # fmt: skip
    return out


def tree_summary(plant) -> dict:
    """The figures compared between a reconstructed tree and one regrown from it: the
    ``height``, ``width_to_height`` (the stems' extent across the front view over the
    height), number of ``branches``, largest ``orders``, and over the branches that
    have a parent the median ``angle``, ``length_ratio`` and ``radius_ratio``.

    Examples
    --------
    >>> from growsim.models import honda
    >>> s = tree_summary(honda.develop(honda.PRESETS["zelkova"]))
    >>> sorted(s)[:3], s["branches"] > 10
    (['angle', 'branches', 'height'], True)
    """
    t = branch_table(plant)
    lat = t[t.parent >= 0]
    stem = plant.kind == STEM
    pts = np.concatenate([plant.start[stem], plant.end[stem]])
    height = float(np.ptp(pts[:, 1])) if pts.size else 0.0
    width = float(np.ptp(pts[:, 0])) if pts.size else 0.0
    return {
        "height": height,
        "width_to_height": width / height if height > 0 else float("nan"),
        "branches": len(t),
        "orders": int(t.order.max()) if len(t) else 0,
        "angle": float(lat.angle.median()) if len(lat) else float("nan"),
        "length_ratio": float(lat.length_ratio.median()) if len(lat) else float("nan"),
        "radius_ratio": float(lat.radius_ratio.median()) if len(lat) else float("nan"),
    }
