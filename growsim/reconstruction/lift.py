"""Into 3D: the visible branches of a front picture given depth, from a side picture or,
with one picture, by a stated botanical prior. The front view is kept exactly: only the
depth ``z`` is added to each point (``x`` right, ``y`` up, ``z`` towards the viewer of
the front picture; the side picture, seen from the right, shows ``-z`` to the right, as
:func:`growsim.objectives.silhouette.plant_views` draws a Plant's side view).

**One picture** (:func:`lift_prior`; the single-image reconstructions of Tan et al.,
*Single image tree modeling*, 2008, and Kim and Jeong, 2014, also fix depth by priors):

- the trunk's axis (order 0) stays in the picture's plane;
- the ``k``-th axis to leave its parent (counted tree-wide from the ground up) points to
  the azimuth ``phi_k = phi_0 + k x 137.508 deg`` (the golden angle: the spiral
  phyllotaxis of Vogel's model, *A better way to construct the sunflower head*, 1979, as
  limbs spread round a trunk), ``phi_0`` drawn from the seed; a continuation keeps its
  axis's azimuth;
- a branch's depth: its horizontal run in the picture ``dx`` read as the run along
  ``phi`` (``|dx| |tan phi|``, ``|tan phi|`` at most :data:`TAN_CAP`), or, when larger,
  the foreshortening its thickness tells: a branch's length grows with its radius as
  ``L = a r^(2/3)`` (McMahon's elastic similarity, *Size and shape in biology*, 1973), ``a``
  the :data:`ALLOMETRY_QUANTILE` quantile of ``L / r^(2/3)`` over the tree's visible axes (the
  axes seen longest for their thickness lie nearest the picture's plane), and an axis
  seen shorter than its ``L`` hides ``sqrt(L^2 - L_seen^2)`` of depth (at most
  ``L_seen``: no axis leaves the picture's plane by more than 45 degrees); the depth grows
  along the branch in proportion to its length, towards the viewer when ``sin phi > 0``;
- the tree reaches no deeper than it reaches across: ``|z|`` stays below the largest
  ``|x|`` from the base, ``R``, smoothly (a branch's depth offsets ``dz`` from its start's
  ``z0`` are added as ``z = R tanh(atanh(z0 / R) + dz / R)``);
- at each height the crown is as deep as it is wide (a crown about round in plan, as
  forest mensuration takes a crown's projection for a circle): in each of
  :data:`ENVELOPE_BANDS` bands of height, the depths in front of the trunk's plane and
  those behind it are scaled so that the deepest reaches half the band's width in the
  picture (by at most :data:`ENVELOPE_CAP` either way), the scales interpolated between
  the bands' middles so that every branch stays smooth.

**Two pictures** (:func:`lift_two_views`; after Shlyakhter, Rozenoer, Dorsey and Teller,
*Reconstructing 3D tree models from instrumented photographs*, 2001, who intersect the
views): the height is shared. The trunk (the branches of order 0) takes the side
trunk's depth at each point's own height. Each other visible branch of the front picture
is matched to one of the side picture's other branches (greedily, least cost first: the
difference of their bases' and tips' heights and lengths, as shares of the tree's height,
at most :data:`MATCH_COST`); a
matched branch takes the side branch's place (``z = -u``) at the same share of its
length, reached from its parent's end (the offset at its start fading linearly along
it), when that place lies within :data:`PLACE_REACH` of its length in the picture from
the parent's end; farther, the match is taken for wrong and the branch, like an
unmatched one, takes the prior's depth offsets (a short branch sent to a far side
branch's place became a long stroke in depth: the side view was horizontal hatching,
depths travelled 2-16 times the branches' length in the picture, and scored well at 256
px by filling the side silhouette). Then each branch's depths
are carved onto the side picture's skeleton (after the silhouette intersection of
Shlyakhter et al.): along the branch, every point may take the depth of a side-skeleton
point at its height or keep its guess (at a cost of :data:`OFF_SIDE` pixels), and the
path of least total change of depth from the branch's start is chosen (Viterbi), so the
side view's branches lie on the side picture's where the heights allow.

**One leafy picture** is read as its own side picture, mirrored (a crown looks much the
same from the side as from the front): a limb is matched as above to another limb and
runs in depth as that one runs across, from its parent's end.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from growsim.reconstruction.skeleton import Skeleton2D

__all__ = [
    "ALLOMETRY_QUANTILE",
    "ENVELOPE_BANDS",
    "ENVELOPE_CAP",
    "GOLDEN_ANGLE",
    "GUESS_WEIGHT",
    "MATCH_COST",
    "MAX_CANDIDATES",
    "OFF_SIDE",
    "PLACE_REACH",
    "TAN_CAP",
    "lift_prior",
    "lift_two_views",
    "to_world",
]

#: the golden angle (degrees): 360 (1 - 1 / phi)
GOLDEN_ANGLE = 360.0 * (1.0 - 2.0 / (1.0 + math.sqrt(5.0)))
#: the largest |tan(phi)| a horizontal run is stretched by into depth (80 degrees; tuned on
#: the discovery renders' side views, 1 to 8: more depth, better side views up to about 4)
TAN_CAP = math.tan(math.radians(80.0))
#: the bands of height in which one picture's crown is made as deep as it is wide, and
#: the most its depths are scaled by either way (both chosen on the discovery renders'
#: side views: 6-48 bands and caps 1.5-5 give 0.78-0.80 there)
ENVELOPE_BANDS = 24
ENVELOPE_CAP = 3.0
#: the allometric constant: this quantile of L / r^(2/3) over the visible axes
ALLOMETRY_QUANTILE = 0.75
#: the largest matching cost (shares of the height) of a front and a side branch
MATCH_COST = 0.6
#: carving a branch's depth onto the side skeleton: a point kept off it costs this many
#: pixels of depth change; at most this many side-skeleton depths looked at a point
OFF_SIDE = 3.0
#: ... and a side-skeleton depth this much a pixel of its distance from the guess
GUESS_WEIGHT = 1.0
MAX_CANDIDATES = 24
#: a matched branch takes the side branch's place only when it lies within this share of
#: the branch's length (in the picture) of the parent's end; else its run in depth
PLACE_REACH = 1.0


def to_world(sk: Skeleton2D, scale: float) -> list[np.ndarray]:
    """Each branch of ``sk`` as ``(k, 3)`` points ``(x, y, 0)`` in metres: ``x`` from the
    base's column, ``y`` up from the base's row, ``scale`` metres a pixel.

    Examples
    --------
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> from growsim.reconstruction.skeleton import extract_skeleton
    >>> to_world(extract_skeleton(m), 0.1)[0][0].tolist()
    [0.0, 0.0, 0.0]
    """
    r0, c0 = sk.base
    out = []
    for p in sk.branches:
        out.append(np.stack([(p[:, 1] - c0) * scale, (r0 - p[:, 0]) * scale,
                             np.zeros(len(p))], axis=1))  # fmt: skip
    return out


def _arc(p: np.ndarray) -> np.ndarray:
    """Cumulative length along a polyline (first 0)."""
    return np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))]


def _axes(sk: Skeleton2D) -> tuple[np.ndarray, np.ndarray]:
    """Each branch's axis id (a continuation shares its parent's) and each axis's first
    branch."""
    axis = np.zeros(len(sk.branches), np.int64)
    firsts = [0]
    for b in range(1, len(sk.branches)):
        p = sk.parent[b]
        if p >= 0 and sk.order[b] == sk.order[p]:
            axis[b] = axis[p]
        else:
            axis[b] = len(firsts)
            firsts.append(b)
    return axis, np.asarray(firsts)


def _axis_lengths(world, axis):
    n = int(axis.max()) + 1
    lengths = np.zeros(n)
    for b, p in enumerate(world):
        lengths[axis[b]] += _arc(p[:, :2])[-1]
    return lengths


def lift_prior(sk: Skeleton2D, world: list[np.ndarray], seed: int = 0):
    """Depth for one picture's branches ``world`` (:func:`to_world`) by the prior of the
    module docstring: ``(branches (k, 3) each, assumptions dict)``; the same for the same
    seed. A child starts where its parent ends (the tree stays connected).

    Examples
    --------
    >>> from growsim.reconstruction.skeleton import extract_skeleton
    >>> m = np.zeros((80, 60), bool); m[40:80, 28:33] = True
    >>> for i in range(30):
    ...     m[40 - i, 30 - i // 2 - 1: 30 - i // 2 + 2] = True
    ...     m[40 - i, 30 + i // 2 - 1: 30 + i // 2 + 2] = True
    >>> sk = extract_skeleton(m)
    >>> w = to_world(sk, 0.1)
    >>> lifted, why = lift_prior(sk, w, seed=0)
    >>> bool(all(np.allclose(a[:, :2], b[:, :2]) for a, b in zip(lifted, w)))  # front kept
    True
    >>> round(why["golden_angle_deg"], 3)
    137.508
    """
    axis, firsts = _axes(sk)
    phi0 = float(np.random.default_rng(seed).uniform(0.0, 360.0))
    # axes numbered from the ground up by their base's height
    base_y = np.array([world[b][0, 1] for b in firsts])
    rank = np.empty(len(firsts), np.int64)
    rank[np.argsort(base_y, kind="stable")] = np.arange(len(firsts))
    phi = np.radians(phi0 + rank * GOLDEN_ANGLE)
    lengths = _axis_lengths(world, axis)
    rad = np.array([float(sk.radii[b][0]) for b in firsts])
    lat = np.arange(len(firsts)) > 0
    ratio = lengths[lat] / np.maximum(rad[lat], 1e-9) ** (2.0 / 3.0)
    a = float(np.quantile(ratio, ALLOMETRY_QUANTILE)) if ratio.size else 0.0
    reach = max(max(float(np.abs(p[:, 0]).max()) for p in world), 1e-9)
    out: list[np.ndarray] = []
    for b, p in enumerate(world):
        q = p.copy()
        z0 = 0.0 if sk.parent[b] < 0 else float(out[sk.parent[b]][-1, 2])
        ax = axis[b]
        if sk.order[b] == 0:
            q[:, 2] = z0
        else:
            s, c = math.sin(phi[ax]), math.cos(phi[ax])
            run = abs(p[-1, 0] - p[0, 0]) * min(abs(s) / max(abs(c), 1e-9), TAN_CAP)
            seen = lengths[ax]
            allo = a * max(rad[ax], 1e-9) ** (2.0 / 3.0)
            hidden = min(math.sqrt(max(allo * allo - seen * seen, 0.0)), seen)
            arc = _arc(p[:, :2])
            share = arc[-1] / max(seen, 1e-12)  # this branch's share of its axis's length
            depth = max(run, hidden * share)
            dz = math.copysign(1.0, s) * depth * arc / max(arc[-1], 1e-12)
            # |z| < reach, smoothly: z = reach tanh(atanh(z0 / reach) + dz / reach)
            u0 = math.atanh(max(min(z0 / reach, 1.0 - 1e-9), -1.0 + 1e-9))
            q[:, 2] = reach * np.tanh(u0 + dz / reach)
            q[0, 2] = z0
        out.append(q)
    _round_crown(out)
    why = {
        "depth": "one view: golden-angle azimuths and allometric foreshortening, the "
        "crown as deep as it is wide at each height",
        "envelope_bands": ENVELOPE_BANDS,
        "envelope_cap": ENVELOPE_CAP,
        "golden_angle_deg": GOLDEN_ANGLE,
        "phi0_deg": phi0,
        "tan_cap": TAN_CAP,
        "allometry": "L = a r^(2/3) (elastic similarity)",
        "allometry_quantile": ALLOMETRY_QUANTILE,
        "allometry_a": a,
        "trunk_axis": "in the picture's plane",
        "depth_limit": "|z| < R = max |x| from the base: z = R tanh(atanh(z0/R) + dz/R)",
        "seed": int(seed),
    }
    return out, why


def _round_crown(branches: list[np.ndarray]) -> None:
    """Scale the depths ``z`` of ``branches`` (in place) so that in each band of height
    the deepest point in front of the picture's plane, and the deepest behind it, lie
    half the band's width away (the scale at most :data:`ENVELOPE_CAP` either way; 1 in a
    band with no depth on that side), interpolated in height between the bands' middles.

    Examples
    --------
    >>> b = [np.array([[-2.0, 0, 0], [2.0, 0, 0.5]]), np.array([[0.0, 0, 0], [0.5, 0, -1]])]
    >>> _round_crown(b)  # 4 wide: 0.5 in front scaled by 4, at most 3; 1 behind by 2
    >>> float(b[0][1, 2]), float(b[1][1, 2])
    (1.5, -2.0)
    """
    pts = np.concatenate(branches)
    top = max(float(pts[:, 1].max()), 1e-12)
    edges = np.linspace(0.0, top, ENVELOPE_BANDS + 1)
    band = np.minimum(np.searchsorted(edges, pts[:, 1], side="right") - 1, ENVELOPE_BANDS - 1)
    front, back = np.ones(ENVELOPE_BANDS), np.ones(ENVELOPE_BANDS)
    for i in range(ENVELOPE_BANDS):
        x, z = pts[band == i, 0], pts[band == i, 2]
        if x.size == 0:
            continue
        half = 0.5 * float(x.max() - x.min())
        if z.max() > 1e-12:
            front[i] = half / float(z.max())
        if z.min() < -1e-12:
            back[i] = half / float(-z.min())
    lo = 1.0 / ENVELOPE_CAP
    front, back = np.clip(front, lo, ENVELOPE_CAP), np.clip(back, lo, ENVELOPE_CAP)
    mids = 0.5 * (edges[1:] + edges[:-1])
    for q in branches:
        scale = np.where(q[:, 2] > 0, np.interp(q[:, 1], mids, front),
                         np.interp(q[:, 1], mids, back))  # fmt: skip
        q[:, 2] *= scale


def _pixel(world) -> float:
    """The front picture's pixel in metres: the median step along the polylines."""
    steps = np.concatenate([np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1) for p in world])
    steps = steps[steps > 0]
    return float(np.median(steps)) if steps.size else 1.0


