"""The trunk below the cut: GrabCut in the standing object's columns, seeded by the crown
above (:func:`below_cut`), the trunk's columns read against the row beside them, a trunk
hidden behind the horizon's clutter bridged over; a crown's trunk of the sky's colour
(:func:`hanging_trunk`). Its foot, traced down to and trimmed at, is
:mod:`growsim.pictures.foot`'s.
"""

from __future__ import annotations

import numpy as np

from growsim.pictures.backdrop import row_background
from growsim.pictures.colours import background_coloured
from growsim.pictures.coverage import MIN_DE, robust_sigma, tree_cover
from growsim.pictures.crown import row_spans
from growsim.pictures.reading import SPECK
from growsim.pictures.scene import runs, trunk_feet

__all__ = ["below_cut", "hanging_trunk"]

#: below the cut: GrabCut in the standing object's columns and this share of its width
#: either side (the ground's and clutter's colours), so many iterations
BELOW_MARGIN = 0.15
GRABCUT_ITERATIONS = 5
#: ... down to this share of the tree's height (of its width, when wider, for a crown the
#: horizon was found under: its trunk may reach farther below the horizon than half the
#: crown's height) below the cut's lowest row, on at most this
#: many pixels (a larger window is reduced for it)
BELOW_DEPTH = 0.5
#: ... and, for such a crown, whose feet span its width, its trunk is looked for under the
#: middle of it: the feet less this share of its width on each side (its wings hang over
#: the horizon)
WINGS = 0.2
GRABCUT_PIXELS = 30_000
#: ... and differing from the row's colour beside the tree by more than this many times
#: that colour's spread along the row (robust sigma), at least MIN_DE
ROW_K = 3.0
#: the trunk's columns below the cut (its feet there, widened by this share of their width
#: either side, at least FOOT_MARGIN_MIN pixels) are read against the row's colour within
#: FOOT_REACH pixels beside them
FOOT_MARGIN, FOOT_MARGIN_MIN, FOOT_REACH = 0.5, 3, 6
#: ... or taken by GrabCut and differing from it by more than this (Delta E)
FOOT_DE = 15.0
#: the trunk, hidden behind the horizon's clutter (a hedge of its colour), is bridged over
#: gaps of up to this share of the tree's height
TRUNK_GAP = 0.4
#: ... to a piece below the gap at least this share of the gap tall (the trunk seen
#: again below the clutter, not a speck of the ground far below its foot)
HIDDEN_SEEN = 1 / 3
#: ... when its foot above the gap is at most this share of the crown's width, and the
#: piece below the gap less than FLAT_PIECE times as wide as it is tall (else a shadow or
#: a patch of ground; a trunk's stub below a hedge may be twice as wide as tall)
TRUNK_WIDTH, FLAT_PIECE = 0.3, 3.0
#: a run of the trunk's columns wider than TRUNK_WIDTH of the tree's width (the crown's low
#: side resting on the band, not a trunk): only what stands at least this share of the
#: tree's height tall (STAND_MIN pixels at least) is kept of its reading there
STAND, STAND_MIN = 0.05, 5


