"""Growing what the picture cannot show: the crown's envelope, and twigs and leaves grown
into it from the reconstructed limbs by space colonization.

Why space colonization (Runions, Lane and Prusinkiewicz, *Modeling trees with a space
colonization algorithm*, 2007) and not Honda's rule continued from the limbs: the limbs
are given, the crown's envelope is given, and what is missing is the branches that fill
the one from the other. Space colonization is exactly that: the tree grows towards
attraction points scattered in the envelope and stops where the space is taken, so the
result fills the crown the picture shows whatever the limbs are; Honda's rule grows by its
own angles and lengths and would fill it only by chance (it is used instead to regrow "a
tree of this kind", :mod:`growsim.reconstruction.infer`).

**The envelope** (:func:`envelope_points`): the crown's silhouette swept into 3D: a point
of the crown's mask at height ``y``, and a depth ``z`` within the circle over its row's
extent (each row of the crown turned about its own centre, a solid of revolution about a
vertical axis through the crown), so the envelope seen from the front is the crown's
mask; with a side picture, the depth range is the side crown's row at the same height
(the two sweeps intersected). Points are drawn uniformly from the seed.

**The algorithm** (:func:`colonize`, the paper's section 3 with its three radii): every
node of the tree may grow; each step, every attraction point pulls the node nearest to
it within the radius of influence ``d_i``; a pulled node grows a new node one step ``D``
along the normalised sum of the unit vectors to its points; points within the kill
distance ``d_k`` of a node are removed; steps repeat until no point pulls or
``iterations`` are done. The nearest-node search is the kernel
:func:`growsim.kernels.colonize.colonize_step` (incremental: each step looks only at the
new nodes). Radii by the pipe model: a tip's radius ``tip_radius``, a node's the root of
the sum of its children's squares (da Vinci's rule, exponent 2), never more than the limb
it grows from.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from growsim.kernels.colonize import colonize_step

__all__ = ["ColonizeSettings", "Grown", "colonize", "envelope_points"]


@dataclass(frozen=True)
class ColonizeSettings:
    """Space colonization's settings, lengths as shares of the tree's height: ``points``
    attraction points, ``step`` (``D``), ``influence`` (``d_i``), ``kill`` (``d_k``),
    ``iterations`` at most; ``tip_radius`` the twigs' radius at their tips (metres a
    metre of height); ``leaf_length`` a leaf's length, ``leaf_width`` its width over its
    length; ``leaves`` per grown node (``None``: as many as make the crown as dense as the
    picture shows it, :func:`growsim.reconstruction.build.reconstruct` chooses).

    Examples
    --------
    >>> ColonizeSettings().record()["points"]
    2500
    """

    points: int = 2500
    step: float = 0.02
    influence: float = 0.12
    kill: float = 0.035
    iterations: int = 80
    tip_radius: float = 0.0006
    leaf_length: float = 0.03
    leaf_width: float = 0.6
    leaves: int | None = None

    def record(self) -> dict:
        """The settings as a JSON-able dict.

        Examples
        --------
        >>> sorted(ColonizeSettings().record())[:3]
        ['influence', 'iterations', 'kill']
        """
        return asdict(self)


@dataclass(frozen=True, eq=False)
class Grown:
    """What :func:`colonize` grew: ``nodes`` ``(m, 3)`` the new nodes, ``parent``
    ``(m,)`` each one's parent (``>= 0``: a new node; ``< 0``: ``-1 - k``, the ``k``-th
    given node), ``radius`` ``(m,)`` at each node's segment base (pipe model),
    ``iterations`` done, ``points_left`` unreached.

    Examples
    --------
    >>> Grown(np.zeros((0, 3)), np.zeros(0, int), np.zeros(0), 0, 0).nodes.shape
    (0, 3)
    """

    nodes: np.ndarray
    parent: np.ndarray
    radius: np.ndarray
    iterations: int
    points_left: int


def envelope_points(crown, scale: float, base, n: int, seed: int = 0, side=None, side_base=None):
    """``n`` attraction points (``(n, 3)``, metres, the base at the origin) drawn in the
    crown's envelope (module docstring): ``crown`` ``(H, W)`` bool the crown's front mask,
    ``base`` its ``(row, col)`` base; ``side``, ``side_base`` the same for a side view at
    the same scale (optional).

    Examples
    --------
    >>> crown = np.zeros((50, 50), bool); crown[5:25, 10:40] = True
    >>> p = envelope_points(crown, 0.1, (49.0, 25.0), 500, seed=1)
    >>> p.shape, bool(np.abs(p[:, 2]).max() <= 1.5), bool(p[:, 1].min() >= 2.4)
    ((500, 3), True, True)
    """
    rng = np.random.default_rng(seed)
    rows, cols = np.nonzero(crown)
    if rows.size == 0 or n <= 0:
        return np.zeros((0, 3))
    left = np.full(crown.shape[0], np.inf)
    right = np.full(crown.shape[0], -np.inf)
    np.minimum.at(left, rows, cols.astype(np.float64))
    np.maximum.at(right, rows, cols.astype(np.float64) + 1.0)
    k = rng.integers(0, rows.size, n)
    r = rows[k] + rng.random(n)
    c = cols[k] + rng.random(n)
    centre = 0.5 * (left[rows[k]] + right[rows[k]])
    half = 0.5 * (right[rows[k]] - left[rows[k]])
    reach = np.sqrt(np.maximum(half**2 - (c - centre) ** 2, 0.0))
    lo, hi = -reach, reach
    if side is not None:
        srows, scols = np.nonzero(side)
        sl = np.full(side.shape[0], np.nan)
        sr = np.full(side.shape[0], np.nan)
        if srows.size:
            sl_ = np.full(side.shape[0], np.inf)
            sr_ = np.full(side.shape[0], -np.inf)
            np.minimum.at(sl_, srows, scols.astype(np.float64))
            np.maximum.at(sr_, srows, scols.astype(np.float64) + 1.0)
            ok = np.isfinite(sl_)
            sl[ok], sr[ok] = sl_[ok], sr_[ok]
        # the same height above the base in the side picture
        srow = np.clip(np.round(side_base[0] - (base[0] - r)).astype(int), 0, side.shape[0] - 1)
        # side picture's u = -z: z in [-(right - base), -(left - base)]
        zlo = -(sr[srow] - side_base[1] - 0.5)
        zhi = -(sl[srow] - side_base[1] - 0.5)
        have = np.isfinite(zlo)
        both_lo, both_hi = np.maximum(lo, zlo), np.minimum(hi, zhi)
        meet = have & (both_lo < both_hi)
        lo = np.where(meet, both_lo, np.where(have, zlo, lo))
        hi = np.where(meet, both_hi, np.where(have, zhi, hi))
    z = lo + (hi - lo) * rng.random(n)
    return np.stack([(c - base[1] - 0.5) * scale, (base[0] + 0.5 - r) * scale, z * scale], axis=1)


def colonize(start_nodes, start_radius, points, height: float, settings: ColonizeSettings):
    """Grow new nodes from ``start_nodes`` ``(k, 3)`` (their radii ``start_radius``
    ``(k,)``) towards the attraction ``points`` ``(P, 3)`` by space colonization (module
    docstring), lengths from ``settings`` times ``height``. Deterministic: no random draw.

    Examples
    --------
    >>> pts = np.array([[0.0, 0.05 + 0.01 * i, 0.0] for i in range(50)])
    >>> g = colonize(np.zeros((1, 3)), np.array([0.1]), pts, 1.0, ColonizeSettings())
    >>> g.parent[0], round(float(g.nodes[:, 1].max()), 2), g.points_left
    (np.int64(-1), 0.52, 0)
    >>> bool(g.radius.max() <= 0.1)   # never thicker than the limb it grows from
    True
    """
    start_nodes = np.asarray(start_nodes, np.float64).reshape(-1, 3)
    k = start_nodes.shape[0]
    points = np.ascontiguousarray(points, np.float64).reshape(-1, 3)
    D = settings.step * height
    radii = (settings.influence * height, settings.kill * height)
    cap = k + settings.iterations * max(k, 1) + 16
    nodes = np.zeros((min(cap, k + 200_000), 3))
    nodes[:k] = start_nodes
    par = np.full(nodes.shape[0], -1, np.int64)
    par[:k] = -1 - np.arange(k)
    n, first = k, 0
    alive = np.ones(points.shape[0], np.bool_)
    best = np.full(points.shape[0], -1, np.int64)
    best_d2 = np.full(points.shape[0], np.inf)
    it = 0
    for it in range(1, settings.iterations + 1):  # noqa: B007
        if not alive.any():
            break
        pull, count = colonize_step(points, alive, nodes, n, first, best, best_d2, radii)
        grow = np.flatnonzero(count > 0)
        if grow.size == 0:
            break
        d = pull[grow]
        norm = np.linalg.norm(d, axis=1)
        keep = norm > 1e-9
        grow, d, norm = grow[keep], d[keep], norm[keep]
        if grow.size == 0 or n + grow.size > nodes.shape[0]:
            break
        new = nodes[grow] + D * d / norm[:, None]
        first = n
        nodes[n : n + grow.size] = new
        par[n : n + grow.size] = grow
        n += grow.size
    new_nodes = nodes[k:n].copy()
    parent = par[k:n].copy()
    # parents among the new nodes as indices into new_nodes; given nodes as -1 - index
    parent = np.where(parent >= k, parent - k, np.where(parent >= 0, -1 - parent, parent))
    # pipe model, tips first: every new node's index is above its parent's
    m = new_nodes.shape[0]
    tip = settings.tip_radius * height
    area = np.zeros(m)
    has_child = np.zeros(m, bool)
    for i in range(m - 1, -1, -1):
        if not has_child[i]:
            area[i] = tip * tip
        j = parent[i]
        if j >= 0:
            area[j] += area[i]
            has_child[j] = True
    radius = np.sqrt(area)
    # never more than the limb it grows from
    limit = np.empty(m)
    for i in range(m):
        j = parent[i]
        limit[i] = start_radius[-1 - j] if j < 0 else limit[j]
    radius = np.minimum(radius, limit)
    return Grown(new_nodes, parent, radius, it, int(alive.sum()))
