"""The sky behind the crown and the horizon's band at the working size: the plain sky's
quadratic model (:func:`plain_sky`), the sky seen through the crown (:func:`smooth_sky`),
thin lines the reduced picture lost (:func:`thin_lines`), the band moved onto the
horizon's own outline (:func:`band_shift`, :func:`band_follow`). The coarse scene they
refine is :mod:`growsim.pictures.scene`'s.
"""

from __future__ import annotations

import numpy as np

from growsim.pictures.coverage import robust_sigma
from growsim.pictures.scene import PALETTE_DE

__all__ = ["band_follow", "band_shift", "plain_sky", "smooth_sky", "thin_lines"]

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


def _quadratic_basis(r, c, h, w) -> np.ndarray:
    y = np.asarray(r, np.float64) / max(h - 1, 1) - 0.5
    x = np.asarray(c, np.float64) / max(w - 1, 1) - 0.5
    return np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=-1)


def plain_sky(lab: np.ndarray, sky: np.ndarray, seen: np.ndarray):
    """The sky's model when it is plain: per CIELAB channel a quadratic in (row, column)
    fitted to the pixels ``sky`` (three rounds, outliers dropped), ``(model (H, W, 3),
    noise)`` when their colour varies by at most :data:`PLAIN_SKY` (Delta E, robust) around
    it and at least :data:`PLAIN_SHARE` of the sky ``seen`` (between the branches too)
    lies within its noise band, else ``(None, noise)``: clouds (behind the crown too),
    haze in patches.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> lab = rgb2lab(np.ones((20, 20, 3)) * [0.8, 0.9, 1.0])
    >>> sky = np.ones((20, 20), bool); sky[5:15, 8:12] = False   # a trunk left out
    >>> model, noise = plain_sky(lab, sky, sky)
    >>> model.shape, noise
    ((20, 20, 3), 0.25)
    """
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
        sigma = max(robust_sigma(res[keep]), 0.25)
        keep = res <= np.median(res[keep]) + 4.0 * sigma
    noise = float(np.median(res[keep]) + robust_sigma(res[keep]))
    if noise > PLAIN_SKY or keep.mean() < PLAIN_SHARE:
        return None, noise
    rr, cc = np.mgrid[0:h, 0:w]
    model = _quadratic_basis(rr, cc, h, w) @ coef
    band = np.median(res[keep]) + 4.0 * max(robust_sigma(res[keep]), 0.25)
    near = np.linalg.norm(lab[seen] - model[seen], axis=1) <= band
    if near.mean() < PLAIN_SHARE:
        return None, noise
    return model, max(noise, 0.25)


def band_shift(rgb: np.ndarray, band: np.ndarray, cols: np.ndarray, reach: int) -> int:
    """How many rows (``-reach``..``reach``) the band ``band`` (rows per column) moves to
    lie on the first row of the ground below the horizon: where the colour changes most
    from the row above, over the columns ``cols`` (those away from the tree).

    Examples
    --------
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> band_shift(rgb, np.full(50, 48.0), np.r_[0:20, 30:50], 3)  # 48 -> 50
    2
    """
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


def band_follow(rgb: np.ndarray, band: np.ndarray, cols: np.ndarray, reach: int):
    """The band ``band`` (rows per column) following the horizon's own outline (a hill's
    curve, a slope the line misses): in each column of ``cols`` the row within ``reach``
    where the colour changes most from the row above, when that change is clear (over
    half the line's median), smoothed along the columns (a median over
    :data:`FOLLOW_WINDOW` of the width) and interpolated across the others (the tree's).

    Examples
    --------
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> band_follow(rgb, np.full(50, 48.0), np.r_[0:20, 30:50], 3)[[0, 25, 49]].tolist()
    [50.0, 50.0, 50.0]
    """
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


def smooth_sky(lab: np.ndarray, sky: np.ndarray) -> np.ndarray:
    """The pixels of ``lab`` (CIELAB) as smooth as the sky ``sky`` and of its colours: their
    lightness's gradient (Sobel, smoothed over :data:`POCKET_SMOOTH` pixels) under
    :data:`POCKET_K` times the sky's median (at least :data:`POCKET_MIN`), their colour
    within
    :data:`~growsim.pictures.scene.PALETTE_DE` of one of the sky's.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> lab = rgb2lab(np.ones((20, 20, 3)) * [0.8, 0.9, 1.0])
    >>> sky = np.zeros((20, 20), bool); sky[:5] = True
    >>> int(smooth_sky(lab, sky).sum())  # all of it: smooth and of the sky's colour
    400
    """
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


def thin_lines(lab: np.ndarray) -> np.ndarray:
    """The pixels of thin lines in ``lab`` (CIELAB): those differing by more than
    :data:`THIN_DE` (Delta E) from the median of their :data:`THIN_SIZE` square (OpenCV's
    median filter on each channel at 8 bits): a twig, pale or dark, not a cloud's edge.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> rgb = np.ones((20, 20, 3)) * [0.8, 0.9, 1.0]; rgb[5:15, 9:11] = [0.3, 0.25, 0.2]
    >>> int(thin_lines(rgb2lab(rgb)).sum())  # the twig, 2 x 10 pixels
    20
    """
    import cv2

    codes = np.stack([lab[..., 0] * 2.55, lab[..., 1] + 128.0, lab[..., 2] + 128.0], axis=-1)
    u8 = np.clip(np.round(codes), 0, 255).astype(np.uint8)
    med = cv2.medianBlur(np.ascontiguousarray(u8), THIN_SIZE).astype(np.float64)
    med[..., 0] /= 2.55
    med[..., 1:] -= 128.0
    return np.linalg.norm(lab - med, axis=-1) > THIN_DE