def below_cut(rgb, tree, below, sky, obj, scale, keep):
    """The tree's pixels below the cut (``below``): GrabCut (OpenCV) in the columns of the
    standing object ``obj`` (and :data:`BELOW_MARGIN` of its width either side), seeded
    with the tree found above the cut (``tree``) as sure foreground, the ``sky`` and
    the columns either side below the cut as sure background, the columns where the tree
    enters the band as probable foreground. What it takes that looks like the row's
    ground or clutter beside the tree (within :data:`ROW_K` times that row's spread) is
    dropped; in the trunk's columns each pixel is read against the row just beside them
    (:func:`tree_cover`, as the crown against the sky; in a run of them as wide as a good
    part of the crown, only what stands :data:`STAND` of the tree's height tall: not the
    stripes of the rows beside); outside the feet's columns, the
    pieces of the clutter's colours, not the crown's, are dropped too
    (:func:`~growsim.pictures.colours.background_coloured`: a hedge's or treeline's top
    beside the trunk, where the row beside it is half sky), and in them what is wider in
    its row than :data:`TRUNK_WIDTH` of the crown (the grass under a crown hanging below
    the band, read against a road beside it); and in each row, what runs on
    from the window's side outside the object's columns (the clutter running on past it:
    a treeline's top along the band: :func:`_not_running_past`). Returns ``(tree,
    spill)``: what joins the tree above (a trunk hidden by a hedge of its colour bridged
    over up to :data:`TRUNK_GAP` of the tree's height, :func:`_hidden_trunk`; a trunk's
    rows filled across), and the share of those rows where it reaches both sides of the
    object's columns (a wood behind it).

    Examples
    --------
    >>> from growsim.pictures.scene import find_scene
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> scene = find_scene(rgb, np.ones((60, 50), bool))
    >>> below = np.arange(60)[:, None] >= scene.cut[None, :]     # rows 44 and lower
    >>> tree = (rgb[..., 0] == 0.4) & ~below                     # the crown found above
    >>> low, spill = below_cut(rgb, tree, below, scene.sky & ~below, scene.objects[0], 1.0,
    ...                        np.ones((60, 50), bool))
    >>> int(low.sum()), int(low.any(axis=1).nonzero()[0].max()), spill  # the trunk to 54
    (33, 54, 0.0)
    """
    import cv2
    from scipy import ndimage
    from skimage.color import rgb2lab
    from skimage.measure import label

    h, w = tree.shape
    k = 1.0 / scale
    rows = np.nonzero(tree.any(axis=1))[0]
    height = rows.max() - rows.min() + 1
    width = (obj.right - obj.left + 1) * k
    m = max(8, int(BELOW_MARGIN * width))
    x0, x1 = max(0, int(obj.left * k) - m), min(w, int((obj.right + 1) * k) + m)
    cols = np.arange(x0, x1)
    top = int(np.nonzero(below[:, cols].any(axis=1))[0].min()) if below[:, cols].any() else h
    y0 = max(0, top - max(8, int(0.15 * height)))
    lowest = int(np.ceil(np.max(np.argmax(below[:, cols], axis=0))))
    reach = max(height, width) if obj.lifted else height
    y1 = min(h, lowest + int(BELOW_DEPTH * reach) + 1)
    if y0 >= y1 - 1:
        return np.zeros((h, w), dtype=bool), 0.0
    win = (slice(y0, y1), slice(x0, x1))
    under, seed, kept = below[win], tree[win], keep[win]
    mask = np.full(under.shape, cv2.GC_PR_BGD, dtype=np.uint8)
    mask[sky[win]] = cv2.GC_BGD
    mask[~under & seed] = cv2.GC_FGD
    feet = np.zeros(w, dtype=bool)
    wing = int(WINGS * (obj.right - obj.left + 1)) if obj.lifted else 0
    for a, b in obj.feet:
        a, b = max(a, obj.left + wing), min(b, obj.right - wing)
        feet[int(a * k) : int(np.ceil((b + 1) * k))] = True
    mask[under & feet[None, x0:x1]] = cv2.GC_PR_FGD
    inside = np.zeros(w, dtype=bool)
    inside[int(obj.left * k) : int(np.ceil((obj.right + 1) * k))] = True
    mask[under & ~inside[None, x0:x1]] = cv2.GC_BGD
    mask[~kept] = cv2.GC_BGD
    if not (mask == cv2.GC_FGD).any() or not (mask == cv2.GC_BGD).any():
        return np.zeros((h, w), dtype=bool), 0.0
    img = np.ascontiguousarray(np.round(255 * rgb[win][..., ::-1]).astype(np.uint8))
    size = mask.shape[::-1]
    f = min(1.0, np.sqrt(GRABCUT_PIXELS / mask.size))
    if f < 1.0:  # a large window: GrabCut on it reduced, its answer enlarged again
        small = (max(2, round(size[0] * f)), max(2, round(size[1] * f)))
        img = cv2.resize(img, small, interpolation=cv2.INTER_AREA)
        mask = cv2.resize(mask, small, interpolation=cv2.INTER_NEAREST)
        if not np.isin(mask, (cv2.GC_FGD, cv2.GC_PR_FGD)).any():  # a seed too small for it
            return np.zeros((h, w), dtype=bool), 0.0
    bgd, fgd = np.zeros((1, 65)), np.zeros((1, 65))
    cv2.setRNGSeed(0)
    cv2.grabCut(img, mask, None, bgd, fgd, GRABCUT_ITERATIONS, cv2.GC_INIT_WITH_MASK)
    if f < 1.0:
        mask = cv2.resize(mask, size, interpolation=cv2.INTER_NEAREST)
    fg = ((mask == cv2.GC_FGD) | (mask == cv2.GC_PR_FGD)) & under & kept
    # what GrabCut took but looks like the row's ground or clutter either side of the
    # tree's columns (a hedge, a treeline running behind it) is not the tree, but in the
    # feet's columns (the trunk, hidden or not, is bridged below)
    lab = rgb2lab(rgb[win])
    a, b = int(obj.left * k) - x0, int(np.ceil((obj.right + 1) * k)) - x0 - 1
    rows_bg = row_background(lab, max(a, 0), min(b, x1 - x0 - 1), slice(None), reach=m)
    d_row = np.zeros(under.shape)
    d_row[:, max(a, 0) : min(b, x1 - x0 - 1) + 1] = np.linalg.norm(
        lab[:, max(a, 0) : min(b, x1 - x0 - 1) + 1] - rows_bg, axis=-1
    )
    flanks = under & ~inside[None, x0:x1]
    spread = np.linalg.norm(lab - np.median(lab, axis=1, keepdims=True), axis=-1)
    row_noise = robust_sigma(spread[flanks]) if flanks.any() else 0.0
    taken = fg.copy()
    fg &= d_row > max(MIN_DE, ROW_K * row_noise)
    # the trunk's columns: told apart from the row's ground or clutter just beside them
    # pixel by pixel, as the crown from the sky (thresholds, unmixing: its outline exact)
    widened = np.zeros(x1 - x0, dtype=bool)
    for fa, fb in runs(np.nonzero(feet[x0:x1])[0]):
        fm = max(FOOT_MARGIN_MIN, int(FOOT_MARGIN * (fb - fa + 1)))
        widened[max(0, fa - fm) : fb + fm + 1] = True
    for za, zb in runs(np.nonzero(widened)[0]):
        zone = under[:, za : zb + 1]
        back = row_background(lab, za, zb, slice(None), reach=FOOT_REACH)
        part = (slice(None), slice(za, zb + 1))
        d = np.linalg.norm(lab[part] - back, axis=-1)
        local = lab[:, max(0, za - FOOT_REACH) : zb + 1 + FOOT_REACH]
        noise = robust_sigma(
            np.linalg.norm(local - np.median(local, axis=1, keepdims=True), axis=-1)[
                under[:, max(0, za - FOOT_REACH) : zb + 1 + FOOT_REACH]
            ]
        )
        trunk, _, _ = tree_cover(rgb[win][part], lab[part], back, d, max(noise, 0.25), zone)
        # on a textured ground (stripes of a field) the thresholds may miss it: what
        # GrabCut took there and differs from the row beside it clearly stays
        trunk |= taken[part] & (d > FOOT_DE)
        if zb - za + 1 > TRUNK_WIDTH * width:
            # read against the row beside so wide a run, the rows of a treeline or a field
            # whose colour changes along them (a field's rows at a slant, a wood, a lawn
            # and a sky) come out as stripes: only what stands tall stays (a trunk, a limb)
            stand = max(STAND_MIN, int(STAND * height))
            trunk = ndimage.binary_opening(trunk, np.ones((stand, 1), dtype=bool))
        fg[part] = np.where(zone, trunk, fg[part])
    # and the pieces of the clutter's colours, not the tree's (a treeline's or a hedge's
    # top beside the trunk, where the row beside it is half sky), but in the feet's columns
    sure = ndimage.binary_erosion(seed, np.ones((3, 3), dtype=bool)) & ~under
    # (a run of feet as wide as a good part of the crown is its low side resting on the
    # band: there only what is narrow in its row is spared, a trunk, not the ground under
    # the crown taken across it)
    spared = feet[None, x0:x1] & ~ndimage.binary_opening(
        fg, np.ones((1, max(3, int(TRUNK_WIDTH * width))), dtype=bool)
    )
    fg &= ~(background_coloured(lab, fg, flanks & kept, under, sure) & ~spared)
    parts = label(fg | seed, connectivity=2)
    joined = np.isin(parts, np.unique(parts[seed])) & fg
    joined |= _hidden_trunk(fg & ~joined, seed | joined, under, TRUNK_GAP * height,
                            TRUNK_WIDTH * width)  # fmt: skip
    # a trunk is solid across: in the trunk's columns (a zone as narrow as a trunk) each
    # row's tree runs from its leftmost to its rightmost pixel (where the hedge behind is
    # of its colour, part of a row is missed)
    for za, zb in runs(np.nonzero(widened)[0]):
        if zb - za + 1 <= TRUNK_WIDTH * width:
            part = (slice(None), slice(za, zb + 1))
            joined[part] |= row_spans(joined[part]) & under[part]
    joined = _not_running_past(joined, inside[x0:x1], seed)
    # the spill: the rows below the cut where what was taken reaches the object's sides
    span = inside[x0:x1]
    first, last = int(np.argmax(span)), len(span) - 1 - int(np.argmax(span[::-1]))
    reach = 2 + int(0.02 * width)
    sides = joined[:, first : first + reach].any(axis=1) & joined[:, last - reach + 1 :].any(axis=1)
    taken = np.nonzero(joined.any(axis=1) & under.any(axis=1))[0]
    spill = float(sides[taken].mean()) if len(taken) else 0.0
    out = np.zeros((h, w), dtype=bool)
    out[win] = joined
    return out, spill


