"""Pictures of a reconstruction: the visible skeleton over the photograph, the target
beside the fit in each view, and the statistics of the photo's tree beside a regrown
one's.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pandas as pd

from growsim.objectives.silhouette import plant_views
from growsim.pictures.images import frame_silhouettes, silhouette_image
from growsim.reconstruction.stats import branch_table, order_summary, tree_summary

__all__ = ["compare_statistics", "fit_picture", "skeleton_picture", "trees_picture"]


def skeleton_picture(rec, picture, path: str | os.PathLike, *, dpi: int = 100) -> Path:
    """Draw ``rec``'s visible skeleton (:attr:`Reconstruction.skeleton2d`) over
    ``picture`` (an ``(H, W, 3)`` photo, ``(H, W)`` grey or a bool mask, the one it was
    reconstructed from) as a PNG: each branch a line as wide as it is, coloured by its
    order; returns the path.

    Examples
    --------
    >>> import tempfile
    >>> from growsim.reconstruction.build import reconstruct
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> p = skeleton_picture(reconstruct(m), m, Path(tempfile.mkdtemp()) / "sk.png")
    >>> p.name, p.exists()
    ('sk.png', True)
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    img = np.asarray(picture)
    if img.dtype == bool:
        img = np.where(img, 0.55, 1.0)
    h, w = img.shape[:2]
    fig = plt.figure(figsize=(w / dpi, h / dpi), dpi=dpi)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.imshow(img, cmap="gray" if img.ndim == 2 else None, vmin=0, vmax=1 if img.max() <= 1
              else 255, interpolation="nearest")  # fmt: skip
    df = rec.skeleton2d
    lines = np.stack([df[["col0", "row0"]].to_numpy(), df[["col1", "row1"]].to_numpy()], axis=1)
    cmap = plt.get_cmap("autumn")
    top = max(int(df.order.max()), 1) if len(df) else 1
    colors = cmap(np.minimum(df.order.to_numpy() / top, 1.0))
    # a width in points: 2 r pixels at this dpi
    widths = np.maximum(2.0 * df.radius.to_numpy() * 72.0 / dpi, 0.6)
    ax.add_collection(LineCollection(lines, colors=colors, linewidths=widths, alpha=0.85))
    ax.set_xlim(-0.5, w - 0.5)
    ax.set_ylim(h - 0.5, -0.5)
    ax.axis("off")
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out


def fit_picture(plant, front, path: str | os.PathLike, side=None, *, size: int = 256,
                scale: int = 2) -> Path:  # fmt: skip
    """Target beside fit, framed as the fit judges them (at ``size`` px): the front mask
    and ``plant``'s front view, and with ``side`` the side mask and its side view (both
    views framed together); a PNG, returns the path.

    Examples
    --------
    >>> import tempfile
    >>> from growsim.reconstruction.build import reconstruct
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> fit_picture(reconstruct(m).plant, m, Path(tempfile.mkdtemp()) / "f.png", size=32).name
    'f.png'
    """
    n = 1 if side is None else 2
    target = frame_silhouettes(front, side, size, "radius")
    fit = plant_views(plant, size, "radius", views=n)
    panels, titles = [], []
    for i, view in enumerate(("front", "side")[:n]):
        panels += [target[i], fit[i]]
        titles += [f"{view} target", f"{view} fit"]
    return silhouette_image(panels, path, titles=titles, scale=scale)


def trees_picture(plants, path: str | os.PathLike, *, titles=None, size: int = 256,
                  scale: int = 2) -> Path:  # fmt: skip
    """Each plant's front and side views, side by side (e.g. the photo's tree and the
    Honda tree regrown from it); a PNG, returns the path.

    Examples
    --------
    >>> import tempfile
    >>> from growsim.models import honda
    >>> t = honda.develop(honda.PRESETS["plane"])
    >>> trees_picture([t, t], Path(tempfile.mkdtemp()) / "t.png", size=32).name
    't.png'
    """
    panels, names = [], []
    titles = titles or [f"tree {i}" for i in range(len(plants))]
    for plant, title in zip(plants, titles):
        v = plant_views(plant, size, "radius", views=2)
        panels += [v[0], v[1]]
        names += [f"{title} front", f"{title} side"]
    return silhouette_image(panels, path, titles=names, scale=scale)


def compare_statistics(plants: dict) -> tuple[pd.DataFrame, pd.DataFrame]:
    """The branch statistics of several plants (``{name: Plant}``) side by side:
    ``(summary, per_order)``: one column of :func:`~growsim.reconstruction.stats.tree_summary`
    per plant, and every plant's :func:`~growsim.reconstruction.stats.order_summary` with
    a ``tree`` column.

    Examples
    --------
    >>> from growsim.models import honda
    >>> s, o = compare_statistics({"a": honda.develop(honda.PRESETS["plane"])})
    >>> list(s.columns), "angle" in s.index, list(o.columns)[:2]
    (['a'], True, ['tree', 'order'])
    """
    summary = pd.DataFrame({k: tree_summary(p) for k, p in plants.items()})
    orders = [order_summary(branch_table(p)).assign(tree=k) for k, p in plants.items()]
    per_order = pd.concat(orders, ignore_index=True)
    cols = ["tree", *[c for c in per_order.columns if c != "tree"]]
    return summary, per_order[cols]