def _carve(q: np.ndarray, z0: float, bins: dict, pix: float) -> np.ndarray:
    """Depths along a branch ``q`` (``(k, 3)``, its ``z`` the guess) that lie on the side
    picture's skeleton at each point's height where they can (``bins``: the side
    skeleton's depths ``-u`` by row of height ``pix``): the path of least total change of
    depth from ``z0`` (Viterbi), a point off the side skeleton (keeping its guess) costing
    :data:`OFF_SIDE` pixels."""
    guess = q[:, 2]
    z = np.empty(len(q))
    z[0] = z0
    cand_prev = np.array([z0])
    cost_prev = np.zeros(1)
    back: list[np.ndarray] = []
    cands: list[np.ndarray] = [cand_prev]
    for i in range(1, len(q)):
        r = round(float(q[i, 1]) / pix)
        found = [bins[k] for k in (r - 1, r, r + 1) if k in bins]
        side = np.unique(np.concatenate(found)) if found else np.zeros(0)
        if side.size > MAX_CANDIDATES:
            side = side[np.argsort(np.abs(side - guess[i]))[:MAX_CANDIDATES]]
        dg = guess[i] - guess[i - 1]
        # state 0 follows the guess's step from wherever the path was (off the side
        # skeleton, OFF_SIDE pixels a point); the others sit on a side-skeleton depth
        step_cost = np.empty((len(cand_prev), 1 + side.size))
        step_cost[:, 0] = abs(dg) + OFF_SIDE * pix
        step_cost[:, 1:] = np.abs(side[None, :] - cand_prev[:, None])
        step_cost[:, 1:] += GUESS_WEIGHT * np.abs(side - guess[i])[None, :]
        total = cost_prev[:, None] + step_cost
        arg = np.argmin(total, axis=0)
        cost_prev = total[arg, np.arange(1 + side.size)]
        cand = np.r_[cand_prev[arg[0]] + dg, side]
        back.append(arg)
        cands.append(cand)
        cand_prev = cand
    k = int(np.argmin(cost_prev))
    for i in range(len(q) - 1, 0, -1):
        z[i] = cands[i][k]
        k = int(back[i - 1][k])
    return z


