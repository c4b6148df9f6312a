"""The visible tree, from its silhouette: the medial axis of the mask as a branch graph,
rooted at the tree's base, each branch a polyline with a radius profile.

The method (after the skeleton stage of Tan, Zeng, Wang, Quan and Tan, *Single image tree
modeling*, 2008, and Kim and Jeong, *Single image-based 3D tree and growth models
reconstruction*, 2014; the medial axis transform of Blum, *A transformation for
extracting new descriptors of shape*, 1967):

1. **Connect.** The mask is skeletonised (Zhang and Suen's thinning,
   :func:`skimage.morphology.skeletonize`). A twig thinner than a pixel is drawn as a
   dotted line: the pieces of skeleton apart from the tree are bridged to it by a
   straight line, nearest first, in rounds of growing reach (:data:`BRIDGE_REACH`: at
   most a share of the tree's height); pieces farther away, or of fewer than
   :data:`MIN_PIECE` skeleton pixels and more than two pixels away, are dropped. When
   the pieces left apart hold more skeleton than the piece at the base (a trunk's foot
   seen below a gap, its trunk hidden), the largest is joined to it whatever the gap.
2. **Radii.** The radius at a skeleton pixel is the Euclidean distance transform of the
   mask (undilated) there, less half a pixel (a pixel centre on the edge of a one-pixel
   line is half a pixel from it), at least half a pixel. The mask is continued below its
   lowest row first, so the trunk's foot is not read as thin.
3. **Graph.** :class:`skan.Skeleton` splits the skeleton into paths between junctions
   and ends (Nunez-Iglesias et al., *A new Python library to analyse skeleton images
   confirms malaria parasite remodelling of the red blood cell membrane skeleton*, 2018).
4. **Spurs.** A path from a junction to a free end shorter than :data:`SPUR_K` times the
   junction's radius plus :data:`SPUR_PIXELS` is a wrinkle of the outline, not a branch:
   it is removed, and removals repeat until none is left (a junction left with two paths
   joins them).
5. **Root.** The base is the framing's (:func:`growsim.pictures.images.frame_silhouettes`):
   the lowest row of the mask, at the mean column of its lowest
   :data:`~growsim.pictures.framing.BASE_BAND` of the height. The graph node nearest to it
   is the root, joined to the base by the trunk's foot (the first path from the root cut
   :data:`FOOT_RISE` foot radii above the base, where the skeleton forks into the mask's
   lowest corners, and joined to the base by a straight line). A shortest-path tree from
   the root (Dijkstra; a path's cost its length over its median radius, so a limb is
   reached along the thick way, not through a twig) orients every path; a path closing a
   loop (two branches crossing in the picture) hangs from its end nearer the root.
6. **Axes.** At a junction, the child path that turns least from its parent's direction
   continues the parent's axis (same order); the others start axes one order higher.
7. **Tips.** A free tip is carried on along its direction while the mask does, at most
   :data:`TIP_REACH` times its radius plus :data:`TIP_PIXELS` (the skeleton stops short of
   a branch's end); the tip nearest the mask's highest pixel is carried up to it when
   the skeleton falls short of it (the framing's height is the mask's).
8. **Pipe model.** Along every path the radius is smoothed (a running median over
   :data:`SMOOTH` pixels) and made never to grow towards the tip (the non-increasing
   profile nearest it in least squares, by pooling adjacent violators); then, from the
   tips down, a parent thinner than its child's median radius where they meet (in a
   picture: a limb seen through a gap, or passing behind another) is thickened to it, and
   from the base up each child is cut to its parent's radius there: a child is no thicker
   than its parent (Shinozaki, Yoda, Hozumi and Kira, *A quantitative
   analysis of plant form: the pipe model theory*, 1964).

The result, :class:`Skeleton2D`, is in pixel coordinates (row 0 at the top).
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass

import numpy as np
import pandas as pd

from growsim.errors import UserInputError
from growsim.pictures.framing import BASE_BAND

__all__ = [
    "BRIDGE_REACH",
    "FOOT_RISE",
    "MIN_PIECE",
    "SMOOTH",
    "SPUR_K",
    "SPUR_PIXELS",
    "TIP_PIXELS",
    "TIP_REACH",
    "Skeleton2D",
    "base_point",
    "check_mask",
    "extract_skeleton",
    "radius_map",
]

#: a piece of skeleton apart from the tree is bridged to it when nearer than this share of
#: the tree's height
BRIDGE_REACH = 0.06
#: pieces of fewer skeleton pixels than this, apart from the tree, are dropped
MIN_PIECE = 3
#: a spur (junction to free end) shorter than SPUR_K x the junction's radius + SPUR_PIXELS
#: is removed
SPUR_K = 1.5
SPUR_PIXELS = 2.0
#: running median of the radius along a path (pixels)
SMOOTH = 5
#: a free tip is carried on along its direction while on the mask, at most TIP_REACH x its
#: radius + TIP_PIXELS
TIP_REACH = 2.0
TIP_PIXELS = 3.0
#: the trunk's first path is cut this many foot radii above the base (the skeleton's fork
#: into the corners of the lowest row)
FOOT_RISE = 1.5
#: the direction of a path at its ends: its chord over this many pixels
DIRECTION_PIXELS = 6


@dataclass(frozen=True, eq=False)
class Skeleton2D:
    """The visible branch graph of a mask, in pixels (row 0 at the top).

    ``branches``: one polyline per branch (``(k, 2)`` float64 ``(row, col)`` from its base
    to its tip); ``radii``: the radius (pixels) at each polyline point; ``parent``: the
    parent branch (``-1``: the trunk's foot, the root); ``order``: the axis order (0 the
    trunk's axis); ``base``: ``(row, col)`` of the tree's base; ``height``: the mask's
    height in pixels (lowest minus highest row); ``shape``: the mask's shape.

    Examples
    --------
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> sk = extract_skeleton(m)
    >>> len(sk.branches), sk.base, sk.height         # the foot and the trunk
    (2, (59.0, 20.0), 49.0)
    """

    branches: tuple[np.ndarray, ...]
    radii: tuple[np.ndarray, ...]
    parent: np.ndarray
    order: np.ndarray
    base: tuple[float, float]
    height: float
    shape: tuple[int, int]

    def segments(self) -> pd.DataFrame:
        """One row per polyline piece: ``branch``, ``parent`` (the parent branch),
        ``order``, ``row0``, ``col0``, ``row1``, ``col1``, ``radius`` (pixels, at the
        piece's base).

        Examples
        --------
        >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
        >>> df = extract_skeleton(m).segments()
        >>> list(df.columns)[:4], float(df.row0.max())
        (['branch', 'parent', 'order', 'row0'], 59.0)
        """
        rows = []
        for b, (pts, rad) in enumerate(zip(self.branches, self.radii)):
            for i in range(len(pts) - 1):
                rows.append((b, int(self.parent[b]), int(self.order[b]), *pts[i], *pts[i + 1],
                             float(rad[i])))  # fmt: skip
        cols = ["branch", "parent", "order", "row0", "col0", "row1", "col1", "radius"]
        return pd.DataFrame(rows, columns=cols)

    def total_length(self) -> float:
        """The summed length of the branches, in pixels.

        Examples
        --------
        >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
        >>> round(extract_skeleton(m).total_length())
        49
        """
        return float(sum(np.hypot(*np.diff(p, axis=0).T).sum() for p in self.branches))


def check_mask(mask, name: str = "mask") -> np.ndarray:
    """``mask`` as a 2D bool array with a tree in it, else :class:`UserInputError`.

    Examples
    --------
    >>> check_mask(np.ones((3, 3))).dtype
    dtype('bool')
    >>> check_mask(np.zeros((3, 3)))
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: mask: no tree pixel (True) in it
    """
    m = np.asarray(mask)
    if m.ndim != 2:
        raise UserInputError(f"{name}: expected a 2D array, got shape {m.shape}")
    m = m.astype(bool)
    if not m.any():
        raise UserInputError(f"{name}: no tree pixel (True) in it")
    return m


def base_point(mask: np.ndarray) -> tuple[float, float, float]:
    """``(row, col, height)`` of a mask's base as the framing reads it: the lowest tree
    row, the mean column of the tree pixels in its lowest ``BASE_BAND`` of the height
    (pixel centres), and the height (lowest minus highest row, at least 1).

    Examples
    --------
    >>> m = np.zeros((10, 9), bool); m[2:10, 4] = True
    >>> base_point(m)
    (9.0, 4.0, 7.0)
    """
    rows, cols = np.nonzero(mask)
    rmax = float(rows.max())
    h = max(rmax - float(rows.min()), 1.0)
    band = rows >= rmax - BASE_BAND * h
    return rmax, float(cols[band].mean()), h


def radius_map(mask: np.ndarray) -> np.ndarray:
    """The radius (pixels) of the branch whose centre line passes through each pixel: the
    Euclidean distance to the background less half a pixel, at least 0.5 (0 off the
    mask); the mask continued below its lowest row, so its foot is not thin.

    Examples
    --------
    >>> m = np.zeros((20, 11), bool); m[:, 3:8] = True   # 5 px wide: radius 2.5
    >>> float(radius_map(m)[10, 5]), float(radius_map(m)[19, 5])
    (2.5, 2.5)
    """
    from scipy import ndimage

    pad = max(8, mask.shape[0] // 8)
    padded = np.vstack([mask, np.repeat(mask[-1:], pad, axis=0)])
    edt = ndimage.distance_transform_edt(np.pad(padded, ((0, 0), (1, 1))))[:, 1:-1]
    r = np.maximum(edt[: mask.shape[0]] - 0.5, 0.5)
    return np.where(mask, r, 0.0)


def _connected_skeleton(mask: np.ndarray, root: tuple[int, int], reach: float) -> np.ndarray:
    """The skeleton of the mask, its pieces bridged to the piece nearest ``root`` in
    rounds of growing reach (at most ``reach`` pixels); the pieces left apart dropped."""
    from scipy import ndimage
    from skimage.draw import line
    from skimage.morphology import skeletonize

    skel = skeletonize(mask)
    eight = np.ones((3, 3), bool)
    labels, n = ndimage.label(skel, structure=eight)
    if n == 0:
        raise UserInputError("mask: no skeleton")
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    rr, cc = np.nonzero(skel)
    d = (rr - root[0]) ** 2 + (cc - root[1]) ** 2
    main = labels[rr[np.argmin(d)], cc[np.argmin(d)]]
    tree = labels == main
    left = set(range(1, n + 1)) - {int(main)}

    def bridge(gaps, largest=False):
        """Join the pieces left to the tree, each by a straight line from its pixel
        nearest the tree: in rounds of ``gaps``, or only the largest piece, whatever
        its distance."""
        for gap in gaps:
            if not left:
                return
            dist, (ir, ic) = ndimage.distance_transform_edt(~tree, return_indices=True)
            # each piece's pixel nearest the tree
            pr, pc = np.nonzero((labels > 0) & ~tree)
            lab = labels[pr, pc]
            dd = dist[pr, pc]
            order = np.lexsort((dd, lab))
            lab, pr, pc, dd = lab[order], pr[order], pc[order], dd[order]
            first = np.flatnonzero(np.r_[True, lab[1:] != lab[:-1]])
            if largest:
                first = first[[np.argmax(sizes[lab[first]])]]
            for k in first:
                piece = int(lab[k])
                if dd[k] > gap or (sizes[piece] < MIN_PIECE and dd[k] > 2.0):
                    continue
                a, b = (pr[k], pc[k]), (ir[pr[k], pc[k]], ic[pr[k], pc[k]])
                lr, lc = line(int(a[0]), int(a[1]), int(b[0]), int(b[1]))
                skel[lr, lc] = True
                tree[:] |= labels == piece
                tree[lr, lc] = True
                left.discard(piece)

    steps = [2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0, 48.0, 64.0]
    rounds = [g for g in steps if g < reach] + [reach]
    bridge(rounds)
    if left and sizes[list(left)].max() > tree.sum():
        # the piece at the base is a trunk's foot seen apart from most of the tree (the
        # trunk hidden between them, behind a hedge or before a treeline of its colours):
        # the largest piece is joined to it, and the rest to both
        bridge([np.inf], largest=True)
        bridge(rounds)
    out = skel & tree
    # the bridges may have made 2x2 blocks: thin once more (keeps connectivity)
    return skeletonize(out)


def _graph(skel: np.ndarray):
    """``(nodes (m, 2) int pixel coords, edges [(u, v, path (k, 2) float)])`` of the
    skeleton, by :class:`skan.Skeleton`."""
    from skan import Skeleton

    sk = Skeleton(skel)
    coords = np.asarray(sk.coordinates)
    node_of: dict[int, int] = {}
    nodes: list[tuple[int, int]] = []
    edges = []
    for i in range(sk.n_paths):
        idx = np.asarray(sk.path(i))
        ends = []
        for e in (int(idx[0]), int(idx[-1])):
            if e not in node_of:
                node_of[e] = len(nodes)
                nodes.append(tuple(int(v) for v in coords[e]))
            ends.append(node_of[e])
        edges.append([ends[0], ends[1], coords[idx].astype(np.float64)])
    return np.array(nodes, dtype=np.int64).reshape(-1, 2), edges


def _length(path: np.ndarray) -> float:
    return float(np.hypot(*np.diff(path, axis=0).T).sum()) if len(path) > 1 else 0.0


def _prune(edges: list, radius: np.ndarray, nodes: np.ndarray, root: int) -> list:
    """The edges without spurs (see the module docstring, step 4); a node left with two
    edges joins them."""
    edges = [e for e in edges if e[0] != e[1] or len(e[2]) > 2]
    for _ in range(20):
        deg = np.zeros(len(nodes), np.int64)
        for u, v, _p in edges:
            deg[u] += 1
            deg[v] += 1
        drop = set()
        for i, (u, v, p) in enumerate(edges):
            for free, joint in ((u, v), (v, u)):
                if free == root or deg[free] != 1 or deg[joint] < 3:
                    continue
                rj = radius[nodes[joint][0], nodes[joint][1]]
                if _length(p) < SPUR_K * rj + SPUR_PIXELS:
                    drop.add(i)
        if not drop:
            break
        edges = [e for i, e in enumerate(edges) if i not in drop]
        edges = _join_twos(edges, len(nodes), root)
    return edges


def _join_twos(edges: list, n_nodes: int, root: int) -> list:
    """Edges through a node of degree two (not the root) joined into one."""
    at: list[set[int]] = [set() for _ in range(n_nodes)]
    for i, (u, v, _p) in enumerate(edges):
        at[u].add(i)
        at[v].add(i)
    edges = list(edges)
    dead = set()
    stack = [k for k in range(n_nodes) if len(at[k]) == 2 and k != root]
    while stack:
        node = stack.pop()
        if len(at[node]) != 2 or node == root:
            continue
        i, j = sorted(at[node])
        (u1, v1, p1), (u2, v2, p2) = edges[i], edges[j]
        if u1 == v1 or u2 == v2:
            continue
        if v1 != node:
            u1, v1, p1 = v1, u1, p1[::-1]
        if u2 != node:
            u2, v2, p2 = v2, u2, p2[::-1]
        k = len(edges)
        edges.append([u1, v2, np.vstack([p1, p2[1:]])])
        dead.update((i, j))
        at[node] = set()
        for end in (u1, v2):
            at[end].discard(i)
            at[end].discard(j)
            at[end].add(k)
    return [e for i, e in enumerate(edges) if i not in dead]


def _direction(path: np.ndarray, at_start: bool) -> np.ndarray:
    """Unit direction ``(drow, dcol)`` of a path leaving its start (or arriving at its
    end), its chord over :data:`DIRECTION_PIXELS`."""
    k = min(len(path) - 1, DIRECTION_PIXELS)
    d = path[k] - path[0] if at_start else path[-1] - path[-1 - k]
    n = float(np.hypot(*d))
    return d / n if n > 0 else np.array([-1.0, 0.0])


def _decreasing(r: np.ndarray) -> np.ndarray:
    """The non-increasing sequence nearest ``r`` in least squares (pool adjacent
    violators: a run that grows is replaced by its mean)."""
    vals: list[float] = []
    counts: list[int] = []
    for v in r.tolist():
        vals.append(v)
        counts.append(1)
        while len(vals) > 1 and vals[-2] < vals[-1]:
            n = counts[-2] + counts[-1]
            vals[-2] = (vals[-2] * counts[-2] + vals[-1] * counts[-1]) / n
            counts[-2] = n
            vals.pop()
            counts.pop()
    return np.repeat(vals, counts)


def _profile(path: np.ndarray, radius: np.ndarray, cap: float) -> np.ndarray:
    """The radius along a path (base to tip): a running median, the non-increasing
    profile nearest it (:func:`_decreasing`), at most ``cap``."""
    r = radius[np.round(path[:, 0]).astype(int), np.round(path[:, 1]).astype(int)]
    r = np.maximum(r, 0.5)
    if len(r) >= 3:
        h = SMOOTH // 2
        padded = np.pad(r, h, mode="edge")
        win = np.lib.stride_tricks.sliding_window_view(padded, 2 * h + 1)
        r = np.median(win, axis=1)
    return np.minimum(_decreasing(r), cap)


def extract_skeleton(mask, *, reach: float = BRIDGE_REACH, crown=None,
                     crown_radius: float = np.inf) -> Skeleton2D:  # fmt: skip
    """The visible branch graph of the tree in ``mask`` (2D bool, True the tree, row 0 at
    the top, the base at the bottom): see the module docstring for the steps and their
    rules. ``reach``: pieces apart from the tree are bridged up to this share of its
    height. ``crown`` (bool, the mask's shape): the leaves' region, where the mask's
    thickness is foliage, not wood: the radius read there is at most ``crown_radius``.

    Examples
    --------
    >>> m = np.zeros((80, 60), bool)
    >>> m[40:80, 28:33] = True                       # a trunk to row 40
    >>> for i in range(30):                          # two limbs, up left and up right
    ...     m[40 - i, 30 - i // 2 - 1: 30 - i // 2 + 2] = True
    ...     m[40 - i, 30 + i // 2 - 1: 30 + i // 2 + 2] = True
    >>> sk = extract_skeleton(m)
    >>> len(sk.branches), sorted(sk.order.tolist())  # the foot, the trunk, two limbs
    (4, [0, 0, 0, 1])
    >>> bool(all(r[0] >= r[-1] for r in sk.radii))    # the pipe model: thinner up
    True
    """
    m = check_mask(mask)
    rbase, cbase, height = base_point(m)
    radius = radius_map(m)
    # a skeleton pixel off the mask (a bridge) takes its neighbours' radius
    from scipy import ndimage

    radius = np.where(m, radius, np.maximum(ndimage.maximum_filter(radius, 3), 0.5))
    if crown is not None:
        radius = np.where(np.asarray(crown, bool), np.minimum(radius, crown_radius), radius)
    skel = _connected_skeleton(m, (int(rbase), round(cbase)), reach * height + 2.0)
    if skel.sum() < 2:  # a dot: one vertical pixel pair
        skel = np.zeros_like(skel)
        rr, _cc = np.nonzero(m)
        skel[rr.min() : int(rbase) + 1, round(cbase)] = True
    nodes, edges = _graph(skel)
    d = (nodes[:, 0] - rbase) ** 2 + (nodes[:, 1] - cbase) ** 2
    # the root: the lowest free end near the base, else the nearest node
    root = int(np.argmin(d))
    edges = _prune(edges, radius, nodes, root)
    # Dijkstra from the root: each node's distance and the edge it is reached by
    adj: list[list[int]] = [[] for _ in range(len(nodes))]
    for i, (u, v, _p) in enumerate(edges):
        adj[u].append(i)
        adj[v].append(i)
    dist = np.full(len(nodes), np.inf)
    via = np.full(len(nodes), -1)
    dist[root] = 0.0
    heap = [(0.0, root)]
    # a path's cost: its length over its median radius (the thick way round a loop wins:
    # a limb is not reached through a twig)
    lengths = [
        _length(p) / max(float(np.median(radius[p[:, 0].astype(int), p[:, 1].astype(int)])), 0.5)
        for _u, _v, p in edges
    ]
    while heap:
        du, u = heapq.heappop(heap)
        if du > dist[u]:
            continue
        for i in adj[u]:
            a, b, _p = edges[i]
            w = b if a == u else a
            if du + lengths[i] < dist[w]:
                dist[w] = du + lengths[i]
                via[w] = i
                heapq.heappush(heap, (dist[w], w))
    # orient every reached edge from its end nearer the root
    oriented = []
    for i, (u, v, p) in enumerate(edges):
        if not (np.isfinite(dist[u]) and np.isfinite(dist[v])):
            continue
        if dist[u] > dist[v] or (dist[u] == dist[v] and via[u] == i):
            u, v, p = v, u, p[::-1]
        tree_edge = via[v] == i
        oriented.append((u, v, p, tree_edge))
    # the branches: the trunk's foot first, then breadth first from the root
    foot = np.array([[rbase, cbase], nodes[root].astype(np.float64)])
    if np.hypot(*(foot[1] - foot[0])) < 0.5:
        foot = np.array([[rbase, cbase], [rbase - 1.0, cbase]])
    branches = [foot]
    # the foot: as thick as the trunk's thickest in its lowest rows
    low = radius[max(0, int(rbase) - max(2, int(0.08 * height))) : int(rbase) + 1]
    radii = [np.full(2, max(float(low.max()), float(radius[nodes[root][0], nodes[root][1]])))]
    parent, order = [-1], [0]
    ends_at = {root: 0}  # node -> the branch arriving there (its continuation's parent)
    queue = [root]
    out_of: dict[int, list] = {}
    for u, v, p, tree_edge in oriented:
        out_of.setdefault(u, []).append((v, p, tree_edge))
    while queue:
        u = queue.pop(0)
        par = ends_at[u]
        pdir = _direction(branches[par], at_start=False)
        kids = out_of.get(u, [])
        turns = [float(np.dot(pdir, _direction(p, at_start=True))) for _v, p, _t in kids]
        best = int(np.argmax(turns)) if kids else -1
        for k, (v, p, tree_edge) in enumerate(kids):
            branches.append(p)
            radii.append(_profile(p, radius, np.inf))
            parent.append(par)
            order.append(order[par] + (0 if k == best else 1))
            if tree_edge:
                ends_at[v] = len(branches) - 1
                queue.append(v)
    # the trunk's foot: the skeleton forks into the corners of the mask's lowest row, so
    # the first path from the root is cut where it is a foot's radius above the base, and
    # the foot drawn straight from the base to there
    kids0 = [b for b in range(1, len(branches)) if parent[b] == 0]
    if len(kids0) == 1:
        b = kids0[0]
        p = branches[b]
        keep = p[:, 0] <= rbase - FOOT_RISE * float(radii[0][0])
        first = int(np.argmax(keep)) if keep.any() else len(p) - 1
        first = min(first, len(p) - 2) if len(p) > 2 else 0
        if first > 0:
            branches[b] = p[first:]
            radii[b] = radii[b][first:]
            branches[0] = np.array([[rbase, cbase], p[first]])
    # the pipe model, from the tips down: a parent thinner than its child where they
    # meet (a limb seen through a gap, or behind another) is thickened to it
    # (to the child's median radius: a child starting in the blob where branches cross
    # must not thicken the tree below it); then, from the base up, each child is cut to
    # its parent's radius where they meet
    for b in range(len(branches) - 1, 0, -1):
        par = parent[b]
        need = float(np.median(radii[b]))
        if radii[par][-1] < need:
            radii[par] = np.maximum(radii[par], need)
    for b in range(1, len(branches)):
        radii[b] = np.minimum(radii[b], radii[parent[b]][-1])
    # a free tip reaches on along its direction while the mask does (the skeleton stops
    # short of a branch's end, and pruning shortens it), at most TIP_REACH x its radius
    # + TIP_PIXELS
    top = float(np.flatnonzero(m.any(axis=1)).min())
    tips = [b for b in range(1, len(branches)) if b not in set(parent)]
    for b in tips:
        p, r = branches[b], radii[b]
        d = _direction(p, at_start=False)
        reach_px = TIP_REACH * float(r[-1]) + TIP_PIXELS
        tip = p[-1].copy()
        for t in np.arange(1.0, reach_px + 1e-9, 1.0):
            q = p[-1] + t * d
            i, j = round(q[0]), round(q[1])
            if not (0 <= i < m.shape[0] and 0 <= j < m.shape[1]) or not m[i, j]:
                break
            tip = q
        if np.hypot(*(tip - p[-1])) > 0.5:
            branches[b] = np.vstack([p, tip])
            radii[b] = np.r_[r, r[-1]]
    # the tree's top is the mask's (the framing's height): the tip nearest the highest
    # mask pixel is carried up to it when the skeleton falls short
    hi = min(float(p[:, 0].min()) for p in branches)
    if hi > top + 0.5 and tips:
        cols = np.flatnonzero(m[int(top)])
        near = min(
            tips,
            key=lambda b: float(
                np.min(np.hypot(branches[b][-1][0] - top, branches[b][-1][1] - cols))
            ),
        )
        p = branches[near]
        j = float(cols[np.argmin(np.abs(cols - p[-1][1]))])
        branches[near] = np.vstack([p, [top, j]])
        radii[near] = np.r_[radii[near], radii[near][-1]]
    return Skeleton2D(
        branches=tuple(branches),
        radii=tuple(radii),
        parent=np.asarray(parent, np.int64),
        order=np.asarray(order, np.int32),
        base=(rbase, cbase),
        height=height,
        shape=(int(m.shape[0]), int(m.shape[1])),
    )
