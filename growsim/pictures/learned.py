"""The tree below the horizon read by a classifier learned on the picture itself
(:func:`learned_below`), inside the crown's outline carried on below the cut
(:func:`envelope`).

Below the cut the tree stands before the horizon's clutter (a treeline, a hedge, a hill),
often of its own colours; read pixel by pixel against the row beside it, a crown's lower
part is taken for that clutter and the silhouette ends in a straight line along the
horizon. Where it does, a random forest (scikit-learn) learns the tree from the picture's
own pixels: the crown found above the cut against the sky and what lies below the cut
beside the crown's columns, on colour, edges and texture at scales of 1 to 4 pixels
(scikit-image's ``multiscale_basic_features``, as in its trainable segmentation).
"""

from __future__ import annotations

import numpy as np

from growsim.pictures.record import ENDS_AT_HORIZON, horizon_share

__all__ = ["envelope", "learned_below"]

#: the features are computed on at most this many pixels (a larger window is reduced)
FEATURE_PIXELS = 400_000
#: ... at Gaussian scales from SIGMA_MIN to SIGMA_MAX pixels
SIGMA_MIN, SIGMA_MAX = 1.0, 4.0
#: the forest: so many trees of at most this depth, trained on at most SAMPLES pixels of
#: the tree and as many of its background
TREES, DEPTH, SAMPLES = 40, 12, 4000
#: the window reaches this share of the crown's height (its width, when wider, for a crown
#: the horizon was found under) below the cut's lowest row
BELOW = 1.0
#: the ground beside the tree, darkened by a factor drawn from this range, is background
#: too (the tree's shadow on it)
SHADE = (0.25, 0.8)
#: candidates: the forest's probability above this, at most NEAR_ROWS rows above the cut
#: (the crown just above it, thinned where the band was read), inside the envelope
P_TREE, NEAR_ROWS = 0.5, 15
#: the envelope widens below the cut by so many pixels a row on each side
WIDEN = 0.5
#: a plain background below the cut (90 % of its pixels within this many Delta E of its
#: median colour: a render's flat ground) is read exactly by the row's colour already:
#: nothing is learned (on renders it only took the ground between sparse low twigs;
#: photographs' grounds and treelines vary by 13 Delta E or more)
PLAIN_DE = 6.0


def envelope(above: np.ndarray) -> np.ndarray:
    """Where the crown ``above`` the cut (``(H, W)`` bool) may reach: in its rows, from the
    leftmost to the rightmost column it reached in them or higher; below its lowest row,
    from its sides over its lowest tenth of rows, widening by :data:`WIDEN` pixels a row
    on each side (a crown that widens below the horizon).

    Examples
    --------
    >>> above = np.zeros((30, 20), bool); above[:20, 8:12] = True; above[5:20, 6:14] = True
    >>> env = envelope(above)
    >>> env[10].nonzero()[0].tolist() == list(range(6, 14)), env[28].nonzero()[0].tolist()
    (True, [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18])
    """
    h, w = above.shape
    out = np.zeros((h, w), dtype=bool)
    rows = np.flatnonzero(above.any(axis=1))
    if len(rows) < 10:
        return out
    lefts = np.argmax(above[rows], axis=1)
    rights = w - 1 - np.argmax(above[rows, ::-1], axis=1)
    for r, a, b in zip(rows, np.minimum.accumulate(lefts), np.maximum.accumulate(rights)):
        out[r, a : b + 1] = True
    n = max(3, int(0.1 * len(rows)))
    ext = np.arange(rows[-1] + 1, h)
    dy = ext - rows[-1]
    lo = np.trunc(lefts[-n:].min() - WIDEN * dy)
    hi = np.ceil(rights[-n:].max() + WIDEN * dy)
    cols = np.arange(w)[None, :]
    out[ext] = (cols >= lo[:, None]) & (cols <= hi[:, None])
    return out


