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
from dataclasses import dataclass

import numpy as np

from growsim.errors import UserInputError
from growsim.pictures.reading import SPECK, check_silhouette, load_gray, over_white, read_picture

__all__ = [
    "Segmentation",
    "linear_to_srgb",
    "load_rgb",
    "segment_photo",
    "srgb_to_linear",
    "unmix",
]

# What segment_photo refuses and how it decides. Measured on the benchmark's pictures
# (benchmarks/make_photos.py: JPEG renders of growsim trees on a ground plane under a sky)
# and on growsim's line drawings.
#: width of the border strips sampled for the sky and the ground, share of the picture
#: (at least 2 pixels)
BORDER = 0.01
#: the bottom edge is ground (a band to find) when its colour differs from the sky's by
#: more than this (CIE76 Delta E in CIELAB; 2.3 is a just-noticeable difference)
GROUND_MIN_DE = 10.0
#: the ground band ends where a side edge's colour jumps by more than this from the rows
#: below it (the horizon, or a tree touching the edge)
GROUND_STEP_DE = 8.0
#: rows either side of the horizon whose pixels may blend sky and ground (anti-aliasing)
HORIZON_ROWS = 3
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
#: a pixel as pale as the sky), before the bounding-box rule
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
#: refused: the sky's colour varies more than this (robust sigma, Delta E) around a smooth
#: gradient: not a plain sky (clutter, clouds, a wall with texture)
MAX_SKY_NOISE = 4.0
#: refused: the tree's median colour difference from its background under this (Delta E)
MIN_CONTRAST = 15.0
#: refused: objects apart from the tree (8-connected pieces of at least SPECK pixels away
#: from it) holding more than this share of the foreground
MAX_OTHER_SHARE = 0.25
#: refused: the tree touching the top, left or right edge with this many pixels or more
#: (it is cut off; the framing needs the whole tree)
MAX_EDGE_PIXELS = 3


def load_rgb(path: str | os.PathLike) -> np.ndarray:
    """A picture file as ``(H, W, 3)`` float64 RGB in ``[0, 1]``; transparency is
    composited over white. An unreadable or missing file raises :class:`UserInputError`
    naming it.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from PIL import Image
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "a.png"
    >>> Image.new("RGB", (4, 3), (255, 0, 0)).save(p)
    >>> load_rgb(p)[0, 0].tolist()
    [1.0, 0.0, 0.0]
    """
    rgb = read_picture(path, lambda im: np.asarray(over_white(im).convert("RGB"), np.float64))
    return rgb / 255.0


@dataclass(frozen=True)
class Segmentation:
    """What :func:`segment_photo` found: ``tree`` ``(H, W)`` bool (the silhouette),
    ``ground`` ``(H, W)`` bool, ``horizon`` (the first row of the ground band, ``None``
    without ground), ``distance`` ``(H, W)`` (each pixel's colour difference from its
    background, Delta E), ``threshold`` (the least one a fully covered pixel has, Delta E),
    ``sky_noise`` (robust sigma of the sky around its smooth model, Delta E),
    ``contrast`` (the tree's median difference from its background, Delta E) and
    ``coverage`` ``(H, W)`` (each pixel's estimated share covered by the tree, by linear
    unmixing; ``tree`` is where it is at least :data:`COVERAGE`, before connectivity)."""

    tree: np.ndarray
    ground: np.ndarray
    horizon: int | None
    distance: np.ndarray
    threshold: float
    sky_noise: float
    contrast: float
    coverage: np.ndarray | None = None

    def describe(self) -> str:
        """One line: what was found (for messages and logs)."""
        ground = "no ground" if self.horizon is None else f"ground from row {self.horizon}"
        return (
            f"photo segmentation: {ground}, sky noise {self.sky_noise:.1f}, tree/background "
            f"threshold {self.threshold:.1f}, contrast {self.contrast:.1f} (Delta E)"
        )


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


def _quadratic_basis(r, c, h, w) -> np.ndarray:
    y = np.asarray(r, np.float64) / max(h - 1, 1) - 0.5
    x = np.asarray(c, np.float64) / max(w - 1, 1) - 0.5
    return np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=-1)


def _robust_sigma(x) -> float:
    x = np.asarray(x, np.float64)
    return float(1.4826 * np.median(np.abs(x - np.median(x)))) if x.size else 0.0


