"""Oracles of the view kernels (:mod:`growsim.kernels.views`): vectorised NumPy and loops.

Framing by its formulas on whole arrays, lines by their samples one segment at a time,
the blur as an explicit 2D convolution, the NCC by its definition per view.
"""

from __future__ import annotations

import numpy as np

from growsim.kernels.views import MARGIN


def frame_scale(height, half_width, size):
    """Pixels per world unit fitting ``height`` and ``half_width`` (1.0 if neither > 0).

    Examples
    --------
    >>> frame_scale(2.0, 0.0, 64)
    31.5
    """
    k = np.inf
    if height > 0:
        k = (size - 2 * MARGIN) / height
    if half_width > 0:
        k = min(k, (size / 2 - MARGIN) / half_width)
    return float(k) if np.isfinite(k) else 1.0


def frame_view(u, y, u_base, y_min, scale, size):
    """Columns and rows of points ``(u, y)`` (y up) of one view."""
    u = np.asarray(u, dtype=float)
    y = np.asarray(y, dtype=float)
    return size / 2 + scale * (u - u_base), size - MARGIN - scale * (y - y_min)


def frame_points(start, end, base, size):
    """``coords`` ``(2, 2, M, 2)`` of the front (u = x) and side (u = -z) views, and ``k``.

    Examples
    --------
    >>> import numpy as np
    >>> c, k = frame_points(np.zeros((1, 3)), np.array([[0.0, 2.0, 0.0]]), np.zeros(3), 64)
    >>> c[1, :, 0].tolist(), k
    ([[32.0, 63.5], [32.0, 0.5]], 31.5)
    """
    start = np.asarray(start, dtype=float).reshape(-1, 3)
    end = np.asarray(end, dtype=float).reshape(-1, 3)
    pts = np.concatenate([start, end])
    h = hw = 0.0
    y_min = 0.0
    if len(pts):
        y_min = pts[:, 1].min()
        h = pts[:, 1].max() - y_min
        hw = max(np.abs(pts[:, 0] - base[0]).max(), np.abs(pts[:, 2] - base[2]).max())
    k = frame_scale(h, hw, size)
    out = np.empty((2, 2, len(start), 2))
    for e, P in enumerate((start, end)):
        out[0, e, :, 0], out[0, e, :, 1] = frame_view(P[:, 0], P[:, 1], base[0], y_min, k, size)
        out[1, e, :, 0], out[1, e, :, 1] = frame_view(-P[:, 2], P[:, 1], -base[2], y_min, k, size)
    return out, k


def _samples(ax, ay, bx, by):
    """The ``n + 1`` samples of a segment, ``n = max(1, ceil(max(|dx|, |dy|)))``."""
    dx, dy = bx - ax, by - ay
    n = max(1, int(np.ceil(max(abs(dx), abs(dy)))))
    f = np.arange(n + 1) * (1.0 / n)
    return ax + dx * f, ay + dy * f


def render_thin(coords, size):
    """``(V, size, size)`` uint8: the pixel of every sample of every segment is set.

    Examples
    --------
    >>> import numpy as np
    >>> render_thin(np.array([[[[0.5, 0.5]], [[0.5, 1.5]]]]), 2)[0].tolist()
    [[1, 0], [1, 0]]
    """
    coords = np.asarray(coords, dtype=float)
    img = np.zeros((coords.shape[0], size, size), np.uint8)
    for v in range(coords.shape[0]):
        for (ax, ay), (bx, by) in zip(coords[v, 0], coords[v, 1]):
            x, y = _samples(ax, ay, bx, by)
            ok = (x >= 0) & (y >= 0) & (x < size) & (y < size)
            img[v, y[ok].astype(int), x[ok].astype(int)] = 1
    return img


def render_antialiased(coords, size):
    """``(V, size, size)``: each sample's ink (length / samples) spread bilinearly, capped at 1.

    Examples
    --------
    >>> import numpy as np
    >>> render_antialiased(np.array([[[[1.0, 0.5]], [[1.0, 1.5]]]]), 2)[0].tolist()
    [[0.25, 0.25], [0.25, 0.25]]
    """
    coords = np.asarray(coords, dtype=float)
    acc = np.zeros((coords.shape[0], size, size))
    for v in range(coords.shape[0]):
        for (ax, ay), (bx, by) in zip(coords[v, 0], coords[v, 1]):
            xs, ys = _samples(ax, ay, bx, by)
            ink = np.hypot(bx - ax, by - ay) / len(xs)
            for x, y in zip(xs - 0.5, ys - 0.5):
                j0, i0 = int(np.floor(x)), int(np.floor(y))
                for ii, wy in ((i0, 1 - (y - i0)), (i0 + 1, y - i0)):
                    for jj, wx in ((j0, 1 - (x - j0)), (j0 + 1, x - j0)):
                        if 0 <= ii < size and 0 <= jj < size:
                            acc[v, ii, jj] += ink * wx * wy
    return np.minimum(acc, 1.0)


def blur_views(img, sigma):
    """Gaussian blur (taps to ``ceil(3 sigma)``, zero outside) as an explicit 2D convolution.

    Examples
    --------
    >>> import numpy as np
    >>> round(float(blur_views(np.ones((1, 1, 1)), 1.0)[0, 0, 0]), 4)  # the centre tap squared
    0.1592
    """
    img = np.asarray(img, dtype=float)
    r = int(np.ceil(3 * sigma))
    g = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k2 = np.outer(g, g) / g.sum() ** 2
    V, S0, S1 = img.shape
    out = np.zeros(img.shape)
    pad = np.zeros((V, S0 + 2 * r, S1 + 2 * r))
    pad[:, r : r + S0, r : r + S1] = img
    for i in range(S0):
        for j in range(S1):
            out[:, i, j] = (pad[:, i : i + 2 * r + 1, j : j + 2 * r + 1] * k2).sum(axis=(1, 2))
    return out


def _area_rejected(f_area, g_area):
    ratio = f_area / max(1, g_area)
    return not 0.5 <= ratio <= 2.0


def ncc(views, target, area_rejection=False):
    """Mean over views of ``|F and G| / sqrt(|F| |G|)`` (0 for an empty view).

    Examples
    --------
    >>> import numpy as np
    >>> ncc(np.ones((1, 1, 2)), np.array([[[1, 0]]]))  # 1 / sqrt(2 * 1)
    0.7071067811865475
    """
    F = np.asarray(views) > 0
    G = np.asarray(target) > 0
    scores = []
    for f, g in zip(F, G):
        both = f.sum() > 0 and g.sum() > 0
        scores.append((f & g).sum() / np.sqrt(f.sum() * g.sum()) if both else 0.0)
    if area_rejection and _area_rejected(F.sum(), G.sum()):
        return 0.0
    return float(np.mean(scores))


def blurred_ncc(views, target, sigma, area_rejection=False):
    """Mean over views of ``<Fb, Gb> / (|Fb| |Gb|)`` of both blurred by :func:`blur_views`.

    The area rule compares the unblurred sums.
    """
    F = np.asarray(views, dtype=float)
    G = (np.asarray(target) > 0).astype(float)
    Fb, Gb = blur_views(F, sigma), blur_views(G, sigma)
    scores = []
    for f, g in zip(Fb, Gb):
        nn = np.sqrt((f * f).sum() * (g * g).sum())
        scores.append((f * g).sum() / nn if nn > 0 else 0.0)
    if area_rejection and _area_rejected(F.sum(), G.sum()):
        return 0.0
    return float(np.mean(scores))
