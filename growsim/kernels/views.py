"""Numba kernels of plant views: framing, thin and anti-aliased silhouettes, blur and NCC.

Every silhouette objective scores *views*: ``(V, S, S)`` rasters, ``V = 2`` for the front
and side views of a plant. This module is the one home of what turns segments into views
and compares views; :mod:`growsim.kernels.ifs3d` (the population scorer),
:mod:`growsim.objectives.silhouette` (any plant) and :mod:`growsim.pictures.images` (photos) use it.

Pixel convention (as :mod:`growsim.kernels.raster`): pixel ``(i, j)`` (row ``i``, column
``j``) covers the square ``[j, j+1) x [i, i+1)`` of pixel coordinates ``(x, y)``; ``x`` is
the column, ``y`` the row (rows grow downwards). ``coords`` arrays hold segments as
``(V, 2, M, 2)``: ``[view, endpoint (0 start, 1 end), segment, (x, y)]``.

Framing (:func:`frame_points`): the *front* view looks along ``-z`` (``u = x``), the
*side* view along ``-x`` (``u = -z``); ``y`` is up in both. Both views share one scale
(:func:`frame_scale`): the height fills the raster unless the half-width around the trunk
base is the tighter fit; the trunk base sits at the horizontal centre and the lowest
point on the bottom row (:func:`frame_view` places any points so).

Layers: the public functions validate their inputs, allocate and call ``@njit`` kernels
(``*_kernel``: public, because other kernel modules call them inside their own loops,
on buffers they own); small ``@njit`` helpers (``_frame_*``, ``_zero``, ``_n_samples``)
hold the shared formulas.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = [
    "MARGIN",
    "blur_kernel",
    "blur_views",
    "blurred_ncc",
    "blurred_ncc_kernel",
    "frame_points",
    "frame_points_kernel",
    "frame_scale",
    "frame_view",
    "gaussian_taps",
    "ncc",
    "ncc_kernel",
    "render_antialiased",
    "render_antialiased_kernel",
    "render_thin",
    "render_thin_kernel",
]

#: Distance in pixels kept between the outermost points and the raster's border: with
#: 0.5 the extreme points land on pixel centres of the first/last row and column.
MARGIN = 0.5


# --------------------------------------------------------------------------- helpers


@njit
def _frame_scale(h, hw, size):
    """Pixels per world unit fitting height ``h`` and half-width ``hw`` (1 if neither > 0)."""
    k = np.inf
    if h > 0.0:
        k = (size - 2.0 * MARGIN) / h
    if hw > 0.0:
        k = min(k, (0.5 * size - MARGIN) / hw)
    if not np.isfinite(k):
        k = 1.0
    return k


@njit
def _frame_col(u, u_base, k, size):
    """Column of horizontal coordinate ``u``: the base ``u_base`` at the centre."""
    return 0.5 * size + k * (u - u_base)


@njit
def _frame_row(y, y_min, k, size):
    """Row of height ``y``: ``y_min`` on the bottom row's centre line."""
    return (size - MARGIN) - k * (y - y_min)


def _check_coords(coords) -> np.ndarray:
    coords = np.ascontiguousarray(coords, dtype=np.float64)
    if coords.ndim != 4 or coords.shape[1] != 2 or coords.shape[3] != 2:
        raise ValueError(f"coords must have shape (V, 2, M, 2), got {coords.shape}")
    if not np.isfinite(coords).all():
        raise ValueError("coords must be finite")
    return coords


def _check_size(size) -> int:
    if isinstance(size, bool) or int(size) != size or size < 0:
        raise ValueError(f"size must be an integer >= 0, got {size!r}")
    return int(size)


def _check_views(views, target, what: str) -> tuple[np.ndarray, np.ndarray]:
    views = np.asarray(views)
    target = np.asarray(target)
    if views.ndim != 3 or views.shape[0] < 1 or views.shape != target.shape:
        raise ValueError(
            f"{what}: views and target must both have shape (V, S0, S1) with V >= 1, "
            f"got {views.shape} and {target.shape}"
        )
    return views, target


# --------------------------------------------------------------------------- kernels


