"""Numba kernels of the 2D IFS (seed 002): the chaos game and point rasters.

An IFSP code is ``N`` affine maps ``x' = a x + b y + e``, ``y' = c x + d y + f`` with
probabilities ``p``; the maps are a ``(N, 6)`` float64 table of rows ``(a, b, c, d, e, f)``
(:mod:`growsim.models.ifs2d` converts the seed's ``(r, q, theta, phi)`` form).

The chaos game (:func:`chaos_game`): start at ``(x0, y0)``, repeatedly pick map ``k``
with probability ``p_k`` and apply it; the first ``burn_in`` points are dropped, the next
``n`` are returned. Randomness is SplitMix64 (Steele, Lea & Flood, "Fast splittable
pseudorandom number generators", 2014) on a 64-bit state seeded by ``seed``: one draw per
point, its top 53 bits a uniform ``u`` in ``[0, 1)``, and map ``k`` is the first with
``u < cum[k]`` (``cum`` the cumulative probabilities, last entry forced to 1). A
generator of our own, inline, because numba's ``np.random`` (a Mersenne Twister behind a
function call) is several times slower here and its stream is not reproducible by a plain
NumPy oracle; this one is (``tests/naive/ifs2d.py`` replays it bit for bit).

Rasters (:func:`points_raster`): points already placed in pixel coordinates (``col``,
``row``, e.g. by :func:`growsim.kernels.views.frame_view`) mark or count the pixel that
holds them, with the pixel convention of :mod:`growsim.kernels.views`.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = [
    "MAX_POINTS",
    "bounds",
    "bounds_kernel",
    "chaos_game",
    "chaos_game_kernel",
    "cumulative",
    "points_raster",
    "points_raster_kernel",
    "splitmix64",
]

#: Most points one :func:`chaos_game` call returns (16 bytes each: 1.6 GB).
MAX_POINTS = 100_000_000

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
_S30 = np.uint64(30)
_S27 = np.uint64(27)
_S31 = np.uint64(31)
_S11 = np.uint64(11)


@njit
def splitmix64(state):
    """One SplitMix64 step: ``(new_state, output)`` (both uint64).

    Examples
    --------
    >>> import numpy as np
    >>> s, z = splitmix64(np.uint64(0))
    >>> hex(int(z))
    '0xe220a8397b1dcdaf'
    """
    state = state + _GOLDEN
    z = state
    z = (z ^ (z >> _S30)) * _M1
    z = (z ^ (z >> _S27)) * _M2
    return state, z ^ (z >> _S31)


@njit
def _pick(z, thresholds):
    """Index of the first map with ``z >> 11 < thresholds[k]`` (the last if none)."""
    u = z >> _S11
    N = thresholds.shape[0]
    k = 0
    while k < N - 1 and u >= thresholds[k]:
        k += 1
    return k


@njit
def chaos_game_kernel(maps, cum, x0, y0, burn_in, seed, out):
    """Chaos game of ``maps`` ``(N, 6)`` with cumulative probabilities ``cum`` ``(N,)``.

    Starts at ``(x0, y0)``, drops ``burn_in`` points and writes the next ``out.shape[0]``
    into ``out`` ``(n, 2)``. ``seed``: uint64. See the module docstring for the draws:
    ``u < cum[k]`` is tested as ``z >> 11 < ceil(cum[k] 2^53)`` on integers (the same
    choice, exactly, without converting each draw to a float: measured 1.3x faster).

    Examples
    --------
    >>> import numpy as np
    >>> out = np.empty((3, 2))
    >>> chaos_game_kernel(np.array([[0.5, 0, 0, 0.5, 0, 0]]), np.ones(1), 1.0, 2.0, 1,
    ...                   np.uint64(0), out)
    >>> out.tolist()
    [[0.25, 0.5], [0.125, 0.25], [0.0625, 0.125]]
    """
    N = maps.shape[0]
    thresholds = np.empty(N, np.uint64)
    for k in range(N):
        thresholds[k] = np.uint64(math.ceil(cum[k] * 9007199254740992.0))
    s = seed
    x = x0
    y = y0
    for _ in range(burn_in):
        s, z = splitmix64(s)
        k = _pick(z, thresholds)
        xn = maps[k, 0] * x + maps[k, 1] * y + maps[k, 4]
        y = maps[k, 2] * x + maps[k, 3] * y + maps[k, 5]
        x = xn
    for t in range(out.shape[0]):
        s, z = splitmix64(s)
        k = _pick(z, thresholds)
        xn = maps[k, 0] * x + maps[k, 1] * y + maps[k, 4]
        y = maps[k, 2] * x + maps[k, 3] * y + maps[k, 5]
        x = xn
        out[t, 0] = x
        out[t, 1] = y


@njit
def points_raster_kernel(col, row, img, count):
    """Mark (``count`` False: set to 1) or count (True: add 1) the pixel of each point.

    ``col``, ``row`` ``(n,)`` pixel coordinates; ``img`` ``(S0, S1)`` (zeroed first; an
    int64 raster when counting). Points outside the raster are skipped.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.empty((2, 3), np.int64)
    >>> points_raster_kernel(np.array([0.5, 2.9, 2.1, 7.0]), np.array([0.5, 1.2, 1.0, 0.0]),
    ...                      img, True)
    >>> img.tolist()
    [[1, 0, 0], [0, 0, 2]]
    """
    S0, S1 = img.shape
    for i in range(S0):
        for j in range(S1):
            img[i, j] = 0
    for q in range(col.shape[0]):
        x = col[q]
        y = row[q]
        if x >= 0.0 and y >= 0.0 and x < S1 and y < S0:
            i = int(y)
            j = int(x)
            if count:
                img[i, j] += 1
            else:
                img[i, j] = 1


@njit
def bounds_kernel(points):
    """``(x_min, x_max, y_min, y_max, x_low)`` of ``points`` ``(n, 2)``, ``n >= 1``:
    ``x_low`` is the x of the lowest point (the first of equals). One pass (NumPy's
    axis-0 reductions of an ``(n, 2)`` array were measured several times slower).

    Examples
    --------
    >>> import numpy as np
    >>> bounds_kernel(np.array([[1.0, 2.0], [3.0, 0.5], [-1.0, 4.0]]))
    (-1.0, 3.0, 0.5, 4.0, 3.0)
    """
    x0 = x1 = xl = points[0, 0]
    y0 = y1 = points[0, 1]
    for i in range(1, points.shape[0]):
        x = points[i, 0]
        y = points[i, 1]
        if x < x0:
            x0 = x
        if x > x1:
            x1 = x
        if y < y0:
            y0 = y
            xl = x
        if y > y1:
            y1 = y
    return x0, x1, y0, y1, xl


def bounds(points) -> tuple[float, float, float, float, float]:
    """``(x_min, x_max, y_min, y_max, x_low)`` of ``(n, 2)`` points (:func:`bounds_kernel`;
    all 0 when there are none).

    Examples
    --------
    >>> bounds([[0.0, 1.0], [2.0, -1.0]])
    (0.0, 2.0, -1.0, 1.0, 2.0)
    """
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    if points.shape[0] == 0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    return tuple(float(v) for v in bounds_kernel(points))


def cumulative(p) -> np.ndarray:
    """Cumulative probabilities ``(N,)`` of weights ``p`` (normalised; last entry exactly 1).

    All-zero weights mean equal probabilities. Raises ``ValueError`` for a negative or
    non-finite weight.

    Examples
    --------
    >>> cumulative([1, 1, 2]).tolist()
    [0.25, 0.5, 1.0]
    """
    p = np.asarray(p, dtype=np.float64).reshape(-1)
    if p.size == 0 or not np.isfinite(p).all() or (p < 0).any():
        raise ValueError(f"probabilities must be >= 0 and finite, got {p.tolist()}")
    if p.sum() == 0.0:
        p = np.ones_like(p)
    cum = np.cumsum(p / p.sum())
    cum[-1] = 1.0
    return cum


def chaos_game(maps, p, n: int, *, seed: int = 0, burn_in: int = 100, start=(0.0, 0.0)):
    """``(n, 2)`` float64 points of the attractor of ``maps`` by the chaos game.

    ``maps`` ``(N, 6)`` rows ``(a, b, c, d, e, f)``; ``p`` ``(N,)`` probability weights
    (normalised by :func:`cumulative`); ``seed`` any integer (taken modulo 2^64);
    ``burn_in`` points dropped first; ``start`` the first point.

    Examples
    --------
    >>> sierpinski = [[0.5, 0, 0, 0.5, 0, 0], [0.5, 0, 0, 0.5, 0.5, 0], [0.5, 0, 0, 0.5, 0, 0.5]]
    >>> pts = chaos_game(sierpinski, [1, 1, 1], 1000, seed=1)
    >>> pts.shape, bool((pts >= 0).all() and (pts.sum(axis=1) <= 1.0).all())
    ((1000, 2), True)
    """
    maps = np.ascontiguousarray(maps, dtype=np.float64)
    if maps.ndim != 2 or maps.shape[1] != 6 or maps.shape[0] < 1:
        raise ValueError(f"maps must have shape (N, 6) with N >= 1, got {maps.shape}")
    if not np.isfinite(maps).all():
        raise ValueError("maps must be finite")
    cum = cumulative(p)
    if cum.shape[0] != maps.shape[0]:
        raise ValueError(f"{maps.shape[0]} maps but {cum.shape[0]} probabilities")
    n = int(n)
    burn_in = int(burn_in)
    if not 0 <= n <= MAX_POINTS or burn_in < 0:
        raise ValueError(f"n must be in [0, {MAX_POINTS}] and burn_in >= 0, got {n}, {burn_in}")
    x0, y0 = (float(v) for v in start)
    out = np.empty((n, 2))
    chaos_game_kernel(maps, cum, x0, y0, burn_in, np.uint64(int(seed) % 2**64), out)
    return out


def points_raster(col, row, shape, *, count: bool = False) -> np.ndarray:
    """A raster ``shape`` ``(S0, S1)`` of points at pixel coordinates ``col``, ``row``.

    ``count`` False: uint8, 1 where a point fell; True: int64 counts per pixel.

    Examples
    --------
    >>> points_raster([0.5, 1.5, 1.6], [0.5, 0.5, 0.9], (1, 2), count=True).tolist()
    [[1, 2]]
    """
    col = np.ascontiguousarray(col, dtype=np.float64).reshape(-1)
    row = np.ascontiguousarray(row, dtype=np.float64).reshape(-1)
    if col.shape != row.shape:
        raise ValueError(f"col and row must have the same length, got {col.size}, {row.size}")
    S0, S1 = (int(s) for s in shape)
    if S0 < 0 or S1 < 0:
        raise ValueError(f"shape must be non-negative, got {shape}")
    img = np.empty((S0, S1), dtype=np.int64 if count else np.uint8)
    points_raster_kernel(col, row, img, bool(count))
    return img
