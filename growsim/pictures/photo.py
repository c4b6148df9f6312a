"""Colour photos of a tree: the tree apart from the sky and the ground.

:func:`segment_photo` turns a colour picture (a tree standing on a ground strip under a
sky) into the tree's silhouette, or refuses it naming the picture; :func:`load_rgb`
reads a picture in colour. :func:`growsim.pictures.images.picture_silhouettes` calls it for
``segmentation = "photo"``; the grey-level threshold and the framing for fitting are in
:mod:`growsim.pictures.images`, the checks every silhouette passes in
:mod:`growsim.pictures.reading`.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass

import numpy as np

from growsim.errors import UserInputError
from growsim.pictures.reading import (
    SPECK,
    check_silhouette,
    load_gray,
    load_rgb,
    working_scale,
)
from growsim.pictures.scene import (
    PALETTE_DE,
    RIVAL_AREA,
    RIVAL_HEIGHT,
    Scene,
    find_scene,
    row_background,
    runs,
    sky_background,
)

__all__ = [
    "Segmentation",
    "linear_to_srgb",
    "load_rgb",
    "segment_photo",
    "segmentation_picture",
    "srgb_to_linear",
    "unmix",
]

# How segment_photo tells the tree's pixels from their background. Measured on the
# benchmark's pictures (benchmarks/make_photos.py: JPEG renders of growsim trees on a
# ground plane under a sky), on composites of trees on outdoor backgrounds and on
# growsim's line drawings.
#: Fully covered pixels (the interior of the tree's thick parts) are found first by local
#: thresholds on the colour difference: this share of the strongest difference within a
#: window of this many pixels, never under NOISE_K times the background's noise nor MIN_DE
LOCAL_WINDOW = 7
LOCAL_SHARE = 0.3
#: JPEG compression rings beside a strong edge (up to the far side of its 8 x 8 block):
#: pixels under this share of the strongest difference within RINGING_WINDOW pixels are
#: background
RINGING = 0.15
RINGING_WINDOW = 17
NOISE_K = 5.0
#: beside a thick part (pixels whose whole 3 x 3 neighbourhood differs from the
#: background) a pixel differing by less than this share of the full difference within
#: LOCAL_WINDOW pixels is background
THICK_SHARE = 0.4
#: pieces of foreground this many pixels or less from the tree join it (a twig broken by
#: a pixel as pale as the sky)
GAP = 2
#: every pixel's coverage by linear unmixing in linear light: the tree's colour at a pixel
#: is the nearest fully covered pixel's up to this many pixels from it, the median of
#: the fully covered pixels beyond (thin twigs); a pixel is tree when covered at least
#: half (COVERAGE), as the true silhouette is defined
UNMIX_REACH = 3.0
COVERAGE = 0.5
#: a round part's surface turns away from the light toward its outline (Lambert's cosine
#: law), so a partly covered pixel at its rim sees a darker tree than the nearest fully
#: covered pixel inside: that colour darkened by this share in linear light. A Lambert
#: cylinder lit from the camera's side with a fifth ambient light is 0.42 darker on the
#: outer quarter of its width than on its middle half; 0.3 allows for light from other
#: sides.
RIM_SHADE = 0.3
#: a thin twig (no fully covered pixel within UNMIX_REACH) takes the colour of its most
#: covered pixel up to this many pixels along it (its best-centred pixel recurs every few
#: pixels along a slanted twig); near thick parts, of its 3 x 3 only
THIN_WINDOW = 3
MIN_DE = 10.0
#: the sky's own pixels, where the background is filled in from: the coarse scene's sky
#: less its thin dark or pale lines (a twig the reduced picture lost: a pixel differing by
#: more than this, Delta E, from the median of its THIN_SIZE x THIN_SIZE neighbourhood)
THIN_DE = 6.0
THIN_SIZE = 7
#: the band at the working size follows the horizon's outline, smoothed over this share
#: of the width
FOLLOW_WINDOW = 0.02
#: ... when the band is this smooth (its columns' spread around it, coarse rows): not
#: along a treeline's crowns
SMOOTH_BAND = 1.0
#: the crown's region reaches this share of its height around the rows' spans (faint twig
#: tips beyond the reduced picture's object join when joined to the tree)
CROWN_PAD = 0.05
#: a sky whose colour varies by at most this around a quadratic gradient (Delta E, robust;
#: the legacy segmentation's plain sky, up to 4) is that gradient behind the tree
PLAIN_SKY = 2.0
#: ... with at least this share of its pixels near the gradient (the rest: faint twigs)
PLAIN_SHARE = 0.75
#: a pixel of the crown as smooth as the sky (its lightness's gradient smoothed over
#: POCKET_SMOOTH pixels under POCKET_K times the sky's median, at least POCKET_MIN Delta L a
#: pixel) and of the sky's colours is
#: the sky seen through the crown (a cloud behind it)
POCKET_SMOOTH, POCKET_K, POCKET_MIN = 1.5, 3.0, 1.5
#: the crown's region: the standing object of the coarse scene grown by this many coarse
#: pixels (twigs thinner than a coarse pixel, the texture's smoothing)
CROWN_MARGIN = 2
#: below the cut: GrabCut in the standing object's columns and this share of its width
#: either side (the ground's and clutter's colours), so many iterations
BELOW_MARGIN = 0.15
GRABCUT_ITERATIONS = 5
#: ... down to this share of the tree's height below the cut's lowest row, on at most this
#: many pixels (a larger window is reduced for it)
BELOW_DEPTH = 0.5
GRABCUT_PIXELS = 30_000
#: ... and differing from the row's colour beside the tree by more than this many times
#: that colour's spread along the row (robust sigma), at least MIN_DE
ROW_K = 3.0
#: refused without a box: the tree taken below the cut reaches both sides of its columns
#: in more than this share of those rows (a wood, a hedge of its colours behind it)
MAX_SPILL = 0.5
#: refused without a box: the horizon's clutter (from the band's top to the ground) is
#: more than this share of the tree's height (from its top to the ground): a tree in
#: front of a wood
MAX_CLUTTER = 0.45
#: the trunk's columns below the cut (its feet there, widened by this share of their width
#: either side, at least FOOT_MARGIN_MIN pixels) are read against the row's colour within
#: FOOT_REACH pixels beside them
FOOT_MARGIN, FOOT_MARGIN_MIN, FOOT_REACH = 0.5, 3, 6
#: ... or taken by GrabCut and differing from it by more than this (Delta E)
FOOT_DE = 15.0
#: the trunk, hidden behind the horizon's clutter (a hedge of its colour), is bridged over
#: gaps of up to this share of the tree's height
TRUNK_GAP = 0.4
#: ... when its foot above the gap is at most this share of the crown's width
TRUNK_WIDTH = 0.3
#: refused: the tree's median colour difference from its background under this (Delta E)
MIN_CONTRAST = 15.0
#: refused: the tree touching the top, left or right edge with this many pixels or more
#: (it is cut off; the framing needs the whole tree)
MAX_EDGE_PIXELS = 3
#: the confidence reported: the share of the tree's outline that differs from its
#: background by more than this many times the threshold's floor
CONFIDENT = 2.0


@dataclass(frozen=True)
class Segmentation:
    """What :func:`segment_photo` found: ``tree`` ``(H, W)`` bool (the silhouette),
    ``ground`` ``(H, W)`` bool (below the horizon's band, not tree), ``horizon`` (the
    band's row at the tree's trunk, ``None`` without ground), ``distance`` ``(H, W)``
    (each pixel's colour difference from its background, Delta E), ``threshold`` (the
    least one a fully covered pixel has, Delta E), ``sky_noise`` (robust sigma of the sky
    around its filled-in model, Delta E), ``contrast`` (the tree's median difference
    from its background, Delta E), ``coverage`` ``(H, W)`` (each pixel's estimated share
    covered by the tree, by linear unmixing; ``tree`` is where it is at least
    :data:`COVERAGE`, before connectivity); and how it was found: ``sky`` ``(H, W)`` bool,
    ``band`` (the top of the horizon's band per column, rows; ``H`` where there is no
    ground), ``cut`` (what rises above this line per column stands out of the band),
    ``objects`` (the boxes ``(x0, y0, x1, y1)`` of the standing objects, the tree's
    first), ``hint`` (``{"box": ...}``, ``{"point": ...}`` or ``None``, in working
    pixels), ``method``, ``outline_contrast`` (the median difference of the outline's
    pixels, Delta E) and ``confidence`` (the share of the outline differing from its
    background by more than :data:`CONFIDENT` times the threshold), ``seconds``,
    ``hint_scale`` (working pixels a pixel of the picture as given: the hint's)."""

    tree: np.ndarray
    ground: np.ndarray
    horizon: int | None
    distance: np.ndarray
    threshold: float
    sky_noise: float
    contrast: float
    coverage: np.ndarray | None = None
    sky: np.ndarray | None = None
    band: np.ndarray | None = None
    cut: np.ndarray | None = None
    objects: tuple = ()
    hint: dict | None = None
    method: str = "sky and skyline"
    outline_contrast: float = 0.0
    confidence: float = 0.0
    seconds: float = 0.0
    hint_scale: float = 1.0

    def describe(self) -> str:
        """One line: what was found (for messages and logs)."""
        ground = "no ground" if self.horizon is None else f"ground from row {self.horizon}"
        hint = "" if not self.hint else f", hint {_hint_text(self.hint)}"
        return (
            f"photo segmentation ({self.method}{hint}): {ground}, {len(self.objects)} "
            f"standing object(s), sky noise {self.sky_noise:.1f}, tree/background threshold "
            f"{self.threshold:.1f}, contrast {self.contrast:.1f}, outline "
            f"{self.outline_contrast:.1f} (Delta E), confidence {self.confidence:.2f}"
        )

    def record(self) -> dict:
        """What was found, as plain values (``fit.json``'s ``segmentation``)."""
        h, w = self.tree.shape
        rows, cols = np.nonzero(self.tree)
        band = None
        if self.band is not None and self.horizon is not None:
            xs = np.linspace(0, w - 1, 9).round().astype(int)
            band = {"columns": xs.tolist(), "rows": [round(float(self.band[x]), 1) for x in xs]}
        return {
            "method": self.method,
            "hint": self.hint,
            "size": [w, h],
            "horizon": self.horizon,
            "band": band,
            "objects": [list(map(int, o)) for o in self.objects],
            "tree_box": _box_of(rows, cols),
            "tree_pixels": int(rows.size),
            "sky_noise": round(self.sky_noise, 2),
            "threshold": round(self.threshold, 2),
            "contrast": round(self.contrast, 2),
            "outline_contrast": round(self.outline_contrast, 2),
            "confidence": round(self.confidence, 3),
            "seconds": round(self.seconds, 3),
        }


def _box_of(rows, cols):
    """``[x0, y0, x1, y1]`` around pixels at ``rows``, ``cols`` (``None``: none)."""
    if not len(rows):
        return None
    return [int(cols.min()), int(rows.min()), int(cols.max()) + 1, int(rows.max()) + 1]


def _hint_text(hint: dict) -> str:
    if "box" in hint:
        return "box " + ",".join(f"{v:g}" for v in hint["box"])
    return "point " + ",".join(f"{v:g}" for v in hint["point"])


def srgb_to_linear(v):
    """sRGB values in ``[0, 1]`` to linear light (IEC 61966-2-1), where colours mix as
    light does: a pixel a camera sees half covered by a branch has the mean of the
    branch's and the sky's linear colours, not of their sRGB values.

    Examples
    --------
    >>> round(float(srgb_to_linear(0.5)), 4), float(srgb_to_linear(1.0))
    (0.214, 1.0)
    """
    v = np.clip(np.asarray(v, dtype=np.float64), 0.0, 1.0)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(v):
    """Linear light in ``[0, 1]`` to sRGB values, the inverse of :func:`srgb_to_linear`.

    Examples
    --------
    >>> round(float(linear_to_srgb(srgb_to_linear(0.3))), 6)
    0.3
    """
    v = np.clip(np.asarray(v, dtype=np.float64), 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def unmix(colour, background, tree) -> np.ndarray:
    """Linear unmixing: the share ``a`` of each pixel covered by the tree, from
    ``colour = background + a (tree - background)`` (least squares over the channels);
    ``(H, W, C)`` arrays in one colour space (linear light for a camera's picture).

    Examples
    --------
    >>> sky, bark = np.array([0.8, 0.9, 1.0]), np.array([0.2, 0.15, 0.1])
    >>> px = (0.3 * bark + 0.7 * sky)[None, None]
    >>> round(float(unmix(px, sky[None, None], bark[None, None])[0, 0]), 6)
    0.3
    """
    fb = tree - background
    return np.einsum("ijk,ijk->ij", colour - background, fb) / np.maximum(
        np.einsum("ijk,ijk->ij", fb, fb), 1e-12
    )


def _robust_sigma(x) -> float:
    x = np.asarray(x, np.float64)
    return float(1.4826 * np.median(np.abs(x - np.median(x)))) if x.size else 0.0


def _upsample(coarse: np.ndarray, shape, scale: float) -> np.ndarray:
    """A coarse ``(h, w)`` array at the working ``shape``: each working pixel takes the
    coarse pixel it falls in (``scale`` coarse pixels a working pixel)."""
    h, w = coarse.shape[:2]
    r = np.minimum((np.arange(shape[0]) * scale).astype(np.int64), h - 1)
    c = np.minimum((np.arange(shape[1]) * scale).astype(np.int64), w - 1)
    return coarse[r[:, None], c[None, :]]


def _per_column(coarse_rows: np.ndarray, width: int, scale: float) -> np.ndarray:
    """A coarse per-column row line at the working ``width``, in working rows."""
    c = np.minimum((np.arange(width) * scale).astype(np.int64), len(coarse_rows) - 1)
    return np.asarray(coarse_rows, dtype=np.float64)[c] / scale


def _hint_pixels(values, n: int, per_pixel: float, shape, flag: str, name: str):
    """A hint ``values`` (``n`` numbers, pixels of the picture as given) in working pixels,
    checked: inside the picture."""
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


def _choose(scene: Scene, point, boxed: bool, name: str, flags, how: str, per_pixel=1.0):
    """The tree among the scene's standing objects: the one at the ``point`` (coarse
    ``(x, y)``), else the largest; refused when there is none, or another one nearly as
    large and no hint (``boxed``: the objects are already those inside a box)."""
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
    tree = objects[0]
    height = tree.bottom - tree.top + 1
    rivals = [o for o in objects[1:]
              if o.area >= RIVAL_AREA * tree.area
              and o.bottom - o.top + 1 >= RIVAL_HEIGHT * height]  # fmt: skip
    if rivals and not boxed:
        boxes = " or ".join(
            f"{flags[0]} {','.join(map(str, _suggested_box(scene, o, per_pixel)))}"
            for o in sorted((tree, *rivals[:2]), key=lambda o: o.left)
        )
        raise UserInputError(
            f"{name}: other objects beside the tree stand as tall as it, which is the tree? "
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


def segment_photo(
    image,
    *,
    mask=None,
    box=None,
    point=None,
    name: str = "image",
    flags: tuple[str, str] = ("--box", "--point"),
) -> Segmentation:
    """Find the tree in a colour picture: apart from the sky, the ground and the clutter
    along the horizon.

    ``image``: a path or an ``(H, W, 3)`` RGB (or ``(H, W)`` grey) array in ``[0, 1]``;
    ``mask``: optional picture or array of the same size, only its light part (> 0.5) may
    be tree; ``box`` ``(x0, y0, x1, y1)``: the tree lies in this box; ``point``
    ``(x, y)``: a pixel on the tree (the hints, in pixels of the picture as given: a file
    is read at its working size, :func:`~growsim.pictures.reading.working_scale`);
    ``name`` labels errors, ``flags`` names the hints in them. Colours are compared in
    CIELAB (:func:`skimage.color.rgb2lab`; Delta E, CIE76).

    1. **the scene** (:func:`~growsim.pictures.scene.find_scene`, on the picture reduced):
       the sky (smooth, connected to the top edge: clouds and gradients included), the
       skyline, the horizon's band of clutter (its lower envelope), the objects standing
       on the band and rising into the sky; the tree is the largest (or the one at the
       hint), its crown's region that object, its trunk's columns where it enters the
       band;
    2. each pixel's **background**: in the crown's region the sky filled in from the sky
       around and between the branches (:func:`~growsim.pictures.scene.sky_background`,
       thin lines left out: :data:`THIN_DE`), the sky's pockets in the crown added to it;
       in the trunk's columns below the band's top each row's colour beside the trunk,
       interpolated across it (:func:`~growsim.pictures.scene.row_background`: the
       ground, a hedge, a field behind the trunk);
    3. the **fully covered** pixels: the interior (3 x 3 erosion) of those over a local
       threshold (:data:`LOCAL_SHARE` of the strongest difference within
       :data:`LOCAL_WINDOW` pixels, :data:`THICK_SHARE` of the full difference of the
       nearest thick part, the JPEG ringing share :data:`RINGING`, never under
       :data:`NOISE_K` times the sky's noise or :data:`MIN_DE`);
    4. each pixel's **coverage** by linear unmixing in linear light (a camera's pixel
       sums the light of what it sees): its colour is its background's plus the coverage
       times the tree's colour minus the background's; the tree's colour is the nearest
       fully covered pixel's (within :data:`UNMIX_REACH`) darkened by :data:`RIM_SHADE`
       (a round part's rim is darker than its inside), or the median of them all (a thin
       twig, never fully covered), or the colour of a pixel of its 3 x 3 (of its
       :data:`THIN_WINDOW` on a thin twig) farther from the background than that. A pixel is
       tree when covered at least :data:`COVERAGE` (a half, as the true silhouette of a
       render is defined) and more than the sky's noise, or fully covered;
    5. **connectivity** (:func:`skimage.measure.label`, 8-connected): the tree is the
       piece that holds most of the standing object, the pieces up to :data:`GAP` pixels
       from it (a twig broken by a pixel as pale as the sky) and every piece in the
       crown's region; below the band's top, the trunk's pieces joined to it, bridged over
       gaps up to :data:`TRUNK_GAP` of its height (a trunk the colour of the hedge behind
       it).

    Refused with :class:`UserInputError` naming ``name`` (a bad segmentation is not
    fitted): no sky along the top edge, no object standing on the ground, other objects
    as tall and large as the tree without a hint (the message names the hint that settles
    it), a tree that hardly differs from its background (:data:`MIN_CONTRAST`), a tree cut
    off by the top or side edges (:data:`MAX_EDGE_PIXELS`), and every silhouette
    :func:`check_silhouette` refuses.

    Examples
    --------
    >>> import numpy as np
    >>> rgb = np.ones((60, 50, 3)) * [0.8, 0.9, 1.0]           # sky
    >>> rgb[50:] = [0.3, 0.5, 0.2]                               # ground strip
    >>> rgb[15:55, 24:27] = [0.4, 0.3, 0.2]                      # trunk, standing on it
    >>> rgb[20, 12:38] = [0.4, 0.3, 0.2]                         # a branch
    >>> seg = segment_photo(rgb)
    >>> seg.horizon, int(seg.tree.sum()), bool(seg.tree[52, 25]), bool(seg.tree[52, 5])
    (50, 143, True, False)
    """
    from scipy import ndimage
    from skimage.color import gray2rgb, rgb2lab
    from skimage.morphology import disk

    t_start = time.perf_counter()
    per_pixel = 1.0  # working pixels per pixel of the picture as given (the hints')
    if isinstance(image, (str, os.PathLike)):
        name = str(image)
        per_pixel = working_scale(image)
        image = load_rgb(image)
    rgb = np.asarray(image, dtype=np.float64)
    if rgb.ndim == 2:
        rgb = gray2rgb(rgb)
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.shape[0] < 8 or rgb.shape[1] < 8:
        raise UserInputError(f"{name}: expected an RGB picture of at least 8 x 8, got {rgb.shape}")
    if float(np.ptp(rgb)) < 1e-6:
        raise UserInputError(f"{name}: the picture is uniform (blank): no silhouette to fit")
    rgb = np.clip(rgb, 0.0, 1.0)
    h, w = rgb.shape[:2]
    keep = np.ones((h, w), dtype=bool)
    if mask is not None:
        mname = str(mask) if isinstance(mask, (str, os.PathLike)) else f"{name} mask"
        m = load_gray(mask) if isinstance(mask, (str, os.PathLike)) else np.asarray(mask, float)
        if m.shape != rgb.shape[:2]:
            raise UserInputError(
                f"{mname}: mask size {m.shape[::-1]} differs from the image's {rgb.shape[1::-1]}"
            )
        keep = m > 0.5
        if not keep.any():
            raise UserInputError(f"{mname}: the mask keeps no pixel (it is all black)")
    hint: dict = {}
    if box is not None:
        (x0, y0, x1, y1), given = _hint_pixels(box, 4, per_pixel, (h, w), flags[0], name)
        inside = np.zeros((h, w), dtype=bool)
        inside[max(0, int(y0)) : int(np.ceil(y1)), max(0, int(x0)) : int(np.ceil(x1))] = True
        keep &= inside
        hint["box"] = given
    at = None
    if point is not None:
        (px, py), given = _hint_pixels(point, 2, per_pixel, (h, w), flags[1], name)
        hint["point"] = given
        at = (px, py, *given)
    try:
        scene = find_scene(rgb, keep, name=name, hint=flags[0])
        s = scene.scale
        how = f"{len(scene.objects)} standing object(s)"
        coarse_at = None if at is None else (at[0] * s, at[1] * s, at[2], at[3])
        obj = _choose(scene, coarse_at, box is not None, name, flags, how, per_pixel)
    except UserInputError:
        if box is None:
            raise
        # no sky, or nothing standing out of it: the tree is what the box holds apart
        # from what lies around it (GrabCut)
        return _in_box(rgb, keep, None, hint, per_pixel, name, t_start)
    # the object reaching the picture's side (the box's, with a box): a tree cut off, or
    # one merging with a wood or other trees that do
    w_c = scene.shape[1]
    left, right = 0, w_c - 1
    if box is not None:
        left = max(0, int(np.ceil(max(box[0], 0.0) * per_pixel * s)))
        right = min(w_c - 1, int(box[2] * per_pixel * s) - 1)
    touching = [side for side, col in (("left", left), ("right", right))
                if obj.mask[:, col].sum() >= MAX_EDGE_PIXELS]  # fmt: skip
    # the horizon's clutter as tall as a good part of the tree: it stands in front of a
    # wood (its crown's lower part, its trunk among trees of its colours)
    band_at = float(np.median(scene.band[obj.left : obj.right + 1]))
    clutter = (scene.ground_line - band_at) / max(scene.ground_line - obj.top, 1.0)
    if scene.ground and clutter > MAX_CLUTTER and (box is not None or not touching):
        if box is None:
            raise UserInputError(
                f"{name}: the tree stands in front of a wood or a treeline as tall as "
                f"{100 * clutter:.0f} % of it: give {flags[0]} x0,y0,x1,y1 around the tree"
            )
        # the box holds the tree and the wood behind it: GrabCut, the sky known (away from
        # the crown's outline, which the reduced picture blurs)
        sky = ndimage.binary_erosion(scene.sky, disk(2 * CROWN_MARGIN), border_value=1)
        return _in_box(rgb, keep, _upsample(sky, (h, w), s), hint, per_pixel, name, t_start)
    if touching and box is None:
        raise UserInputError(
            f"{name}: the tree reaches the picture's {touching[0]} edge, or merges with "
            "something that does (a wood, a hedge, other trees): if the whole tree is in the "
            f"picture give {flags[0]} x0,y0,x1,y1 around it, else take it from farther away"
        )

    # the tree's region at the working size: its crown above the cut
    cut = _per_column(scene.cut, w, s)
    band = _per_column(scene.band, w, s)
    shift = 0
    if scene.ground:
        # the band at the working size: where the colour changes most across it, near
        # the coarse line (the texture's smoothing moved it a few pixels up)
        lo, hi = int(obj.left / s), int(np.ceil((obj.right + 1) / s))
        away = np.r_[0:lo, hi:w]
        shift = _band_shift(rgb, band, away, int(np.ceil(3.0 / s)) + 1)
        rise = band - cut
        band = band + shift
        if scene.roughness <= SMOOTH_BAND:  # a clean horizon, a hill: its own outline
            band = _band_follow(rgb, band, away, int(np.ceil(2.0 / s)) + 1)
        cut = band - rise
    rows = np.arange(h)[:, None]
    below = rows >= cut[None, :]
    core = _upsample(ndimage.binary_dilation(obj.mask, disk(CROWN_MARGIN)), (h, w), s)
    if shift > 0:  # down to the band found at the working size
        core[shift:] |= core[:-shift].copy()
    core &= ~below & keep
    # the crown's region: each row from the object's leftmost to its rightmost pixel (twigs
    # too pale for the reduced picture lie between its branches)
    hull = _row_spans(core) & ~below & keep
    crown = hull | (_upsample(obj.region, (h, w), s) & ~below & keep)
    # and around it, twigs too faint for the reduced picture (they join when joined)
    rr, cc = np.nonzero(hull)
    if len(rr):
        m = int(np.ceil(CROWN_PAD * (rr.max() - rr.min() + 1)))
        around = np.zeros((h, w), dtype=bool)
        around[max(0, rr.min() - m) : rr.max() + 1, max(0, cc.min() - m) : cc.max() + m + 1] = True
        crown |= ndimage.binary_dilation(hull, np.ones((3, 3), bool), iterations=m) & around
        crown &= ~below & keep
    rr, cc = np.nonzero(crown)
    pad = RINGING_WINDOW + 2
    r0, r1 = max(0, rr.min() - pad), min(h, rr.max() + pad + 1)
    c0, c1 = max(0, cc.min() - pad), min(w, cc.max() + pad + 1)
    crop = (slice(r0, r1), slice(c0, c1))
    part = rgb[crop]
    lab = rgb2lab(part)
    crown_c = crown[crop]
    # the sky's own pixels: the scene's sky, less the thin lines it lost
    sky_c = _upsample(scene.sky, (h, w), s)[crop]
    thin = _thin_lines(lab)
    region = (core | _upsample(obj.region, (h, w), s))[crop]
    ref = sky_c & ~thin & ~region
    if ref.sum() < 16:
        ref = sky_c & ~thin
    if ref.sum() < 16:
        ref = ~crown_c
    # a plain sky (a smooth gradient, no clouds) is its quadratic model, faint twigs
    # and all left out; any other sky is filled in from its pixels around the tree
    bg, noise = _plain_sky(lab, ref, sky_c & ~thin)
    plain = bg is not None
    if not plain:
        bg = sky_background(lab, ref)
    dist = np.linalg.norm(lab - bg, axis=-1)
    # the smooth pixels of the sky's colours in the crown are the sky seen through it (a
    # cloud behind the crown, or joined to it in the reduced picture)
    seen = crown_c & ~thin & _smooth_sky(lab, ref)
    if plain:
        dist[seen] = 0.0
    else:
        noise = max(_robust_sigma(dist[ref]), 0.25)
        # the sky's pockets in the crown (between leaves and twigs) join its pixels: those
        # differing little from the sky filled in, and the smooth ones of the sky's
        # colours (a cloud behind the crown)
        pockets = crown_c & ~thin & (dist < max(NOISE_K * noise, 0.5 * MIN_DE)) | seen
        if pockets.any():
            bg = sky_background(lab, ref | pockets)
            dist = np.linalg.norm(lab - bg, axis=-1)
    fg, coverage, floor = _cover(part, lab, bg, dist, noise, crown_c)
    tree_c = _connected(fg, obj, hull[crop], (r0, c0), (h, w), s)
    tree = np.zeros((h, w), dtype=bool)
    tree[crop] = tree_c
    distance = np.zeros((h, w))
    distance[crop] = np.where(crown_c, dist, 0.0)
    cover = np.zeros((h, w))
    cover[crop] = np.where(crown_c, coverage, 0.0)
    if scene.ground and tree.any():
        # below the cut: the trunk and what hangs low, apart from the ground and the
        # horizon's clutter by their colours (GrabCut, seeded by the crown above)
        sky = _upsample(scene.sky, (h, w), s) & ~below & ~tree
        low, spill = _below_cut(rgb, tree, below, sky, obj, s, keep)
        tree |= low
        if spill > MAX_SPILL and box is None:
            raise UserInputError(
                f"{name}: the tree's lower part cannot be told from what stands behind it "
                f"(a wood, a hedge, other trees of its colours reach out to both sides of it "
                f"in {100 * spill:.0f} % of the rows below the skyline): give {flags[0]} "
                f"x0,y0,x1,y1 around the tree"
            )
    how = (f"{how}, sky noise {noise:.1f}, threshold >= {floor:.1f} Delta E")  # fmt: skip
    if not tree.any():
        raise UserInputError(f"{name}: the silhouette is empty ({how})")
    # measured on the crown, above the cut (below it GrabCut told the tree apart)
    judged = tree & ~below if (tree & ~below).any() else tree
    contrast = float(np.median(distance[judged]))
    outline = judged & ~ndimage.binary_erosion(tree, np.ones((3, 3), dtype=bool))
    outline_contrast = float(np.median(distance[outline])) if outline.any() else contrast
    confidence = float(np.mean(distance[outline] > CONFIDENT * floor)) if outline.any() else 0.0
    horizon = None
    ground = np.zeros((h, w), dtype=bool)
    if scene.ground:
        tr, tc = np.nonzero(tree)
        foot = tc[tr >= tr.max() - max(1, 0.02 * (tr.max() - tr.min()))]
        horizon = round(float(band[int(np.clip(np.median(foot), 0, w - 1))]))
        ground = (rows >= band[None, :]) & ~tree
    k = 1.0 / s
    objects = tuple(
        (o.left * k, o.top * k, (o.right + 1) * k, (o.bottom + 1) * k)
        for o in [obj, *[o for o in scene.objects if o is not obj]]
    )
    seg = Segmentation(
        tree, ground, horizon, distance, floor, noise, contrast, cover,
        sky=_upsample(scene.sky, (h, w), s) & ~tree, band=band, cut=cut,
        objects=tuple(tuple(round(v) for v in o) for o in objects), hint=hint or None,
        method="sky and skyline", outline_contrast=outline_contrast, confidence=confidence,
        seconds=time.perf_counter() - t_start, hint_scale=per_pixel,
    )  # fmt: skip
    if contrast < MIN_CONTRAST:
        raise UserInputError(
            f"{name}: the tree hardly differs from its background: median colour difference "
            f"{contrast:.1f} Delta E (at least {MIN_CONTRAST:g}; {how}); use a picture with "
            "more contrast, or a mask"
        )
    for edge_name, n_edge in (
        ("top", int(tree[0].sum())),
        ("left", int(tree[: int(cut[0]), 0].sum())),
        ("right", int(tree[: int(cut[-1]), -1].sum())),
    ):
        if n_edge >= MAX_EDGE_PIXELS:
            settle = (
                "the whole tree must be in the picture: take it from farther away"
                if box is not None
                else "it is cut off, or merges with something that does (a wood, other "
                f"trees): if the whole tree is in the picture give {flags[0]} x0,y0,x1,y1 "
                "around it, else take it from farther away"
            )
            raise UserInputError(
                f"{name}: the tree touches the picture's {edge_name} edge ({n_edge} pixels): "
                f"{settle} ({how})"
            )
    check_silhouette(tree, keep, name=name, how=how)
    return seg


def _cover(rgb, lab, bg, dist, noise, keep):
    """The tree's pixels by their difference from the background ``bg`` (CIELAB): fully
    covered pixels by local thresholds, then every pixel's coverage by linear unmixing
    (steps 3 and 4 of :func:`segment_photo`); returns ``(fg, coverage, floor)``."""
    from scipy import ndimage
    from skimage.color import lab2rgb

    h, w = dist.shape
    dist = np.where(keep, dist, 0.0)
    floor = max(NOISE_K * noise, MIN_DE)
    local = ndimage.maximum_filter(dist, size=LOCAL_WINDOW, mode="nearest")
    # JPEG rings around strong edges up to the 8 x 8 block's far side
    ringing = ndimage.maximum_filter(dist, size=RINGING_WINDOW, mode="nearest")
    threshold = np.maximum(np.maximum(LOCAL_SHARE * local, RINGING * ringing), floor)
    # thick parts: the least difference of a 3 x 3 neighbourhood is the full difference of
    # a fully covered pixel; near them the share is THICK_SHARE of it. A thin twig has no
    # fully covered pixel (its eroded difference is the sky's) and keeps LOCAL_SHARE of its
    # own peak, so 1-pixel twigs are not erased.
    thick = ndimage.maximum_filter(
        ndimage.minimum_filter(dist, size=3, mode="nearest"), size=LOCAL_WINDOW, mode="nearest"
    )
    threshold = np.maximum(threshold, THICK_SHARE * thick)
    fg = (dist > threshold) & keep
    # fully covered pixels: the interior of what the thresholds take (a drawing's lines
    # one or two pixels wide have none: then those lines themselves)
    full = ndimage.binary_erosion(fg, np.ones((3, 3), dtype=bool))
    interior = full.copy()
    if not full.any():
        full = fg
    coverage = np.zeros((h, w))
    if not full.any():
        return fg, coverage, floor
    # every pixel's coverage by linear unmixing in linear light (a camera's pixel sums the
    # light of the tree and of the sky it sees): colour = background + a (tree -
    # background), the tree's colour the nearest fully covered pixel's, or, beyond
    # UNMIX_REACH (a thin twig, never fully covered), the median of them all
    light = srgb_to_linear(rgb)
    back = srgb_to_linear(lab2rgb(bg))
    reach, (ir, ic) = ndimage.distance_transform_edt(~full, return_indices=True)
    colour = np.where(
        (reach <= UNMIX_REACH)[..., None], light[ir, ic], np.median(light[full], axis=0)
    )
    rim = (reach > 0) & (reach <= UNMIX_REACH)
    colour = np.where(rim[..., None], (1.0 - RIM_SHADE) * colour, colour)
    coverage = unmix(light, back, colour)
    # a part's rim may be darker (or paler) still: where a pixel of the 3 x 3 (of the
    # THIN_WINDOW around a thin twig's pixel) is farther from the background than that
    # colour, its colour is the tree's
    k = THIN_WINDOW
    thin = reach > UNMIX_REACH
    pad = np.pad(coverage, k, mode="edge")
    lpad = np.pad(light, ((k, k), (k, k), (0, 0)), mode="edge")
    best = np.ones((h, w))
    for dy in range(2 * k + 1):
        for dx in range(2 * k + 1):
            a = pad[dy : dy + h, dx : dx + w]
            better = a > best
            if max(abs(dy - k), abs(dx - k)) > 1:
                better &= thin
            best = np.where(better, a, best)
            colour = np.where(better[..., None], lpad[dy : dy + h, dx : dx + w], colour)
    coverage = unmix(light, back, colour)
    fg = ((coverage >= COVERAGE) & (dist > NOISE_K * noise) | interior) & keep
    return fg, coverage, floor


def _quadratic_basis(r, c, h, w) -> np.ndarray:
    y = np.asarray(r, np.float64) / max(h - 1, 1) - 0.5
    x = np.asarray(c, np.float64) / max(w - 1, 1) - 0.5
    return np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=-1)


def _plain_sky(lab: np.ndarray, sky: np.ndarray, seen: np.ndarray):
    """The sky's model when it is plain: per CIELAB channel a quadratic in (row, column)
    fitted to the pixels ``sky`` (three rounds, outliers dropped), ``(model (H, W, 3),
    noise)`` when their colour varies by at most :data:`PLAIN_SKY` (Delta E, robust) around
    it and at least :data:`PLAIN_SHARE` of the sky ``seen`` (between the branches too)
    lies within its noise band, else ``(None, noise)``: clouds (behind the crown too),
    haze in patches."""
    h, w = lab.shape[:2]
    rows, cols = np.nonzero(sky)
    if len(rows) < 16:
        return None, 0.0
    step = max(1, len(rows) // 20000)
    rows, cols = rows[::step], cols[::step]
    a = _quadratic_basis(rows, cols, h, w)
    v = lab[rows, cols]
    keep = np.ones(len(rows), dtype=bool)
    for _ in range(3):
        coef, *_ = np.linalg.lstsq(a[keep], v[keep], rcond=None)
        res = np.linalg.norm(v - a @ coef, axis=1)
        sigma = max(_robust_sigma(res[keep]), 0.25)
        keep = res <= np.median(res[keep]) + 4.0 * sigma
    noise = float(np.median(res[keep]) + _robust_sigma(res[keep]))
    if noise > PLAIN_SKY or keep.mean() < PLAIN_SHARE:
        return None, noise
    rr, cc = np.mgrid[0:h, 0:w]
    model = _quadratic_basis(rr, cc, h, w) @ coef
    band = np.median(res[keep]) + 4.0 * max(_robust_sigma(res[keep]), 0.25)
    near = np.linalg.norm(lab[seen] - model[seen], axis=1) <= band
    if near.mean() < PLAIN_SHARE:
        return None, noise
    return model, max(noise, 0.25)


def _band_shift(rgb: np.ndarray, band: np.ndarray, cols: np.ndarray, reach: int) -> int:
    """How many rows (``-reach``..``reach``) the band ``band`` (rows per column) moves to
    lie on the first row of the ground below the horizon: where the colour changes most
    from the row above, over the columns ``cols`` (those away from the tree)."""
    h = rgb.shape[0]
    if len(cols) < 4:
        cols = np.arange(rgb.shape[1])
    best, shift = -1.0, 0
    for o in range(-reach, reach + 1):
        r = np.round(band[cols] + o).astype(np.int64)
        ok = (r >= 1) & (r < h)
        if ok.sum() < 4:
            continue
        step = np.linalg.norm(rgb[r[ok], cols[ok]] - rgb[r[ok] - 1, cols[ok]], axis=-1)
        g = float(np.median(step))
        if g > best + 1e-12:
            best, shift = g, o
    return shift


def _band_follow(rgb: np.ndarray, band: np.ndarray, cols: np.ndarray, reach: int):
    """The band ``band`` (rows per column) following the horizon's own outline (a hill's
    curve, a slope the line misses): in each column of ``cols`` the row within ``reach``
    where the colour changes most from the row above, when that change is clear (over
    half the line's median), smoothed along the columns (a median over
    :data:`FOLLOW_WINDOW` of the width) and interpolated across the others (the tree's)."""
    from scipy import ndimage

    h, w = rgb.shape[:2]
    if len(cols) < 4:
        return band
    offsets = np.arange(-reach, reach + 1)
    r = np.clip(np.round(band[cols][None, :] + offsets[:, None]).astype(np.int64), 1, h - 1)
    step = np.linalg.norm(rgb[r, cols[None, :]] - rgb[r - 1, cols[None, :]], axis=-1)
    best = np.argmax(step, axis=0)
    strong = step[best, np.arange(len(cols))]
    clear = strong > 0.5 * np.median(step[reach])
    if clear.sum() < 4:
        return band
    moved = band.copy()
    known = cols[clear]
    at = band[known] + offsets[best[clear]]
    moved[:] = np.interp(np.arange(w), known, at)
    size = max(3, int(FOLLOW_WINDOW * w) | 1)
    return ndimage.median_filter(moved, size=size, mode="nearest")


def _smooth_sky(lab: np.ndarray, sky: np.ndarray) -> np.ndarray:
    """The pixels of ``lab`` (CIELAB) as smooth as the sky ``sky`` and of its colours: their
    lightness's gradient (Sobel, smoothed over :data:`POCKET_SMOOTH` pixels) under
    :data:`POCKET_K` times the sky's median (at least :data:`POCKET_MIN`), their colour
    within
    :data:`~growsim.pictures.scene.PALETTE_DE` of one of the sky's."""
    from scipy import ndimage
    from scipy.spatial import cKDTree

    lum = lab[..., 0]
    g = np.hypot(ndimage.sobel(lum, 0, mode="nearest"), ndimage.sobel(lum, 1, mode="nearest"))
    g = ndimage.gaussian_filter(g / 8.0, POCKET_SMOOTH, mode="nearest")
    out = g < max(POCKET_K * float(np.median(g[sky])), POCKET_MIN)
    colours = lab[sky]
    if not len(colours) or not out.any():
        return np.zeros(sky.shape, dtype=bool)
    palette = cKDTree(colours[:: max(1, len(colours) // 4000)])
    d, _ = palette.query(lab[out], k=1)
    out[out] = d < PALETTE_DE
    return out


def _row_spans(mask: np.ndarray) -> np.ndarray:
    """Each row of ``mask`` filled from its leftmost to its rightmost pixel.

    Examples
    --------
    >>> m = np.zeros((2, 6), bool); m[0, [1, 4]] = True
    >>> _row_spans(m).astype(int).tolist()
    [[0, 1, 1, 1, 1, 0], [0, 0, 0, 0, 0, 0]]
    """
    any_ = mask.any(axis=1)
    w = mask.shape[1]
    left = np.where(any_, mask.argmax(axis=1), w)
    right = np.where(any_, w - 1 - mask[:, ::-1].argmax(axis=1), -1)
    cols = np.arange(w)[None, :]
    return (cols >= left[:, None]) & (cols <= right[:, None])


def _thin_lines(lab: np.ndarray) -> np.ndarray:
    """The pixels of thin lines in ``lab`` (CIELAB): those differing by more than
    :data:`THIN_DE` (Delta E) from the median of their :data:`THIN_SIZE` square (OpenCV's
    median filter on each channel at 8 bits): a twig, pale or dark, not a cloud's edge."""
    import cv2

    codes = np.stack([lab[..., 0] * 2.55, lab[..., 1] + 128.0, lab[..., 2] + 128.0], axis=-1)
    u8 = np.clip(np.round(codes), 0, 255).astype(np.uint8)
    med = cv2.medianBlur(np.ascontiguousarray(u8), THIN_SIZE).astype(np.float64)
    med[..., 0] /= 2.55
    med[..., 1:] -= 128.0
    return np.linalg.norm(lab - med, axis=-1) > THIN_DE


def _connected(fg, obj, crown, origin, shape, scale):
    """The tree among the foreground ``fg`` of a crop at ``origin`` (step 5 of
    :func:`segment_photo`): the piece holding most of the standing object ``obj``, the
    pieces up to :data:`GAP` pixels from it and those in the ``crown`` region (the rows'
    spans of the object: its twigs and leaves, cut off by the threshold)."""
    from scipy import ndimage
    from skimage.measure import label
    from skimage.morphology import disk

    labels = label(fg, connectivity=2)
    if labels.max() == 0:
        return fg
    core = _upsample(obj.mask, shape, scale)[
        origin[0] : origin[0] + fg.shape[0], origin[1] : origin[1] + fg.shape[1]
    ]
    hits = np.bincount(labels[core & fg].ravel(), minlength=labels.max() + 1)
    hits[0] = 0
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    main = int(np.argmax(hits)) if hits.max() > 0 else int(np.argmax(sizes))
    bridged = label(ndimage.binary_dilation(fg, disk(GAP)), connectivity=2)
    group = bridged == bridged[labels == main][0]
    ids = np.unique(labels[(group | crown) & fg])
    return np.isin(labels, ids[ids > 0])


def _below_cut(rgb, tree, below, sky, obj, scale, keep):
    """The tree's pixels below the cut (``below``): GrabCut (OpenCV) in the columns of the
    standing object ``obj`` (and :data:`BELOW_MARGIN` of its width either side), seeded
    with the tree found above the cut (``tree``) as sure foreground, the ``sky`` and
    the columns either side below the cut as sure background, the columns where the tree
    enters the band as probable foreground. What it takes that looks like the row's
    ground or clutter beside the tree (within :data:`ROW_K` times that row's spread) is
    dropped; in the trunk's columns each pixel is read against the row just beside them
    (:func:`_cover`, as the crown against the sky). Returns ``(tree, spill)``: what joins
    the tree above (a trunk hidden by a hedge of its colour bridged over up to
    :data:`TRUNK_GAP` of the tree's height, :func:`_hidden_trunk`; a trunk's rows filled
    across), and the share of those rows where it reaches both sides of the object's
    columns (a wood behind it)."""
    import cv2
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
    y1 = min(h, lowest + int(BELOW_DEPTH * height) + 1)
    if y0 >= y1 - 1:
        return np.zeros((h, w), dtype=bool)
    win = (slice(y0, y1), slice(x0, x1))
    under, seed, kept = below[win], tree[win], keep[win]
    mask = np.full(under.shape, cv2.GC_PR_BGD, dtype=np.uint8)
    mask[sky[win]] = cv2.GC_BGD
    mask[~under & seed] = cv2.GC_FGD
    feet = np.zeros(w, dtype=bool)
    for a, b in obj.feet:
        feet[int(a * k) : int(np.ceil((b + 1) * k))] = True
    mask[under & feet[None, x0:x1]] = cv2.GC_PR_FGD
    inside = np.zeros(w, dtype=bool)
    inside[int(obj.left * k) : int(np.ceil((obj.right + 1) * k))] = True
    mask[under & ~inside[None, x0:x1]] = cv2.GC_BGD
    mask[~kept] = cv2.GC_BGD
    if not (mask == cv2.GC_FGD).any() or not (mask == cv2.GC_BGD).any():
        return np.zeros((h, w), dtype=bool)
    img = np.ascontiguousarray(np.round(255 * rgb[win][..., ::-1]).astype(np.uint8))
    size = mask.shape[::-1]
    f = min(1.0, np.sqrt(GRABCUT_PIXELS / mask.size))
    if f < 1.0:  # a large window: GrabCut on it reduced, its answer enlarged again
        small = (max(2, round(size[0] * f)), max(2, round(size[1] * f)))
        img = cv2.resize(img, small, interpolation=cv2.INTER_AREA)
        mask = cv2.resize(mask, small, interpolation=cv2.INTER_NEAREST)
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
    row_noise = _robust_sigma(spread[flanks]) if flanks.any() else 0.0
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
        noise = _robust_sigma(
            np.linalg.norm(local - np.median(local, axis=1, keepdims=True), axis=-1)[
                under[:, max(0, za - FOOT_REACH) : zb + 1 + FOOT_REACH]
            ]
        )
        trunk, _, _ = _cover(rgb[win][part], lab[part], back, d, max(noise, 0.25), zone)
        # on a textured ground (stripes of a field) the thresholds may miss it: what
        # GrabCut took there and differs from the row beside it clearly stays
        trunk |= taken[part] & (d > FOOT_DE)
        fg[part] = np.where(zone, trunk, fg[part])
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
            joined[part] |= _row_spans(joined[part]) & under[part]
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


def _in_box(rgb, keep, sky, hint, per_pixel, name, t_start) -> Segmentation:
    """The tree in the box of ``keep`` (the hint ``--box``) where the scene could not tell
    it (no sky, nothing standing out of it, or what stands merges with a wood reaching
    past the box): GrabCut initialised with the box (and the ``sky``, when known, as
    background), its largest piece; checked as every silhouette is."""
    import cv2
    from skimage.measure import label

    h, w = keep.shape
    rows, cols = np.nonzero(keep)
    y0, y1, x0, x1 = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    m = max(4, int(0.1 * max(y1 - y0, x1 - x0)))
    win = (slice(max(0, y0 - m), min(h, y1 + m)), slice(max(0, x0 - m), min(w, x1 + m)))
    img = np.ascontiguousarray(np.round(255 * rgb[win][..., ::-1]).astype(np.uint8))
    mask = np.where(keep[win], cv2.GC_PR_FGD, cv2.GC_BGD).astype(np.uint8)
    if sky is not None:
        mask[sky[win]] = cv2.GC_BGD
    size = mask.shape[::-1]
    f = min(1.0, np.sqrt(2 * GRABCUT_PIXELS / mask.size))
    if f < 1.0:
        small = (max(2, round(size[0] * f)), max(2, round(size[1] * f)))
        img = cv2.resize(img, small, interpolation=cv2.INTER_AREA)
        mask = cv2.resize(mask, small, interpolation=cv2.INTER_NEAREST)
    if not (mask == cv2.GC_BGD).any():
        mask[[0, -1], :] = cv2.GC_BGD
        mask[:, [0, -1]] = cv2.GC_BGD
    bgd, fgd = np.zeros((1, 65)), np.zeros((1, 65))
    cv2.setRNGSeed(0)
    cv2.grabCut(img, mask, None, bgd, fgd, GRABCUT_ITERATIONS, cv2.GC_INIT_WITH_MASK)
    if f < 1.0:
        mask = cv2.resize(mask, size, interpolation=cv2.INTER_NEAREST)
    fg = ((mask == cv2.GC_FGD) | (mask == cv2.GC_PR_FGD)) & keep[win]
    parts = label(fg, connectivity=2)
    tree = np.zeros((h, w), dtype=bool)
    if parts.max() > 0:
        sizes = np.bincount(parts.ravel())
        sizes[0] = 0
        tree[win] = parts == int(np.argmax(sizes))
    how = "GrabCut in the box"
    if not tree.any():
        raise UserInputError(f"{name}: the silhouette is empty ({how})")
    seg = Segmentation(
        tree, np.zeros((h, w), dtype=bool), None, np.zeros((h, w)), 0.0, 0.0, 0.0,
        np.where(tree, 1.0, 0.0), sky=None, band=None, cut=None, objects=(), hint=hint,
        method="GrabCut in the box", seconds=time.perf_counter() - t_start,
        hint_scale=per_pixel,
    )  # fmt: skip
    for edge_name, n_edge in (("top", int(tree[0].sum())), ("left", int(tree[:, 0].sum())),
                              ("right", int(tree[:, -1].sum()))):  # fmt: skip
        if n_edge >= MAX_EDGE_PIXELS:
            raise UserInputError(
                f"{name}: the tree touches the picture's {edge_name} edge ({n_edge} pixels): "
                "it is cut off, and the whole tree must be in the picture: take it from "
                f"farther away ({how})"
            )
    check_silhouette(tree, keep, name=name, how=how)
    return seg


def _hidden_trunk(loose, tree, under, reach, widest=np.inf):
    """A trunk hidden for a stretch (by a hedge of its colour): the largest piece of
    ``loose`` below the foot of ``tree`` (in the rows ``under``) that starts at most
    ``reach`` rows lower, under it and about as wide, joined to it by the straight trunk
    between them; nothing when there is none, or when the foot is wider than ``widest``
    (the crown reaches down there).

    Examples
    --------
    >>> tree = np.zeros((30, 10), bool); tree[:8, 4:6] = True
    >>> loose = np.zeros((30, 10), bool); loose[20:, 4:7] = True
    >>> under = np.zeros((30, 10), bool); under[8:] = True
    >>> out = _hidden_trunk(loose, tree, under, 15)
    >>> bool(out[8:20, 4:6].all()), bool(out[20:, 4:7].all()), bool(out[:8].any())
    (True, True, False)
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
        top = p.coords[p.coords[:, 0] < rt + 5]
        c, d = int(top[:, 1].min()), int(top[:, 1].max())
        # the foot above it: the tree's lowest pixels over its columns
        # the run of the foot's columns that overlaps it most (not the specks beside)
        slack = max(2, d - c)
        spans = [(min(e, d) - max(f, c), f, e) for f, e in runs(np.nonzero(foot)[0])
                 if e >= c - slack and f <= d + slack]  # fmt: skip
        if not spans:
            continue
        _, a, b = max(spans)
        if b - a + 1 > widest or b - a > 3 * (d - c) + 6 or d - c > 3 * (b - a) + 6:
            continue  # the crown reaches down there, or it is no trunk below it
        if best is None or p.area > best[4]:  # the trunk, not a speck of the clutter
            best = (rt, c, d, p.coords, p.area, a, b)
    if best is None:
        return out
    rt, c, d, coords, _, a, b = best
    for r in range(rb + 1, rt):
        t = (r - rb) / (rt - rb)
        lo, hi = round((1 - t) * a + t * c), round((1 - t) * b + t * d)
        out[r, lo : hi + 1] = True
    out[coords[:, 0], coords[:, 1]] = True
    return out & under


def segmentation_picture(seg: Segmentation, rgb: np.ndarray) -> np.ndarray:
    """What :func:`segment_photo` found, to look at: ``(H, 2 W + 8, 3)`` uint8, on the
    left the photo ``rgb`` (``(H, W, 3)`` in ``[0, 1]``, the picture segmented) with the
    tree's outline in red, on the right the labels: the sky blue, the ground and the
    horizon's clutter (below the band's top, yellow) brown, the tree red, the line above
    which an object stands out of the band dashed orange, the standing objects' boxes
    (the tree's green, the others orange) and the hint (a box or a cross, magenta).

    Examples
    --------
    >>> rgb = np.ones((60, 50, 3)) * [0.8, 0.9, 1.0]
    >>> rgb[50:] = [0.3, 0.5, 0.2]; rgb[15:55, 24:27] = [0.4, 0.3, 0.2]
    >>> rgb[20, 12:38] = [0.4, 0.3, 0.2]
    >>> segmentation_picture(segment_photo(rgb), rgb).shape
    (60, 108, 3)
    """
    from PIL import Image, ImageDraw
    from scipy import ndimage

    rgb = np.clip(np.asarray(rgb, dtype=np.float64), 0.0, 1.0)
    if rgb.ndim == 2:
        rgb = np.repeat(rgb[..., None], 3, axis=2)
    h, w = seg.tree.shape
    if rgb.shape[:2] != (h, w):
        from skimage.transform import resize

        rgb = resize(rgb, (h, w), order=1, anti_aliasing=True)
    tree = seg.tree
    outline = ndimage.binary_dilation(tree, np.ones((3, 3), bool)) & ~tree
    left = rgb.copy()
    left[outline] = (1.0, 0.0, 0.0)
    grey = rgb.mean(axis=2, keepdims=True) * np.ones(3)
    right = 0.5 * grey + 0.5
    if seg.sky is not None:
        right[seg.sky] = 0.5 * grey[seg.sky] + 0.5 * np.array([0.35, 0.6, 1.0])
    right[seg.ground] = 0.5 * grey[seg.ground] + 0.5 * np.array([0.6, 0.45, 0.25])
    right[tree] = 0.3 * grey[tree] + 0.7 * np.array([0.9, 0.1, 0.1])
    gap = np.ones((h, 8, 3))
    im = Image.fromarray(np.round(255 * np.hstack([left, gap, right])).astype(np.uint8))
    draw = ImageDraw.Draw(im)
    off = w + 8
    if seg.band is not None and seg.horizon is not None:
        xs = np.arange(w)
        draw.line([(off + x, float(y)) for x, y in zip(xs, seg.band)], fill=(255, 220, 0))
        if seg.cut is not None:
            for x in range(0, w - 4, 8):
                draw.line([(off + x, float(seg.cut[x])), (off + x + 4, float(seg.cut[x + 4]))],
                          fill=(255, 140, 0))  # fmt: skip
    for i, (x0, y0, x1, y1) in enumerate(seg.objects):
        colour = (0, 170, 0) if i == 0 else (255, 140, 0)
        draw.rectangle([off + x0, y0, off + x1 - 1, y1 - 1], outline=colour)
    hint = seg.hint or {}
    for x0 in (0, off):
        if "box" in hint:
            b = [v * seg.hint_scale for v in hint["box"]]
            draw.rectangle([x0 + b[0], b[1], x0 + b[2], b[3]], outline=(255, 0, 255))
        if "point" in hint:
            px, py = (v * seg.hint_scale for v in hint["point"])
            r = max(3, w // 100)
            draw.line([(x0 + px - r, py), (x0 + px + r, py)], fill=(255, 0, 255), width=2)
            draw.line([(x0 + px, py - r), (x0 + px, py + r)], fill=(255, 0, 255), width=2)
    return np.asarray(im)
