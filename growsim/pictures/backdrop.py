"""What lies behind the tree, filled in where the tree hides it: the sky as it would be
without the tree, from the sky around and between its branches (:func:`sky_background`,
by :func:`fill`), and the ground and the horizon's clutter of each row, across a trunk
(:func:`row_background`). :func:`growsim.pictures.photo.segment_photo` reads each pixel
against them.
"""

from __future__ import annotations

import numpy as np

__all__ = ["fill", "row_background", "sky_background"]


def fill(values: np.ndarray, known: np.ndarray, *, smooth: float = 1.0) -> np.ndarray:
    """``values`` ``(H, W, C)`` filled in where not ``known`` (``(H, W)`` bool) from the
    known pixels around, by normalized convolution on a pyramid (push-pull): each pixel
    takes the mean of the known pixels near it, as near as they are (a Gaussian of
    ``smooth`` pixels at the finest level, twice as wide at each level up). Known pixels
    keep about their own local mean.

    Examples
    --------
    >>> v = np.zeros((8, 8, 1)); v[:, 4:] = 1.0
    >>> known = np.ones((8, 8), bool); known[2:6, 3:5] = False
    >>> out = fill(v, known)
    >>> bool(out[4, 1, 0] < 0.1 < out[4, 3, 0] < out[4, 4, 0] < 0.9 < out[4, 6, 0])
    True
    """
    from scipy import ndimage

    v = np.asarray(values, dtype=np.float64)
    k = np.asarray(known, dtype=np.float64)
    num = ndimage.gaussian_filter(v * k[..., None], (smooth, smooth, 0), mode="nearest")
    den = ndimage.gaussian_filter(k, smooth, mode="nearest")
    levels = [(num, den)]
    while min(levels[-1][1].shape) > 2:
        n, d = levels[-1]
        hh, ww = (d.shape[0] // 2) * 2, (d.shape[1] // 2) * 2
        if hh == 0 or ww == 0:
            break
        n = n[:hh, :ww].reshape(hh // 2, 2, ww // 2, 2, -1).mean(axis=(1, 3))
        d = d[:hh, :ww].reshape(hh // 2, 2, ww // 2, 2).mean(axis=(1, 3))
        levels.append((n, d))
    n, d = levels[-1]
    est = n / np.maximum(d, 1e-12)[..., None]
    if not (d > 1e-9).any():
        est[:] = v.reshape(-1, v.shape[-1]).mean(axis=0)
    else:
        est[d <= 1e-9] = (n.sum(axis=(0, 1)) / d.sum())[None, :]
    for n, d in levels[-2::-1]:
        up = _double(est, d.shape)
        weight = np.clip(d / 0.3, 0.0, 1.0)[..., None]
        est = weight * n / np.maximum(d, 1e-12)[..., None] + (1.0 - weight) * up
    return est


def _double(est: np.ndarray, shape) -> np.ndarray:
    """``est`` ``(h, w, C)`` at twice its size, bilinear (pixel centres), to ``shape``."""
    h, w = est.shape[:2]

    def axis(n_out, n_in):
        x = (np.arange(n_out) + 0.5) / 2.0 - 0.5
        x = np.clip(x, 0.0, n_in - 1.0)
        i0 = np.minimum(np.floor(x).astype(np.int64), max(n_in - 2, 0))
        t = x - i0
        return i0, np.minimum(i0 + 1, n_in - 1), t

    r0, r1, tr = axis(shape[0], h)
    c0, c1, tc = axis(shape[1], w)
    tr, tc = tr[:, None, None], tc[None, :, None]
    top = est[r0][:, c0] * (1 - tc) + est[r0][:, c1] * tc
    bottom = est[r1][:, c0] * (1 - tc) + est[r1][:, c1] * tc
    return top * (1 - tr) + bottom * tr


def sky_background(lab: np.ndarray, sky: np.ndarray) -> np.ndarray:
    """The sky behind each pixel ``(H, W, 3)`` CIELAB: the sky pixels ``sky`` ``(H, W)``
    bool filled in under everything else (:func:`fill`), so a twig is compared with the
    sky just beside it, a cloud's edge included.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> lab = rgb2lab(rgb)
    >>> sky = (rgb == [0.8, 0.9, 1.0]).all(axis=-1)
    >>> bg = sky_background(lab, sky)
    >>> bool(np.allclose(bg[30, 25], lab[5, 5]))  # the sky behind the trunk
    True
    """
    return fill(lab, sky)


def row_background(lab: np.ndarray, left: int, right: int, rows: slice, reach: int = 6):
    """The background of columns ``left``..``right`` (inclusive) in ``rows`` of ``lab``
    ``(H, W, 3)``: each row's colour beside them (the median of ``reach`` pixels on each
    side, smoothed over 5 rows), interpolated across; ``(rows, right - left + 1, 3)``.
    For the ground and the horizon's clutter behind a trunk: alike along a row, not
    down it.

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> from growsim.pictures.scene import example_photo
    >>> rgb = example_photo()  # sky, ground strip, a trunk standing on it, a branch
    >>> lab = rgb2lab(rgb)
    >>> back = row_background(lab, 22, 28, slice(52, 58))       # behind the trunk's foot
    >>> back.shape, bool(np.allclose(back[0, 3], lab[52, 5]))  # the ground
    ((6, 7, 3), True)
    """
    from scipy import ndimage

    w = lab.shape[1]
    part = lab[rows]
    lo, hi = max(0, left - reach), min(w, right + 1 + reach)
    sides = []
    if left > 0:
        sides.append(np.median(part[:, lo:left], axis=1))
    if right + 1 < w:
        sides.append(np.median(part[:, right + 1 : hi], axis=1))
    if not sides:
        sides = [np.median(part, axis=1)]
    a = ndimage.median_filter(sides[0], size=(5, 1), mode="nearest")
    b = ndimage.median_filter(sides[-1], size=(5, 1), mode="nearest")
    n = right - left + 1
    t = ((np.arange(n) + 0.5) / n)[None, :, None] if len(sides) > 1 else np.zeros((1, n, 1))
    return a[:, None, :] * (1.0 - t) + b[:, None, :] * t
