"""Refusals and hints: a hint's pixels (:func:`hint_pixels`), the tree among the
standing objects or a refusal naming the hint that settles it (:func:`choose_tree`), the
tree inside a box by GrabCut when the scene cannot tell it (:func:`in_box`, less what
is like the rows beside the box: :func:`apart_from_rows`), and the
thresholds of the refusals.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from growsim.errors import UserInputError
from growsim.pictures.pieces import largest_piece
from growsim.pictures.reading import SPECK, check_silhouette
from growsim.pictures.record import Segmentation
from growsim.pictures.scene import RIVAL_AREA, RIVAL_HEIGHT, Scene
from growsim.pictures.trunk import GRABCUT_ITERATIONS

__all__ = ["apart_from_rows", "choose_tree", "grazing", "hint_pixels", "in_box", "judge_edges"]

#: refused without a box: the tree taken below the cut reaches both sides of its columns
#: in more than this share of those rows (a wood, a hedge of its colours behind it)
MAX_SPILL = 0.5
#: refused without a box: the horizon's clutter (from the band's top to the ground) is
#: more than this share of the tree's height (from its top to the ground): a tree in
#: front of a wood
MAX_CLUTTER = 0.45
#: ... when the band is rougher than this (its columns' spread around it, coarse rows): a
#: wood's or a treeline's crowns; a hill's or a field's edge is smoother (1.2-1.4 on the
#: real photographs, woods and treelines 2.1-3.9)
WOOD_ROUGH = 1.7
#: refused: the tree's median colour difference from its background under this (Delta E)
MIN_CONTRAST = 15.0
#: what stands on the band at a side edge and is less than this times as tall as wide is
#: the landscape (a hill, a mountainside going on past the frame), not a tree when
#: another object is at least LANDSCAPE_SHARE of its size
LANDSCAPE_TALL = 1.0
LANDSCAPE_SHARE = 0.25
#: refused: the tree touching the top, left or right edge with this many pixels or more
#: (it is cut off; the framing needs the whole tree)
MAX_EDGE_PIXELS = 3
#: ... but with a box (the user's word that the whole tree is in the picture) a tree
#: touching the top edge over at most this share of its width is whole: twig tips or the
#: crown's top grazing the frame (:func:`grazing`); a crown cut off is wide at the edge
GRAZE_WIDTH = 0.05
#: GrabCut in a box starts from each row's background: a pixel of the box within
#: BOX_BACKGROUND_DE (Delta E) of a colour beside the box in its row (or BOX_ROWS rows
#: above or below) starts as probable background, the rest as probable tree; GrabCut runs
#: on the whole picture (its background colours all known) reduced so that the box holds
#: at most BOX_GRABCUT_PIXELS pixels and the picture BOX_PICTURE_PIXELS (chosen on the
#: composites of tests/data/composites and runs/composites_b2, benchmarks/log/fitting.md)
BOX_BACKGROUND_DE = 8.0
BOX_ROWS = 2
BOX_GRABCUT_PIXELS = 150_000
BOX_PICTURE_PIXELS = 500_000
#: after GrabCut, a pixel it took for the tree is background where its colour is nearer
#: the colours beside the box in its rows than the tree's own (its pixels farther than
#: BOX_BACKGROUND_DE from every colour beside them, at least BOX_SURE of them): a wood or
#: the sky between a bare crown's twigs (but not in pinholes); unless that would leave
#: less than BOX_KEEP of what GrabCut took
BOX_SURE, BOX_KEEP = 50, 0.2
#: what settles a tree found in a box touching a side or the top edge: the box reaches
#: that edge (the silhouette lies in the box), so what runs on past it (a courtyard, a
#: hedge, a wood) may have been taken with the tree
BOXED_AT_EDGE = (
    "it is cut off (take it from farther away), or what runs on past that edge was taken "
    "with it: if the whole tree is in the picture, stop the box a few pixels short of "
    "that edge"
)


def hint_pixels(values, n: int, per_pixel: float, shape, flag: str, name: str):
    """A hint ``values`` (``n`` numbers, pixels of the picture as given) in working pixels,
    checked: inside the picture.

    Examples
    --------
    >>> hint_pixels(["10", 20, 30, 40], 4, 0.5, (60, 50), "--box", "tree.jpg")
    ([5.0, 10.0, 15.0, 20.0], [10.0, 20.0, 30.0, 40.0])
    """
    try:
        v = [float(x) for x in values]
    except (TypeError, ValueError):
        v = []
    if len(v) != n or not np.all(np.isfinite(v)):
        form = "x0,y0,x1,y1" if n == 4 else "x,y"
        raise UserInputError(f"{name}: {flag}: expected {form}, got {values!r}")
    h, w = shape
    big_w, big_h = w / per_pixel, h / per_pixel
    xs, ys = v[0::2], v[1::2]
    outside = (max(xs) <= 0 or min(xs) >= big_w or max(ys) <= 0 or min(ys) >= big_h
               if n == 4 else not (0 <= xs[0] < big_w and 0 <= ys[0] < big_h))  # fmt: skip
    if n == 4 and not (v[0] < v[2] and v[1] < v[3]):
        raise UserInputError(f"{name}: {flag}: expected x0 < x1 and y0 < y1, got {values!r}")
    if outside:
        raise UserInputError(
            f"{name}: {flag} {','.join(f'{x:g}' for x in v)} lies outside the picture "
            f"({big_w:.0f} x {big_h:.0f} pixels)"
        )
    return [x * per_pixel for x in v], v


def choose_tree(scene: Scene, point, boxed: bool, name: str, flags, how: str, per_pixel=1.0):
    """The tree among the scene's standing objects: the one at the ``point`` (coarse
    ``(x, y)``), else the largest but the landscape's (an object standing on the band at a
    side edge, less than :data:`LANDSCAPE_TALL` times as tall as wide: a hill) when
    another is at least :data:`LANDSCAPE_SHARE` of its size; refused when there is none,
    or another one (not the landscape's) nearly as large and no hint (``boxed``: the
    objects are already those inside a box). Beside a whole tree, one cut by the
    picture's side edge is no rival: the photograph is of the whole one.

    Examples
    --------
    >>> from growsim.pictures.scene import find_scene
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> scene = find_scene(rgb, np.ones((60, 50), bool))
    >>> o = choose_tree(scene, None, False, "tree.jpg", ("--box", "--point"), "")
    >>> o.left, o.top, o.right, o.bottom
    (10, 13, 39, 43)
    """
    objects = scene.objects
    hint = f"give {flags[0]} x0,y0,x1,y1 around the tree to fit, or {flags[1]} x,y on it"
    if not objects:
        if scene.ground:
            raise UserInputError(
                f"{name}: no tree stands on the ground: nothing rises from the horizon into "
                f"the sky ({how}); {hint}, or a mask"
            )
        raise UserInputError(f"{name}: the silhouette is empty ({how})")
    if point is not None:
        x, y = point[:2]
        h, w = scene.shape
        r, c = min(max(int(y), 0), h - 1), min(max(int(x), 0), w - 1)
        near = []
        for o in objects:
            rr, cc = np.nonzero(o.mask)
            d = np.min(np.hypot(rr - r, cc - c))
            # a point on the trunk below the cut: the object whose feet are above it
            if r >= o.bottom and any(a - 2 <= c <= b + 2 for a, b in o.feet):
                d = 0.0
            near.append(d)
        best = int(np.argmin(near))
        if near[best] > 0.05 * max(h, w):
            raise UserInputError(
                f"{name}: no tree found at {flags[1]} {point[2]:g},{point[3]:g}: nothing "
                f"standing on the ground there ({how}); give a point on the tree's crown or "
                f"trunk, or {flags[0]} x0,y0,x1,y1 around it"
            )
        return objects[best]
    # a hill, a mountainside going on past the frame: what stands on the band at a side
    # edge and is wider than tall is the landscape, never a rival, and not the tree when
    # something at least LANDSCAPE_SHARE of its size stands clear of it (a crown cut by
    # the frame is not the landscape: sky lies between it and the band there)
    w = scene.shape[1]

    def landscape(o) -> bool:
        flat = o.bottom - o.top + 1 < LANDSCAPE_TALL * (o.right - o.left + 1)
        return flat and any(a == 0 or b == w - 1 for a, b in o.feet)

    inside = [o for o in objects if not landscape(o)]
    tree = objects[0]
    if inside and inside[0] is not tree and inside[0].area >= LANDSCAPE_SHARE * tree.area:
        tree = inside[0]
    height = tree.bottom - tree.top + 1
    rivals = [o for o in inside if o is not tree
              and o.area >= RIVAL_AREA * tree.area
              and o.bottom - o.top + 1 >= RIVAL_HEIGHT * height]  # fmt: skip
    if tree.left > 0 and tree.right < w - 1:  # a whole tree: one cut by the frame is not
        rivals = [o for o in rivals if o.left > 0 and o.right < w - 1]  # what it shows
    if rivals and not boxed:
        boxes = " or ".join(
            f"{flags[0]} {','.join(map(str, _suggested_box(scene, o, per_pixel)))}"
            for o in sorted((tree, *rivals[:2]), key=lambda o: o.left)
        )
        beside = ("another tree whose crown touches the tree's stands nearly as tall as it"
                  if any(o.apart is not None for o in (tree, *rivals))
                  else "other objects beside the tree stand as tall as it")  # fmt: skip
        raise UserInputError(
            f"{name}: {beside}, which is the tree? "
            f"give {flags[0]} x0,y0,x1,y1 around it ({boxes}), or {flags[1]} x,y on it"
        )
    return tree


def _suggested_box(scene: Scene, o, per_pixel: float) -> list[int]:
    """A box around the standing object ``o``, down to the bottom edge, in pixels of the
    picture as given (``per_pixel`` working pixels a picture pixel): the hint offered."""
    h, w = scene.shape
    k = 1.0 / (scene.scale * per_pixel)
    m = 0.05 * max(o.right - o.left + 1, o.bottom - o.top + 1)
    x0, y0 = max(0.0, o.left - m) * k, max(0.0, o.top - m) * k
    x1, y1 = min(float(w), o.right + 1 + m) * k, float(h) * k  # down to the bottom edge
    return [int(x0), int(y0), int(np.ceil(x1)), int(np.ceil(y1))]


def _row_background(lab: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Each pixel of ``box`` (bool, the picture's shape): the least Delta E to the colours
    outside the box in its row, or :data:`BOX_ROWS` rows above or below (``inf`` where a
    row has none; colours rounded to 2 units, at most 200 a row)."""
    h = box.shape[0]
    d = np.full(box.shape, np.inf)
    for r in np.flatnonzero(box.any(axis=1)):
        lo, hi = max(0, r - BOX_ROWS), min(h, r + BOX_ROWS + 1)
        beside = lab[lo:hi][~box[lo:hi]]
        if not beside.size:
            continue
        code = np.round(beside / 2.0).astype(np.int64) + 128  # Lab in 2-unit steps
        key = np.unique((code[:, 0] * 256 + code[:, 1]) * 256 + code[:, 2])
        q = np.stack([key // 65536, key // 256 % 256, key % 256], axis=1) * 2.0 - 256.0
        if q.shape[0] > 200:
            q = q[np.random.default_rng(int(r)).choice(q.shape[0], 200, replace=False)]
        inside = lab[r, box[r]]
        d[r, box[r]] = np.sqrt(((inside[:, None, :] - q[None, :, :]) ** 2).sum(-1)).min(axis=1)
    return d


def grazing(tree: np.ndarray) -> bool:
    """True when the silhouette ``tree`` ``(H, W)`` bool touches the picture's top edge
    over at most :data:`GRAZE_WIDTH` of its width (twig tips or a crown's top grazing the
    frame: whole when a box says the tree is in the picture); False when it does not touch
    it, or touches it wider (cut off).

    Examples
    --------
    >>> yy, xx = np.mgrid[0:200, 0:200]
    >>> crown = (yy - 80) ** 2 + (xx - 100) ** 2 <= 80.05 ** 2  # touches row 0 (5 px)
    >>> cut = (yy - 40) ** 2 + (xx - 100) ** 2 <= 80 ** 2       # its top 40 rows cut off
    >>> grazing(crown), grazing(cut), grazing(crown[1:])
    (True, False, False)
    """
    tree = np.asarray(tree, dtype=bool)
    touching = int(tree[0].sum())
    if not touching:
        return False
    cols = np.flatnonzero(tree.any(axis=0))
    return bool(touching <= GRAZE_WIDTH * (cols.max() - cols.min() + 1))


def judge_edges(seg: Segmentation, edges, boxed: bool, name: str, settle: str, how: str):
    """``seg`` judged by its tree's pixels on the picture's edges, ``edges`` ``((name,
    pixels), ...)``: refused naming the edge and what would ``settle`` it when they are
    :data:`MAX_EDGE_PIXELS` or more (cut off, or merging with what is), but with a box
    (``boxed``) a tree :func:`grazing` the top edge is whole: ``seg`` returned with
    ``grazes`` set.

    Examples
    --------
    >>> tree = np.zeros((60, 100), bool); tree[5:40, 5:95] = True   # a crown 90 px wide
    >>> tree[0:5, 48:51] = True                                      # a twig: 3 on the top
    >>> seg = Segmentation(tree, np.zeros((60, 100), bool), 50, np.zeros((60, 100)), 10.0,
    ...                    0.5, 40.0)
    >>> judge_edges(seg, (("top", 3),), True, "t.jpg", "take it from farther away", "").grazes
    3
    >>> judge_edges(seg, (("top", 3),), False, "t.jpg", "give --box", "")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    growsim.errors.UserInputError: t.jpg: the tree touches the picture's top edge (3 ...
    """
    for edge_name, n_edge in edges:
        if boxed and edge_name == "top" and grazing(seg.tree):
            seg = replace(seg, grazes=n_edge)  # the box holds the whole tree
        elif n_edge >= MAX_EDGE_PIXELS:
            raise UserInputError(
                f"{name}: the tree touches the picture's {edge_name} edge ({n_edge} pixels): "
                f"{settle} ({how})"
            )
    return seg


def apart_from_rows(lab: np.ndarray, tree: np.ndarray, beside: np.ndarray) -> np.ndarray:
    """``tree`` (``(H, W)`` bool, what GrabCut took in a box) less its pixels whose colour
    in ``lab`` is nearer the colours beside the box in their rows (``beside``: each pixel's
    least Delta E to them, :func:`_row_background`) than the tree's own colours: those of
    its pixels farther than :data:`BOX_BACKGROUND_DE` from every colour beside them. A
    wood seen between a bare crown's twigs is like the wood beside the box, the twigs are
    not. What it would leave out in pieces under :data:`~growsim.pictures.reading.SPECK`
    pixels stays (pinholes: a speckled crown is refused as too noisy). Unchanged when
    fewer than :data:`BOX_SURE` pixels are sure, or when less than :data:`BOX_KEEP` of
    ``tree`` would be left.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> rgb = np.zeros((40, 60, 3)); rgb[:] = [0.2, 0.3, 0.2]          # a dark wood
    >>> rgb[5:35, [26, 27, 30, 31, 34, 35]] = [0.85, 0.85, 0.8]         # pale twigs
    >>> box = np.zeros((40, 60), bool); box[:, 15:45] = True
    >>> lab = rgb2lab(rgb)
    >>> beside = _row_background(lab, box)
    >>> grabcut = box & (np.abs(np.arange(60) - 30) <= 6)[None, :]    # a solid blob
    >>> kept = apart_from_rows(lab, grabcut, beside)
    >>> int(grabcut.sum()), int(kept.sum()), bool(kept[5:35, 26].all())
    (520, 180, True)
    """
    from scipy.spatial import cKDTree

    tree = np.asarray(tree, dtype=bool)
    sure = tree & np.isfinite(beside) & (beside > BOX_BACKGROUND_DE)
    if sure.sum() < BOX_SURE:
        return tree
    from scipy import ndimage

    own = lab[sure][:: max(1, int(sure.sum()) // 4000)]
    out = tree.copy()
    out[tree] = cKDTree(own).query(lab[tree], k=1)[0] <= beside[tree]
    gone, _ = ndimage.label(tree & ~out)  # pinholes (under a speck's size) are noise
    out |= (np.bincount(gone.ravel()) < SPECK)[gone] & (gone > 0)
    return out if out.sum() >= BOX_KEEP * tree.sum() else tree


def in_box(rgb, keep, sky, hint, per_pixel, name, t_start) -> Segmentation:
    """The tree in the box of ``keep`` (the hint ``--box``) where the scene could not tell
    it (no sky, nothing standing out of it, or what stands merges with a wood reaching
    past the box): GrabCut in the box, started from each row's background (a pixel like
    the colours beside the box in its row is probably background: the sky, a treeline, a
    field run on past the box; :data:`BOX_BACKGROUND_DE`), the ``sky``, when known, and
    everything outside the box background; what GrabCut took less what is more like the
    row beside the box than like the tree (:func:`apart_from_rows`); its largest piece;
    checked as every silhouette is.

    Examples
    --------
    >>> rgb = np.ones((60, 50, 3)) * [0.8, 0.9, 1.0]
    >>> yy, xx = np.mgrid[0:60, 0:50]
    >>> rgb[(yy - 25) ** 2 + (xx - 25) ** 2 < 100] = [0.2, 0.4, 0.1]  # a crown
    >>> rgb[30:50, 24:27] = [0.4, 0.3, 0.2]                             # its trunk
    >>> keep = np.zeros((60, 50), bool); keep[10:55, 10:40] = True      # --box 10,10,40,55
    >>> seg = in_box(rgb, keep, None, {"box": [10, 10, 40, 55]}, 1.0, "tree.jpg", 0.0)
    >>> seg.method, bool(seg.tree[25, 25]), bool(seg.tree[45, 25]), bool(seg.tree[5, 5])
    ('GrabCut in the box', True, True, False)
    """
    import cv2
    from skimage.color import rgb2lab

    h, w = keep.shape
    f = min(1.0, np.sqrt(BOX_GRABCUT_PIXELS / max(1, int(keep.sum()))),
            np.sqrt(BOX_PICTURE_PIXELS / (h * w)))  # fmt: skip
    size = (max(2, round(w * f)), max(2, round(h * f)))
    small = cv2.resize(np.ascontiguousarray(rgb, dtype=np.float32), size,
                       interpolation=cv2.INTER_AREA) if f < 1.0 else rgb  # fmt: skip
    box = cv2.resize(keep.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST) > 0
    mask = np.where(box, cv2.GC_PR_FGD, cv2.GC_BGD).astype(np.uint8)
    lab = rgb2lab(np.clip(small, 0, 1))
    beside = _row_background(lab, box)
    mask[box & (beside < BOX_BACKGROUND_DE)] = cv2.GC_PR_BGD
    if sky is not None:
        mask[cv2.resize(sky.astype(np.uint8), size, interpolation=cv2.INTER_NEAREST) > 0] = (
            cv2.GC_BGD
        )
    if not (mask == cv2.GC_BGD).any():
        mask[[0, -1], :] = cv2.GC_BGD
        mask[:, [0, -1]] = cv2.GC_BGD
    if not (mask == cv2.GC_PR_FGD).any():  # every pixel in the box is like its row beside
        mask[box & (mask == cv2.GC_PR_BGD)] = cv2.GC_PR_FGD  # it: GrabCut from the box alone
    if not (mask == cv2.GC_PR_FGD).any():
        raise UserInputError(
            f"{name}: the box holds nothing but the sky: give the box around the tree"
        )
    img = np.ascontiguousarray(np.round(255 * np.clip(small, 0, 1)[..., ::-1]).astype(np.uint8))
    bgd, fgd = np.zeros((1, 65)), np.zeros((1, 65))
    cv2.setRNGSeed(0)
    cv2.grabCut(img, mask, None, bgd, fgd, GRABCUT_ITERATIONS, cv2.GC_INIT_WITH_MASK)
    fg = apart_from_rows(lab, (mask == cv2.GC_FGD) | (mask == cv2.GC_PR_FGD), beside)
    if f < 1.0:
        fg = cv2.resize(fg.astype(np.uint8), (w, h), interpolation=cv2.INTER_LINEAR) > 0
    fg &= keep
    tree = largest_piece(fg)
    how = "GrabCut in the box"
    if not tree.any():
        raise UserInputError(f"{name}: the silhouette is empty ({how})")
    seg = Segmentation(
        tree, np.zeros((h, w), dtype=bool), None, np.zeros((h, w)), 0.0, 0.0, 0.0,
        np.where(tree, 1.0, 0.0), sky=None, band=None, cut=None, objects=(), hint=hint,
        method="GrabCut in the box", seconds=time.perf_counter() - t_start,
        hint_scale=per_pixel,
    )  # fmt: skip
    edges = (("top", int(tree[0].sum())), ("left", int(tree[:, 0].sum())),
             ("right", int(tree[:, -1].sum())))  # fmt: skip
    settle = BOXED_AT_EDGE
    seg = judge_edges(seg, edges, True, name, settle, how)
    check_silhouette(tree, keep, name=name, how=how)
    return seg