def lift_two_views(sk: Skeleton2D, world, side: Skeleton2D, side_world, seed: int = 0,
                   *, same_picture: bool = False):  # fmt: skip
    """Depth for the front branches ``world`` from the side picture's branches
    ``side_world`` (both :func:`to_world`, at one scale: the height is shared), matched as
    the module docstring says; the unmatched ones by :func:`lift_prior`. Returns
    ``(branches, assumptions)``. ``same_picture``: the front picture stands for the side
    one (a leafy crown seen from one side): a front branch is never matched to its own,
    a matched branch takes the other's run in depth from its parent's end (its shape, not
    its place: placed, short branches became long strokes in depth), and nothing is
    carved.

    Examples
    --------
    >>> from growsim.reconstruction.skeleton import extract_skeleton
    >>> f = np.zeros((60, 40), bool); f[10:60, 19:22] = True
    >>> s = np.zeros((60, 40), bool)
    >>> for r in range(10, 60): s[r, 20 + (60 - r) // 5 - 1: 20 + (60 - r) // 5 + 2] = True
    >>> a, b = extract_skeleton(f), extract_skeleton(s)
    >>> lifted, why = lift_two_views(a, to_world(a, 1.0), b, to_world(b, 1.0))
    >>> why["matched"], round(float(lifted[-1][-1, 2]))     # leans away from the viewer
    (2, -11)
    """
    prior, why = lift_prior(sk, world, seed)
    height = max(max(float(p[:, 1].max()) for p in world), 1e-9)

    def key(p):
        arc = _arc(p[:, :2])
        return p[0, 1], p[-1, 1], arc[-1]

    keys = np.array([key(p) for p in side_world], dtype=np.float64).reshape(-1, 3)
    # the trunk: the front's order-0 branches take the side trunk's depth at their height
    trunk = [j for j in range(len(side_world)) if side.order[j] == 0]
    tp = np.concatenate([side_world[j] for j in trunk]) if trunk else np.zeros((0, 3))
    tp = tp[np.argsort(tp[:, 1], kind="stable")]
    used = np.zeros(len(side_world), dtype=bool)
    used[trunk] = True

    def cheapest(i: int):
        # front branch i's cheapest free side branch (least cost, then index), or None
        a0, a1, al = key(world[i])
        cost = np.abs(a0 - keys[:, 0]) + np.abs(a1 - keys[:, 1]) + np.abs(al - keys[:, 2])
        cost = cost / height
        cost[used | (cost > MATCH_COST)] = np.inf
        if same_picture and i < len(cost):
            cost[i] = np.inf
        j = int(np.argmin(cost)) if len(cost) else 0
        return None if not len(cost) or not np.isfinite(cost[j]) else (float(cost[j]), i, j)

    # the pairs taken greedily, least cost first (then the front's index, then the
    # side's): each front branch's cheapest free side branch in a heap, looked up again
    # when another took it
    heap = [c for i in range(len(world)) if not (sk.order[i] == 0 and len(tp))
            if (c := cheapest(i)) is not None]  # fmt: skip
    heapq.heapify(heap)
    match: dict[int, int] = {}
    while heap:
        _c, i, j = heapq.heappop(heap)
        if used[j]:
            if (c := cheapest(i)) is not None:
                heapq.heappush(heap, c)
            continue
        match[i] = j
        used[j] = True
    # the side picture's skeleton points by height (rows one front pixel high)
    pix = _pixel(world)
    sp = np.concatenate(side_world)
    bins: dict[int, np.ndarray] = {}
    rows = np.round(sp[:, 1] / pix).astype(np.int64)
    for r in np.unique(rows):
        bins[int(r)] = np.unique(np.round(-sp[rows == r, 0] / pix * 2) / 2 * pix)
    out: list[np.ndarray] = []
    for b, p in enumerate(world):
        z0 = 0.0 if sk.parent[b] < 0 else float(out[sk.parent[b]][-1, 2])
        arc = _arc(p[:, :2])
        t = arc / max(arc[-1], 1e-12)
        if sk.order[b] == 0 and len(tp):
            match[b] = trunk[0]
            q = p.copy()
            q[:, 2] = -np.interp(p[:, 1], tp[:, 1], tp[:, 0])
            q[:, 2] += (z0 - q[0, 2]) * (1.0 - t)
        elif b in match:
            s = side_world[match[b]]
            ts = _arc(s[:, :2])
            ts = ts / max(ts[-1], 1e-12)
            u = np.interp(t, ts, s[:, 0])
            q = p.copy()
            if same_picture:  # another limb's run in depth, from the parent's end
                q[:, 2] = z0 - (u - u[0])
            elif abs(z0 + u[0]) > PLACE_REACH * arc[-1]:
                # the side branch's place lies farther from the parent's end than the
                # branch can reach: a wrong match; the prior's depths
                q[:, 2] = z0 + (prior[b][:, 2] - prior[b][0, 2])
            else:  # the side branch's place (z = -u), reached from the parent's end: the
                # offset at the start fades along the branch
                q[:, 2] = -u + (z0 + u[0]) * (1.0 - t)
        else:
            q = p.copy()
            q[:, 2] = z0 + (prior[b][:, 2] - prior[b][0, 2])
        if not same_picture:  # onto the side picture's skeleton
            q[:, 2] = _carve(q, z0, bins, pix)
        # within the side picture's extent: a chain of unmatched branches cannot run away
        q[:, 2] = np.clip(q[:, 2], -sp[:, 0].max(), -sp[:, 0].min())
        out.append(q)
    why = {**why, "depth": "two views: branches matched by height, the rest by the prior",
           "side_extent": "every depth within the side picture's skeleton's extent",
           "matched": len(match), "unmatched": len(world) - len(match),
           "side_matched": sorted(int(j) for j in match.values()),
           "match_cost": MATCH_COST}  # fmt: skip
    return out, why
