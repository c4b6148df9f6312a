"""What a picture is: a drawing (or silhouette) read by its grey levels, or a photo
segmented by its colours (:func:`classify_picture`, ``fit-image --segmentation auto``).
"""

from __future__ import annotations

import os

import numpy as np

from growsim.pictures.reading import load_rgb

__all__ = ["classify_picture"]

#: :func:`classify_picture`: a pixel is coloured when its chroma (max - min of R, G, B in
#: ``[0, 1]``) exceeds this
CHROMA = 0.08

#: :func:`classify_picture`: a drawing has at most this share of coloured pixels
MAX_COLOURED = 0.01

#: :func:`classify_picture`: a drawing has at least this share of its pixels within
#: :data:`MODE_REACH` of its two main grey levels (paper and ink: a bimodal histogram)
MIN_TWO_LEVELS = 0.9
MODE_REACH = 0.12

# A grey photo can be bimodal too (a pale sky over a dark ground, the tree between). What
# tells it from a drawing, measured on 57 drawings (growsim's, of the Table 1 tree, its
# renders and the attractors; scanned, blurred, noisy, JPEG at quality 50-90, enlarged to
# 3000 px) against 26 photos made grey (the benchmark's renders, 4 of them cropped above
# the ground, and 12 of scikit-image's):
#: a photo's bottom edge is ground under a sky: the median level of the bottom edge
#: differs from the top edge's by more than this share of the contrast between the two
#: main levels (the renders 0.77-1.0; drawings, whose paper runs all round, 0.006 at most)
GROUND_STEP = 0.5
#: a drawing has at most this share of its pixels in grey levels of their own: smooth (in
#: their 3 x 3, less than a quarter of the contrast), away from both main levels (by
#: :data:`GREY_REACH`, or 4 x the noise) and from the edges between them (7 x 7 px): a
#: sky's gradient, a lit branch (drawings at most 1.0 %; the photos without ground
#: 0.15-58 %)
MAX_OWN_GREYS = 0.02
GREY_REACH = 0.05
#: a drawing has at most this share of its pixels in texture: varying by a quarter of the
#: contrast in their 3 x 3 with no paper within 5 x 5 px (leaves, bark, grass; drawings
#: at most 0.9 %, their edges always border the paper; the photos 0.03-21 %). Two leafy
#: renders cropped above the ground (flat leaves on a smooth sky, 1.2 % and 0.15 % of
#: grey levels of their own, 0.5 % and 1.2 % texture) are still taken for drawings.
MAX_TEXTURE = 0.02