def _not_running_past(taken, inside, seed):
    """``taken`` (below the cut, in a window) less, in each row, the run from the window's
    left or right side outside the object's columns (``inside``, per column): the clutter
    running on past the window (a treeline's top along the band, joined to the crown's low
    side), and what no longer joins ``seed`` (the tree above the cut) then.

    Examples
    --------
    >>> taken = np.zeros((6, 12), bool); taken[3, :] = True        # a strip to both sides
    >>> taken[3:, 5:7] = True                                       # the trunk under it
    >>> seed = np.zeros((6, 12), bool); seed[:3, 3:9] = True        # the crown above
    >>> inside = np.zeros(12, bool); inside[3:9] = True
    >>> out = _not_running_past(taken, inside, seed)
    >>> out[3].astype(int).tolist(), bool(out[5, 5:7].all())
    ([0, 0, 0, 1, 1, 1, 1, 1, 1, 0, 0, 0], True)
    >>> low = np.zeros((6, 12), bool); low[3, 1:11] = True          # not reaching a side
    >>> bool(_not_running_past(low, inside, seed)[3, 1])
    True
    """
    from skimage.measure import label

    edge = np.cumprod(taken, axis=1) | np.cumprod(taken[:, ::-1], axis=1)[:, ::-1]
    past = edge.astype(bool) & ~inside[None, :]
    if not past.any():
        return taken
    parts = label((taken & ~past) | seed, connectivity=2)
    return taken & ~past & np.isin(parts, np.unique(parts[seed & (parts > 0)]))