@njit
def frame_points_kernel(start, end, base, size, coords):
    """Pixel coordinates of segments in the front and side views, framed alike.

    ``start``, ``end`` ``(M, 3)``, ``base`` ``(3,)``, ``size`` the raster side; writes
    ``coords`` ``(2, 2, M, 2)`` (see :func:`frame_points`) and returns the scale ``k``.

    Examples
    --------
    >>> import numpy as np
    >>> c = np.empty((2, 2, 1, 2))
    >>> frame_points_kernel(np.zeros((1, 3)), np.array([[0.0, 2.0, 0.0]]), np.zeros(3), 64, c)
    31.5
    """
    M = start.shape[0]
    vmin = np.inf
    vmax = -np.inf
    hw = 0.0
    for e in range(2):
        P = start if e == 0 else end
        for i in range(M):
            y = P[i, 1]
            if y < vmin:
                vmin = y
            if y > vmax:
                vmax = y
            hw = max(hw, abs(P[i, 0] - base[0]), abs(P[i, 2] - base[2]))
    k = _frame_scale(vmax - vmin, hw, size)
    for e in range(2):
        P = start if e == 0 else end
        for i in range(M):
            y = _frame_row(P[i, 1], vmin, k, size)
            coords[0, e, i, 0] = _frame_col(P[i, 0], base[0], k, size)
            coords[0, e, i, 1] = y
            # side view: u = -z
            coords[1, e, i, 0] = _frame_col(-P[i, 2], -base[2], k, size)
            coords[1, e, i, 1] = y
    return k


@njit
def _frame_view(u, y, u_base, y_min, k, size, col, row):
    """``col``, ``row`` ``(n,)`` of points ``u``, ``y`` ``(n,)`` (see :func:`frame_view`)."""
    for i in range(u.shape[0]):
        col[i] = _frame_col(u[i], u_base, k, size)
        row[i] = _frame_row(y[i], y_min, k, size)


@njit
def _zero(a):
    """Set every element of the C-contiguous array ``a`` to 0, in place."""
    flat = a.reshape(-1)
    for q in range(flat.size):
        flat[q] = 0


@njit
def _n_samples(dx, dy):
    """``max(1, ceil(max(|dx|, |dy|)))``: steps of at most one pixel along ``(dx, dy)``."""
    n = math.ceil(max(abs(dx), abs(dy)))
    if n < 1:
        n = 1
    return n


@njit
def render_thin_kernel(coords, img):
    """Thin-line views of segments ``coords`` ``(V, 2, M, 2)`` into ``img`` ``(V, S0, S1)``.

    ``img`` (uint8) is zeroed first. Each segment is sampled at the ``n + 1`` points
    ``a + (b - a) * (t * (1 / n))``, ``t = 0..n``, ``n = ceil(max(|dx|, |dy|))`` (at least
    1), and the pixel holding each sample is set: consecutive samples are at most one pixel
    apart, so the line is 8-connected. This DDA replaced the exact supercover of
    :func:`growsim.kernels.raster.draw_segments` for views because it was measured faster
    on IFS trees (most segments are below a pixel; few data-dependent branches). Samples
    outside the raster (none, after :func:`frame_points`) are skipped.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.empty((1, 2, 3), np.uint8)
    >>> render_thin_kernel(np.array([[[[0.5, 0.5]], [[2.5, 0.5]]]]), img)
    >>> img[0].tolist()
    [[1, 1, 1], [0, 0, 0]]
    """
    _zero(img)
    _, S0, S1 = img.shape
    for v in range(coords.shape[0]):
        for i in range(coords.shape[2]):
            ax = coords[v, 0, i, 0]
            ay = coords[v, 0, i, 1]
            dx = coords[v, 1, i, 0] - ax
            dy = coords[v, 1, i, 1] - ay
            n = _n_samples(dx, dy)
            inv = 1.0 / n
            for t in range(n + 1):
                f = t * inv
                x = ax + dx * f
                y = ay + dy * f
                if x >= 0.0 and y >= 0.0 and x < S1 and y < S0:
                    img[v, int(y), int(x)] = 1


