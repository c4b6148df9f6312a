"""Numba kernels of the 3D IFS tree: map matrices, composition, framing, silhouettes, NCC.

The tree (Kuwahara, Shiwa, Kishino, "fitting a 3D fractal tree to front/side tree images
with a GA", ATR TR-C-0135) is the trunk ``OS`` (``O = (0, 0, 0)``, ``S = (0, 1, 0)``) and
every composition ``w_j1 ... w_jk (OS)``, ``k = 1..depth``, of ``N`` affine maps

    w_n = Trans(0, y_n, 0) Rot_y(theta_y_n) Rot_z(-theta_z_n) Scale(s_n).

Segment order (used by every caller): level by level (breadth first); inside a level the
compositions ``(j1, ..., jk)`` in lexicographic order. Segment ``i`` of level ``k`` has
index ``offset_k + sum_m j_m N^(k-m)`` and its parent is ``offset_{k-1} + (i - offset_k) // N``
(the composition without its last map): applying ``w_jk`` first puts a branch on the trunk,
and the parent's transform carries trunk and branch onto the parent segment.

Views and framing (see :func:`frame_points`): the *front* view looks along ``-z`` (image
``u = x``), the *side* view along ``-x`` (image ``u = -z``); ``v = y`` is up in both. Both
views share one scale: the plant's height fills the raster, unless its half-width around
the trunk base is the tighter fit; the trunk base sits at the horizontal centre and the
lowest point on the bottom row.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from growsim.kernels.config import njit

__all__ = [
    "MARGIN",
    "blur_views",
    "compose_tree",
    "frame_points",
    "gaussian_taps",
    "map_matrices",
    "n_segments",
    "render_views",
    "score_population",
]

#: Distance in pixels kept between the outermost points and the raster's border: with
#: 0.5 the extreme points land on pixel centres of the first/last row and column.
MARGIN = 0.5


def n_segments(n_maps: int, depth: int) -> int:
    """Number of segments of a tree of ``n_maps`` maps to ``depth``: ``sum_k N^k``, k=0..depth.

    Examples
    --------
    >>> n_segments(5, 5)
    3906
    """
    return sum(int(n_maps) ** k for k in range(int(depth) + 1))


# --------------------------------------------------------------------------- maps


@njit
def _map_matrix(s, y, theta_z, theta_y, M):
    """Fill ``M`` ``(3, 4)`` with ``Trans(0,y,0) Rot_y(theta_y) Rot_z(-theta_z) Scale(s)``.

    Angles in degrees. ``Rot_z(-theta_z)`` tilts the y axis towards +x by ``theta_z``;
    ``Rot_y(theta_y)`` then turns that tilt about the trunk.
    """
    tz = math.radians(theta_z)
    ty = math.radians(theta_y)
    cz = math.cos(tz)
    sz = math.sin(tz)
    cy = math.cos(ty)
    sy = math.sin(ty)
    # Rot_z(-tz) = [[cz, sz, 0], [-sz, cz, 0], [0, 0, 1]]
    # Rot_y(ty)  = [[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]]
    # product Rot_y(ty) Rot_z(-tz):
    M[0, 0] = s * cy * cz
    M[0, 1] = s * cy * sz
    M[0, 2] = s * sy
    M[1, 0] = -s * sz
    M[1, 1] = s * cz
    M[1, 2] = 0.0
    M[2, 0] = -s * sy * cz
    M[2, 1] = -s * sy * sz
    M[2, 2] = s * cy
    M[0, 3] = 0.0
    M[1, 3] = y
    M[2, 3] = 0.0


@njit
def _maps_of(p, W):
    """``p`` ``(N, 4)`` rows ``(s, y, theta_z, theta_y)`` -> ``W`` ``(N, 3, 4)``."""
    for n in range(p.shape[0]):
        _map_matrix(p[n, 0], p[n, 1], p[n, 2], p[n, 3], W[n])


@njit
def _compose(W, depth, mats, start, end):
    """Endpoints of every segment into ``start``/``end`` ``(M, 3)``.

    ``mats`` ``(M_internal, 3, 4)`` is scratch for the transforms of non-leaf segments
    (``M_internal = number of segments above the last level``). Leaves need only their two
    end points, so the last (largest) level skips the full 3x3 product.
    """
    N = W.shape[0]
    # level 0: the identity transform, the trunk OS
    start[0, 0] = 0.0
    start[0, 1] = 0.0
    start[0, 2] = 0.0
    end[0, 0] = 0.0
    end[0, 1] = 1.0
    end[0, 2] = 0.0
    if depth == 0:
        return
    mats[0, :, :] = 0.0
    mats[0, 0, 0] = 1.0
    mats[0, 1, 1] = 1.0
    mats[0, 2, 2] = 1.0
    # precomputed for the leaf shortcut: the image of OS under each map
    ws = np.empty((N, 3))
    wd = np.empty((N, 3))
    for j in range(N):
        for r in range(3):
            ws[j, r] = W[j, r, 3]
            wd[j, r] = W[j, r, 1]
    poff = 0  # offset of the parent level
    plen = 1
    off = 1
    # explicit indexing (no array views in the inner loops): measured 2x faster
    for level in range(1, depth + 1):
        last = level == depth
        for q in range(plen):
            p = poff + q
            for j in range(N):
                idx = off + q * N + j
                if last:
                    for r in range(3):
                        p0 = mats[p, r, 0]
                        p1 = mats[p, r, 1]
                        p2 = mats[p, r, 2]
                        s0 = mats[p, r, 3] + p0 * ws[j, 0] + p1 * ws[j, 1] + p2 * ws[j, 2]
                        start[idx, r] = s0
                        end[idx, r] = s0 + p0 * wd[j, 0] + p1 * wd[j, 1] + p2 * wd[j, 2]
                else:
                    for r in range(3):
                        p0 = mats[p, r, 0]
                        p1 = mats[p, r, 1]
                        p2 = mats[p, r, 2]
                        for c in range(4):
                            mats[idx, r, c] = p0 * W[j, 0, c] + p1 * W[j, 1, c] + p2 * W[j, 2, c]
                        mats[idx, r, 3] += mats[p, r, 3]
                        start[idx, r] = mats[idx, r, 3]
                        end[idx, r] = mats[idx, r, 3] + mats[idx, r, 1]
        poff = off
        off += plen * N
        plen *= N


# --------------------------------------------------------------------------- framing


@njit
def _frame(start, end, base, size, coords):
    """Pixel coordinates of both views, framed alike (see :func:`frame_points`).

    ``coords`` ``(2, 2, M, 2)``: ``[view, endpoint (0 start, 1 end), segment, (x, y)]``.
    Returns the scale (pixels per world unit).
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
    h = vmax - vmin
    k = np.inf
    if h > 0.0:
        k = (size - 2.0 * MARGIN) / h
    if hw > 0.0:
        k = min(k, (0.5 * size - MARGIN) / hw)
    if not np.isfinite(k):
        k = 1.0
    cx = 0.5 * size
    by = size - MARGIN
    for e in range(2):
        P = start if e == 0 else end
        for i in range(M):
            y = by - k * (P[i, 1] - vmin)
            coords[0, e, i, 0] = cx + k * (P[i, 0] - base[0])
            coords[0, e, i, 1] = y
            coords[1, e, i, 0] = cx - k * (P[i, 2] - base[2])
            coords[1, e, i, 1] = y
    return k


