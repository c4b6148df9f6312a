"""Pieces of a mask: its largest connected piece, and a standing object split at a neck
into the tree and a small tree beside it at the picture's edge (shape alone; two trees of
clearly different colours are split by :func:`~growsim.pictures.colours.split_touching`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from growsim.pictures.scene import Standing

__all__ = ["NECK_AREA", "NECK_SPAN", "NECK_TALL", "NECK_THIN", "largest_piece", "split_at_neck"]

#: a small tree at a side edge joined to the tree by a neck (:func:`split_at_neck`): the
#: part beyond the neck (within NECK_SPAN of the object's width from the edge) at most
#: NECK_AREA of the object's area and NECK_TALL of its height above the cut, the neck's
#: column at most NECK_THIN of that part's thickest
NECK_SPAN, NECK_AREA, NECK_TALL, NECK_THIN = 0.2, 0.1, 0.5, 0.6


def largest_piece(mask: np.ndarray) -> np.ndarray:
    """The largest 8-connected piece of ``mask`` (bool; the first on equal sizes; all
    False when ``mask`` is).

    Examples
    --------
    >>> m = np.zeros((5, 8), bool); m[1:3, 0:2] = True; m[1:4, 4:8] = True
    >>> int(largest_piece(m).sum()), bool(largest_piece(m)[1, 0])
    (12, False)
    """
    from skimage.measure import label

    parts = label(mask, connectivity=2)
    if parts.max() == 0:
        return np.zeros(mask.shape, dtype=bool)
    sizes = np.bincount(parts.ravel())
    sizes[0] = 0
    return parts == int(np.argmax(sizes))


def split_at_neck(obj: Standing, cut: np.ndarray, side: str) -> Standing | None:
    """``obj`` (which reaches the picture's ``side`` edge, "left" or "right") less a small
    tree at that edge joined to it by a neck, or ``None`` when there is none: the column
    within :data:`NECK_SPAN` of its width from the edge holding the fewest of its pixels,
    where the part beyond it is at most :data:`NECK_AREA` of its area, at most
    :data:`NECK_TALL` of its height above the ``cut`` (per column), and at least
    1 / :data:`NECK_THIN` times as thick (pixels a column) as the neck. The part cut off
    becomes the object's ``apart`` (never the tree's); a crown cut by the frame (as tall
    at the edge as inside) stays whole.

    Examples
    --------
    >>> m = np.zeros((40, 60), bool)
    >>> m[5:30, 10:45] = True; m[30:38, 25:29] = True   # a crown on its trunk
    >>> m[24:30, 45:50] = True                          # a thin join ...
    >>> m[28:38, 50:60] = True                          # ... to a small tree at the edge
    >>> o = Standing(m, int(m.sum()), 5, 37, 10, 59)
    >>> t = split_at_neck(o, np.full(60, 37.0), "right")
    >>> t.right, bool(t.apart[:, 55].any()), bool(t.mask[:, 49:].any())
    (48, True, False)
    """
    m = obj.mask
    n = m.sum(axis=0)
    width = obj.right - obj.left + 1
    span = max(2, int(NECK_SPAN * width))
    if side == "right":
        cand = np.arange(obj.right - span, obj.right)
    else:
        cand = np.arange(obj.left + 1, obj.left + span + 1)
    cand = cand[(cand > obj.left) & (cand < obj.right)]
    if not cand.size:
        return None
    c = int(cand[np.argmin(n[cand])])
    cols = np.arange(m.shape[1])
    beyond = cols > c if side == "right" else cols < c
    part = m & beyond[None, :]
    rows = np.flatnonzero(m.any(axis=1))
    tall = float(np.max(cut[obj.left : obj.right + 1])) - rows.min()
    prow = np.flatnonzero(part.any(axis=1))
    if not prow.size or n[c] == 0:
        return None
    part_tall = float(np.max(cut[beyond])) - prow.min()
    if (part.sum() > NECK_AREA * obj.area or part_tall > NECK_TALL * tall
            or n[c] > NECK_THIN * n[beyond].max()):  # fmt: skip
        return None
    rest = m & ~beyond[None, :]
    rest[:, c] = False
    main = largest_piece(rest)
    if not main.any():
        return None
    kept = np.flatnonzero(main.any(axis=0))
    left, right = int(kept.min()), int(kept.max())
    return replace(
        obj, mask=main, area=int(main.sum()), top=int(np.flatnonzero(main.any(axis=1)).min()),
        left=left, right=right, feet=tuple(f for f in obj.feet if f[0] >= left and f[1] <= right),
        region=None if obj.region is None else obj.region & ~beyond[None, :],
        apart=m & ~main,
    )  # fmt: skip