def _sky_model(lab, rows, cols):
    """A smooth sky: per CIELAB channel a quadratic in (row, column), fitted to the
    sample pixels with two rounds of dropping outliers (a branch crossing the border);
    returns the model over the whole picture ``(H, W, 3)`` and the residual sigma."""
    h, w = lab.shape[:2]
    a = _quadratic_basis(rows, cols, h, w)
    v = lab[rows, cols]
    keep = np.ones(len(rows), dtype=bool)
    for _ in range(3):
        coef, *_ = np.linalg.lstsq(a[keep], v[keep], rcond=None)
        res = np.linalg.norm(v - a @ coef, axis=1)
        sigma = max(_robust_sigma(res[keep]), 0.25)
        keep = res <= np.median(res[keep]) + 4.0 * sigma
    rr, cc = np.mgrid[0:h, 0:w]
    model = _quadratic_basis(rr, cc, h, w) @ coef
    return model, float(np.median(res[keep]) + _robust_sigma(res[keep]))


def _ground_band(lab, b: int, sky_colour):
    """The ground band along the bottom edge: ``(horizon row, left colours (H, 3), right
    colours (H, 3))`` smoothed over 5 rows, then the same unsmoothed (the horizon's
    blended rows), or ``None`` when the bottom edge looks like the sky. Walks up from
    the bottom while both side edges keep the ground's colour (within
    :data:`GROUND_STEP_DE` of the rows below)."""
    from scipy import ndimage

    h = lab.shape[0]
    left = np.median(lab[:, :b], axis=1)
    right = np.median(lab[:, -b:], axis=1)
    bottom = np.median(np.concatenate([lab[-b:, :b], lab[-b:, -b:]], axis=1).reshape(-1, 3), 0)
    if np.linalg.norm(bottom - sky_colour) < GROUND_MIN_DE:
        return None
    horizon = h - 1
    ref_l, ref_r = left[-1].copy(), right[-1].copy()
    for r in range(h - 2, -1, -1):
        if (
            np.linalg.norm(left[r] - ref_l) > GROUND_STEP_DE
            or np.linalg.norm(right[r] - ref_r) > GROUND_STEP_DE
        ):
            break
        horizon = r
        # follow a slow gradient (perspective, haze): the reference drifts with the rows
        ref_l = 0.8 * ref_l + 0.2 * left[r]
        ref_r = 0.8 * ref_r + 0.2 * right[r]
    smooth_left = ndimage.median_filter(left, size=(5, 1), mode="nearest")
    smooth_right = ndimage.median_filter(right, size=(5, 1), mode="nearest")
    return horizon, smooth_left, smooth_right, left, right


#: :func:`_without_lines`: a row this full of foreground, at most this many rows tall, is
#: a line across the picture (a horizon's seam, a wire), not the tree
LINE_FULL, LINE_ROWS = 0.95, 3


def _without_lines(fg: np.ndarray) -> np.ndarray:
    """``fg`` ``(H, W)`` without lines across the picture: runs of at most
    :data:`LINE_ROWS` rows, each at least :data:`LINE_FULL` foreground, are cleared but
    where the rows just above and below them are foreground too (a trunk crossing the
    line keeps its pixels).

    Examples
    --------
    >>> fg = np.zeros((7, 10), bool); fg[3] = True; fg[:, 4] = True
    >>> out = _without_lines(fg)
    >>> int(out[3].sum()), bool(out[:, 4].all())
    (1, True)
    """
    full = fg.mean(axis=1) >= LINE_FULL
    out = fg.copy()
    h = fg.shape[0]
    r = 0
    while r < h:
        if not full[r]:
            r += 1
            continue
        end = r
        while end + 1 < h and full[end + 1]:
            end += 1
        if end - r + 1 <= LINE_ROWS:
            above = fg[r - 1] if r > 0 else np.zeros(fg.shape[1], bool)
            below = fg[end + 1] if end + 1 < h else np.zeros(fg.shape[1], bool)
            out[r : end + 1] = (above & below)[None, :]
        r = end + 1
    return out