@njit
def _render(coords, img):
    """Thin-line silhouettes of both views into ``img`` ``(2, S, S)`` (zeroed first).

    Each segment is sampled at the ``n + 1`` points ``a + (b - a) * (t * (1 / n))``,
    ``t = 0..n``, ``n = ceil(max(|dx|, |dy|))`` (at least 1), and the pixel holding each
    sample is set: consecutive samples are at most one pixel apart, so the line is
    8-connected. This DDA replaced the exact supercover of
    :func:`growsim.kernels.raster.draw_segments` here because it was measured faster on
    IFS trees (most segments are below a pixel; few data-dependent branches). Points
    outside the raster (none, after :func:`_frame`) are skipped.
    """
    flat = img.reshape(-1)
    for q in range(flat.size):
        flat[q] = 0
    M = coords.shape[2]
    S0 = img.shape[1]
    S1 = img.shape[2]
    for v in range(2):
        for i in range(M):
            ax = coords[v, 0, i, 0]
            ay = coords[v, 0, i, 1]
            dx = coords[v, 1, i, 0] - ax
            dy = coords[v, 1, i, 1] - ay
            n = math.ceil(max(abs(dx), abs(dy)))
            if n < 1:
                n = 1
            inv = 1.0 / n
            for t in range(n + 1):
                f = t * inv
                x = ax + dx * f
                y = ay + dy * f
                if x >= 0.0 and y >= 0.0 and x < S1 and y < S0:
                    img[v, int(y), int(x)] = 1