@njit
def render_antialiased_kernel(coords, acc):
    """Anti-aliased thin-line views of ``coords`` ``(V, 2, M, 2)`` into float ``acc``.

    ``acc`` ``(V, S0, S1)`` float64 is zeroed first. The samples of
    :func:`render_thin_kernel` each carry ``length / (n + 1)`` of ink (pixels), spread
    bilinearly over the four pixels whose centres surround it; each pixel is then capped at
    1 (fully covered). The image, hence any score of it, moves continuously with the
    segment end points, unlike the binary rendering, whose pixels jump.

    Examples
    --------
    >>> import numpy as np
    >>> acc = np.empty((1, 1, 3))
    >>> render_antialiased_kernel(np.array([[[[0.5, 0.5]], [[2.5, 0.5]]]]), acc)
    >>> acc.round(6).tolist()  # length 2 in three samples of 2/3, on pixel centres
    [[[0.666667, 0.666667, 0.666667]]]
    """
    _zero(acc)
    _, S0, S1 = acc.shape
    for v in range(coords.shape[0]):
        for i in range(coords.shape[2]):
            ax = coords[v, 0, i, 0] - 0.5
            ay = coords[v, 0, i, 1] - 0.5
            dx = coords[v, 1, i, 0] - coords[v, 0, i, 0]
            dy = coords[v, 1, i, 1] - coords[v, 0, i, 1]
            n = _n_samples(dx, dy)
            inv = 1.0 / n
            w = math.sqrt(dx * dx + dy * dy) / (n + 1)
            for t in range(n + 1):
                f = t * inv
                x = ax + dx * f
                y = ay + dy * f
                j0 = math.floor(x)
                i0 = math.floor(y)
                fx = x - j0
                fy = y - i0
                for di in range(2):
                    ii = i0 + di
                    if ii < 0 or ii >= S0:
                        continue
                    wy = fy if di == 1 else 1.0 - fy
                    for dj in range(2):
                        jj = j0 + dj
                        if jj < 0 or jj >= S1:
                            continue
                        wx = fx if dj == 1 else 1.0 - fx
                        acc[v, ii, jj] += w * wx * wy
    flat = acc.reshape(-1)
    for q in range(flat.size):
        if flat[q] > 1.0:
            flat[q] = 1.0


@njit
def blur_kernel(img, taps, tmp, out):
    """Separable blur of views ``img`` ``(V, S0, S1)`` by ``taps`` ``(2 r + 1,)`` into ``out``.

    ``out`` ``(V, S0, S1)`` float64; ``tmp`` ``(S0, S1)`` float64 is scratch. Zero outside
    the raster. The horizontal pass scatters only the non-zero pixels (most of a silhouette
    is background). ``img``: binary (uint8) or grey levels (float64).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((1, 3, 3), np.uint8); img[0, 1, 1] = 1
    >>> out = np.empty((1, 3, 3))
    >>> blur_kernel(img, np.array([0.25, 0.5, 0.25]), np.empty((3, 3)), out)
    >>> out[0].tolist()  # the outer product of the taps
    [[0.0625, 0.125, 0.0625], [0.125, 0.25, 0.125], [0.0625, 0.125, 0.0625]]
    """
    V = img.shape[0]
    S0 = img.shape[1]
    S1 = img.shape[2]
    r = (taps.size - 1) // 2
    for v in range(V):
        for i in range(S0):
            for j in range(S1):
                tmp[i, j] = 0.0
        for i in range(S0):
            for j in range(S1):
                x = img[v, i, j]
                if x != 0:
                    lo = max(0, j - r)
                    hi = min(S1, j + r + 1)
                    for q in range(lo, hi):
                        tmp[i, q] += x * taps[q - j + r]
        for i in range(S0):
            lo = max(0, i - r)
            hi = min(S0, i + r + 1)
            for j in range(S1):
                acc = 0.0
                for q in range(lo, hi):
                    acc += taps[q - i + r] * tmp[q, j]
                out[v, i, j] = acc


@njit
def _view_mean(total, V, f_all, g_all, area_reject):
    """``total / V``, or 0.0 if ``area_reject`` and the seed's area rule rejects the
    views: their total area ``f_all`` not within 0.5x-2x of the target's ``g_all``."""
    if area_reject:
        ratio = f_all / max(1.0, g_all)
        if ratio < 0.5 or ratio > 2.0:
            return 0.0
    return total / V


