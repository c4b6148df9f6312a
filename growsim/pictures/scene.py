"""The scene of an outdoor photograph: the sky, the ground with the clutter along the
horizon, and the objects that stand on it and rise into the sky (:func:`find_scene`).

:func:`growsim.pictures.photo.segment_photo` finds the tree in two steps: here, on the
picture reduced to :data:`COARSE` pixels (its long side), *where* the tree is (which
object, its crown's region, its trunk's columns where it enters the horizon's clutter);
then, at the working size, *which pixels* are tree, each against its own background
(:mod:`growsim.pictures.backdrop`).

The scene, coarse:

1. **texture**: each pixel's colour gradient (CIELAB, Delta E a pixel), smoothed; the sky,
   clouds and haze included, is smooth, a tree's leaves and twigs are not;
2. **sky**: the smooth pixels connected to the top edge (a cloud's soft edge is smooth; a
   crown's outline, a hedge's, a hill's is not);
3. **skyline**: in each column, the row below the lowest sky pixel: the top of what stands
   on the ground there (clutter, a hill, the tree's trunk and crown where it stands);
4. **band**: the horizon's clutter, the skyline's lower envelope: the line or gentle curve
   that most columns' skylines lie on, none far below it (a robust fit, :func:`band_line`);
5. **standing objects**: the pieces of the non-sky rising above the band (by more than
   its roughness) that reach down into it; the tree is the largest (or a crown hanging
   just above the band, its pale trunk taken for sky, standing on the trunk's foot
   found below it: :func:`_hanging_crown`). Another one nearly as large (a second tree)
   makes the picture ambiguous: a hint (a box around the tree, a point on it) settles
   which.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from growsim.errors import UserInputError
from growsim.pictures import backdrop

__all__ = [
    "COARSE",
    "Scene",
    "Standing",
    "band_feet",
    "band_line",
    "example_photo",
    "find_scene",
    "runs",
    "trunk_feet",
]

#: moved to :mod:`growsim.pictures.backdrop` (0.2 -> 0.3): still importable from here,
#: with a warning, until 0.4
_MOVED = ("fill", "row_background", "sky_background")


def __getattr__(name: str):
    if name in _MOVED:
        warnings.warn(
            f"growsim.pictures.scene.{name} moved to growsim.pictures.backdrop.{name}",
            DeprecationWarning,
            stacklevel=2,
        )
        return getattr(backdrop, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


#: the long side, in pixels, the picture is reduced to for finding the scene
COARSE = 384
#: the smoothing (Gaussian sigma, coarse pixels) of the colour before its gradient, and of
#: the gradient into the texture
PRE_SMOOTH, TEXTURE_SMOOTH = 0.7, 1.5
#: smooth (sky-like) where the texture is under this many times the median texture along
#: the top edge, clipped to TEXTURE_RANGE (Delta E a coarse pixel)
TEXTURE_K = 4.0
TEXTURE_RANGE = (1.5, 3.0)
#: ... and where the working picture's own texture (:func:`fine_texture`) is under
#: TEXTURE_K times the top edge's, at least FINE_MIN (a colour step a working pixel)
FINE_MIN = 1.0
#: clouds the texture missed: a smooth piece within PALETTE_DE of the sky's colours
#: (Delta E) is sky, within EDGE_PALETTE_DE when it reaches a side edge and is at least
#: as light as the sky's median; a textured pixel among the sky's colours around it
#: (RIM_REACH, RIM_DE), and farther than STRONG_REACH coarse pixels from any that is
#: not, is a cloud's rim
PALETTE_DE = 6.0
EDGE_PALETTE_DE = 18.0
RIM_REACH, RIM_DE = 5, 3.0
STRONG_REACH = 2
#: the band's fit: a column's skyline within this share of the picture's height from the
#: line supports it; one farther below it counts against it (BELOW_COST)
BAND_TOL = 0.02
BELOW_COST = 0.5
#: the band's line is about level: its slope at most this (rows a column)
MAX_SLOPE = 0.3
#: an object stands out of the band when it rises this far above it: the band's roughness
#: (BAND_ROUGH times the spread of its columns around the line) and at least this share of
#: the height
RISE = 0.005
BAND_ROUGH = 2.5
#: the textured pixels joined to a standing object, up to this share of its height around
#: its box, are its region (where its pale twigs may be)
REGION_REACH = 0.3
#: a standing object at least this share of the tree's area and HEIGHT_SHARE of its height
#: is another tree: the picture is ambiguous without a hint
RIVAL_AREA = 0.3
RIVAL_HEIGHT = 0.5
#: the clutter's foot (where the ground begins) is a change of the rows' colour of more
#: than this (Delta E, over two rows)
GROUND_EDGE = 8.0
#: a crown hanging in the sky (its trunk taken for sky, :func:`_hanging_crown`): a
#: floating piece at least HANG_AREA of the picture, HANG_OVER times the largest standing
#: object, HANG_TALL as tall as wide, its lowest row within HANG_GAP of its height above
#: the cut; its trunk's foot a run of columns at most HANG_FOOT of its width whose colour
#: below the cut differs from the rows' beside it by HANG_DE (Delta E); the trunk's region
#: HANG_REACH of the crown's height either side of it
HANG_AREA, HANG_OVER, HANG_TALL, HANG_GAP = 0.005, 4.0, 1 / 3, 1.0
HANG_FOOT, HANG_DE, HANG_REACH = 0.2, 10.0, 0.05
#: ... or its trunk ending above the band (snow the sky's colour): :func:`_trunk_below`
TRUNK_BELOW_GAP, TRUNK_BELOW_TALL = 3, 0.3
#: a wide crown's top taken for the band (:func:`_under_bump`): the sky reaches below it in
#: at least this share of the columns on each side of it, the horizon under it about level
#: (rising at most BUMP_LEVEL rows a column)
BUMP_SIDES = 0.02
BUMP_LEVEL = 0.1
#: more than this share of the columns without ground (the sky reaching the bottom edge):
#: no ground, the tree is the largest object
NO_GROUND = 0.7


@dataclass(frozen=True)
class Standing:
    """An object standing on the band (coarse pixels): its ``mask`` ``(h, w)``, ``area``,
    ``top`` and lowest row, its columns ``left``..``right`` and the columns where it
    enters the band, ``feet`` (``[(c0, c1), ...]``, the runs of its row just above the
    cut); ``region``: the textured pixels around it, joined to it (within
    :data:`REGION_REACH` of its height: pale twigs the sky's colours hid, frost);
    ``apart``: the pixels of another tree it touched, split off it
    (:func:`~growsim.pictures.colours.split_touching`; ``None``: none), never its own;
    ``hanging``: a crown whose trunk the sky took (:func:`_hanging_crown`), standing on
    the foot found below it; ``foot``: the row its trunk ends at when the ground there is
    the sky's (snow under a white sky), above the band: nothing below it is the tree;
    ``lifted``: standing on a horizon found under its crown, whose top was most columns'
    skyline (:func:`_under_bump`): its trunk may reach farther below the band than the
    crown rises above it."""

    mask: np.ndarray
    area: int
    top: int
    bottom: int
    left: int
    right: int
    feet: tuple = ()
    region: np.ndarray | None = None
    apart: np.ndarray | None = None
    hanging: bool = False
    foot: int | None = None
    lifted: bool = False

    def box(self, scale: float) -> tuple[int, int, int, int]:
        """``(x0, y0, x1, y1)`` in pixels of a picture ``1 / scale`` times larger."""
        k = 1.0 / scale
        return (int(self.left * k), int(self.top * k), int((self.right + 1) * k),
                int((self.bottom + 1) * k))  # fmt: skip


@dataclass(frozen=True)
class Scene:
    """What :func:`find_scene` found, in coarse pixels (``scale`` coarse pixels a working
    pixel): ``lab`` the coarse picture (CIELAB), ``texture``, ``smooth_below`` (the
    threshold), ``sky`` ``(h, w)`` bool, ``skyline`` and ``band`` per column (rows; the
    band ``h`` in a column without ground), ``cut`` (the band less its roughness: what
    rises above it stands out), ``ground`` (whether there is one), ``objects`` (the
    standing objects, largest first), ``ground_line`` (the row where the horizon's
    clutter ends and the ground begins, :func:`_ground_line`; the band's lowest row when
    no edge tells them apart), ``roughness`` (the spread of the skyline's columns around
    the band, rows: a treeline's crowns, a hedge's top)."""

    scale: float
    lab: np.ndarray
    texture: np.ndarray
    smooth_below: float
    sky: np.ndarray
    skyline: np.ndarray
    band: np.ndarray
    cut: np.ndarray
    ground: bool
    objects: list = field(default_factory=list)
    ground_line: float = 0.0
    roughness: float = 0.0

    @property
    def shape(self) -> tuple[int, int]:
        return self.sky.shape


def _resize(rgb: np.ndarray, shape) -> np.ndarray:
    """``rgb`` reduced to ``shape`` by block means (area interpolation)."""
    from skimage.transform import resize

    if rgb.shape[:2] == tuple(shape):
        return rgb
    return resize(rgb, shape, order=1, anti_aliasing=True, mode="edge")


def texture_of(lab: np.ndarray) -> np.ndarray:
    """Each pixel's texture: the colour gradient's magnitude (Delta E a pixel, Sobel on the
    smoothed CIELAB channels), smoothed (:data:`PRE_SMOOTH`, :data:`TEXTURE_SMOOTH`).

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> t = texture_of(rgb2lab(rgb))
    >>> bool(t[5, 5] < 0.5), bool(t[20, 25] > 1.0)  # the sky smooth, the tree not
    (True, True)
    """
    from scipy import ndimage

    labs = ndimage.gaussian_filter(lab, (PRE_SMOOTH, PRE_SMOOTH, 0), mode="nearest")
    g = np.zeros(lab.shape[:2])
    for k in range(3):
        g += ndimage.sobel(labs[..., k], 0, mode="nearest") ** 2
        g += ndimage.sobel(labs[..., k], 1, mode="nearest") ** 2
    return ndimage.gaussian_filter(np.sqrt(g) / 8.0, TEXTURE_SMOOTH, mode="nearest")


def fine_texture(rgb: np.ndarray, shape) -> np.ndarray:
    """The colour gradient of the working picture (its R, G, B channels times 100, Sobel
    after a Gaussian of :data:`PRE_SMOOTH` pixels: about Delta E a working pixel), averaged
    over each pixel of the coarse ``shape``.

    Examples
    --------
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> fine_texture(rgb, (30, 25)).shape
    (30, 25)
    """
    from scipy import ndimage

    g = np.zeros(rgb.shape[:2])
    for k in range(3):
        c = ndimage.gaussian_filter(100.0 * rgb[..., k], PRE_SMOOTH, mode="nearest")
        g += ndimage.sobel(c, 0, mode="nearest") ** 2 + ndimage.sobel(c, 1, mode="nearest") ** 2
    return _resize(np.sqrt(g)[..., None] / 8.0, shape)[..., 0]


def band_line(
    skyline: np.ndarray,
    h: int,
    *,
    least: float = 1.0 - NO_GROUND,
    curved: bool = True,
    below_cost: float = BELOW_COST,
) -> tuple[np.ndarray, float]:
    """The horizon's band under a skyline (rows per column; ``h``: no ground in that
    column): the line most columns' skylines lie on within :data:`BAND_TOL` of the height,
    counting those far below it against it (``below_cost`` each), refined by a quadratic
    (a straight line unless ``curved``) fitted to the columns on it; returns the band per
    column and the spread of those columns around it (rows). ``h`` everywhere when there
    is no ground (ground in under ``least`` of the columns).

    Examples
    --------
    >>> y = np.full(100, 80.0); y[40:60] = 20.0   # a tree rising from a flat band
    >>> band, spread = band_line(y, 100)
    >>> round(float(band[50]), 6), round(spread, 6)
    (80.0, 0.0)
    """
    w = len(skyline)
    y = np.asarray(skyline, dtype=np.float64)
    ok = y < h
    if ok.sum() < max(least * w, 3):
        return np.full(w, float(h)), 0.0
    x = np.arange(w, dtype=np.float64)
    tol = max(BAND_TOL * h, 2.0)
    cols = np.nonzero(ok)[0]
    sample = cols[np.linspace(0, len(cols) - 1, min(len(cols), 40)).round().astype(int)]
    # candidate lines: through each pair of sample columns, and level through each
    i, j = np.triu_indices(len(sample), 1)
    xi, xj, yi, yj = x[sample[i]], x[sample[j]], y[sample[i]], y[sample[j]]
    slope = np.concatenate([(yj - yi) / np.maximum(xj - xi, 1.0), np.zeros(len(sample))])
    x0 = np.concatenate([xi, x[sample]])
    y0 = np.concatenate([yi, y[sample]])
    lines = y0[:, None] + slope[:, None] * (x[None, :] - x0[:, None])
    res = y[None, ok] - lines[:, ok]
    score = (np.abs(res) <= tol).sum(axis=1) - below_cost * (res > tol).sum(axis=1)
    score = np.where(np.abs(slope) <= MAX_SLOPE, score, -np.inf)
    best = lines[int(np.argmax(score))]
    for _ in range(3):
        on = ok & (np.abs(y - best) <= tol)
        if on.sum() < 3:
            break
        span = (x[on].max() - x[on].min()) / max(w - 1, 1)
        deg = 2 if span > 0.5 and curved else 1
        coef = np.polyfit(x[on] / w, y[on], deg)
        best = np.polyval(coef, x / w)
    on = ok & (np.abs(y - best) <= tol)
    spread = float(np.sqrt(np.mean((y[on] - best[on]) ** 2))) if on.any() else 0.0
    return np.minimum(best, float(h)), spread


def example_photo() -> np.ndarray:
    """A small photograph for the examples of :mod:`growsim.pictures`: ``(60, 50, 3)``
    RGB in [0, 1], a pale blue sky, a green ground strip from row 50, a brown trunk
    (columns 24-26) standing on it from row 15, and a branch across row 20.

    Examples
    --------
    >>> rgb = example_photo()
    >>> rgb.shape, rgb[5, 5].tolist(), rgb[30, 25].tolist()
    ((60, 50, 3), [0.8, 0.9, 1.0], [0.4, 0.3, 0.2])
    """
    rgb = np.ones((60, 50, 3)) * [0.8, 0.9, 1.0]
    rgb[50:] = [0.3, 0.5, 0.2]
    rgb[15:55, 24:27] = [0.4, 0.3, 0.2]
    rgb[20, 12:38] = [0.4, 0.3, 0.2]
    return rgb


def find_scene(
    rgb: np.ndarray, keep: np.ndarray | None = None, *, name: str = "image", hint: str = "--box"
) -> Scene:
    """The scene of a picture ``rgb`` ``(H, W, 3)`` in ``[0, 1]`` (see the module
    docstring), reduced to :data:`COARSE` pixels; ``keep``: where the tree may be (a
    mask). Refuses (:class:`UserInputError` naming ``name``) a picture with no sky along
    its top edge (naming the ``hint`` that settles it).

    Examples
    --------
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> scene = find_scene(rgb, np.ones((60, 50), bool))
    >>> scene.ground, len(scene.objects), scene.objects[0].feet, bool(scene.sky[5, 5])
    (True, 1, ((22, 28),), True)
    """
    from skimage.color import rgb2lab
    from skimage.measure import label

    big_h, big_w = rgb.shape[:2]
    scale = min(1.0, COARSE / max(big_h, big_w))
    shape = (max(8, round(big_h * scale)), max(8, round(big_w * scale)))
    scale = shape[1] / big_w
    small = np.clip(_resize(rgb, shape), 0.0, 1.0)
    lab = rgb2lab(small)
    tex = texture_of(lab)
    h = shape[0]
    top = tex[: max(2, h // 40)]
    smooth_below = float(np.clip(TEXTURE_K * np.median(top), *TEXTURE_RANGE))
    smooth = tex < smooth_below
    if scale < 1.0:
        # the texture the reduction smoothed away (twigs thinner than a coarse pixel,
        # frost): the working picture's own gradient, averaged over each coarse pixel
        fine = fine_texture(rgb, shape)
        top = fine[: max(2, h // 40)]
        smooth &= fine < max(TEXTURE_K * float(np.median(top)), FINE_MIN)
    comps = label(smooth, connectivity=1)
    ids = np.unique(comps[0][smooth[0]])
    sky = np.isin(comps, ids[ids > 0])
    if sky[0].mean() < 0.3:
        raise UserInputError(
            f"{name}: no sky along the top of the picture ({100 * sky[0].mean():.0f} % of the "
            "top edge smooth, the rest textured: foliage, a wall, a tree cut off by the top "
            f"edge): give {hint} x0,y0,x1,y1 around the whole tree"
        )
    sky = _clouds(lab, smooth, comps, sky)
    # the skyline: below the lowest sky pixel of each column
    rows = np.arange(h)[:, None]
    lowest = np.where(sky, rows, -1).max(axis=0)
    skyline = (lowest + 1).astype(np.float64)
    band, spread = band_line(skyline, h)
    standing = _standing(lab, smooth, sky, band, spread, keep)
    if band.min() < h and not standing[2]:
        # nothing rises from the band: it may be a wide crown's top, the horizon lower
        # on both sides of it (a flat-topped acacia, an umbrella of a crown)
        low = _under_bump(skyline, band, h)
        if low is not None:
            lifted = _standing(lab, smooth, sky, *low, keep)
            if lifted[2]:
                band, spread = low
                standing = (*lifted[:2], [replace(o, lifted=True) for o in lifted[2]])
    sky, cut, objects = standing
    ground = bool(np.any(band < h))
    foot = _ground_line(lab, band) if ground else float(h)
    return Scene(scale, lab, tex, smooth_below, sky, skyline, band, cut, ground, objects, foot,
                 spread)  # fmt: skip


def _under_bump(skyline: np.ndarray, band: np.ndarray, h: int):
    """The horizon under a wide crown whose top :func:`band_line` took for it, as
    ``(band, spread)``, or ``None``: the straight line most columns' skylines lie on
    with none below it (the sky never reaches below the horizon), when its columns make
    at least :data:`BUMP_SIDES` of the picture's on each side of those on ``band`` (the
    sky reaching down past the crown on both sides) and none between them (one crown, not
    a row of trees), it is about level (its slope at most :data:`BUMP_LEVEL`: a camera
    held level, not a hill's flank) and ``band`` lies above it there by more than
    :data:`BAND_TOL`.

    Examples
    --------
    >>> y = np.full(100, 80.0); y[8:92] = 20.0 + 0.001 * (np.arange(8, 92) - 50) ** 2
    >>> top, _ = band_line(y, 100)                  # the crown's top taken for the band
    >>> round(float(top[50]), 1)
    20.0
    >>> low, spread = _under_bump(y, top, 100)
    >>> round(float(low[50]), 6), round(spread, 6)
    (80.0, 0.0)
    """
    w = len(skyline)
    y = np.asarray(skyline, dtype=np.float64)
    tol = max(BAND_TOL * h, 2.0)
    ok = y < h
    on = np.flatnonzero(ok & (np.abs(y - band) <= tol))
    if not len(on):
        return None
    low, spread = band_line(y, h, curved=False, below_cost=float(w))
    near = ok & (np.abs(y - low) <= tol)
    if low.min() >= h or min(near[: on.min()].sum(), near[on.max() + 1 :].sum()) < BUMP_SIDES * w:
        return None
    if abs(low[-1] - low[0]) > BUMP_LEVEL * w or near[on.min() : on.max() + 1].any():
        return None  # a tilted line (a hill's flank), or sky down to it: several objects
    if np.any(band[on] > low[on] - tol):
        return None
    return low, spread


def _standing(lab, smooth, sky, band, spread, keep):
    """``(sky, cut, objects)`` over the horizon's ``band`` (its columns' ``spread``): the
    sky with its clouds' rims, the cut (the band less its roughness) and the objects
    standing on the band, largest first (a crown hanging in the sky first of all)."""
    from skimage.measure import label, regionprops

    h, w = sky.shape
    rows = np.arange(h)[:, None]
    ground = bool(np.any(band < h))
    rise = max(BAND_ROUGH * spread, RISE * h, 2.0) if ground else 0.0
    cut = band - rise
    up = rows < cut[None, :]
    sky = sky | (up & _rims(lab, sky, up))
    above = ~sky & up
    if keep is not None:
        above &= _resize(keep.astype(np.float64)[..., None], (h, w))[..., 0] > 0.5
    comps = label(above, connectivity=2)
    textured = label((above | ~smooth) & up, connectivity=2)
    objects = []
    floating = []
    for p in regionprops(comps):
        r0, c0, r1, c1 = p.bbox
        m = comps == p.label
        feet = band_feet(m, cut)
        if ground and not feet:
            floating.append(p)  # a cloud's edge, a bird, a wire; or a crown hanging
            continue
        ids = np.unique(textured[m])
        reach = max(2, int(REGION_REACH * (r1 - r0)))
        near = np.zeros((h, w), dtype=bool)
        near[max(0, r0 - reach) : r1 + reach, max(0, c0 - reach) : c1 + reach] = True
        region = np.isin(textured, ids[ids > 0]) & near
        objects.append(Standing(m, int(p.area), r0, r1 - 1, c0, c1 - 1, tuple(feet), region))
    # without ground (a tree cut out on white, a drawing) every object counts
    objects.sort(key=lambda o: -o.area)
    # another standing object (a hedge, a second tree) is not in an object's region
    every = np.logical_or.reduce([o.mask for o in objects]) if objects else None
    objects = [replace(o, region=o.region & (o.mask | ~every)) for o in objects]
    crown = _hanging_crown(lab, floating, objects, comps, cut, textured) if ground else None
    if crown is not None:
        sky = sky & ~crown.region
        objects.insert(0, crown)
    return sky, cut, objects


def _hanging_crown(lab, floating, objects, comps, cut, textured):
    """The tree whose trunk the sky took (a pale trunk before pale clouds), as a standing
    object; ``None`` when there is none. It is the largest floating piece of ``comps``
    when that is at least :data:`HANG_AREA` of the picture and :data:`HANG_OVER` times the
    largest standing object, clear of the side edges, at least :data:`HANG_TALL` as tall
    as wide, its lowest row within :data:`HANG_GAP` of its height above the cut, and a
    trunk enters the band under it: a run of columns, at most :data:`HANG_FOOT` of its
    width and clear of the feet of what stands there, whose colour just below the cut
    differs from the rows' beside it by :data:`HANG_DE`. Its trunk rises straight up from
    that foot to the crown; the trunk's surroundings (:data:`HANG_REACH` of the crown's
    height either side) join its region, where the tree is read against the sky filled
    in from around it."""
    h, w = comps.shape
    if not floating:
        return None
    p = max(floating, key=lambda q: q.area)
    largest = objects[0].area if objects else 0
    r0, c0, r1, c1 = p.bbox
    if p.area < HANG_AREA * h * w or p.area < HANG_OVER * largest or c0 == 0 or c1 == w:
        return None  # small, or reaching a side edge: a cloud bank, a mountain range
    if r1 - r0 < HANG_TALL * (c1 - c0):
        return None  # flat: a range of hills, not a crown
    at = float(np.median(cut[c0:c1]))
    if at - r1 > HANG_GAP * (r1 - r0) or at <= r1:
        return None  # far above the band: a cloud
    a = int(np.ceil(at))
    rows = slice(min(a, h - 1), min(h, a + max(2, (r1 - r0) // 10)))
    stood = np.zeros(w, dtype=bool)  # the feet of what stands: not a hidden trunk's
    for o in objects:
        for fa, fb in o.feet:
            stood[max(0, fa - 2) : fb + 3] = True
    feet = [(fa, fb) for fa, fb in trunk_feet(lab, rows, c0, c1 - 1)
            if fb - fa + 1 <= HANG_FOOT * (c1 - c0) and not stood[fa : fb + 1].any()]  # fmt: skip
    m = comps == p.label
    if not feet:  # no trunk enters the band: a cloud, or a tree on snow the sky's colour
        trunk = _trunk_below(floating, p, comps, HANG_FOOT * (c1 - c0))
        if trunk is None:
            return None
        m, foot = trunk
        tr = np.flatnonzero(m[foot])
        lo, hi = int(tr.min()), int(tr.max()) + 1
    else:
        lo, hi, foot = feet[0][0], feet[0][1] + 1, None
    # the trunk: up from its foot to the crown
    over = np.flatnonzero(m[:, lo:hi].any(axis=1))
    start = int(over.max()) if len(over) else r1 - 1
    mask = m.copy()
    mask[start : a + 1, lo:hi] = True
    reach = int(np.ceil(HANG_REACH * (r1 - r0)))
    region = np.zeros_like(m)
    region[start : a + 1, max(0, lo - reach) : hi + reach] = True
    ids = np.unique(textured[m])
    near = np.zeros_like(m)
    reach = max(2, int(REGION_REACH * (r1 - r0)))
    near[max(0, r0 - reach) : r1 + reach, max(0, c0 - reach) : c1 + reach] = True
    region |= np.isin(textured, ids[ids > 0]) & near
    edge = np.clip(np.ceil(cut).astype(int) - 1, 0, h - 1)
    cols = np.nonzero(mask[edge, np.arange(w)])[0]
    rr, cc = np.nonzero(mask)
    return Standing(mask, int(mask.sum()), int(rr.min()), int(rr.max()), int(cc.min()),
                    int(cc.max()), tuple(runs(cols)), region, hanging=True, foot=foot)  # fmt: skip


def _trunk_below(floating, crown, comps, widest: float):
    """The trunk of a floating ``crown`` on a ground the sky took (snow under a white sky):
    its lowest :data:`TRUNK_BELOW_TALL` of its height narrower than ``widest``, or a
    floating piece that narrow in its columns, at most :data:`TRUNK_BELOW_GAP` rows under
    it and that long. ``(the crown with it, its lowest row)``, or ``None`` (a cloud)."""
    r0, c0, r1, c1 = crown.bbox
    own = comps == crown.label
    low = own[max(r0, r1 - max(2, int(TRUNK_BELOW_TALL * (r1 - r0)))) : r1]
    cols = np.flatnonzero(low.any(axis=0))
    if len(cols) and np.ptp(cols) + 1 <= widest:
        return own, r1 - 1
    for q in floating:
        q0, d0, q1, d1 = q.bbox
        if q is crown or d1 - d0 > widest or d0 < c0 or d1 > c1:
            continue
        if q0 - r1 <= TRUNK_BELOW_GAP and q1 - r1 >= TRUNK_BELOW_TALL * (r1 - r0):
            return own | (comps == q.label), q1 - 1
    return None


def _clouds(lab, smooth, comps, sky):
    """The sky ``sky`` (the smooth pixels connected to the top edge) with the clouds it
    missed: the smooth pieces whose colour is the sky's (within :data:`PALETTE_DE` of one
    of its colours: a cloud's inside, cut off by its sharp rim; within
    :data:`EDGE_PALETTE_DE` for a piece reaching a side edge and as light as the sky: the
    sky goes on past it, a sunset's glow under the clouds), but those nearer the colours
    along the bottom edge (the ground: snow under a white sky)."""
    from scipy import ndimage
    from scipy.spatial import cKDTree

    colours = lab[sky]
    step = max(1, len(colours) // 4000)
    palette = cKDTree(colours[::step])
    n = comps.max() + 1
    other = smooth & ~sky
    if other.any():
        d, _ = palette.query(lab[other], k=1)
        med = np.asarray(ndimage.median(d, comps[other], index=np.arange(n)))
        cloud = np.zeros(n, dtype=bool)
        cloud[1:] = med[1:] < PALETTE_DE
        # the sky past a side edge (a sunset's glow, a hazy band under the clouds):
        # smooth pieces reaching it, within EDGE_PALETTE_DE of the sky's colours and
        # at least as light as its median (a treeline, a hill, a wall is darker)
        edge = np.zeros(n, dtype=bool)
        edge[np.unique(np.r_[comps[:, 0], comps[:, -1]])] = True
        light = np.asarray(ndimage.median(lab[..., 0][other], comps[other], index=np.arange(n)))
        edge &= light >= np.median(colours[:, 0])
        cloud[1:] |= edge[1:] & (med[1:] < EDGE_PALETTE_DE)
        # nearer the ground's colours (along the bottom edge) than the sky's: the ground
        # (snow under a white sky), not a cloud
        bottom = lab[-max(2, lab.shape[0] // 40) :].reshape(-1, 3)
        below, _ = cKDTree(bottom[:: max(1, len(bottom) // 2000)]).query(lab[other], k=1)
        low = np.asarray(ndimage.median(below, comps[other], index=np.arange(n)))
        cloud[1:] &= low[1:] > med[1:]
        sky = sky | (cloud[comps] & smooth)
    return sky


def _rims(lab, sky, where):
    """The pixels of ``where`` that are the sky's after all: those whose colour is one of
    the sky's (within :data:`PALETTE_DE`: a cloud's textured inside), or lies among the
    sky's within :data:`RIM_REACH` pixels (each channel in its range, give or take
    :data:`RIM_DE`: a cloud's rim, a mix of the colours either side of it), farther than
    :data:`STRONG_REACH` pixels from any that is neither (a twig, a crown, a hedge)."""
    from scipy import ndimage
    from scipy.spatial import cKDTree
    from skimage.morphology import disk

    colours = lab[sky]
    if not len(colours):
        return np.zeros(sky.shape, dtype=bool)
    palette = cKDTree(colours[:: max(1, len(colours) // 4000)])
    like = np.zeros(sky.shape, dtype=bool)
    test = where & ~sky
    d, _ = palette.query(lab[test], k=1)
    like[test] = d < PALETTE_DE
    size = 2 * RIM_REACH + 1
    among = np.ones(sky.shape, dtype=bool)
    for k in range(3):
        hi = ndimage.maximum_filter(np.where(sky, lab[..., k], -np.inf), size, mode="nearest")
        lo = ndimage.minimum_filter(np.where(sky, lab[..., k], np.inf), size, mode="nearest")
        among &= (lab[..., k] >= lo - RIM_DE) & (lab[..., k] <= hi + RIM_DE)
    strong = where & ~sky & ~like & ~among
    near = ndimage.binary_dilation(strong, disk(STRONG_REACH))
    return where & ~sky & ~near


def _ground_line(lab: np.ndarray, band: np.ndarray) -> float:
    """The row below the band where the horizon's clutter ends and the ground begins:
    the strongest change of the rows' median colour (over the whole width) from the
    band's lowest row down, when it exceeds :data:`GROUND_EDGE` (Delta E); else the
    band's lowest row (no clutter, or none told apart)."""
    from scipy import ndimage

    h = lab.shape[0]
    start = int(np.ceil(np.max(band)))
    if start >= h - 3:
        return float(min(start, h))
    med = ndimage.median_filter(np.median(lab[start:], axis=1), size=(3, 1), mode="nearest")
    step = np.linalg.norm(np.diff(med, axis=0), axis=1)
    # a change across two rows (an edge blurred by the reduction)
    step = step[:-1] + step[1:] if len(step) > 1 else step
    i = int(np.argmax(step))
    return float(start + i + 1) if step[i] > GROUND_EDGE else float(start)


