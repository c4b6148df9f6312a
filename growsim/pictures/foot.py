"""The trunk's foot: a trunk that stops short of it (or is seen only below the crown)
carried on down along its two edges (:func:`traced_trunk`), and the flat pieces reaching
out from it dropped (:func:`trim_foot`: a shadow, a strip of darker ground). Both run on
the silhouette :func:`growsim.pictures.photo.segment_photo` found, after the steps below
the cut (:mod:`growsim.pictures.trunk`).
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.trunk import FORBIDDEN, edge_pair_scores, trace_path
from growsim.pictures.coverage import MIN_DE
from growsim.pictures.scene import runs
from growsim.pictures.trunk import TRUNK_WIDTH

__all__ = ["traced_trunk", "trim_foot"]

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