@njit
def ncc_kernel(img, target, g_area, area_reject):
    """Mean over views of the binary NCC ``|F and G| / sqrt(|F| |G|)`` (see :func:`ncc`).

    ``img``, ``target`` ``(V, S0, S1)`` (non-zero = foreground); ``g_area`` ``(V,)``
    float64 the target's areas. A view with an empty ``F`` or ``G`` scores 0; with
    ``area_reject``, 0 unless the total area of ``img`` is within 0.5x-2x of ``g_area``'s.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((1, 2, 2), np.uint8); a[0, 0] = 1
    >>> ncc_kernel(a, np.ones_like(a), np.array([4.0]), False)  # 2 / sqrt(2 * 4)
    0.7071067811865475
    """
    V, S0, S1 = img.shape
    total = f_all = g_all = 0.0
    for v in range(V):
        c = 0
        f = 0
        for i in range(S0):
            for j in range(S1):
                if img[v, i, j]:
                    f += 1
                    if target[v, i, j]:
                        c += 1
        if f > 0 and g_area[v] > 0:
            total += c / math.sqrt(f * g_area[v])
        f_all += f
        g_all += g_area[v]
    return _view_mean(total, V, f_all, g_all, area_reject)


@njit
def blurred_ncc_kernel(img, taps, target_b, tb_norm, tmp, fb, g_area, area_reject):
    """Mean over views of the NCC ``<Fb, Gb> / (|Fb| |Gb|)`` of blurred views.

    ``img`` ``(V, S0, S1)`` float64 (e.g. anti-aliased) is blurred by ``taps`` into the
    scratch ``fb`` (``tmp`` ``(S0, S1)`` scratch, see :func:`blur_kernel`); ``target_b``
    ``(V, S0, S1)`` is the blurred target, ``tb_norm`` ``(V,)`` its norms, ``g_area``
    ``(V,)`` the unblurred target's areas. The area rule compares the sums of ``img``
    with ``g_area``, as :func:`ncc_kernel`. Sums run pixel by pixel (so the result may
    differ from :func:`blurred_ncc`'s NumPy sums in the last bits).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((1, 1, 3)); img[0, 0, 1] = 1.0
    >>> taps = np.array([0.25, 0.5, 0.25])
    >>> tb = np.array([[[0.25, 0.5, 0.25]]])
    >>> s = blurred_ncc_kernel(img, taps, tb, np.sqrt([0.375]), np.empty((1, 3)),
    ...                        np.empty((1, 1, 3)), np.array([1.0]), False)
    >>> round(s, 12)
    1.0
    """
    blur_kernel(img, taps, tmp, fb)
    V, S0, S1 = img.shape
    total = f_all = g_all = 0.0
    for v in range(V):
        dot = 0.0
        ff = 0.0
        f = 0.0
        for i in range(S0):
            for j in range(S1):
                x = fb[v, i, j]
                dot += x * target_b[v, i, j]
                ff += x * x
                f += img[v, i, j]
        if ff > 0.0 and tb_norm[v] > 0.0:
            total += dot / (math.sqrt(ff) * tb_norm[v])
        f_all += f
        g_all += g_area[v]
    return _view_mean(total, V, f_all, g_all, area_reject)


# --------------------------------------------------------------------------- public


def frame_scale(height: float, half_width: float, size: int) -> float:
    """Pixels per world unit of the framing: the largest scale that fits ``height`` into
    ``size - 2 MARGIN`` pixels and ``half_width`` into ``size / 2 - MARGIN``.

    A zero ``height`` or ``half_width`` does not constrain; 1.0 if neither is positive.

    Examples
    --------
    >>> frame_scale(2.0, 0.5, 64), frame_scale(1.0, 1.0, 64), frame_scale(0.0, 0.0, 64)
    (31.5, 31.5, 1.0)
    """
    size = _check_size(size)
    return float(_frame_scale(float(height), float(half_width), size))


