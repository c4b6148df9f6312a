"""Pieces of a mask: its largest connected piece, a standing object split at a neck into
the tree and a small tree beside it at the picture's edge, one less the horizon's low
clutter joined to it from a side edge (its skirt), and one split between its two
feet into two trees whose crowns touch (shape alone; two trees of clearly different
colours are split by :func:`~growsim.pictures.colours.split_touching`, which uses both).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from growsim.pictures.scene import Standing, band_feet

__all__ = [
    "FEET_CONTACT",
    "FEET_GAP",
    "FEET_JOIN",
    "FEET_TALL",
    "NECK_AREA",
    "NECK_SPAN",
    "NECK_TALL",
    "NECK_THIN",
    "SKIRT_OVER",
    "SKIRT_TALL",
    "between_feet",
    "largest_piece",
    "split_at_neck",
    "trim_skirt",
]

#: a small tree at a side edge joined to the tree by a neck (:func:`split_at_neck`): the
#: part beyond the neck (within NECK_SPAN of the object's width from the edge) at most
#: NECK_AREA of the object's area and NECK_TALL of its height above the cut, the neck's
#: column at most NECK_THIN of that part's thickest
NECK_SPAN, NECK_AREA, NECK_TALL, NECK_THIN = 0.2, 0.1, 0.5, 0.6
#: the horizon's low clutter joined to the tree from a side edge (:func:`trim_skirt`): the
#: columns from the edge in which the object rises at most SKIRT_TALL of its height above
#: the cut (distant trees, hedges, hills, houses), at most SKIRT_SPAN of its width ...
SKIRT_TALL, SKIRT_SPAN = 0.4, 0.5
#: ... and under the crown on from them, the lowest run of a column standing on the band
#: with sky above it, at most SKIRT_OVER times the skirt's height
SKIRT_OVER = 1.2
#: two trees side by side (:func:`between_feet`): the object's two feet on the band (runs
#: of columns less than FEET_JOIN apart are one foot) apart by at least FEET_GAP times the
#: narrower one's width (two trunks with ground between them, not one trunk's two sides)
FEET_GAP = 1.0
FEET_JOIN = 3
#: ... and the two parts touching over at most FEET_CONTACT of the taller one's height
#: (crowns side by side touch over a short stretch; one crown cut between a trunk's foot
#: and a low limb's is cut from its top to near the ground: 0.7-0.9 on the composites)
FEET_CONTACT = 0.5
#: ... each part at least FEET_TALL times as tall as it is wide (a tree, not a bank of
#: low clouds touching the band beside the crown)
FEET_TALL = 0.5


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


def trim_skirt(obj: Standing, cut: np.ndarray, side: str) -> tuple[Standing, np.ndarray] | None:
    """``obj`` (which reaches the picture's ``side`` edge, "left" or "right") less its
    skirt: the horizon's clutter joined to it along the band (distant trees, a hedge, a
    hill's edge, houses), the columns from that edge in which it rises at most
    :data:`SKIRT_TALL` of its height above the ``cut`` (per column), at most
    :data:`SKIRT_SPAN` of its width, and on from them under the crown, column by column,
    the lowest run of the object standing on the band with sky above it, at most
    :data:`SKIRT_OVER` times as tall as the skirt (the hedge below the crown's low side).
    Returns the object less them and the skirt's pixels (never the tree's), or ``None``
    when it has no skirt or still reaches the edge (a crown cut by the frame rises as high
    at the edge as inside).

    Examples
    --------
    >>> m = np.zeros((40, 60), bool)
    >>> m[5:30, 10:45] = True; m[30:38, 25:29] = True   # a crown on its trunk
    >>> m[26:30, 45:60] = True                          # a hedge along the band
    >>> o = Standing(m, int(m.sum()), 5, 37, 10, 59)
    >>> t, skirt = trim_skirt(o, np.full(60, 38.0), "right")
    >>> t.right, int(skirt.sum()), bool(t.mask[:, 45:].any()), t.feet
    (44, 60, False, ((25, 28),))
    >>> m[5:30, 45:60] = True                           # the crown cut by the frame
    >>> trim_skirt(Standing(m, int(m.sum()), 5, 37, 10, 59), np.full(60, 38.0), "right")
    """
    m = obj.mask
    w = m.shape[1]
    has = m.any(axis=0)
    rise = np.where(has, cut - np.argmax(m, axis=0), 0.0)
    tall = float(rise.max())
    high = np.flatnonzero(rise > SKIRT_TALL * tall)
    if tall <= 0 or not high.size:
        return None
    cols = np.arange(w)
    skirt = cols > high.max() if side == "right" else cols < high.min()
    width = obj.right - obj.left + 1
    if not skirt.any() or skirt[obj.left : obj.right + 1].sum() > SKIRT_SPAN * width:
        return None
    low = m & skirt[None, :]
    # and on under the crown: the lowest run of each column on from the skirt that stands
    # on the band, apart from the crown above it (sky between) and no taller than the skirt
    floor = cut - max(float(rise[skirt].max()), 1.0) * SKIRT_OVER
    for c in (range(int(np.flatnonzero(skirt).max()) + 1, w) if side == "left"
              else range(int(np.flatnonzero(skirt).min()) - 1, -1, -1)):  # fmt: skip
        on = np.flatnonzero(m[:, c])
        if not on.size or on[-1] < cut[c] - 2:
            break
        gaps = np.flatnonzero(np.diff(on) > 1)
        start = on[gaps[-1] + 1] if gaps.size else on[0]
        if not gaps.size or start < floor[c]:
            break
        low[start:, c] = m[start:, c]
    main = largest_piece(m & ~low)
    edge = w - 1 if side == "right" else 0
    if not main.any() or main[:, edge].any():
        return None
    kept = np.flatnonzero(main.any(axis=0))
    trimmed = replace(
        obj, mask=main, area=int(main.sum()), top=int(np.flatnonzero(main.any(axis=1)).min()),
        left=int(kept.min()), right=int(kept.max()), feet=tuple(band_feet(main, cut)),
        region=None if obj.region is None else obj.region & ~skirt[None, :] & ~low,
    )  # fmt: skip
    return trimmed, m & ~main


def between_feet(mask: np.ndarray, feet, rows: np.ndarray, least: float, shared: float):
    """A standing object's ``mask`` split between its two ``feet`` (runs of columns where it
    stands on the band, at ``rows`` per column): two trees side by side whose crowns touch.
    Each pixel goes with the foot it is nearer through the mask (a flood from both feet:
    :func:`skimage.segmentation.watershed` on a flat picture). Split when the feet lie
    apart (:data:`FEET_GAP`), each part holds at least ``least`` of the area and is a
    tree's shape (:data:`FEET_TALL`), and the two touch along at most ``shared`` of the
    smaller part's outline and over at most :data:`FEET_CONTACT` of the taller's height
    (crowns side by side, not a crown cut in half from a low limb's foot); else ``None``.

    Examples
    --------
    >>> m = np.zeros((40, 60), bool)
    >>> m[5:20, 5:30] = True; m[20:38, 16:19] = True            # a crown on its trunk
    >>> m[10:24, 29:55] = True; m[24:38, 41:44] = True          # another, touching it
    >>> a, b = between_feet(m, ((16, 18), (41, 43)), np.full(60, 37), 0.1, 0.4)
    >>> bool(a[10, 10]), bool(b[15, 50]), int((a & b).sum())
    (True, True, 0)
    """
    from scipy import ndimage
    from skimage.segmentation import watershed

    joined: list[list[int]] = []
    for c0, c1 in sorted(feet):
        if joined and c0 - joined[-1][1] - 1 < FEET_JOIN:
            joined[-1][1] = max(joined[-1][1], c1)
        else:
            joined.append([c0, c1])
    if len(joined) != 2:
        return None
    (a0, a1), (b0, b1) = joined
    if b0 - a1 - 1 < FEET_GAP * min(a1 - a0 + 1, b1 - b0 + 1):
        return None
    markers = np.zeros(mask.shape, dtype=np.int32)
    for label_, (c0, c1) in ((1, (a0, a1)), (2, (b0, b1))):
        cols = np.arange(c0, c1 + 1)
        r = np.clip(np.asarray(rows)[cols].astype(int), 0, mask.shape[0] - 1)
        on = mask[r, cols]
        markers[r[on], cols[on]] = label_
    if not ((markers == 1).any() and (markers == 2).any()):
        return None
    parts = watershed(np.zeros(mask.shape), markers, mask=mask)
    a, b = parts == 1, parts == 2
    if min(a.sum(), b.sum()) < least * mask.sum():
        return None
    for part in (a, b):
        rr, cc = np.nonzero(part)
        if np.ptp(rr) + 1 < FEET_TALL * (np.ptp(cc) + 1):
            return None
    small, other = (a, b) if a.sum() <= b.sum() else (b, a)
    k = np.ones((3, 3), dtype=bool)
    outline = small & ~ndimage.binary_erosion(small, k)
    contact = outline & ndimage.binary_dilation(other, k)
    if contact.sum() > shared * max(int(outline.sum()), 1):
        return None
    touching = np.flatnonzero(contact.any(axis=1))
    tall = max(np.ptp(np.flatnonzero(part.any(axis=1))) + 1 for part in (a, b))
    if np.ptp(touching) + 1 > FEET_CONTACT * tall:
        return None
    return a, b