def runs(cols: np.ndarray, gap: int = 0) -> list[tuple[int, int]]:
    """Runs of consecutive column indices: ``[(first, last), ...]``; with ``gap``, runs at
    most ``gap`` columns apart are one.

    Examples
    --------
    >>> runs(np.array([1, 2, 3, 7, 9, 10]))
    [(1, 3), (7, 7), (9, 10)]
    >>> runs(np.array([1, 2, 3, 7, 9, 10]), gap=1)
    [(1, 3), (7, 10)]
    """
    if not len(cols):
        return []
    breaks = np.nonzero(np.diff(cols) > 1 + gap)[0]
    starts = np.r_[cols[0], cols[breaks + 1]]
    ends = np.r_[cols[breaks], cols[-1]]
    return [(int(a), int(b)) for a, b in zip(starts, ends)]


def band_feet(mask: np.ndarray, cut: np.ndarray) -> list[tuple[int, int]]:
    """Where a standing object's ``mask`` (coarse) enters the band: the runs of columns
    in which it reaches the row just above the ``cut`` (per column) or the one above that.

    Examples
    --------
    >>> m = np.zeros((10, 8), bool); m[2:9, 3:5] = True; m[2:4, 6:8] = True
    >>> band_feet(m, np.full(8, 9.0))
    [(3, 4)]
    """
    h, w = mask.shape
    edge, cols = np.clip(np.ceil(cut).astype(int) - 1, 0, h - 1), np.arange(w)
    return runs(np.flatnonzero(mask[edge, cols] | mask[np.clip(edge - 1, 0, h - 1), cols]))


def trunk_feet(lab: np.ndarray, rows: slice, left: int, right: int, reach: int = 6):
    """Where a trunk may enter the ground among the columns ``left``..``right``
    (inclusive) of ``lab`` (CIELAB): the runs of them whose colour in ``rows`` differs
    from the rows' own beside them (:func:`~growsim.pictures.backdrop.row_background`,
    ``reach`` pixels either side) by more than :data:`HANG_DE` on average;
    ``[(first, last), ...]``, the most different (summed over the run) first.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> trunk_feet(rgb2lab(rgb), slice(51, 54), 15, 35)
    [(24, 26)]
    """
    back = backdrop.row_background(lab, left, right, rows, reach=reach)
    d = np.linalg.norm(lab[rows, left : right + 1] - back, axis=-1).mean(axis=0)
    found = [(left + a, left + b) for a, b in runs(np.flatnonzero(d > HANG_DE))]
    return sorted(found, key=lambda f: -float(d[f[0] - left : f[1] - left + 1].sum()))