def segment_photo(image, *, mask=None, name: str = "image") -> Segmentation:
    """Separate a tree from the sky and the ground in a colour picture.

    ``image``: a path or an ``(H, W, 3)`` RGB (or ``(H, W)`` grey) array in ``[0, 1]``;
    ``mask``: optional picture or array of the same size, only its light part (> 0.5) may
    be tree; ``name`` labels errors. Colours are compared in CIELAB
    (:func:`skimage.color.rgb2lab`; Delta E, CIE76) against the picture's background:

    1. **ground**: a band along the bottom edge whose colour differs from the sky's; it
       runs up while both side edges keep its colour (:data:`GROUND_STEP_DE`), and its
       colour at each pixel is the side edges' colours of that row, interpolated across;
    2. **sky**: the large smooth region: a quadratic colour gradient fitted to the top
       edge and the side edges above the ground (outliers dropped);
    3. each pixel's **distance** from its background (the sky above the horizon; the
       ground below the horizon's blended rows; in them the nearer of sky, ground and the
       row's blend); the **fully covered** pixels: the interior (3 x 3 erosion) of those
       over a local threshold (:data:`LOCAL_SHARE` of the strongest difference within
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
       largest piece, with the pieces up to :data:`GAP` pixels from it (a twig broken by
       a pixel as pale as the sky) and every piece inside the bounding box of these
       (twigs and leaf clusters cut off by the threshold), standing on the ground; other
       objects are dropped.

    Refused with :class:`UserInputError` naming ``name`` (a bad segmentation is not
    fitted): a background that is not a plain sky (:data:`MAX_SKY_NOISE`), a tree that
    hardly differs from it (:data:`MIN_CONTRAST`), a tree cut off by the top or side
    edges (:data:`MAX_EDGE_PIXELS`), a tree that does not reach the ground, other
    objects as large as the tree (:data:`MAX_OTHER_SHARE`), and every silhouette
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
    from skimage.measure import label
    from skimage.morphology import disk

    if isinstance(image, (str, os.PathLike)):
        name = str(image)
        image = load_rgb(image)
    rgb = np.asarray(image, dtype=np.float64)
    if rgb.ndim == 2:
        rgb = gray2rgb(rgb)
    if rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.shape[0] < 8 or rgb.shape[1] < 8:
        raise UserInputError(f"{name}: expected an RGB picture of at least 8 x 8, got {rgb.shape}")
    if float(np.ptp(rgb)) < 1e-6:
        raise UserInputError(f"{name}: the picture is uniform (blank): no silhouette to fit")
    keep = np.ones(rgb.shape[:2], dtype=bool)
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
    lab = rgb2lab(np.clip(rgb, 0.0, 1.0))
    h, w = keep.shape
    b = max(2, round(BORDER * min(h, w)))
    top_colour = np.median(lab[:b].reshape(-1, 3), axis=0)
    band = _ground_band(lab, b, top_colour)
    horizon = None if band is None else band[0]
    sky_rows = h if horizon is None else horizon - HORIZON_ROWS
    if sky_rows < 2 * b:
        raise UserInputError(
            f"{name}: no sky found above the ground (the ground band reaches row "
            f"{horizon} of {h}): photograph the tree against the sky, or give a mask"
        )
    # the sky's samples: the top edge and the side edges above the ground
    rr, cc = np.mgrid[0:sky_rows, 0:w]
    edge = (rr < b) | (cc < b) | (cc >= w - b)
    sky, sky_noise = _sky_model(lab, rr[edge], cc[edge])
    dist = np.linalg.norm(lab - sky, axis=-1)
    bg = sky.copy()
    ground = np.zeros((h, w), dtype=bool)
    if horizon is not None:
        _, left, right, raw_left, raw_right = band
        t = (np.arange(w) / max(w - 1, 1))[None, :, None]
        lo = max(horizon - HORIZON_ROWS, 0)
        below = slice(lo, h)
        g = left[below, None, :] * (1.0 - t) + right[below, None, :] * t  # ground colour
        d_ground = np.linalg.norm(lab[below] - g, axis=-1)
        # the horizon's rows blend sky and ground (anti-aliasing, JPEG's chroma bleeding),
        # alike along the row: their background is the row's own edge colours
        g_raw = raw_left[below, None, :] * (1.0 - t) + raw_right[below, None, :] * t
        d_blend = np.linalg.norm(lab[below] - g_raw, axis=-1)
        near = np.arange(lo, h)[:, None] <= horizon + HORIZON_ROWS
        # below the horizon's blended rows the background is the ground alone (the sky's
        # model, extrapolated there, would take pale bark on dark ground for sky)
        d_sky = np.where(near, dist[below], np.inf)
        cands = np.stack([d_sky, d_ground, np.where(near, d_blend, np.inf)])
        which = np.argmin(cands, axis=0)
        d_below = np.take_along_axis(cands, which[None], 0)[0]
        # each pixel's background colour: the sky's, the ground's or the blended row's
        bg[below] = np.where((which == 1)[..., None], g, bg[below])
        bg[below] = np.where((which == 2)[..., None], g_raw, bg[below])
        ground_noise = _robust_sigma(d_ground[horizon + HORIZON_ROWS - lo :])
        ground[below] = d_ground <= d_below + 1e-9
        dist[below] = d_below
        sky_noise = max(sky_noise, min(ground_noise, MAX_SKY_NOISE))
    floor = max(NOISE_K * sky_noise, MIN_DE)
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
    if full.any():
        # every pixel's coverage by linear unmixing in linear light (a camera's pixel
        # sums the light of the tree and of the sky it sees): colour = background + a
        # (tree - background), the tree's colour the nearest fully covered pixel's, or,
        # beyond UNMIX_REACH (a thin twig, never fully covered), the median of them all
        from skimage.color import lab2rgb

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
        fg = ((coverage >= COVERAGE) & (dist > NOISE_K * sky_noise) | interior) & keep
    ground &= ~fg
    how = f"photo segmentation, sky noise {sky_noise:.1f}, threshold >= {floor:.1f} Delta E"
    if sky_noise > MAX_SKY_NOISE:
        raise UserInputError(
            f"{name}: the background is not a plain sky: its colour varies by {sky_noise:.1f} "
            f"Delta E around a smooth gradient (at most {MAX_SKY_NOISE:g}); photograph the "
            "tree against the sky, give a mask, or use the threshold segmentation"
        )
    fg = _without_lines(fg)
    labels = label(fg, connectivity=2)
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    if sizes.max() == 0:
        raise UserInputError(f"{name}: the silhouette is empty ({how})")
    main = int(np.argmax(sizes))
    # pieces up to GAP pixels from it join the tree (a twig broken by a pixel as pale as
    # the sky): the pieces that one component of the foreground grown by GAP holds
    bridged = label(ndimage.binary_dilation(fg, disk(GAP)), connectivity=2)
    group = bridged == bridged[labels == main][0]
    group = np.isin(labels, np.unique(labels[group & fg]))
    rows, cols = np.nonzero(group)
    r0, r1, c0, c1 = rows.min(), rows.max(), cols.min(), cols.max()
    # pieces inside the tree's bounding box belong to it (twigs, leaf clusters); the box is
    # widened by 5 % of the tree's height, and reaches down into the ground band (the
    # trunk's foot, cut from the tree where it crosses the horizon)
    pad = int(np.ceil(0.05 * (r1 - r0 + 1)))
    box = np.zeros((h, w), dtype=bool)
    r_end = r1 + 1 if horizon is None else h
    box[max(r0 - pad, 0) : r_end, max(c0 - pad, 0) : c1 + pad + 1] = True
    ids = np.unique(labels[box & fg])
    tree = np.isin(labels, ids[ids > 0])
    others = sizes.copy()
    others[ids] = 0
    other_share = float(others[others >= SPECK].sum()) / max(float(sizes.sum()), 1.0)
    contrast = float(np.median(dist[tree]))
    seg = Segmentation(tree, ground, horizon, dist, floor, sky_noise, contrast, coverage)
    if contrast < MIN_CONTRAST:
        raise UserInputError(
            f"{name}: the tree hardly differs from its background: median colour difference "
            f"{contrast:.1f} Delta E (at least {MIN_CONTRAST:g}; {how}); use a picture with "
            "more contrast, or a mask"
        )
    for edge_name, n_edge in (
        ("top", int(tree[0].sum())),
        ("left", int(tree[: horizon or h, 0].sum())),
        ("right", int(tree[: horizon or h, -1].sum())),
    ):
        if n_edge >= MAX_EDGE_PIXELS:
            raise UserInputError(
                f"{name}: the tree touches the picture's {edge_name} edge ({n_edge} pixels): "
                "it is cut off, and the whole tree must be in the picture; crop less tightly "
                f"({how})"
            )
    if horizon is not None and r1 < horizon - HORIZON_ROWS:
        raise UserInputError(
            f"{name}: no tree stands on the ground: the largest object ends at row {r1}, "
            f"{horizon - r1} pixels above the ground's first row {horizon} ({how}); give a "
            "mask around the tree"
        )
    if other_share > MAX_OTHER_SHARE:
        raise UserInputError(
            f"{name}: other objects beside the tree hold {100 * other_share:.0f} % of the "
            f"foreground (at most {100 * MAX_OTHER_SHARE:g} %; {how}): crop the picture to "
            "one tree, or give a mask"
        )
    check_silhouette(tree, keep, name=name, how=how)
    return seg