def frame_points(start, end, base, size: int) -> tuple[np.ndarray, float]:
    """Pixel coordinates of segments in the front and side views of a ``size`` raster.

    Framing: one scale ``k`` for both views (:func:`frame_scale` of the height
    ``max(y) - min(y)`` and the half-width around the base,
    ``max(|x - base_x|, |z - base_z|)``); then ``col = size/2 + k (u - u_base)`` and
    ``row = size - MARGIN - k (y - min(y))`` with ``u = x`` (front) or ``u = -z`` (side).

    ``start``, ``end`` ``(M, 3)``; ``base`` ``(3,)`` the trunk base. Returns ``coords``
    ``(2, 2, M, 2)`` (view, start/end, segment, (col, row)) and the scale ``k``.

    Examples
    --------
    >>> import numpy as np
    >>> c, k = frame_points(np.zeros((1, 3)), np.array([[0.0, 2.0, 0.0]]), np.zeros(3), 64)
    >>> c[0, :, 0].tolist(), k
    ([[32.0, 63.5], [32.0, 0.5]], 31.5)
    """
    start = np.ascontiguousarray(start, dtype=np.float64)
    end = np.ascontiguousarray(end, dtype=np.float64)
    base = np.ascontiguousarray(base, dtype=np.float64)
    if start.ndim != 2 or start.shape[1] != 3 or end.shape != start.shape:
        raise ValueError(
            f"start and end must both have shape (M, 3), got {start.shape} and {end.shape}"
        )
    if base.shape != (3,):
        raise ValueError(f"base must have shape (3,), got {base.shape}")
    size = _check_size(size)
    coords = np.empty((2, 2, start.shape[0], 2))
    k = frame_points_kernel(start, end, base, size, coords)
    return coords, float(k)


def frame_view(u, y, u_base: float, y_min: float, scale: float, size: int):
    """Place points of one view on a ``size`` raster with the framing's formulas.

    ``col = size/2 + scale (u - u_base)``, ``row = size - MARGIN - scale (y - y_min)``:
    the base ``u_base`` at the horizontal centre, height ``y_min`` on the bottom row's
    centre line (y up). ``u``, ``y`` ``(n,)``; returns ``col``, ``row`` ``(n,)`` float64.
    :func:`frame_points` places plants so; :func:`growsim.pictures.images.frame_silhouettes`,
    photos.

    Examples
    --------
    >>> col, row = frame_view([0.0, 1.0], [0.0, 2.0], 0.0, 0.0, 31.5, 64)
    >>> col.tolist(), row.tolist()
    ([32.0, 63.5], [63.5, 0.5])
    """
    u = np.ascontiguousarray(u, dtype=np.float64)
    y = np.ascontiguousarray(y, dtype=np.float64)
    if u.ndim != 1 or u.shape != y.shape:
        raise ValueError(f"u and y must both have shape (n,), got {u.shape} and {y.shape}")
    size = _check_size(size)
    col = np.empty(u.shape)
    row = np.empty(u.shape)
    _frame_view(u, y, float(u_base), float(y_min), float(scale), size, col, row)
    return col, row


def render_thin(coords, size: int) -> np.ndarray:
    """Thin-line views ``(V, size, size)`` uint8 of segments ``coords`` ``(V, 2, M, 2)``.

    See :func:`render_thin_kernel` for the line rule; ``coords`` as :func:`frame_points`
    returns them (pixel coordinates; samples outside the raster are skipped).

    Examples
    --------
    >>> import numpy as np
    >>> c, _ = frame_points(np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), np.zeros(3), 8)
    >>> render_thin(c, 8)[0, :, 4].tolist()  # the trunk: the centre column
    [1, 1, 1, 1, 1, 1, 1, 1]
    """
    coords = _check_coords(coords)
    size = _check_size(size)
    img = np.empty((coords.shape[0], size, size), dtype=np.uint8)
    render_thin_kernel(coords, img)
    return img


def render_antialiased(coords, size: int) -> np.ndarray:
    """Anti-aliased views ``(V, size, size)`` float64 in ``[0, 1]`` of ``coords``.

    See :func:`render_antialiased_kernel`; ``coords`` ``(V, 2, M, 2)`` as for
    :func:`render_thin`.

    Examples
    --------
    >>> import numpy as np
    >>> c, _ = frame_points(np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), np.zeros(3), 8)
    >>> a = render_antialiased(c, 8)
    >>> a.shape, round(float(a[0].sum()), 6)  # ink: the trunk's length in pixels
    ((2, 8, 8), 7.0)
    """
    coords = _check_coords(coords)
    size = _check_size(size)
    acc = np.empty((coords.shape[0], size, size))
    render_antialiased_kernel(coords, acc)
    return acc


