"""The trunk below the cut: GrabCut in the standing object's columns, seeded by the crown
above (:func:`below_cut`), the trunk's columns read against the row beside them, a trunk
hidden behind the horizon's clutter bridged over, and a trunk that stops short (or is
seen only below the crown) carried on down along its two edges (:func:`traced_trunk`).
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.trunk import FORBIDDEN, edge_pair_scores, trace_path
from growsim.pictures.backdrop import row_background
from growsim.pictures.colours import background_coloured
from growsim.pictures.coverage import MIN_DE, robust_sigma, tree_cover
from growsim.pictures.crown import row_spans
from growsim.pictures.reading import SPECK
from growsim.pictures.scene import runs, trunk_feet

__all__ = ["below_cut", "hanging_trunk", "traced_trunk", "trim_foot"]

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
#: the trunk carried down (:func:`traced_trunk`): its foot, the silhouette's lowest rows
#: up to this share of the tree's height, each a run overlapping the one below it and
#: narrower than TRUNK_WIDTH of the tree's width, at least FOOT_MIN of its height of them
FOOT_UP, FOOT_MIN = 0.12, 0.05
#: ... followed down at most this share of the tree's height, in a corridor this many
#: widths of the foot either side of it, widening by LEAN pixels a row (a leaning trunk)
TRACE_DEPTH, TRACE_SIDE, LEAN = 0.7, 2.0, 0.4
#: ... as a trunk 0.6-1.6 times the foot's width (its 30th percentile of widths: not a
#: block of clutter joined to it), whose two edges are the colour change across a
#: column (Sobel, Delta E) over the window's median, at least EDGE_FLOOR (a smooth ground's
#: noise is no edge), at most EDGE_CAP; its inside's mean colour within GATE spreads of
#: the foot's mean colour (the foot's median distance from it, at least 2 Delta E)
TRACE_WIDTHS, EDGE_FLOOR, EDGE_CAP, GATE = (0.6, 1.6), 12.0, 4.0, 3.0
#: ... each row's score the weaker edge twice less the colour distance (capped at
#: D_CAP), less the TRACE_Q quantile of every state's score and TRACE_MARGIN: a path
#: gains only where a trunk's two edges are clearly there; a step aside costs SHIFT a
#: column and WIDEN a width; a path shorter than TRACE_MIN of the height is none
D_CAP, TRACE_Q, TRACE_MARGIN, SHIFT, WIDEN, TRACE_MIN = 6.0, 0.8, 1.0, 1.5, 0.3, 0.03
#: ... over at most this many states (rows x columns x widths: 9 bytes each)
TRACE_STATES = 12_000_000
#: the trunk's foot (:func:`trim_foot`): its waist, the lowest of the first WAIST_ROWS or
#: more consecutive rows, in the silhouette's lowest WAIST_ZONE of its height, that are one
#: run (gaps up to WAIST_GAP pixels) narrower than TRUNK_WIDTH of the tree's width; below
#: it, a piece reaching out of the trunk (its width and FLARE of it either side, at least
#: 2 pixels) at least FLAT times as wide as it is tall, and as wide as the trunk, is ground
WAIST_ZONE, WAIST_ROWS, WAIST_GAP, FLARE, FLAT = 0.15, 3, 2, 0.5, 2.0
#: a trunk hidden under the lower crown (the silhouette ends in no trunk,
#: :func:`_hidden_foot`): looked for under the crown's columns between these percentiles
#: of its pixels', this share of the tree's width wide, its weaker edge averaging at least
#: HIDDEN_EDGE (twice its edge over the window's median, capped at EDGE_CAP) over its first
#: FOOT_MIN of the tree's height
HIDDEN_SPAN, HIDDEN_WIDTHS, HIDDEN_EDGE, HIDDEN_TRIES = (15, 85), (0.02, 0.15), 4.0, 100


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


def _foot(tree, rows_up, widest):
    """The trunk's foot: from the silhouette's lowest row up to ``rows_up`` rows, each
    row's run overlapping the one below it (the widest in the lowest row), while narrower
    than ``widest``. Returns ``(rows, centres, widths)``, lowest first."""
    rows = np.flatnonzero(tree.any(axis=1))
    out, prev = [], None
    for y in range(rows.max(), max(rows.min(), rows.max() - rows_up) - 1, -1):
        spans = runs(np.flatnonzero(tree[y]))
        if prev is not None:
            spans = [s for s in spans if min(s[1], prev[1]) >= max(s[0], prev[0])]
        if not spans:
            break
        a, b = max(
            spans,
            key=lambda s: s[1] - s[0] if prev is None else min(s[1], prev[1]) - max(s[0], prev[0]),
        )
        if b - a + 1 > widest:
            break
        out.append((y, (a + b) / 2, b - a + 1))
        prev = (a, b)
    return [np.array(v) for v in zip(*out)] if out else [np.zeros(0)] * 3


def _seen_foot(rgb, tree):
    """Where the trace starts when the silhouette ends in a trunk (:func:`_foot`): ``(row
    below it, centre column, width, mean colour, spread)``, or None."""
    from skimage.color import rgb2lab

    rows, cols = np.flatnonzero(tree.any(axis=1)), np.flatnonzero(tree.any(axis=0))
    height, width = rows.max() - rows.min() + 1, cols.max() - cols.min() + 1
    ys, xs, ws = _foot(tree, max(8, int(FOOT_UP * height)), TRUNK_WIDTH * width)
    n_foot = max(4, int(FOOT_MIN * height))
    if len(ys) < n_foot:
        return None
    # the trunk's colour: its foot, a pixel in from each side
    foot = np.concatenate([rgb[y, round(x - d / 2) + 1 : round(x + d / 2) - 1]
                           for y, x, d in zip(ys, xs, ws)])  # fmt: skip
    if len(foot) < 4:
        return None
    mean, spread = _colour(rgb2lab(foot[None])[0])
    centre, wide = float(np.median(xs[:n_foot])), float(np.percentile(ws, 30))
    return int(rows.max()) + 1, centre, wide, mean, spread


def _hidden_foot(rgb, tree, open_):
    """Where the trace starts when the silhouette ends in a crown (no :func:`_foot`): a
    trunk coming out from under the crown's middle (the columns between the
    :data:`HIDDEN_SPAN` percentiles of its pixels'), :data:`HIDDEN_WIDTHS` of its width
    wide, straight down :data:`FOOT_MIN` of its height from the crown's lowest pixel over
    it, through pixels ``open_`` (below the cut, allowed): the one whose two edges are
    clearest, when its weaker edge averages :data:`HIDDEN_EDGE` at least. Returns
    ``(first row, centre column, width, mean colour, spread)``, or None."""
    from skimage.color import rgb2lab

    h, w = tree.shape
    rows, cols = np.nonzero(tree)
    height, width = rows.max() - rows.min() + 1, cols.max() - cols.min() + 1
    lo, hi = (int(v) for v in np.percentile(cols, HIDDEN_SPAN))
    dmin = max(3, round(HIDDEN_WIDTHS[0] * width))
    dmax = max(dmin + 2, round(HIDDEN_WIDTHS[1] * width))
    n = max(4, int(FOOT_MIN * height))
    has = tree.any(axis=0)
    bottom = np.where(has, h - 1 - np.argmax(tree[::-1], axis=0), -1)
    mid = bottom[lo : hi + 1]
    if not (mid >= 0).any():
        return None
    x0, x1 = max(0, lo - dmax), min(w, hi + dmax + 1)
    y0, y1 = int(mid[mid >= 0].min()) + 1, min(h, int(mid.max()) + 2 + n)
    if y1 - y0 < n:
        return None
    lab = rgb2lab(rgb[max(0, y0 - 2) : y1, x0:x1])
    edge = _edges(lab, y0 - max(0, y0 - 2))
    lab = lab[y0 - max(0, y0 - 2) :]
    step = max(1, -(-(dmax - dmin + 1) * lab.shape[0] * lab.shape[1] // TRACE_STATES))
    nk = (dmax - dmin) // step + 1
    cum = np.zeros((lab.shape[0], lab.shape[1] + 1, 3))
    cum[:, 1:] = np.cumsum(lab, axis=1)
    score = edge_pair_scores(np.ascontiguousarray(edge), cum, np.array([0.0, 0.0, 0.0, 1.0]),
                             (dmin, nk, step), (EDGE_CAP, 0.0, D_CAP, np.inf))  # fmt: skip
    score[~open_[y0:y1, x0:x1]] = FORBIDDEN
    sums = np.cumsum(score, axis=0, out=score)  # each state's score summed down to it
    low = bottom[x0:x1]
    found = []
    for k in range(nk):
        d = dmin + k * step
        # each centre's trunk: its columns' crown's lowest pixel, the first row below it
        padded = np.pad(low, (d // 2, d), constant_values=-1)
        span = np.lib.stride_tricks.sliding_window_view(padded, d)
        first = span.max(axis=1)[: len(low)] + 1 - y0
        inside = (span.min(axis=1)[: len(low)] >= 0) & (np.arange(len(low)) >= lo - x0)
        inside &= (np.arange(len(low)) <= hi - x0) & (first >= 0) & (first + n <= score.shape[0])
        cs = np.flatnonzero(inside)
        above = np.where(first[cs] > 0, sums[np.maximum(first[cs] - 1, 0), cs, k], 0.0)
        gain = (sums[first[cs] + n - 1, cs, k] - above) / n
        found += [(g, first[c], c, d) for g, c in zip(gain, cs) if g >= HIDDEN_EDGE]
    # the clearest (the widest of equals: a trunk's edges, just outside it, are also
    # inside a narrower one's) whose sides hold none of the silhouette (not a piece of
    # ground beside a trunk the silhouette has) and whose inside stands out from each side
    # (by more than that side's spread: not a stretch of a textured ground between two of
    # its edges)
    for _, r, c, d in sorted(found, key=lambda f: (-f[0], -f[3]))[:HIDDEN_TRIES]:
        a = c - d // 2
        if tree[y0 + r + n // 2 : y0 + r + n, max(0, x0 + a - 2 * d) : x0 + a + 3 * d].any():
            continue
        # ... and over it a crown, not the foot of a trunk the silhouette has
        over = tree[max(0, y0 + r - 2 * n) : y0 + r].any(axis=0)
        if not any(e - f + 1 > TRUNK_WIDTH * width and f <= x0 + c <= e
                   for f, e in runs(np.flatnonzero(over))):  # fmt: skip
            continue
        mean, spread = _colour(lab[r : r + n, a + 1 : a + d - 1].reshape(-1, 3))
        sides = [lab[r : r + n, max(0, a - d) : a - 1], lab[r : r + n, a + d + 1 : a + 2 * d]]
        if all(_stands_out(mean, side.reshape(-1, 3)) for side in sides):
            break
    else:
        return None
    return y0 + int(r), float(x0 + c), float(d), mean, spread


def _colour(pixels):
    """A trunk's colour from its ``pixels`` (``(n, 3)``, Lab): their mean, and their
    spread (the median distance from it, at least 2 Delta E)."""
    mean = pixels.mean(axis=0)
    return mean, max(float(np.median(np.linalg.norm(pixels - mean, axis=1))), 2.0)


def _stands_out(mean, side):
    """Whether colour ``mean`` lies farther from the mean of ``side`` (pixels' colours)
    than they do (their median distance from it), and at least :data:`MIN_DE`."""
    if len(side) < 2:
        return False
    centre, spread = _colour(side)  # (its floor of 2 lies under MIN_DE)
    return float(np.linalg.norm(mean - centre)) > max(spread, MIN_DE)


def _edges(lab, skip):
    """The colour change across each column of ``lab`` (Sobel, Delta E), its first
    ``skip`` rows dropped, averaged over three rows, over the window's median (at least
    :data:`EDGE_FLOOR`)."""
    from scipy import ndimage

    edge = np.sqrt(sum(ndimage.sobel(lab[..., i], axis=1) ** 2 for i in range(3)))
    edge = ndimage.uniform_filter1d(edge[skip:], 3, axis=0)
    return edge / max(float(np.median(edge)), EDGE_FLOOR)


def traced_trunk(rgb, tree, under, keep):
    """The trunk below the silhouette's lowest row, where it stops short of its foot: its
    two edges followed down (:func:`growsim.kernels.trunk.trace_path`, a path of most
    gain through the rows, each a trunk centred on a column with a width,
    :func:`growsim.kernels.trunk.edge_pair_scores`), from the silhouette's foot (its
    lowest narrow rows: a trunk, :data:`FOOT_UP`), in a corridor widening below it; a row
    gains where both edges are clear and the inside is of the foot's colours
    (:data:`GATE`); the path ends where it gains most. Only pixels below the cut
    (``under``), allowed (``keep``) and not already ``tree`` are returned. When the
    silhouette has no foot (its lowest rows as wide as a crown), the trace starts from a
    trunk seen coming out under the crown (:func:`_hidden_foot`); nothing when there is
    none.

    Examples
    --------
    >>> rgb = np.ones((60, 40, 3)) * [0.55, 0.75, 0.35]; rgb[:30] = [0.7, 0.8, 0.95]
    >>> rgb[5:20, 8:32] = [0.2, 0.4, 0.15]; rgb[20:50, 18:23] = [0.35, 0.25, 0.2]
    >>> tree = np.zeros((60, 40), bool); tree[5:20, 8:32] = True    # the crown found,
    >>> tree[20:34, 18:23] = True                                   # the trunk to row 33
    >>> under = np.zeros((60, 40), bool); under[30:] = True         # below the cut
    >>> out = traced_trunk(rgb, tree, under, np.ones((60, 40), bool))
    >>> bool(out[34:50, 18:23].all()), int(out.sum()) == 16 * 5    # on down to its foot
    (True, True)
    >>> rgb[36:50, 18:23] = [0.55, 0.75, 0.35]     # a shorter trunk, rows 20 to 35, under
    >>> crown = tree & (np.arange(60)[:, None] < 20)   # the crown found, hanging below the
    >>> under[15:30] = True                            # cut: no foot; the trunk seen under it
    >>> out = traced_trunk(rgb, crown, under, np.ones((60, 40), bool))
    >>> bool(out[20:36, 18:23].all()), int(out.sum()) == 16 * 5
    (True, True)
    """
    from skimage.color import rgb2lab

    h, w = tree.shape
    none = np.zeros((h, w), dtype=bool)
    if not (tree & ~under).any():
        return none
    rows = np.flatnonzero(tree.any(axis=1))
    height = rows.max() - rows.min() + 1
    start, depth, least = _seen_foot(rgb, tree), height, max(4, TRACE_MIN * height)
    if start is None:
        # the silhouette ends in its crown: a trunk seen coming out under it, followed at
        # least as far as it was seen, as far down as the crown is tall or wide
        width = np.ptp(np.flatnonzero(tree.any(axis=0))) + 1
        start, depth = _hidden_foot(rgb, tree, under & keep), max(height, width)
        least = max(least, FOOT_MIN * height)
    if start is None:
        return none
    y0, c0, tw, mean, spread = start
    y1 = min(h, y0 + int(TRACE_DEPTH * depth))
    if tw < 3 or y1 - y0 < 4:
        return none
    reach = TRACE_SIDE * tw + LEAN * (y1 - y0) + 2 * tw
    x0, x1 = int(max(0, c0 - reach)), int(min(w, c0 + reach + 1))
    lab = rgb2lab(rgb[max(0, y0 - 2) : y1, x0:x1])
    edge = _edges(lab, y0 - max(0, y0 - 2))
    lab = lab[y0 - max(0, y0 - 2) :]
    wmin = max(2, round(TRACE_WIDTHS[0] * tw))
    wide = max(3, round(TRACE_WIDTHS[1] * tw)) - wmin  # widths wmin .. wmin + wide
    # a wide trunk's widths by a step, so that the states stay within TRACE_STATES (three
    # widths at least: the narrowest, the middle, the widest)
    step = max(1, -(-(wide + 1) * lab.shape[0] * lab.shape[1] // TRACE_STATES))
    step = min(step, max(1, wide // 2))
    nk = wide // step + 1
    cum = np.zeros((lab.shape[0], lab.shape[1] + 1, 3))
    cum[:, 1:] = np.cumsum(lab, axis=1)
    score = edge_pair_scores(np.ascontiguousarray(edge), cum, np.append(mean, spread),
                             (wmin, nk, step), (EDGE_CAP, 1.0, D_CAP, GATE))  # fmt: skip
    # the corridor, and the rows below the cut that may be tree
    dx = np.abs(np.arange(x0, x1)[None, :] - c0)
    shut = dx > TRACE_SIDE * tw + LEAN * np.arange(y1 - y0)[:, None]
    shut |= ~(under & keep)[y0:y1, x0:x1]
    score[shut] = FORBIDDEN
    open_ = score > FORBIDDEN / 10
    if not open_.any():
        return none
    score -= min(float(np.quantile(score[open_], TRACE_Q)), EDGE_CAP) + TRACE_MARGIN
    start = (round(c0) - x0, int(np.clip(round((round(tw) - wmin) / step), 0, nk - 1)))
    end, cs, ks, _ = trace_path(score, start, (SHIFT, WIDEN))
    out = none.copy()
    if end + 1 < least:
        return out
    for i in range(end + 1):
        d = wmin + ks[i] * step
        out[y0 + i, x0 + cs[i] - d // 2 : x0 + cs[i] - d // 2 + d] = True
    return out & under & keep & ~tree


def trim_foot(tree):
    """The silhouette ``tree`` less the flat pieces reaching out from its trunk's foot: a
    shadow, a strip of darker ground or a patch of mulch that the steps below the cut (or
    the crown's reading, on a horizon found below the foot) joined to the trunk. The trunk
    is found at its waist (the lowest of the first :data:`WAIST_ROWS` consecutive narrow
    rows in the silhouette's lowest :data:`WAIST_ZONE`) and followed down, its centre
    moving at most :data:`LEAN` pixels a row; what lies outside it (its width and
    :data:`FLARE` of it either side) in a piece at least :data:`FLAT` times as wide as it
    is tall and as wide as the trunk is dropped, and so is what only such a piece joined
    to the tree. A tree with no such waist (a crown down to the ground, several stems) is
    returned as it is; so are a trunk's flare, its lean and the twigs along it (pieces
    taller than flat).

    Examples
    --------
    >>> tree = np.zeros((40, 40), bool); tree[2:20, 8:32] = True   # a crown,
    >>> tree[20:36, 18:22] = True                                  # a trunk,
    >>> tree[33:36, 4:22] = True                                   # its shadow aside
    >>> out = trim_foot(tree)               # the trunk and its flare (3 pixels) stay
    >>> bool(out[20:36, 18:22].all()), int(out[33:36].sum()), int((tree & ~out).sum())
    (True, 21, 33)
    """
    from skimage.measure import label, regionprops

    rows = np.flatnonzero(tree.any(axis=1))
    if len(rows) < 2 * WAIST_ROWS:
        return tree
    cols = np.flatnonzero(tree.any(axis=0))
    height, width = rows[-1] - rows[0] + 1, cols[-1] - cols[0] + 1
    foot = int(rows[-1])
    # the narrow rows of one run, in groups of consecutive rows
    groups: list[list[tuple[int, int, float]]] = []
    for y in range(foot - int(WAIST_ZONE * height), foot + 1):
        spans = runs(np.flatnonzero(tree[y]), gap=WAIST_GAP)
        if len(spans) != 1 or spans[0][1] - spans[0][0] + 1 > TRUNK_WIDTH * width:
            continue
        row = (y, spans[0][1] - spans[0][0] + 1, (spans[0][0] + spans[0][1]) / 2)
        if groups and groups[-1][-1][0] == y - 1:
            groups[-1].append(row)
        else:
            groups.append([row])
    groups = [g for g in groups if len(g) >= WAIST_ROWS]
    if not groups:
        return tree
    wide = float(np.median([n for _, n, _ in groups[0]]))
    waist, _, centre = max(r for r in groups[0] if r[1] <= 1.5 * wide)
    if waist >= foot:
        return tree
    half = wide / 2 + max(2.0, FLARE * wide)
    outside = np.zeros_like(tree)
    for y in range(waist + 1, foot + 1):
        lo, hi = int(np.floor(centre - half)), int(np.ceil(centre + half))
        outside[y, : max(0, lo)] = tree[y, : max(0, lo)]
        outside[y, hi + 1 :] = tree[y, hi + 1 :]
        xs = np.flatnonzero(tree[y])
        core = xs[np.abs(xs - centre) <= wide / 2]
        if len(core):
            centre += float(np.clip(core.mean() - centre, -LEAN, LEAN))
    pieces = label(outside, connectivity=2)
    out = tree.copy()
    for p in regionprops(pieces):
        r0, c0, r1, c1 = p.bbox
        if c1 - c0 >= max(wide, FLAT * (r1 - r0)):
            out[pieces == p.label] = False
    if out.sum() == tree.sum():
        return tree
    # and what only those pieces joined to the tree (a strip's far end)
    parts = label(out, connectivity=2)
    return out & np.isin(parts, np.unique(parts[: waist + 1][out[: waist + 1]]))
