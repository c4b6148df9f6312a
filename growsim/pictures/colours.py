"""A per-picture colour model of the background against the tree: the pieces of the
tree's foreground whose colour is the background's, not the tree's (a cloud behind or
beside the crown, taken for it because it differs from the sky filled in around it; the
top of a hedge or a treeline beside the trunk), found by comparing how often their colour
occurs among the background's own pixels and among the tree's sure pixels
(:func:`background_coloured`; the clouds' colours seen away from the tree counted with
the sky's, :func:`cloud_colours`); the clouds paler than the sky behind a tree darker
than it, whatever the tree's colour (:func:`paler_clouds`); the crown below a
treeline's top told from the treeline by their colours (:func:`crown_coloured`); and two
trees of clearly different colours whose crowns touch, one standing object of the
scene, split apart (:func:`split_touching`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from growsim.pictures.backdrop import sky_background
from growsim.pictures.pieces import between_feet, largest_piece
from growsim.pictures.scene import Scene, Standing, runs

__all__ = [
    "background_coloured",
    "cloud_colours",
    "crown_coloured",
    "paler_clouds",
    "split_touching",
]

#: two touching trees (:func:`split_touching`): a standing object's pixels are read for
#: their hue where their colour lies at least SPLIT_CHROMA (Delta E, a* b*) from the sky
#: behind them (an edge pixel mixed with the sky is not); the two hues' pieces differ by
#: at least SPLIT_DE (their median a* b*: clearly different colours, not a crown's lit
#: and shaded sides)
SPLIT_CHROMA = 15.0
SPLIT_DE = 20.0
#: ... each hue held mostly (this share of its pixels, after a majority over
#: SPLIT_WINDOW pixels) by one piece (a crown of its own, not leaves mixed through
#: another's), each piece compact (its area this share of its convex hull's: a crown, not
#: a trunk and its limbs), the smaller at least SPLIT_MIN of the larger's area
SPLIT_COHERENT = 0.8
SPLIT_WINDOW = 5
SPLIT_SOLID = 0.7
SPLIT_MIN = 0.1
#: ... and touching along at most this share of the smaller part's outline (side by side,
#: not one crown's halves)
SPLIT_SHARED = 0.4

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
#: ... and at least this many pixels of the background, of the tree's sure pixels, of its
#: own colours (and of the clouds seen elsewhere, :func:`cloud_colours`, for them to count)
MIN_PIXELS = 50
#: the clouds seen away from the tree (:func:`cloud_colours`): the scene's floating pieces
#: farther than this share of the tree's height (at least CLOUD_MIN_AWAY coarse pixels)
#: from every standing object, and not smaller than CLUMP of the tree's area within that
#: reach of its convex hull (a clump of its leaves on twigs too thin to see)
CLOUD_AWAY = 0.1
CLOUD_MIN_AWAY = 3.0
CLUMP = 0.1


def _at_most(points: np.ndarray, rng) -> np.ndarray:
    """``points`` ``(N, C)``, or :data:`SAMPLES` of them drawn without replacement by
    ``rng`` when there are more (a colour model's samples: the same for every picture)."""
    if len(points) <= SAMPLES:
        return points
    return points[rng.choice(len(points), SAMPLES, replace=False)]


def background_coloured(lab, fg, background, region, sure=None, extra=None) -> np.ndarray:
    """The pixels of the foreground ``fg`` in ``region`` that are the ``background``'s
    colour (``lab``: CIELAB; ``background``: the background's own pixels, e.g. the sky's),
    not the colour of the tree's ``sure`` pixels (by default the interior of ``fg`` in
    ``region``, 3 x 3 erosion), in pieces at least 3 x 3 wide (an opening; a piece is
    then taken whole): clouds taken for the crown, clutter for the trunk. Thin twigs,
    whose pixels are mixed with the sky, are never taken. ``extra``: colours ``(N, 3)`` of
    the background seen elsewhere (the clouds away from the tree, :func:`cloud_colours`;
    not its own pixels: their streaks and rims are textured) counted with the
    ``background``'s own when at least :data:`MIN_PIXELS`. Nothing when the two cannot be
    told apart by colour (:data:`MAX_BACKGROUND_LIKE`, judged on the ``background``'s own
    pixels), the tree is grey (:data:`MIN_CHROMA`) or there are too few of either.

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
    if sure.sum() < MIN_PIXELS or background.sum() < MIN_PIXELS:
        return none
    if np.median(np.hypot(lab[sure][:, 1], lab[sure][:, 2])) < MIN_CHROMA:
        return none
    rng = np.random.default_rng(0)
    cand = fg & region
    # the candidates' colours, rounded to whole units: each looked up once
    colours, back = np.unique(np.round(lab[cand]), axis=0, return_inverse=True)
    backs = _at_most(lab[background], rng)
    picked = _at_most(lab[sure], rng)

    def counts(points):
        # how many of ``points`` lie near each candidate colour; which sure pixels have one
        near = cKDTree(points)
        return (near.query_ball_point(colours, COLOUR_REACH, return_length=True),
                near.query_ball_point(picked, COLOUR_REACH, return_length=True) > 0)  # fmt: skip

    def like_of(n_back, n_backs, own):
        # the tree's own colours: its sure pixels none of the background's colours is near
        trees = picked[own]
        if len(trees) < MIN_PIXELS:
            return None
        n_tree = cKDTree(trees).query_ball_point(colours, COLOUR_REACH, return_length=True)
        odds = ((n_back + 1) / n_backs) / ((n_tree + 1) / len(trees))
        like = none.copy()
        like[cand] = (odds > BACKGROUND_ODDS)[back.ravel()]
        return like

    n_back, near_back = counts(backs)
    like = like_of(n_back, len(backs), ~near_back)
    if like is None or like[sure].mean() > MAX_BACKGROUND_LIKE:
        return none
    if extra is not None and len(extra) >= MIN_PIXELS:
        # and the background seen elsewhere (the clouds away from the tree): the tree's
        # own colours are then its sure pixels none of those is near either
        more = _at_most(np.asarray(extra, dtype=np.float64), rng)
        n_more, near_more = counts(more)
        like = like_of(n_back + n_more, len(backs) + len(more), ~near_back & ~near_more)
        if like is None:
            return none
    opened = ndimage.binary_opening(like, np.ones((3, 3), dtype=bool))
    return ndimage.binary_propagation(opened, mask=like)


#: the crown before a treeline (:func:`crown_coloured`): each pixel is the class of most of
#: its CROWN_K nearest colours among the crown's and the clutter's samples (CIELAB, the
#: lightness weighted CROWN_L: a crown's lit and shaded sides differ most in it; each
#: class's votes weighted by one over its samples, so that a narrow strip of treeline
#: beside a wide crown is not outvoted), with the spread of the lightness over
#: CROWN_TEXTURE_WINDOW pixels weighted CROWN_TEXTURE (a near crown's leaves and gaps
#: against a far treeline's haze); trusted when, each sample left out in turn, at least
#: CROWN_APART of the crown's samples and CLUTTER_APART of the clutter's are told right
CROWN_K = 7
CROWN_L = 0.5
CROWN_TEXTURE = 1.0
CROWN_TEXTURE_WINDOW = 5
CROWN_APART = 0.85
CLUTTER_APART = 0.75
#: ... a pixel farther from every clutter sample than this share of the clutter's samples
#: are from their nearest is not the clutter's either (the tree's bark, a branch)
CLUTTER_NOVEL = 0.999


def crown_coloured(lab, crown, clutter, zone):
    """The pixels of ``zone`` whose colour is the crown's, not the clutter's: a crown
    hanging below a treeline's top, before trees of other colours (a red maple before
    green ones, a pine before bare woods). ``lab``: CIELAB ``(H, W, 3)``; ``crown``: the
    crown's sure pixels (found against the sky); ``clutter``: the treeline's pixels
    beside the tree, in the zone's rows. Each zone pixel takes the class of most of its
    :data:`CROWN_K` nearest samples (:data:`SAMPLES` of each, each class's votes weighted
    by one over its samples; on the colour, lightness weighted :data:`CROWN_L`, and the
    lightness's local spread, :data:`CROWN_TEXTURE`), or is the tree's when nothing of
    the clutter's is near it (:data:`CLUTTER_NOVEL`: a pale trunk), a majority over its
    3 x 3 after. ``None`` when the two are not told apart (:data:`CROWN_APART`,
    :data:`CLUTTER_APART`, each sample judged by the others) or either has fewer than
    :data:`MIN_PIXELS`.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> rng = np.random.default_rng(0)
    >>> rgb = np.ones((60, 80, 3)) * [0.2, 0.4, 0.15]                  # a green treeline
    >>> rgb[:20] = [0.55, 0.7, 0.95]                                   # the sky above it
    >>> rgb[5:45, 25:55] = [0.8, 0.25, 0.1]                            # a red crown
    >>> lab = rgb2lab(np.clip(rgb + rng.normal(0, 0.03, rgb.shape), 0, 1))
    >>> crown = np.zeros((60, 80), bool); crown[6:19, 26:54] = True    # above the treeline
    >>> clutter = np.zeros((60, 80), bool); clutter[20:, :20] = clutter[20:, 60:] = True
    >>> zone = np.zeros((60, 80), bool); zone[20:, 20:60] = True
    >>> low = crown_coloured(lab, crown, clutter, zone)
    >>> bool(low[20:45, 26:54].all()), bool(low[46:, :].any() or low[:, :24].any())
    (True, False)
    >>> crown_coloured(lab, clutter & (np.arange(80) < 10), clutter, zone) is None
    True
    """
    from scipy import ndimage
    from scipy.spatial import cKDTree

    if crown.sum() < MIN_PIXELS or clutter.sum() < MIN_PIXELS:
        return None
    rng = np.random.default_rng(0)
    lightness = lab[..., 0]
    mean = ndimage.uniform_filter(lightness, CROWN_TEXTURE_WINDOW)
    spread = np.sqrt(np.maximum(
        ndimage.uniform_filter(lightness**2, CROWN_TEXTURE_WINDOW) - mean**2, 0.0))  # fmt: skip
    features = np.concatenate(
        [lab * np.array([CROWN_L, 1.0, 1.0]), CROWN_TEXTURE * spread[..., None]], axis=-1
    )
    ours = _at_most(features[crown], rng)
    theirs = _at_most(features[clutter], rng)
    points = np.concatenate([ours, theirs])
    is_crown = np.r_[np.ones(len(ours)), np.zeros(len(theirs))]
    near = cKDTree(points)

    def crown_share(ii):  # the crown's share of the neighbours' votes, each class weighted
        votes = is_crown[ii].sum(axis=1) / len(ours)
        return votes / (votes + (1.0 - is_crown[ii]).sum(axis=1) / len(theirs))

    _, ii = near.query(points, k=CROWN_K + 1)  # each sample's first neighbour: itself
    vote = crown_share(ii[:, 1:])
    if (vote[: len(ours)] > 0.5).mean() < CROWN_APART or (
        vote[len(ours) :] <= 0.5
    ).mean() < CLUTTER_APART:
        return None
    # the zone's features, rounded to whole units: each looked up once
    values, back = np.unique(np.round(features[zone]), axis=0, return_inverse=True)
    _, ii = near.query(values, k=CROWN_K)
    out = np.zeros(zone.shape, dtype=bool)
    take = crown_share(ii) > 0.5
    # and what is like nothing of the clutter's (a pale trunk before a dark wood): farther
    # from its samples than all but CLUTTER_NOVEL of them are from their nearest
    clutter_near = cKDTree(theirs)
    gaps = clutter_near.query(theirs, k=2)[0][:, 1]
    take |= clutter_near.query(values)[0] > np.quantile(gaps, CLUTTER_NOVEL)
    out[zone] = take[back.ravel()]
    return ndimage.median_filter(out.view(np.uint8), size=3).astype(bool) & zone


def cloud_colours(rgb, scene, obj, keep=None) -> np.ndarray:
    """The colours (CIELAB, ``(N, 3)``, at most :data:`SAMPLES`) of the clouds seen away
    from the tree in the working picture ``rgb``: the pieces of the coarse ``scene``
    above the cut that are neither its sky (smooth) nor part of a standing object (a
    sunset's streaks, a cumulus's textured rims and shadows: what the scene leaves
    floating), farther than :data:`CLOUD_AWAY` of the tree's (``obj``'s) height from
    every standing object and, when smaller than :data:`CLUMP` of the tree, from its
    convex hull (a leaf clump hanging apart from the crown on twigs too thin to see is
    not a cloud), where ``keep`` (the working picture's mask, a hint's box: where
    the scene looked for objects; everywhere by default). The same clouds behind the
    crown, between its leaves and branches, have their colours
    (:func:`background_coloured`'s ``extra``).

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> from growsim.pictures.scene import find_scene
    >>> rng = np.random.default_rng(0)
    >>> rgb = np.ones((80, 120, 3)) * [0.95, 0.7, 0.45]             # an orange sky
    >>> rgb[60:] = [0.3, 0.45, 0.2]                                  # the ground
    >>> rgb[20:24, 80:110] = [0.55, 0.4, 0.5]                        # a streak of cloud
    >>> rgb[30:61, 28:32] = [0.3, 0.2, 0.1]                          # a trunk
    >>> rgb[10:35, 15:45] = [0.2, 0.35, 0.1]                         # its crown
    >>> rgb = np.clip(rgb + rng.normal(0, 0.02, rgb.shape), 0, 1)
    >>> scene = find_scene(rgb)
    >>> colours = cloud_colours(rgb, scene, scene.objects[0])  # the streak and its rim
    >>> streak, leaf = rgb2lab(np.array([[[0.55, 0.4, 0.5], [0.2, 0.35, 0.1]]]))[0]
    >>> near = lambda c: int((np.linalg.norm(colours - c, axis=1) < 6).sum())
    >>> len(colours) > 100, near(streak) > 50, near(leaf)
    (True, True, 0)
    """
    from scipy import ndimage
    from skimage.color import rgb2lab
    from skimage.morphology import convex_hull_image

    h, w = scene.shape
    taken = np.zeros((h, w), dtype=bool)
    for o in scene.objects:
        taken |= o.mask
    away = max(CLOUD_MIN_AWAY, CLOUD_AWAY * (obj.bottom - obj.top + 1))
    far = ndimage.distance_transform_edt(~taken) > away if taken.any() else ~taken
    up = np.arange(h)[:, None] < scene.cut[None, :]
    clouds = up & ~scene.sky & far
    # nor a clump of leaves hanging farther out, within the reach of the tree's outline
    # (its convex hull), smaller than CLUMP of it (a cloud there is larger)
    pieces, n = ndimage.label(clouds)
    if n:
        hull = ndimage.distance_transform_edt(~convex_hull_image(obj.mask)) <= away
        index = np.arange(1, n + 1)
        small = np.asarray(ndimage.sum(clouds, pieces, index)) < CLUMP * obj.area
        inside = np.asarray(ndimage.maximum(hull, pieces, index)) > 0
        clouds &= ~np.r_[False, small & inside][pieces]
    if not clouds.any():
        return np.zeros((0, 3))
    # each working pixel in the coarse pixel it falls in
    rows = np.minimum((np.arange(rgb.shape[0]) * scene.scale).astype(np.int64), h - 1)
    cols = np.minimum((np.arange(rgb.shape[1]) * scene.scale).astype(np.int64), w - 1)
    big = clouds[rows[:, None], cols[None, :]]
    if keep is not None:
        big &= keep
    px = _at_most(rgb[big], np.random.default_rng(0))
    return rgb2lab(px[:, None, :])[:, 0, :]


#: clouds paler than the sky (:func:`paler_clouds`): a crown's pixel is cloud when it is
#: more than PALE_DL (CIELAB L*) paler than the sky filled in behind it and its a* b* lie
#: within CLOUD_HUE of a cloud's seen away from the tree, while the tree's foot (its
#: fully covered pixels in the lowest FOOT_ROWS of the crown's rows, at least FOOT_MIN of
#: them) is darker than that sky by more than the threshold of the tree's difference
PALE_DL = 5.0
CLOUD_HUE = 6.0
FOOT_ROWS = 0.1
FOOT_MIN = 10


def paler_clouds(lab, bg, fg, region, hull, clouds, floor) -> np.ndarray:
    """The pixels of the foreground ``fg`` in ``region`` that are clouds paler than the
    sky: more than :data:`PALE_DL` paler (L*) than the sky ``bg`` filled in behind them,
    of the hue of the ``clouds`` seen away from the tree (``(N, 3)`` CIELAB,
    :func:`cloud_colours`; a* b* within :data:`CLOUD_HUE`), when the tree's foot is darker
    than that sky by more than ``floor`` (Delta E). In daylight bark and leaves seen
    against the sky are darker than it, and a lit cloud is paler than the sky around it;
    a pixel mixing a dark twig with a cloud behind it is darker than the sky unless the
    twig covers little of it. This holds whatever the tree's colour, so a grey bare tree
    (which :func:`background_coloured` cannot tell from grey clouds by their colours) is
    told from them by its lightness. Nothing when fewer than :data:`MIN_PIXELS` clouds
    are seen away from the tree (a frosted or blossoming crown under a clear sky is as
    pale as a cloud), nor when the tree's foot is not clearly darker than the sky (a
    birch's white trunk). ``lab``, ``bg``: CIELAB ``(H, W, 3)``; ``fg``, ``region``,
    ``hull``: ``(H, W)`` masks, ``hull`` the crown's rows' spans down to the cut (its
    lowest rows hold the tree's foot).

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> sky = np.ones((40, 40, 3)) * [0.45, 0.6, 0.9]                 # a blue sky
    >>> rgb = sky.copy()
    >>> rgb[5:15, 5:30] = [0.93, 0.94, 0.96]                           # a white cloud
    >>> rgb[:, 18:21] = [0.15, 0.12, 0.1]                              # a dark trunk
    >>> lab, bg = rgb2lab(rgb), rgb2lab(sky)
    >>> clouds = rgb2lab(np.linspace([0.85, 0.86, 0.9], [0.97, 0.97, 0.98], 60)[None])[0]
    >>> fg = np.linalg.norm(lab - bg, axis=-1) > 10                    # cloud and trunk
    >>> everywhere = np.ones((40, 40), bool)
    >>> pale = paler_clouds(lab, bg, fg, everywhere, everywhere, clouds, 10.0)
    >>> int(pale.sum()), bool(pale[10, 10]), bool(pale[10, 19])
    (220, True, False)
    """
    from scipy import ndimage
    from scipy.spatial import cKDTree

    none = np.zeros(fg.shape, dtype=bool)
    rows = np.flatnonzero(hull.any(axis=1))
    if len(clouds) < MIN_PIXELS or not len(rows):
        return none
    foot = np.zeros_like(fg)
    foot[rows[-1] - max(2, int(FOOT_ROWS * (rows[-1] - rows[0] + 1))) : rows[-1] + 1] = True
    foot &= region & fg
    sure = foot & ndimage.binary_erosion(fg, np.ones((3, 3), dtype=bool))
    if sure.sum() < FOOT_MIN:
        sure = foot
    paler = lab[..., 0] - bg[..., 0]
    if sure.sum() < FOOT_MIN or np.median(paler[sure]) >= -floor:
        return none
    pale = fg & region & (paler > PALE_DL)
    if pale.any():
        hues = _at_most(np.asarray(clouds, dtype=np.float64), np.random.default_rng(0))[:, 1:]
        near = cKDTree(hues).query(lab[pale][:, 1:], distance_upper_bound=CLOUD_HUE)[0]
        pale[pale] = np.isfinite(near)
    return pale


def split_touching(scene: Scene) -> Scene:
    """The ``scene`` with each standing object that is two trees whose crowns touch split
    in two (each part's ``apart`` the other's pixels, grown by two pixels): the object's
    pixels of clear colour (:data:`SPLIT_CHROMA` from the sky behind them) fall in two hues
    (around the sky's colour: mixing with the sky keeps a pixel's hue), each held by one
    compact piece (:data:`SPLIT_COHERENT`, :data:`SPLIT_SOLID`, :data:`SPLIT_MIN`) of
    clearly different colours (:data:`SPLIT_DE`), touching along a short part of their
    outlines (:data:`SPLIT_SHARED`), and each part (every pixel of the object goes with
    the piece nearer it) standing on the band by itself. A tree and its trunk or limbs
    (thin, not compact), a crown's lit and shaded sides (touching all along), leaves of
    two colours mixed through one crown stay one object. Objects less than a tenth of
    the largest's area are left as they are; without ground nothing is split.

    Examples
    --------
    >>> from growsim.pictures.scene import find_scene
    >>> rng = np.random.default_rng(0)
    >>> rgb = np.ones((80, 120, 3)) * [0.6, 0.75, 0.95]              # blue sky
    >>> rgb[65:] = [0.3, 0.45, 0.2]                                   # the ground
    >>> yy, xx = np.mgrid[0:80, 0:120]
    >>> rgb[(yy - 30) ** 2 + (xx - 70) ** 2 < 400] = [0.8, 0.5, 0.15]  # an orange crown
    >>> rgb[45:68, 68:73] = [0.5, 0.5, 0.48]                          # its trunk
    >>> rgb[(yy - 52) ** 2 + (xx - 42) ** 2 < 144] = [0.2, 0.4, 0.15]  # a green one
    >>> rgb[60:68, 40:44] = [0.3, 0.25, 0.2]                          # its trunk
    >>> rgb = np.clip(rgb + rng.normal(0, 0.04, rgb.shape), 0, 1)    # leaves' texture
    >>> scene = find_scene(rgb)
    >>> len(scene.objects), len(split_touching(scene).objects)
    (1, 2)
    """
    from scipy import ndimage

    if not scene.ground or not scene.objects:
        return scene
    h, w = scene.shape
    edge = np.clip(np.ceil(scene.cut).astype(int) - 1, 0, h - 1)
    cols = np.arange(w)
    bg = None
    objects = []
    for o in scene.objects:
        parts = None
        if o.area >= SPLIT_MIN * scene.objects[0].area:
            if bg is None:
                bg = sky_background(scene.lab, scene.sky)
            parts = _two_crowns(scene.lab, bg, o)
            if parts is None:  # two trees of one colour: between their feet
                parts = between_feet(o.mask, o.feet, edge, SPLIT_MIN, SPLIT_SHARED)
        if parts is None:
            objects.append(o)
            continue
        feet = [runs(np.nonzero(p[edge, cols] | p[np.clip(edge - 1, 0, h - 1), cols])[0])
                for p in parts]  # fmt: skip
        if not all(feet):  # a part not standing by itself: a crown on a trunk of its own
            objects.append(o)
            continue
        grown = [ndimage.binary_dilation(p, np.ones((5, 5), dtype=bool)) for p in parts]
        for i, p in enumerate(parts):
            rr, cc = np.nonzero(p)
            apart = grown[1 - i] & ~p
            region = None if o.region is None else o.region & ~apart
            objects.append(Standing(p, int(p.sum()), int(rr.min()), int(rr.max()), int(cc.min()),
                                    int(cc.max()), tuple(feet[i]), region, apart))  # fmt: skip
    if len(objects) == len(scene.objects):
        return scene
    objects.sort(key=lambda o: -o.area)
    return replace(scene, objects=objects)


def _two_crowns(lab, bg, o):
    """The standing object ``o`` as two crowns of clearly different colours touching (the
    tests of :func:`split_touching` but the feet): its two parts (masks), or ``None``."""
    from scipy import ndimage
    from skimage.filters import threshold_otsu
    from skimage.morphology import convex_hull_image

    v = lab[..., 1:] - bg[..., 1:]
    clear = o.mask & (np.hypot(v[..., 0], v[..., 1]) >= SPLIT_CHROMA)
    if clear.sum() < 100:
        return None
    hue = np.degrees(np.arctan2(v[..., 1], v[..., 0]))
    mid = float(np.median(hue[clear]))
    hue = (hue - mid + 180.0) % 360.0 - 180.0  # around the median: no wrap-around
    t = hue[clear]
    if np.ptp(t) < 1e-6:
        return None
    cut = threshold_otsu(t)
    upper = clear & (hue > cut)
    # a majority over the window, among the clear pixels
    share = ndimage.uniform_filter(upper.astype(float), SPLIT_WINDOW) / np.maximum(
        ndimage.uniform_filter(clear.astype(float), SPLIT_WINDOW), 1e-9
    )
    pieces = []
    for side in (clear & (share <= 0.5), clear & (share > 0.5)):
        piece = largest_piece(side)
        if not piece.any():
            return None
        if piece.sum() < SPLIT_COHERENT * side.sum():
            return None
        if piece.sum() < SPLIT_SOLID * convex_hull_image(piece).sum():
            return None
        pieces.append(piece)
    a, b = sorted(pieces, key=lambda p: -int(p.sum()))
    if b.sum() < SPLIT_MIN * a.sum():
        return None
    col_a, col_b = (np.median(lab[p][:, 1:], axis=0) for p in (a, b))
    if np.linalg.norm(col_a - col_b) < SPLIT_DE:
        return None
    # every pixel of the object with the piece nearer it
    near_b = ndimage.distance_transform_edt(~b) < ndimage.distance_transform_edt(~a)
    part_a, part_b = o.mask & ~near_b, o.mask & near_b
    k = np.ones((3, 3), dtype=bool)
    outline = part_b & ~ndimage.binary_erosion(part_b, k)
    shared = outline & ndimage.binary_dilation(part_a, k)
    if shared.sum() > SPLIT_SHARED * max(int(outline.sum()), 1):
        return None
    return part_a, part_b