def _hidden_trunk(loose, tree, under, reach, widest=np.inf):
    """A trunk hidden for a stretch (by a hedge of its colour): the largest piece of
    ``loose`` below the foot of ``tree`` (in the rows ``under``) that starts at most
    ``reach`` rows lower, under it (shifted by at most the narrower one's width),
    about as wide and at least :data:`HIDDEN_SEEN` of that stretch tall (a speck of the
    ground far below a foot on the skyline is no trunk seen again), joined to it by the
    straight trunk between them; nothing when there is none, when the foot is wider than
    ``widest`` (the crown reaches down there), or when the largest such piece is
    :data:`FLAT_PIECE` times as wide as it is tall or more (a shadow or a patch of
    ground, not a trunk; a smaller piece then is the clutter's).

    Examples
    --------
    >>> tree = np.zeros((30, 10), bool); tree[:8, 4:6] = True
    >>> loose = np.zeros((30, 10), bool); loose[20:, 4:7] = True
    >>> under = np.zeros((30, 10), bool); under[8:] = True
    >>> out = _hidden_trunk(loose, tree, under, 15)
    >>> bool(out[8:20, 4:6].all()), bool(out[20:, 4:7].all()), bool(out[:8].any())
    (True, True, False)
    >>> weeds = np.zeros((30, 30), bool); weeds[20:, 12:20] = True  # off to the side
    >>> wide = np.zeros((30, 30), bool); wide[:8, 4:6] = True; under = np.zeros_like(wide)
    >>> under[8:] = True
    >>> bool(_hidden_trunk(weeds, wide, under, 15).any())
    False
    >>> shadow = np.zeros((30, 10), bool); shadow[20:22, 0:10] = True  # flat: a shadow
    >>> bool(_hidden_trunk(shadow, tree, np.arange(30)[:, None] >= 8, 15).any())
    False
    """
    from skimage.measure import label, regionprops

    out = np.zeros(tree.shape, dtype=bool)
    mine = tree & ~under
    rows = np.nonzero(mine.any(axis=1))[0]
    if not len(rows) or not loose.any():
        return out
    rb = int(rows.max())
    foot = mine[max(0, rb - 2) : rb + 1].any(axis=0)
    best = None
    for p in regionprops(label(loose, connectivity=2)):
        rt = p.bbox[0]
        if rt <= rb or rt - rb > reach or p.area < SPECK:
            continue
        if p.bbox[2] - rt < HIDDEN_SEEN * (rt - rb):
            continue  # seen too little below so long a stretch: a speck of the ground
        top = p.coords[p.coords[:, 0] < rt + 5]
        c, d = int(top[:, 1].min()), int(top[:, 1].max())
        # the foot above it: the tree's lowest pixels over its columns, the run of the
        # foot's columns that overlaps it most (not the specks beside), shifted from it
        # by at most the narrower one's width (a trunk leans; weeds beside it are not it)
        spans = []
        for f, e in runs(np.nonzero(foot)[0]):
            slack = max(2, min(d - c, e - f))
            if e >= c - slack and f <= d + slack:
                spans.append((min(e, d) - max(f, c), f, e))
        if not spans:
            continue
        _, a, b = max(spans)
        if b - a + 1 > widest or b - a > 3 * (d - c) + 6 or d - c > 3 * (b - a) + 6:
            continue  # the crown reaches down there, or it is no trunk below it
        if best is None or p.area > best[4]:  # the trunk, not a speck of the clutter
            best = (rt, c, d, p.coords, p.area, a, b, p.bbox)
    # the largest flat: a shadow or a patch of ground, and what is smaller the clutter's
    if best is None or best[7][3] - best[7][1] >= FLAT_PIECE * (best[7][2] - best[0]):
        return out
    rt, c, d, coords, _, a, b, _ = best
    for r in range(rb + 1, rt):
        t = (r - rb) / (rt - rb)
        lo, hi = round((1 - t) * a + t * c), round((1 - t) * b + t * d)
        out[r, lo : hi + 1] = True
    out[coords[:, 0], coords[:, 1]] = True
    return out & under