def classify_picture(image) -> tuple[str, str]:
    """``("drawing", why)`` for a drawing or silhouette, ``("photo", why)`` otherwise:
    what ``fit-image --segmentation auto`` reads a picture (path or array, grey ``(H, W)``
    or RGB ``(H, W, 3)`` in ``[0, 1]``; a file is read at the working size,
    :func:`~growsim.pictures.reading.load_rgb`) as. A drawing is near grey (at most
    :data:`MAX_COLOURED` of its pixels have a chroma above :data:`CHROMA`: no sky or
    ground colours), bimodal (at least :data:`MIN_TWO_LEVELS` of its pixels within
    :data:`MODE_REACH` of its two main grey levels: paper and ink) and, unlike a grey
    photo, made of these two levels and the edges between them: its bottom edge is paper
    as its top edge is (no ground under a sky, :data:`GROUND_STEP`), few pixels are in
    smooth grey levels of their own (a sky's gradient, :data:`MAX_OWN_GREYS`) or in
    texture (:data:`MAX_TEXTURE`). ``why``: the figures it looked at, for the messages
    and ``fit.json``.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.full((40, 40), 0.85); g[5:, 20] = 0.1  # a trunk in ink on grey paper
    >>> classify_picture(g)[0]
    'drawing'
    >>> rgb = np.zeros((40, 40, 3)); rgb[:] = (0.5, 0.7, 1.0); rgb[30:] = (0.2, 0.6, 0.1)
    >>> classify_picture(rgb)
    ('photo', 'a photo: 100.0 % of pixels in colour')
    >>> grey = np.full((40, 40), 0.9); grey[32:] = 0.3; grey[8:34, 20] = 0.6  # on ground
    >>> classify_picture(grey)[0]
    'photo'
    """

    if isinstance(image, (str, os.PathLike)):
        rgb = load_rgb(image)
    else:
        rgb = np.asarray(image, dtype=np.float64)
        if rgb.ndim == 2:
            rgb = np.repeat(rgb[..., None], 3, axis=2)
        rgb = rgb[..., :3]
    coloured = float(np.mean(rgb.max(axis=2) - rgb.min(axis=2) > CHROMA))
    if coloured > MAX_COLOURED:
        return "photo", f"a photo: {100 * coloured:.1f} % of pixels in colour"
    grey = rgb.mean(axis=2)
    hist = np.bincount(np.clip((grey * 32).astype(np.int64), 0, 31).ravel(), minlength=32)
    first = int(np.argmax(hist))
    # the second level: the fullest bin away from the first
    away = hist.copy()
    lo, hi = max(0, first - 4), min(32, first + 5)
    away[lo:hi] = 0
    second = int(np.argmax(away))
    levels = np.array([first, second]) + 0.5
    near = np.abs(grey.ravel()[:, None] * 32 - levels[None, :]).min(axis=1) <= MODE_REACH * 32
    share = float(np.mean(near))
    if share < MIN_TWO_LEVELS:
        return "photo", (
            f"a grey photo: {100 * share:.0f} % of pixels near its two main grey levels"
        )
    ground, own, texture = _grey_photo_cues(grey, (first, second))
    if ground > GROUND_STEP:
        return "photo", (
            f"a grey photo: ground under a sky (its bottom edge's grey level differs from "
            f"its top edge's by {100 * ground:.0f} % of the contrast)"
        )
    if own > MAX_OWN_GREYS or texture > MAX_TEXTURE:
        return "photo", (
            f"a grey photo: {100 * own:.1f} % of pixels in smooth grey levels of their own "
            f"(a gradient, lit branches), {100 * texture:.1f} % in texture"
        )
    return "drawing", (
        f"a drawing: grey levels {levels[0] / 32:.2f} and {levels[1] / 32:.2f} hold "
        f"{100 * share:.0f} % of pixels, {100 * coloured:.1f} % in colour"
    )


def _grey_photo_cues(grey: np.ndarray, bins) -> tuple[float, float, float]:
    """What tells a grey photo from a drawing (:func:`classify_picture`), for grey levels
    ``(H, W)`` whose two main levels fall in the 1/32-wide ``bins``: the step from the top
    edge's level to the bottom edge's (share of the contrast, :data:`GROUND_STEP`), the
    share of pixels in smooth grey levels of their own (:data:`MAX_OWN_GREYS`) and the
    share in texture (:data:`MAX_TEXTURE`), on the picture's 3 x 3 median (no noise)."""
    from scipy import ndimage

    levels = []
    for k in bins:  # each level: the median of its bin and the bins beside it
        near = grey[(grey * 32 >= k - 1) & (grey * 32 < k + 2)]
        levels.append(float(np.median(near)) if near.size else (k + 0.5) / 32)
    a, b = levels
    contrast = max(abs(a - b), 1e-6)
    m = ndimage.median_filter(grey, 3)
    h, w = grey.shape
    strip = max(2, round(0.01 * min(h, w)))
    ground = abs(float(np.median(m[:strip])) - float(np.median(m[-strip:]))) / contrast
    edges = (m[:strip], m[-strip:], m[:, :strip], m[:, -strip:])
    paper = float(np.median(np.concatenate([e.ravel() for e in edges])))
    noise = 1.4826 * float(np.median(np.abs(grey - m)))
    reach = max(GREY_REACH, 4.0 * noise)
    varies = ndimage.maximum_filter(m, 3) - ndimage.minimum_filter(m, 3) >= 0.25 * contrast
    near_a = ndimage.maximum_filter(np.abs(m - a) < 0.25 * contrast, 7)
    near_b = ndimage.maximum_filter(np.abs(m - b) < 0.25 * contrast, 7)
    own = (np.abs(m - a) > reach) & (np.abs(m - b) > reach) & ~varies & ~(near_a & near_b)
    papery = ndimage.maximum_filter(np.abs(m - paper) < 0.25 * contrast, 5)
    return ground, float(np.mean(own)), float(np.mean(varies & ~papery))