def learned_below(rgb, tree, low, under, sky, obj, keep, cut, scale):
    """The tree's pixels below the cut (``under``): ``low`` (what
    :func:`~growsim.pictures.trunk.below_cut` found) and, where the silhouette ``tree |
    low`` ends along the ``cut`` over at least
    :data:`~growsim.pictures.record.ENDS_AT_HORIZON` of its width
    (:func:`~growsim.pictures.record.horizon_share`), what a random forest learned on the
    picture takes for the tree there. The forest is trained, in a window around the
    standing object ``obj`` (``scale`` coarse pixels a pixel) down to :data:`BELOW` of
    the crown's height below the cut, on the crown above the cut against the ``sky`` and
    the pixels below the cut outside the object's columns (and those darkened: its
    shadow); its candidates (probability above :data:`P_TREE`, inside the crown's
    :func:`envelope`, not sky, in ``keep``) are kept where their colour is nearer the
    crown's than that of the pixels below the cut outside the envelope (a colour test,
    per pixel: a sparse crown's gaps are not filled), and where they join the tree.
    Nothing is learned where that background is plain (:data:`PLAIN_DE`).

    Examples
    --------
    >>> from growsim.pictures.scene import Standing
    >>> rng = np.random.default_rng(1)
    >>> rgb = np.empty((80, 80, 3)); rgb[:] = [0.75, 0.85, 0.95]            # the sky
    >>> rgb[40:] = [0.6, 0.5, 0.3] + 0.2 * rng.random((40, 80, 1))        # a stony hill
    >>> yy, xx = np.mgrid[:80, :80]
    >>> crown = (yy - 35) ** 2 + (xx - 40) ** 2 < 20 ** 2
    >>> rgb[crown] = [0.15, 0.35, 0.1] + 0.15 * rng.random((crown.sum(), 1))  # leaves
    >>> under = yy >= 40                                       # the cut along the horizon
    >>> obj = Standing(crown & ~under, 0, 15, 55, 20, 60, ((38, 42),))
    >>> found = np.zeros_like(crown)                    # nothing found below the cut yet
    >>> args = (under, ~crown & ~under, obj, np.ones_like(crown), np.full(80, 40.0), 1.0)
    >>> low = learned_below(rgb, crown & ~under, found, *args)
    >>> bool((low & crown).sum() > 0.8 * (crown & under).sum()), int((low & ~crown).sum())
    (True, 0)
    >>> rgb[under & ~crown] = [0.55, 0.5, 0.35]                  # a render's flat ground
    >>> learned_below(rgb, crown & ~under, found, *args) is found
    True
    """
    from scipy import ndimage
    from scipy.spatial import cKDTree
    from skimage.color import rgb2lab
    from skimage.feature import multiscale_basic_features
    from skimage.measure import label
    from skimage.transform import resize
    from sklearn.ensemble import RandomForestClassifier

    if horizon_share(tree | low, cut) < ENDS_AT_HORIZON:
        return low
    above = tree & ~under
    rows = np.flatnonzero(above.any(axis=1))
    if not len(rows):
        return low
    h, w = tree.shape
    k = 1.0 / scale
    height = rows[-1] - rows[0] + 1
    left, right = int(obj.left * k), int(np.ceil((obj.right + 1) * k))
    width = right - left
    x0, x1 = max(0, left - width), min(w, right + width)
    lowest = int(np.max(np.argmax(under[:, x0:x1], axis=0)))
    y1 = min(h, lowest + int(BELOW * max(height, width if obj.lifted else 0)) + 1)
    win = (slice(rows[0], y1), slice(x0, x1))
    img = rgb[win]
    shape = img.shape[:2]
    f = min(1.0, np.sqrt(FEATURE_PIXELS / (shape[0] * shape[1])))
    small = (max(8, round(shape[0] * f)), max(8, round(shape[1] * f)))

    def reduced(a, size=small):
        return resize(a.astype(float), size, order=1) if f < 1.0 else a

    env = envelope(above)[win]
    lab = rgb2lab(img)
    outside = under[win] & ~ndimage.binary_dilation(env, iterations=3) & keep[win]
    if outside.sum() > 50:
        ground = lab[outside]
        spread = np.linalg.norm(ground - np.median(ground, axis=0), axis=-1)
        if np.percentile(spread, 90) < PLAIN_DE:
            return low
    feats = multiscale_basic_features(reduced(img), channel_axis=-1, sigma_min=SIGMA_MIN,
                                      sigma_max=SIGMA_MAX)  # fmt: skip
    X = feats.reshape(-1, feats.shape[-1])
    inside = np.zeros((1, x1 - x0))
    inside[0, max(0, left - x0) : right - x0] = 1.0
    flanks = (reduced(under[win]) > 0.5) & ~(reduced(inside, (1, small[1])) > 0.5)
    fg = ndimage.binary_erosion(reduced(above[win]) > 0.5)
    bg = (reduced(sky[win]) > 0.5) | flanks
    if fg.sum() < 50 or bg.sum() < 50:
        return low
    rng = np.random.default_rng(0)
    fi = rng.choice(np.flatnonzero(fg), min(SAMPLES, int(fg.sum())), replace=False)
    bi = rng.choice(np.flatnonzero(bg), min(SAMPLES, int(bg.sum())), replace=False)
    shaded = bi[flanks.ravel()[bi]]
    back = np.r_[X[bi], X[shaded] * rng.uniform(*SHADE, size=(len(shaded), 1))]
    forest = RandomForestClassifier(n_estimators=TREES, max_depth=DEPTH, n_jobs=1,
                                    random_state=0)  # fmt: skip
    forest.fit(np.r_[X[fi], back], np.r_[np.ones(len(fi)), np.zeros(len(back))])
    p = forest.predict_proba(X)[:, 1].reshape(small)
    if f < 1.0:
        p = resize(p, shape, order=1)
    near = ndimage.binary_dilation(under[win], np.ones((2 * NEAR_ROWS + 1, 1), dtype=bool))
    cand = (p > P_TREE) & near & ~sky[win] & keep[win] & env
    # each candidate nearer the crown's colours than the background's below the cut
    crown = above[win]
    if cand.any() and outside.sum() > 50 and crown.sum() > 50:
        ci = rng.choice(np.flatnonzero(crown), min(3000, int(crown.sum())), replace=False)
        oi = rng.choice(np.flatnonzero(outside), min(3000, int(outside.sum())), replace=False)
        flat = lab.reshape(-1, 3)
        d_crown, _ = cKDTree(flat[ci]).query(lab[cand], k=1)
        d_back, _ = cKDTree(flat[oi]).query(lab[cand], k=1)
        cand[cand] = d_crown < d_back
    base = (tree | low)[win]
    parts = label(cand | base, connectivity=2)
    out = low.copy()
    out[win] |= cand & np.isin(parts, np.unique(parts[base & (parts > 0)]))
    return out & ~tree
