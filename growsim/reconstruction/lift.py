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
views): the height is shared.

1. *Guesses.* The trunk (the branches of order 0) takes the side trunk's depth at each
   point's own height. Each other visible branch of the front picture is matched to one
   of the side picture's other branches (greedily, least cost first: the difference of
   their bases' and tips' heights and lengths, as shares of the tree's height, at most
   :data:`MATCH_COST`); a matched branch guesses the side branch's place (``z = -u``) at
   the same share of its length, reached from its parent's end (the offset fading along
   it), when that place lies within :data:`PLACE_REACH` of its length in the picture from
   the parent's end; else, like an unmatched branch, the prior's depth offsets.
2. *Carving* (:func:`growsim.kernels.carve.carve_depth`, after the silhouette
   intersection of Shlyakhter et al.). Each point of a branch takes the depth of a
   side-skeleton pixel in its row (or its guess, off the skeleton): the path of least
   cost from the parent's end, by dynamic programming (Viterbi), where a step pays
   :data:`SLIDE` a pixel of depth change and :data:`STEEP` more a pixel beyond its length
   in the front picture (a branch turns no more than 45 degrees out of the picture's plane
   for free: a step that sweeps along the side picture's rows drew horizontal hatching),
   :data:`OUTSIDE` a pixel drawn outside the side silhouette, :data:`THICKNESS` a pixel of
   radius unlike the side skeleton's there (a branch is as thick in both pictures), and
   each side-skeleton pixel that no branch covers yet earns :data:`COVER`: the side
   picture's branches are shared out among the front's rather than all piled onto the
   trunk. The branches are carved parents first, :data:`CARVE_PASSES` times, each against
   the others' coverage as it stands (a negotiation, as routers share out wires).
3. *Hidden branches.* A branch running towards the viewer hides in the front picture
   behind the trunk or a limb but shows in the side picture. A side branch whose skeleton
   pixels the carved tree covers less than :data:`HIDDEN_BELOW` of is grafted where it
   leaves the tree in the side picture: its depth the side's, its run across carved
   inside the front silhouette (:func:`growsim.kernels.carve.carve_across`), cut where a
   step would draw more than :data:`GRAFT_GAP` pixels outside it; the branch it leaves
   is split there. The front view gains no pixel outside the picture.

**One leafy picture** is read as its own side picture, mirrored (a crown looks much the
same from the side as from the front): a limb is matched as above to another limb and
runs in depth as that one runs across, from its parent's end.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

from growsim.kernels.carve import carve_across, carve_depth
from growsim.reconstruction.skeleton import Skeleton2D

__all__ = [
    "ALLOMETRY_QUANTILE",
    "CARVE_PASSES",
    "COVER",
    "ENVELOPE_BANDS",
    "ENVELOPE_CAP",
    "GOLDEN_ANGLE",
    "GRAFT_GAP",
    "GUESS_WEIGHT",
    "HIDDEN_BELOW",
    "MATCH_COST",
    "MAX_CANDIDATES",
    "OFF_SIDE",
    "OUTSIDE",
    "PLACE_REACH",
    "SLIDE",
    "TAN_CAP",
    "THICKNESS",
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
#: a matched branch takes the side branch's place only when it lies within this share of
#: the branch's length (in the picture) of the parent's end; else its run in depth
PLACE_REACH = 1.0
#: carving a branch's depth onto the side picture, in pixels of the front picture: a
#: pixel of depth change costs SLIDE, and STEEP more beyond the step's length in the
#: front picture (STEEP = COVER: sweeping along a row never pays for itself), a pixel
#: drawn outside the side silhouette OUTSIDE, a pixel of radius unlike the side
#: skeleton's THICKNESS, a pixel from the guess GUESS_WEIGHT, a point off the side
#: skeleton OFF_SIDE; each side-skeleton pixel no branch covers yet earns COVER. At most
#: MAX_CANDIDATES side columns (the nearest the guess) at a point; every branch carved
#: CARVE_PASSES times. Chosen on the 12 discovery renders' side views and the depth of
#: Honda trees seen from two sides (benchmarks/log/fitting.md)
SLIDE = 0.1
STEEP = 2.0
OUTSIDE = 3.0
COVER = 2.0
THICKNESS = 0.3
GUESS_WEIGHT = 0.05
OFF_SIDE = 3.0
MAX_CANDIDATES = 48
CARVE_PASSES = 3
#: a side branch whose skeleton pixels are covered less than this share is hidden in the
#: front picture and grafted on; its run across stops where a step draws more than
#: GRAFT_GAP pixels outside the front silhouette
HIDDEN_BELOW = 0.7
GRAFT_GAP = 2.0


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


def _raster(rows, cols, radii, shape):
    """A skeleton's pixels ``(rows, cols)`` (int arrays, inside ``shape``) with their
    ``radii``: ``(silhouette, skeleton_radius)``, the silhouette the union of the points'
    discs (at least one pixel), the radius the largest at each skeleton pixel (at least
    0.5; 0 off the skeleton)."""
    import cv2

    sil = np.zeros(shape, np.uint8)
    for r, c, rad in zip(rows.tolist(), cols.tolist(), radii.tolist()):
        cv2.circle(sil, (c, r), round(max(rad, 0.5)), 1, -1)
    skel = np.zeros(shape)
    np.maximum.at(skel, (rows, cols), np.maximum(radii, 0.5))
    return sil.astype(bool) | (skel > 0), skel


def _csr(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A mask's pixels by row: ``(ptr, cols)``, row ``r``'s columns ``cols[ptr[r]:ptr[r+1]]``."""
    r, c = np.nonzero(mask)
    ptr = np.zeros(mask.shape[0] + 1, np.int64)
    np.cumsum(np.bincount(r, minlength=mask.shape[0]), out=ptr[1:])
    return ptr, c.astype(np.int64)


def _outside_cum(sil: np.ndarray) -> np.ndarray:
    """Each row's running count of pixels outside ``sil`` (first column 0)."""
    out = np.zeros((sil.shape[0], sil.shape[1] + 1))
    np.cumsum(~sil, axis=1, out=out[:, 1:])
    return out


def _cover(cover, rows, cols, radii, sign: int) -> None:
    """Add ``sign`` to ``cover`` where a branch drawn through the pixels ``(rows, cols)``
    (float columns) with ``radii`` lies: each step's span in its row, widened by the
    radius."""
    ncols = cover.shape[1]
    prev = cols[0]
    for r, c, rad in zip(rows.tolist(), cols.tolist(), radii.tolist()):
        w = max(rad, 0.5)
        a0 = max(math.floor(min(prev, c) - w + 0.5), 0)
        a1 = min(math.ceil(max(prev, c) + w - 0.5) + 1, ncols)
        if a1 > a0:
            cover[r, a0:a1] += sign
        prev = c


def _carve_params() -> np.ndarray:
    return np.array([SLIDE, OUTSIDE, COVER, GUESS_WEIGHT, THICKNESS, OFF_SIDE, MAX_CANDIDATES,
                     STEEP], np.float64)  # fmt: skip


def _graft_hidden(sk: Skeleton2D, out, side: Skeleton2D, side_world, side_grid, pix):
    """The side picture's branches that no front branch covers (hidden in the front
    picture behind others, as a limb running towards the viewer hides in the trunk), each
    grafted onto the tree where it leaves it in the side picture: its depth the side
    picture's, its run across carved inside the front silhouette (:func:`carve_across`),
    cut where it would leave it by more than :data:`GRAFT_GAP` pixels. Returns ``(sk,
    branches, grafted)``: the skeleton with the grafted branches (a branch they leave
    from split there), in order parents first."""
    cover, c_off, nrows, ncols, _ = side_grid
    r0, c0 = sk.base
    br = [np.asarray(b, np.float64) for b in sk.branches]
    rad = [np.asarray(r, np.float64) for r in sk.radii]
    par = [int(x) for x in sk.parent]
    order = [int(x) for x in sk.order]
    lifted = [q.copy() for q in out]
    # the front silhouette, drawn from the front skeleton's discs
    allp = np.concatenate(lifted)
    f_off = int(-np.floor(allp[:, 0].min() / pix)) + 8
    fcols = int(np.ceil(allp[:, 0].max() / pix)) + f_off + 8
    frows = np.clip(np.round(allp[:, 1] / pix).astype(np.int64), 0, nrows - 1)
    fc = np.round(allp[:, 0] / pix).astype(np.int64) + f_off
    sil, _ = _raster(frows, fc, np.concatenate(rad), (nrows, fcols))
    fgrid = (*_csr(sil), _outside_cum(sil))
    params = np.array([SLIDE, OUTSIDE, GRAFT_GAP], np.float64)
    # every point of the tree: its branch and its index there (the attachments' search)
    owner = np.concatenate([np.full(len(q), b) for b, q in enumerate(lifted)])
    index = np.concatenate([np.arange(len(q)) for q in lifted])
    spix = _pixel(side_world)
    grafted = 0
    for j, s in enumerate(side_world):
        rows = np.clip(np.round(s[:, 1] / pix).astype(np.int64), 0, nrows - 1)
        cc = np.clip(np.round(-s[:, 0] / pix).astype(np.int64) + c_off, 0, ncols - 1)
        if len(s) < 4 or (cover[rows, cc] > 0).mean() >= HIDDEN_BELOW:
            continue
        srad = np.asarray(side.radii[j], np.float64) * spix / pix
        near = np.flatnonzero(np.abs(allp[:, 1] - s[0, 1]) <= 1.5 * pix)
        if not near.size:
            continue
        k = int(near[np.argmin(np.abs(allp[near, 2] + s[0, 0]))])
        if abs(allp[k, 2] + s[0, 0]) > max(3.0, float(srad[0])) * pix:
            continue
        b, i = int(owner[k]), int(index[k])
        x, kept = carve_across((rows, srad), float(allp[k, 0] / pix + f_off), fgrid, params)
        if kept < 3:
            continue
        q = np.stack([(x[:kept] - f_off) * pix, s[:kept, 1], -s[:kept, 0]], axis=1)
        q[0] = allp[k]
        if 0 < i < len(lifted[b]) - 1:  # split b where the hidden branch leaves it
            nb = len(br)
            for name, arr in ((br, br[b]), (rad, rad[b]), (lifted, lifted[b])):
                name.append(arr[i:].copy())
                name[b] = arr[: i + 1]
            par = [nb if p == b else p for p in par]
            par.append(b)
            order.append(order[b])
            moved = (owner == b) & (index > i)
            owner[moved], index[moved] = nb, index[moved] - i
            host = b
        elif i == 0 and par[b] >= 0:
            host = par[b]
        elif i == 0:
            continue
        else:
            host = b
        br.append(np.stack([r0 - q[:, 1] / pix, c0 + q[:, 0] / pix], axis=1))
        rad.append(np.minimum(srad[:kept], rad[host][-1]))
        par.append(host)
        order.append(order[host] + 1)
        lifted.append(q)
        allp = np.concatenate([allp, q[1:]])
        owner = np.r_[owner, np.full(kept - 1, len(br) - 1)]
        index = np.r_[index, np.arange(1, kept)]
        _cover(cover, rows[:kept], -s[:kept, 0] / pix + c_off, srad[:kept], 1)
        grafted += 1
    # parents first (depth first from the root, children in order)
    kids: list[list[int]] = [[] for _ in br]
    roots = []
    for b, p in enumerate(par):
        (roots if p < 0 else kids[p]).append(b)
    seq: list[int] = []
    stack = roots[::-1]
    while stack:
        b = stack.pop()
        seq.append(b)
        stack.extend(kids[b][::-1])
    new = {old: n for n, old in enumerate(seq)}
    out_sk = Skeleton2D(
        branches=tuple(br[o] for o in seq),
        radii=tuple(rad[o] for o in seq),
        parent=np.array([-1 if par[o] < 0 else new[par[o]] for o in seq], np.int64),
        order=np.array([order[o] for o in seq], np.int64),
        base=sk.base,
        height=sk.height,
        shape=sk.shape,
    )
    return out_sk, [lifted[o] for o in seq], grafted


def lift_two_views(sk: Skeleton2D, world, side: Skeleton2D, side_world, seed: int = 0,
                   *, same_picture: bool = False):  # fmt: skip
    """Depth for the front branches ``world`` from the side picture's branches
    ``side_world`` (both :func:`to_world`, at one scale: the height is shared), matched as
    the module docstring says; the unmatched ones by :func:`lift_prior`. Returns
    ``(branches, assumptions, seen)``: ``seen`` the skeleton of ``branches``, ``sk`` with
    the side picture's hidden branches grafted on. ``same_picture``: the front picture
    stands for the side one (a leafy crown seen from one side): a front branch is never
    matched to its own, a matched branch takes the other's run in depth from its
    parent's end (its shape, not its place: placed, short branches became long strokes
    in depth), and nothing is carved or grafted (``seen`` is ``sk``).

    Examples
    --------
    >>> from growsim.reconstruction.skeleton import extract_skeleton
    >>> f = np.zeros((60, 40), bool); f[10:60, 19:22] = True
    >>> s = np.zeros((60, 40), bool)
    >>> for r in range(10, 60): s[r, 20 + (60 - r) // 5 - 1: 20 + (60 - r) // 5 + 2] = True
    >>> a, b = extract_skeleton(f), extract_skeleton(s)
    >>> lifted, why, seen = lift_two_views(a, to_world(a, 1.0), b, to_world(b, 1.0))
    >>> why["matched"], round(float(lifted[-1][-1, 2]))     # leans away from the viewer
    (2, -10)
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
    # the guesses: the matched side branches' places, the prior for the rest
    side_x = np.concatenate(side_world)[:, 0]
    guess: list[np.ndarray] = []
    for b, p in enumerate(world):
        z0 = 0.0 if sk.parent[b] < 0 else float(guess[sk.parent[b]][-1, 2])
        arc = _arc(p[:, :2])
        t = arc / max(arc[-1], 1e-12)
        q = p.copy()
        if sk.order[b] == 0 and len(tp):
            match[b] = trunk[0]
            q[:, 2] = -np.interp(p[:, 1], tp[:, 1], tp[:, 0])
            q[:, 2] += (z0 - q[0, 2]) * (1.0 - t)
        elif b in match:
            s = side_world[match[b]]
            ts = _arc(s[:, :2])
            ts = ts / max(ts[-1], 1e-12)
            u = np.interp(t, ts, s[:, 0])
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
            q[:, 2] = z0 + (prior[b][:, 2] - prior[b][0, 2])
        # within the side picture's extent: a chain of unmatched branches cannot run away
        q[:, 2] = np.clip(q[:, 2], -side_x.max(), -side_x.min())
        guess.append(q)
    why = {**why, "depth": "two views: branches matched by height, the rest by the prior",
           "side_extent": "every depth within the side picture's skeleton's extent",
           "matched": len(match), "unmatched": len(world) - len(match),
           "side_matched": sorted(int(j) for j in match.values()),
           "match_cost": MATCH_COST}  # fmt: skip
    if same_picture:
        return guess, why, sk
    out, side_grid = _carve_all(sk, world, guess, side, side_world)
    sk2, out, grafted = _graft_hidden(sk, out, side, side_world, side_grid, _pixel(world))
    cover, skel = side_grid[0], side_grid[4]
    why = {**why,
           "depth": "two views: branches matched by height, their depths carved onto the "
           "side picture's skeleton (its pixels covered once where the heights allow), the "
           "side's branches hidden in the front picture grafted on",
           "carve": {"slide": SLIDE, "steep": STEEP, "outside": OUTSIDE, "cover": COVER,
                     "thickness": THICKNESS, "guess_weight": GUESS_WEIGHT,
                     "off_side": OFF_SIDE, "passes": CARVE_PASSES},
           "grafted": grafted, "hidden_below": HIDDEN_BELOW, "graft_gap": GRAFT_GAP,
           "side_covered": float((cover[skel] > 0).mean()) if skel.any() else 0.0}  # fmt: skip
    return out, why, sk2


def _carve_all(sk: Skeleton2D, world, guess, side: Skeleton2D, side_world):
    """Each front branch's depth carved onto the side picture (:func:`carve_depth`),
    parents first, :data:`CARVE_PASSES` times (each branch carved again with the others'
    coverage as it stands: the side picture's pixels shared out). Returns ``(branches,
    (cover, column offset, rows, columns, side skeleton mask))``."""
    pix = _pixel(world)
    spix = _pixel(side_world)
    sp = np.concatenate(side_world)
    srad = np.concatenate([np.asarray(r, np.float64) for r in side.radii]) * spix / pix
    rows = np.round(sp[:, 1] / pix).astype(np.int64)
    cols = np.round(-sp[:, 0] / pix).astype(np.int64)
    pad = 8
    c_off = int(-cols.min()) + pad
    top = max(float(p[:, 1].max()) for p in world) / pix
    nrows = int(max(rows.max(), top)) + pad
    ncols = int(cols.max()) + c_off + pad
    rows = np.clip(rows, 0, nrows - 1)
    sil, skel_r = _raster(rows, cols + c_off, srad, (nrows, ncols))
    grid = (*_csr(skel_r > 0), _outside_cum(sil), skel_r)
    cover = np.zeros((nrows, ncols), np.int32)
    params = _carve_params()
    zmin, zmax = -float(sp[:, 0].max()), -float(sp[:, 0].min())
    frad = [np.asarray(r, np.float64) for r in sk.radii]
    brows = [np.clip(np.round(p[:, 1] / pix).astype(np.int64), 0, nrows - 1) for p in world]
    steps = [np.r_[0.0, np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1) / pix] for p in world]
    out: list[np.ndarray] = [p.copy() for p in world]
    drawn: list[np.ndarray | None] = [None] * len(world)
    for _ in range(CARVE_PASSES):
        for b in range(len(world)):
            if drawn[b] is not None:
                _cover(cover, brows[b], drawn[b], frad[b], -1)
            z0 = 0.0 if sk.parent[b] < 0 else float(out[sk.parent[b]][-1, 2])
            branch = (brows[b], guess[b][:, 2] / pix + c_off, frad[b], steps[b])
            z = carve_depth(branch, z0 / pix + c_off, grid, cover, params)
            z = np.clip((z - c_off) * pix, zmin, zmax)
            out[b][:, 2] = z
            drawn[b] = z / pix + c_off
            _cover(cover, brows[b], drawn[b], frad[b], 1)
    return out, (cover, c_off, nrows, ncols, skel_r > 0)