@njit
def _render_aa(coords, acc):
    """Anti-aliased thin-line views into float ``acc`` ``(2, S, S)`` (zeroed first).

    The samples of :func:`_render` each carry ``length / (n + 1)`` of ink (pixels), spread
    bilinearly over the four pixels whose centres surround it; each pixel is then capped
    at 1 (fully covered). The image, hence any score of it, moves continuously with the
    segment end points, unlike the binary rendering, whose pixels jump.
    """
    flat = acc.reshape(-1)
    for q in range(flat.size):
        flat[q] = 0.0
    M = coords.shape[2]
    S0 = acc.shape[1]
    S1 = acc.shape[2]
    for v in range(2):
        for i in range(M):
            ax = coords[v, 0, i, 0] - 0.5
            ay = coords[v, 0, i, 1] - 0.5
            dx = coords[v, 1, i, 0] - coords[v, 0, i, 0]
            dy = coords[v, 1, i, 1] - coords[v, 0, i, 1]
            n = math.ceil(max(abs(dx), abs(dy)))
            if n < 1:
                n = 1
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
    for q in range(flat.size):
        if flat[q] > 1.0:
            flat[q] = 1.0


@njit
def _ncc(img, target, g_area, area_reject):
    """Mean over views of ``|F and G| / sqrt(|F| |G|)``; 0 when rejected by area ratio."""
    S0 = img.shape[1]
    S1 = img.shape[2]
    total = 0.0
    f_all = 0.0
    g_all = 0.0
    for v in range(2):
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
    if area_reject:
        ratio = f_all / g_all
        if ratio < 0.5 or ratio > 2.0:
            return 0.0
    return 0.5 * total


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