def gaussian_taps(sigma: float) -> np.ndarray:
    """Normalised 1D Gaussian taps ``(2 r + 1,)``, ``r = ceil(3 sigma)``, for :func:`blur_views`.

    Examples
    --------
    >>> t = gaussian_taps(1.0)
    >>> t.shape, round(float(t.sum()), 12), bool(t[3] == t.max())
    ((7,), 1.0, True)
    """
    sigma = float(sigma)
    if not sigma > 0.0:
        raise ValueError(f"sigma must be > 0, got {sigma}")
    r = math.ceil(3.0 * sigma)
    x = np.arange(-r, r + 1, dtype=np.float64)
    g = np.exp(-0.5 * (x / sigma) ** 2)
    return g / g.sum()


def blur_views(img, sigma: float) -> np.ndarray:
    """Gaussian-blurred ``(V, S0, S1)`` float64 copy of views ``img`` (zero outside).

    ``img``: binary (uint8) or grey-level (float) images. ``sigma`` in pixels (> 0); the
    kernel is :func:`gaussian_taps`, applied separably (:func:`blur_kernel`).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((1, 9, 9), np.uint8); img[0, 4, 4] = 1
    >>> b = blur_views(img, 1.0)
    >>> round(float(b.sum()), 6), bool(b[0, 4, 4] == b.max())
    (1.0, True)
    """
    img = np.asarray(img)
    img = np.ascontiguousarray(img, dtype=np.uint8 if img.dtype == np.uint8 else np.float64)
    if img.ndim != 3:
        raise ValueError(f"img must have shape (V, S0, S1), got {img.shape}")
    out = np.empty(img.shape)
    blur_kernel(img, gaussian_taps(sigma), np.empty(img.shape[1:]), out)
    return out


def ncc(views, target, area_rejection: bool = False) -> float:
    """Mean over views of binary NCC ``|F and G| / sqrt(|F| |G|)``, in ``[0, 1]``.

    ``views``, ``target``: ``(V, S0, S1)`` arrays (``> 0`` = foreground). A view with an
    empty projection scores 0. With ``area_rejection``, 0 unless the total area of
    ``views`` is within 0.5x-2x of the target's (:func:`ncc_kernel`).

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((2, 4, 4), np.uint8); a[:, 1, :] = 1
    >>> b = a.copy(); b[:, 2, :] = 1
    >>> round(ncc(a, b), 4)  # |F and G| = 4, |F| = 4, |G| = 8
    0.7071
    """
    views, target = _check_views(views, target, "ncc")
    F = np.ascontiguousarray(views > 0, dtype=np.uint8)
    G = np.ascontiguousarray(target > 0, dtype=np.uint8)
    g_area = G.reshape(G.shape[0], -1).sum(axis=1).astype(np.float64)
    return float(ncc_kernel(F, G, g_area, bool(area_rejection)))


def blurred_ncc(views, target, sigma: float, area_rejection: bool = False) -> float:
    """Mean over views of ``<Fb, Gb> / (|Fb| |Gb|)``, ``Fb``, ``Gb`` blurred by ``sigma`` px.

    ``views`` ``(V, S0, S1)``: grey levels in [0, 1] (e.g. anti-aliased); ``target``
    ``(V, S0, S1)`` binary (``> 0`` = foreground). The area rule (``area_rejection``)
    compares the sums of the unblurred images, as :func:`ncc`. The sums are NumPy's
    (pairwise), so the result may differ from :func:`blurred_ncc_kernel`'s in the last bits.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((2, 16, 16)); a[:, 8, 4:12] = 1
    >>> b = np.roll(a, 1, axis=1)  # one pixel lower: binary NCC 0
    >>> # a blurred line's profile is a Gaussian: overlap at 1 px is exp(-1 / (4 sigma^2))
    >>> ncc(a, b), round(blurred_ncc(a, b, 1.5), 3)
    (0.0, 0.895)
    """
    views, target = _check_views(views, target, "blurred_ncc")
    F = np.asarray(views, dtype=np.float64)
    G = (target > 0).astype(np.uint8)
    Fb = blur_views(F, sigma)
    Gb = blur_views(G, sigma)
    scores = []
    for f, g in zip(Fb, Gb):
        nf, ng = float(np.sqrt((f * f).sum())), float(np.sqrt((g * g).sum()))
        scores.append(0.0 if nf == 0 or ng == 0 else float((f * g).sum()) / (nf * ng))
    if area_rejection:
        ratio = F.sum() / max(1, G.sum())
        if ratio < 0.5 or ratio > 2.0:
            return 0.0
    return float(np.mean(scores))