def hanging_trunk(rgb, tree, obj, cut, scale):
    """The trunk of a crown hanging in the sky (``obj.hanging``: the sky's colour took
    its trunk, :func:`~growsim.pictures.scene.find_scene`), between the crown found
    (``tree``) and the ``cut`` (rows per column): among the columns of its foot
    (``obj.feet``, coarse, ``scale`` coarse pixels a pixel), the trunk's just below the
    cut (:func:`~growsim.pictures.scene.trunk_feet`), straight up to the crown's lowest
    pixel over them, as a trunk hidden by a hedge of its colour is bridged
    (:func:`below_cut`). Nothing when there is no such run.

    Examples
    --------
    >>> from growsim.pictures.scene import Standing
    >>> rgb = np.ones((40, 30, 3)) * [0.8, 0.9, 1.0]; rgb[30:] = [0.3, 0.5, 0.2]
    >>> rgb[12:36, 14:17] = [0.8, 0.9, 1.0]                 # a trunk of the sky's colour
    >>> tree = np.zeros((40, 30), bool); tree[2:12, 8:23] = True       # the crown above
    >>> obj = Standing(tree, 150, 2, 29, 8, 22, ((13, 17),), hanging=True)
    >>> out = hanging_trunk(rgb, tree, obj, np.full(30, 30.0), 1.0)
    >>> bool(out[12:30, 14:17].all()), bool(out[12:30, :14].any() or out[:12].any())
    (True, False)
    """
    from skimage.color import rgb2lab

    h, w = tree.shape
    out = np.zeros((h, w), dtype=bool)
    if not obj.hanging or not obj.feet:
        return out
    k = 1.0 / scale
    fa, fb = max(obj.feet, key=lambda f: f[1] - f[0])
    a, b = max(0, int(fa * k) - 2), min(w - 1, int(np.ceil((fb + 1) * k)) + 1)
    r = int(np.ceil(np.median(cut[a : b + 1])))
    rows = slice(min(r, h - 1), min(h, r + max(3, int(2 * k))))
    if rows.stop <= rows.start:
        return out
    found = trunk_feet(rgb2lab(rgb[rows]), slice(None), a, b, reach=FOOT_REACH)
    if not found:
        return out
    lo, hi = found[0][0], found[0][1] + 1
    over = np.flatnonzero(tree[:r, lo:hi].any(axis=1))
    if not len(over):
        return out
    out[over.max() + 1 : r, lo:hi] = True
    return out