@njit
def _blur(img, taps, tmp, out):
    """Separable Gaussian blur of the ``(V, S, S)`` binary ``img`` into float ``out``.

    Zero outside the raster. The horizontal pass scatters only the set pixels (most of a
    silhouette is background); ``tmp`` ``(S, S)`` is scratch.
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
def _ncc_blurred(img, taps, target_b, tb_norm, tmp, fb, g_area, area_reject):
    """Mean over views of the NCC ``<Fb, Gb> / (|Fb| |Gb|)`` of blurred silhouettes.

    ``target_b`` is the blurred target, ``tb_norm`` ``(V,)`` its norms. The area rule uses
    the binary areas, as :func:`_ncc`.
    """
    _blur(img, taps, tmp, fb)
    S0 = img.shape[1]
    S1 = img.shape[2]
    total = 0.0
    f_all = 0.0
    g_all = 0.0
    for v in range(2):
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
    if area_reject:
        ratio = f_all / g_all
        if ratio < 0.5 or ratio > 2.0:
            return 0.0
    return 0.5 * total


@njit(parallel=True)
def _score_population(params, depth, target, area_reject, n_chunks, taps):
    n = params.shape[0]
    N = params.shape[1]
    S = target.shape[1]
    M = 1
    lvl = 1
    for _ in range(depth):
        lvl *= N
        M += lvl
    m_int = max(1, M - lvl)
    g_area = np.zeros(2)
    for v in range(2):
        g_area[v] = float(np.sum(target[v]))
    blurred = taps.size > 0
    target_b = np.zeros((2, S, S))
    tb_norm = np.zeros(2)
    if blurred:
        _blur(target, taps, np.empty((S, S)), target_b)
        for v in range(2):
            tb_norm[v] = math.sqrt(np.sum(target_b[v] * target_b[v]))
    out = np.zeros(n)
    base = np.zeros(3)
    for c in numba.prange(n_chunks):
        # per-chunk scratch, so threads never share buffers
        W = np.empty((N, 3, 4))
        mats = np.empty((m_int, 3, 4))
        start = np.empty((M, 3))
        end = np.empty((M, 3))
        coords = np.empty((2, 2, M, 2))
        img = np.empty((2, S, S), dtype=np.uint8)
        tmp = np.empty((S, S))
        fb = np.empty((2, S, S))
        aimg = np.empty((2, S, S))
        for i in range(c, n, n_chunks):
            _maps_of(params[i], W)
            _compose(W, depth, mats, start, end)
            _frame(start, end, base, S, coords)
            if blurred:
                _render_aa(coords, aimg)
                out[i] = _ncc_blurred(aimg, taps, target_b, tb_norm, tmp, fb, g_area, area_reject)
            else:
                _render(coords, img)
                out[i] = _ncc(img, target, g_area, area_reject)
    return out


# --------------------------------------------------------------------------- public


def _as_maps(maps) -> np.ndarray:
    maps = np.ascontiguousarray(maps, dtype=np.float64)
    if maps.ndim != 2 or maps.shape[1] != 4 or maps.shape[0] < 1:
        raise ValueError(f"maps must have shape (N, 4) with N >= 1, got {maps.shape}")
    return maps


def map_matrices(maps) -> np.ndarray:
    """The affine maps as ``(N, 3, 4)`` matrices ``[A | t]`` (``x -> A x + t``).

    ``maps`` ``(N, 4)``: rows ``(s, y, theta_z, theta_y)``, angles in degrees.

    Examples
    --------
    >>> import numpy as np
    >>> W = map_matrices(np.array([[0.5, 0.4, 90.0, 0.0]]))
    >>> np.round(W[0] @ [0, 1, 0, 1], 6).tolist()  # S = (0, 1, 0) -> tilted 90 deg to +x
    [0.5, 0.4, 0.0]
    """
    maps = _as_maps(maps)
    W = np.empty((maps.shape[0], 3, 4))
    _maps_of(maps, W)
    return W


def compose_tree(maps, depth: int) -> tuple[np.ndarray, np.ndarray]:
    """Segment end points of the IFS tree, in the module's segment order.

    ``maps`` ``(N, 4)`` rows ``(s, y, theta_z, theta_y)`` (degrees); returns ``start`` and
    ``end``, both ``(M, 3)`` with ``M = n_segments(N, depth)``.

    Examples
    --------
    >>> import numpy as np
    >>> s, e = compose_tree(np.array([[0.5, 0.4, 0.0, 0.0]]), 2)
    >>> np.round(e[:, 1], 6).tolist()  # the trunk, then 0.4 + 0.5, then 0.4 + 0.5 * 0.9
    [1.0, 0.9, 0.85]
    """
    maps = _as_maps(maps)
    depth = int(depth)
    if depth < 0:
        raise ValueError(f"depth must be >= 0, got {depth}")
    N = maps.shape[0]
    M = n_segments(N, depth)
    W = np.empty((N, 3, 4))
    _maps_of(maps, W)
    start = np.empty((M, 3))
    end = np.empty((M, 3))
    mats = np.empty((max(1, M - N**depth), 3, 4))
    _compose(W, depth, mats, start, end)
    return start, end


def frame_points(start, end, base, size: int) -> tuple[np.ndarray, float]:
    """Pixel coordinates of segments in the front and side views of a ``size`` raster.

    Framing: one scale ``k`` for both views, the largest that fits the height
    ``max(y) - min(y)`` into ``size - 2 MARGIN`` pixels and the half-width around the base,
    ``max(|x - base_x|, |z - base_z|)``, into ``size / 2 - MARGIN``; then
    ``col = size/2 + k (u - u_base)`` and ``row = size - MARGIN - k (y - min(y))`` with
    ``u = x`` (front) or ``u = -z`` (side).

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
    coords = np.empty((2, 2, start.shape[0], 2))
    k = _frame(start, end, base, int(size), coords)
    return coords, float(k)


