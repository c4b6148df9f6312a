"""Drawings made of square pixels, read back pixel for pixel: a raster enlarged by nearest
neighbour, by a whole or a fractional factor, has every edge of its silhouette on one
lattice; :func:`drawn_pixels` finds it and returns the drawn raster, so such a drawing
frames back exactly (:func:`growsim.pictures.images.frame_thin_lines`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["GRID_MIN_SCALE", "drawn_pixels"]


#: A drawing made of square pixels (a raster enlarged by nearest neighbour, by any factor,
#: whole or not): read back pixel for pixel (:func:`drawn_pixels`) when it is enlarged at
#: least this many times (below, the fractional framing of :func:`frame_thin_lines`)
GRID_MIN_SCALE = 1.15
#: :func:`drawn_pixels`: the scale is searched within this share of the framing's (log)
GRID_SEARCH = 0.03
#: :func:`drawn_pixels`: every boundary between drawn pixels within this many picture
#: pixels of the lattice ``phase + k scale`` (nearest neighbour rounds each boundary to a
#: whole picture pixel: a spread of 1, ties broken either way included)
GRID_RESIDUAL = 1.05
#: :func:`drawn_pixels`: how many of the fitting scales nearest the framing's are tried
GRID_TRIES = 20
#: :func:`drawn_pixels`: the drawn pixels, enlarged back, may differ from the silhouette
#: in at most this share of its pixels (scan noise, JPEG)
GRID_MISMATCH = 0.02


def _grid_boundaries(mask: np.ndarray, axis: int, s0: float):
    """The boundaries between drawn pixels along ``axis`` of a silhouette drawn in square
    pixels about ``s0`` picture pixels wide (within :data:`GRID_SEARCH`):
    ``(positions (K + 1,), scale)`` from the first row (column) holding ink to past the
    last, or ``None`` when the silhouette's edges fit no such lattice."""
    other = 1 - axis
    w = (np.diff(mask.astype(np.int8), axis=axis) != 0).sum(axis=other)
    lines = np.nonzero(mask.any(axis=other))[0]
    lo, hi = int(lines[0]), int(lines[-1]) + 1
    # rows (columns) where the silhouette changes along at least half a drawn pixel
    data = np.nonzero(w >= max(1.0, 0.5 * s0))[0] + 1
    data = np.unique(np.r_[lo, data[(data > lo) & (data < hi)], hi]).astype(np.float64)
    # the scale near s0 whose lattice holds every boundary within a picture pixel: the
    # shortest arc of the circle holding their phases (p / s mod 1), scanned finely
    # enough that the phases drift by at most 0.05 picture pixels over the silhouette
    span = max(float(data[-1] - data[0]), 1.0)
    ss = s0 * np.exp(np.arange(-GRID_SEARCH, GRID_SEARCH, 0.05 / span))
    u = np.sort((data[None, :] / ss[:, None]) % 1.0, axis=1)
    gaps = np.diff(np.c_[u, u[:, :1] + 1.0], axis=1)
    g = np.argmax(gaps, axis=1)
    arc = (1.0 - gaps[np.arange(ss.size), g]) * ss  # in picture pixels
    # with drawn pixels of 1-2 picture pixels several scales fit the phases: of the
    # GRID_TRIES nearest s0 that give each boundary seen its own drawn pixel, the one
    # with the fewest drawn pixels (a wrong lattice adds pixels where the silhouette
    # does not change), then the nearest s0
    fits = np.nonzero((arc <= GRID_RESIDUAL) & (ss >= GRID_MIN_SCALE))[0]
    best = None
    for i in fits[np.argsort(np.abs(np.log(ss[fits] / s0)), kind="stable")][:GRID_TRIES]:
        s = float(ss[i])
        phase = u[i, (g[i] + 1) % data.size] * s + 0.5 * arc[i]  # the arc's middle
        k = np.round((data - phase) / s).astype(np.int64)
        if np.unique(k).size != k.size:
            continue
        # the boundaries seen, and the lattice's where the silhouette does not change (a
        # lattice boundary rounded onto a boundary seen moved a pixel aside)
        pos = np.ceil(phase + np.arange(k[0], k[-1] + 1) * s - 0.5)
        pos[k - k[0]] = data
        seen = np.zeros(pos.size, dtype=bool)
        seen[k - k[0]] = True
        for j in np.nonzero(~seen)[0]:
            pos[j] = max(pos[j], pos[j - 1] + 1)
        for j in np.nonzero(~seen)[0][::-1]:
            pos[j] = min(pos[j], pos[j + 1] - 1)
        if np.all(np.diff(pos) >= 1) and (best is None or pos.size < best[0].size):
            best = pos.astype(np.int64), s
    return best


