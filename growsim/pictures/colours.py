"""A per-picture colour model of the background against the tree: the pieces of the
tree's foreground whose colour is the background's, not the tree's (a cloud behind or
beside the crown, taken for it because it differs from the sky filled in around it; the
top of a hedge or a treeline beside the trunk), found by comparing how often their colour
occurs among the background's own pixels and among the tree's sure pixels
(:func:`background_coloured`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["background_coloured"]

#: a foreground pixel has the background's colour when the background's own pixels are
#: this many times as frequent around its colour (within COLOUR_REACH, Delta E) as the
#: tree's own colours (its sure pixels, less those of colours the background has: what was
#: taken for the tree wrongly is not its colour)
BACKGROUND_ODDS = 4.0
COLOUR_REACH = 4.0
#: ... only for a tree of colours (the median chroma of its sure pixels, CIELAB C*, at
#: least this): a grey tree (a greyscale photograph, a white tree) differs from a grey sky
#: by its lightness alone, which its pale parts share with the sky
MIN_CHROMA = 8.0
#: ... pixels sampled from each (the same for every picture: a fixed seed)
SAMPLES = 4000
#: the model is trusted only when at most this share of the tree's sure pixels have the
#: background's colour (a white tree against white clouds: the colours do not tell them
#: apart)
MAX_BACKGROUND_LIKE = 0.25


def background_coloured(lab, fg, background, region, sure=None) -> np.ndarray:
    """The pixels of the foreground ``fg`` in ``region`` that are the ``background``'s
    colour (``lab``: CIELAB; ``background``: the background's own pixels, e.g. the sky's),
    not the colour of the tree's ``sure`` pixels (by default the interior of ``fg`` in
    ``region``, 3 x 3 erosion), in pieces at least 3 x 3 wide (an opening; a piece is
    then taken whole): clouds taken for the crown, clutter for the trunk. Thin twigs,
    whose pixels are mixed with the sky, are never taken. Nothing when the two cannot be
    told apart by colour (:data:`MAX_BACKGROUND_LIKE`), the tree is grey
    (:data:`MIN_CHROMA`) or there are too few of either.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> rgb = np.ones((40, 40, 3)) * [0.55, 0.7, 0.95]               # blue sky
    >>> rgb[25:35, 3:10] = [0.95, 0.95, 0.95]                        # a white cloud
    >>> rgb[8:32, 12:32] = [0.2, 0.4, 0.1]                           # a green crown
    >>> rgb[12:20, 24:31] = [0.95, 0.95, 0.95]                       # the cloud behind it
    >>> lab = rgb2lab(rgb)
    >>> fg = np.zeros((40, 40), bool); fg[8:32, 12:32] = True        # all taken for tree
    >>> region = np.zeros((40, 40), bool); region[5:35, 10:35] = True
    >>> cloud = background_coloured(lab, fg, ~region, region)
    >>> int(cloud.sum()), bool(cloud[15, 27]), bool(cloud[25, 20])
    (56, True, False)
    """
    from scipy import ndimage
    from scipy.spatial import cKDTree

    none = np.zeros(fg.shape, dtype=bool)
    if sure is None:
        sure = ndimage.binary_erosion(fg, np.ones((3, 3), dtype=bool)) & region
    if sure.sum() < 50 or background.sum() < 50:
        return none
    if np.median(np.hypot(lab[sure][:, 1], lab[sure][:, 2])) < MIN_CHROMA:
        return none
    rng = np.random.default_rng(0)

    def sample(mask):
        pts = lab[mask]
        if len(pts) > SAMPLES:
            pts = pts[rng.choice(len(pts), SAMPLES, replace=False)]
        return pts

    backs = sample(background)
    near_back = cKDTree(backs)
    # the tree's own colours: its sure pixels none of the background's colours is near
    trees = sample(sure)
    trees = trees[near_back.query_ball_point(trees, COLOUR_REACH, return_length=True) == 0]
    if len(trees) < 50:
        return none
    cand = fg & region
    # the candidates' colours, rounded to whole units: each looked up once
    colours, back = np.unique(np.round(lab[cand]), axis=0, return_inverse=True)
    n_back = near_back.query_ball_point(colours, COLOUR_REACH, return_length=True)
    n_tree = cKDTree(trees).query_ball_point(colours, COLOUR_REACH, return_length=True)
    odds = ((n_back + 1) / len(backs)) / ((n_tree + 1) / len(trees))
    like = none.copy()
    like[cand] = (odds > BACKGROUND_ODDS)[back.ravel()]
    if like[sure].mean() > MAX_BACKGROUND_LIKE:
        return none
    opened = ndimage.binary_opening(like, np.ones((3, 3), dtype=bool))
    return ndimage.binary_propagation(opened, mask=like)