def render_views(start, end, base, size: int) -> np.ndarray:
    """Thin-line front and side silhouettes ``(2, size, size)`` uint8 of segments.

    Framed by :func:`frame_points`; drawn with the shared rasteriser's thin lines.

    Examples
    --------
    >>> import numpy as np
    >>> s, e = compose_tree(np.array([[0.5, 0.4, 45.0, 0.0]]), 3)
    >>> img = render_views(s, e, np.zeros(3), 32)
    >>> img.shape, bool(img[0].sum() > img[1].sum())  # branches lean along x: wider in front
    ((2, 32, 32), True)
    """
    coords, _ = frame_points(start, end, base, size)
    img = np.empty((2, int(size), int(size)), dtype=np.uint8)
    _render(coords, img)
    return img


def blur_views(img, sigma: float) -> np.ndarray:
    """Gaussian-blurred ``(V, S, S)`` float64 copy of views ``img`` (zero outside).

    ``img``: binary (uint8) or grey-level (float) images.

    ``sigma`` in pixels (> 0); the kernel is :func:`gaussian_taps`, applied separably.

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
    _blur(img, gaussian_taps(sigma), np.empty(img.shape[1:]), out)
    return out


def score_population(
    params, depth: int, target, area_reject: bool = False, blur: float = 0.0
) -> np.ndarray:
    """Mean front/side binary NCC of a whole population of IFS trees (parallel kernel).

    ``params`` ``(n, N, 4)`` rows ``(s, y, theta_z, theta_y)`` per map (degrees); ``target``
    ``(2, S, S)`` uint8 front and side silhouettes (framed like :func:`render_views`).
    Returns ``(n,)`` float64 in ``[0, 1]``; ``area_reject`` scores 0 a tree whose total
    silhouette area is not within 0.5x-2x of the target's (the seed's rejection).
    ``blur > 0``: the NCC ``<Fb, Gb> / (|Fb| |Gb|)`` of both silhouettes blurred by a
    Gaussian of ``blur`` pixels (:func:`blur_views`), which gives near misses partial
    credit; 0 is the binary NCC.

    Examples
    --------
    >>> import numpy as np
    >>> maps = np.array([[0.5, 0.4, 0.0, 0.0], [0.5, 0.4, 45.0, 0.0]])
    >>> s, e = compose_tree(maps, 4)
    >>> tgt = render_views(s, e, np.zeros(3), 64)
    >>> score_population(maps[None], 4, tgt).round(6).tolist()
    [1.0]
    """
    params = np.ascontiguousarray(params, dtype=np.float64)
    if params.ndim != 3 or params.shape[2] != 4:
        raise ValueError(f"params must have shape (n, N, 4), got {params.shape}")
    target = np.ascontiguousarray(target, dtype=np.uint8)
    if target.ndim != 3 or target.shape[0] != 2 or target.shape[1] != target.shape[2]:
        raise ValueError(f"target must have shape (2, S, S), got {target.shape}")
    if params.shape[0] == 0:
        return np.zeros(0)
    if not blur >= 0.0:
        raise ValueError(f"blur must be >= 0, got {blur}")
    taps = gaussian_taps(blur) if blur > 0.0 else np.zeros(0)
    n_chunks = min(params.shape[0], 4 * numba.get_num_threads())
    return _score_population(params, int(depth), target, bool(area_reject), n_chunks, taps)