def _block_index(n: int, pos: np.ndarray, s: float) -> np.ndarray:
    """The drawn pixel of each of ``n`` picture rows (columns), boundaries ``pos``;
    outside them, drawn pixels ``s`` wide (negative before the first)."""
    p = np.arange(n)
    idx = np.searchsorted(pos, p, side="right") - 1
    below = p < pos[0]
    idx[below] = -np.ceil((pos[0] - p[below]) / s).astype(np.int64)
    above = p >= pos[-1]
    idx[above] = len(pos) - 1 + np.floor((p[above] - pos[-1]) / s).astype(np.int64)
    return idx


def drawn_pixels(mask: np.ndarray, scale: float):
    """A silhouette ``(H, W)`` bool drawn in square pixels about ``scale`` picture pixels
    wide (a raster enlarged by nearest neighbour by a whole or fractional factor, with any
    margin) read back pixel for pixel: ``(pixels (h, w) bool, rows (H,), cols (W,))``,
    ``rows``/``cols`` the drawn pixel of each picture row/column (from 0 at the
    silhouette's first row/column holding ink; negative or ``>= h``/``w`` outside), or
    ``None`` when it is not so drawn (a scan of a pen drawing, ``scale`` below
    :data:`GRID_MIN_SCALE`).

    Nearest neighbour sets picture row ``p`` from drawn row ``floor((p + 1/2 - phase) /
    s)``: every boundary between drawn rows is a whole picture row within half a row of
    ``phase + k s``. The scale is searched near ``scale`` (within :data:`GRID_SEARCH`),
    the boundaries where the silhouette changes must all fit the lattice within
    :data:`GRID_RESIDUAL` picture pixels, and the drawn pixels (the majority of each
    block) enlarged back must match the silhouette but for :data:`GRID_MISMATCH` of it.

    Examples
    --------
    >>> import numpy as np
    >>> from PIL import Image
    >>> raster = np.zeros((20, 20), np.uint8); raster[3:, 10] = 255; raster[8, 4:17] = 255
    >>> big = np.asarray(Image.fromarray(raster).resize((70, 70), Image.NEAREST)) > 127
    >>> pixels, rows, cols = drawn_pixels(np.pad(big, 9), 3.5)
    >>> pixels.shape, bool((pixels == (raster[3:, 4:17] > 0)).all())
    ((17, 13), True)
    >>> drawn_pixels(np.pad(raster > 0, 9), 1.0) is None  # not enlarged
    True
    """
    mask = np.asarray(mask, dtype=bool)
    if scale < GRID_MIN_SCALE or not mask.any():
        return None
    # the scale from the longer side (more boundaries, less ambiguity), the other side's
    # lattice nearest that scale: the pixels are square
    rows, cols = np.nonzero(mask.any(axis=1))[0], np.nonzero(mask.any(axis=0))[0]
    first = 0 if rows[-1] - rows[0] >= cols[-1] - cols[0] else 1
    found = [None, None]
    found[first] = _grid_boundaries(mask, first, scale)
    if found[first] is None:
        return None
    found[1 - first] = _grid_boundaries(mask, 1 - first, found[first][1])
    br, bc = found
    if bc is None or abs(np.log(bc[1] / br[1])) > GRID_SEARCH / 3:
        return None
    ri, ci = _block_index(mask.shape[0], *br), _block_index(mask.shape[1], *bc)
    nr, nc = len(br[0]) - 1, len(bc[0]) - 1
    okr, okc = (ri >= 0) & (ri < nr), (ci >= 0) & (ci < nc)
    block = (ri[okr][:, None] * nc + ci[okc][None, :]).ravel()
    ink = np.bincount(block, weights=mask[np.ix_(okr, okc)].ravel(), minlength=nr * nc)
    count = np.bincount(block, minlength=nr * nc)
    pixels = (ink > 0.5 * count).reshape(nr, nc)  # each block's majority
    back = np.zeros_like(mask)
    back[np.ix_(okr, okc)] = pixels[np.ix_(ri[okr], ci[okc])]
    if int((back != mask).sum()) > GRID_MISMATCH * int(mask.sum()):
        return None
    return pixels, ri, ci
