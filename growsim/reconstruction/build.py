"""One picture's tree reconstructed as a growsim Plant: the visible skeleton
(:mod:`~growsim.reconstruction.skeleton`), lifted into 3D
(:mod:`~growsim.reconstruction.lift`), and, for a leafy crown, twigs and leaves grown
into the crown's envelope (:mod:`~growsim.reconstruction.colonize`).

**Bare or leafy** (``leafy=None``, :func:`crown_of`): the trunk's half-width ``r_t`` is
the largest radius (:func:`~growsim.reconstruction.skeleton.radius_map`) in the lowest
:data:`~growsim.objectives.silhouette.TRUNK_ROWS` of the rows; the mask opened by a disk
of radius ``r_t + 1`` keeps only what is thicker than the trunk: massed leaves. The crown
is leafy when that is at least :data:`LEAFY_SHARE` of the mask's area (on the
modular-tree renders, ``benchmarks/make_mtree.py``: bare trees 0-0.25 but one, leafy ones
0.4-0.65, thin weeping and conical leafage 0.03-0.2, which the bare reconstruction fits).

**Leafy crowns**: the crown is leaves: the limbs read inside it are at most
:data:`CROWN_LIMB` of the trunk's half-width thick; twigs and leaves are grown into the
crown's envelope (:func:`~growsim.reconstruction.colonize.colonize`). With one picture,
a leafy crown's limbs get their depth by the prior that its side looks like its front:
the front picture, mirrored, stands for the side picture
(:func:`~growsim.reconstruction.lift.lift_two_views`, a limb never matched to itself),
each limb placed in depth where another limb of its height and length lies across (on
the discovery renders' side views, blurred NCC at 64 px 0.83 by the golden-angle prior,
0.90 by this one; the bare trees' 0.78 either way, and the golden-angle prior is kept
for them).

**Scale**: ``height_m`` the tree's height in metres, else :data:`DEFAULT_HEIGHT`.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from growsim.objectives.silhouette import TRUNK_ROWS, plant_views
from growsim.phenotypes.plant import LEAF, Plant
from growsim.pictures.framing import picture_frame
from growsim.pictures.images import frame_silhouettes
from growsim.reconstruction.colonize import ColonizeSettings, colonize, envelope_points
from growsim.reconstruction.lift import lift_prior, lift_two_views, to_world
from growsim.reconstruction.skeleton import (
    SPUR_K,
    SPUR_PIXELS,
    Skeleton2D,
    base_point,
    check_mask,
    extract_skeleton,
    radius_map,
)

__all__ = [
    "CROWN_LIMB",
    "DEFAULT_HEIGHT",
    "LEAFY_SHARE",
    "METHOD",
    "SAMPLE_PIXELS",
    "Reconstruction",
    "crown_of",
    "placed",
    "reconstruct",
]

#: the tree's height when none is given (metres)
DEFAULT_HEIGHT = 10.0
#: a crown is leafy when the part of the mask thicker than the trunk is this share of it
LEAFY_SHARE = 0.3
#: in a leafy crown the limbs' radius is at most this share of the trunk's (the crown's
#: thickness in the picture is leaves)
CROWN_LIMB = 0.5
#: the polylines are kept one point every this many pixels (or the local radius, if more,
#: at most 3 times this)
SAMPLE_PIXELS = 1.0
#: what :func:`reconstruct` does, as ``fit.json`` names it
METHOD = "skeleton + space colonization"
#: the golden angle in radians (the leaves' turn about their twig)
_GOLDEN = math.radians(137.50776405003785)


@dataclass(frozen=True, eq=False)
class Reconstruction:
    """A tree reconstructed from its picture(s) (:func:`reconstruct`).

    ``plant``: the growsim :class:`~growsim.phenotypes.plant.Plant`; ``skeleton2d``: the
    visible branch graph in pixels of the front picture, one row per polyline piece
    (:meth:`~growsim.reconstruction.skeleton.Skeleton2D.segments`); ``assumptions``: every
    prior and setting used (JSON-able); ``method``; ``leafy``; ``skeleton``: the
    :class:`~growsim.reconstruction.skeleton.Skeleton2D`; ``crown``: the front mask's
    crown (leaves) or ``None``; ``scale``: metres a pixel.

    Examples
    --------
    >>> m = np.zeros((60, 40), bool); m[10:60, 18:23] = True
    >>> rec = reconstruct(m, height_m=5.0)
    >>> rec.method, rec.leafy, round(rec.plant.height(), 2)
    ('skeleton + space colonization', False, 5.0)
    """

    plant: Plant
    skeleton2d: pd.DataFrame
    assumptions: dict[str, Any]
    method: str
    leafy: bool
    skeleton: Skeleton2D
    crown: np.ndarray | None = field(default=None, repr=False)
    scale: float = 1.0

    def frame(self, mask, size: int, side=None) -> tuple[float, float, float]:
        """The front view's placement where the picture ``mask`` shows the tree, framed
        as :func:`~growsim.pictures.images.frame_silhouettes` frames it at ``size``
        (:func:`placed`): ``plant_views(rec.plant, size, views=1, frame=...)``."""
        return placed(mask, self.skeleton.base, self.scale, size, side)


def placed(mask, base, scale: float, size: int, side=None) -> tuple[float, float, float]:
    """``(u_base, y_min, k)`` for :func:`~growsim.objectives.silhouette.plant_views`'s
    ``frame``: a tree whose base is at pixel ``base`` ``(row, col)`` of ``mask``, ``scale``
    metres a pixel (as :func:`~growsim.reconstruction.lift.to_world` placed it), drawn
    where the picture shows it, framed as ``mask`` (with ``side``) is framed at ``size``
    (:func:`~growsim.pictures.framing.picture_frame`).

    Examples
    --------
    >>> m = np.zeros((101, 60), bool); m[0:101, 30] = True
    >>> placed(m, (100.0, 30.0), 0.1, 64)   # the base on the bottom row's centre
    (0.0, 0.0, 6.3)
    """
    col, rmax, f = picture_frame(mask, side, size)
    r0, c0 = base
    return ((col - c0 - 0.5) * scale, (r0 - rmax) * scale, f / scale)


def crown_of(mask: np.ndarray) -> tuple[np.ndarray, float, float]:
    """``(crown, share, trunk_radius)``: the part of ``mask`` thicker than its trunk (the
    mask opened by a disk of the trunk's half-width plus a pixel), its share of the mask's
    area, and the trunk's half-width in pixels (module docstring).

    Examples
    --------
    >>> m = np.zeros((60, 60), bool); m[30:60, 28:32] = True; m[5:32, 10:50] = True
    >>> crown, share, r = crown_of(m)
    >>> round(share, 2), r, bool(crown[10, 30]), bool(crown[50, 30])
    (0.89, 1.5, True, False)
    """
    from scipy import ndimage
    from skimage.morphology import disk

    rows = np.flatnonzero(mask.any(axis=1))
    n = max(1, round(TRUNK_ROWS * (rows.max() - rows.min() + 1)))
    radius = radius_map(mask)
    r_t = float(radius[rows.max() - n + 1 : rows.max() + 1].max())
    crown = ndimage.binary_opening(mask, structure=disk(round(r_t) + 1))
    return crown, float(crown.sum()) / max(float(mask.sum()), 1.0), r_t


def _sample(points: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Indices of the polyline's points kept: the first, the last, and one every
    ``max(SAMPLE_PIXELS, radius)`` pixels (at most 3 x SAMPLE_PIXELS) between."""
    keep = [0]
    acc = 0.0
    step = np.linalg.norm(np.diff(points, axis=0), axis=1)
    for i in range(1, len(points) - 1):
        acc += step[i - 1]
        if acc >= min(max(SAMPLE_PIXELS, radii[i]), 3 * SAMPLE_PIXELS):
            keep.append(i)
            acc = 0.0
    if len(points) > 1:
        keep.append(len(points) - 1)
    return np.asarray(keep)


def _visible_plant(sk: Skeleton2D, lifted: list[np.ndarray], scale: float):
    """The visible branches as point arrays: ``(points, point_parent, seg_radius,
    seg_order, seg_of_point)``; point 0 is the base."""
    pts = [lifted[0][0]]
    pparent = [-1]
    seg_r: list[float] = []
    seg_o: list[int] = []
    end_point = {}  # branch -> index of its last point
    for b, (q, r) in enumerate(zip(lifted, sk.radii)):
        keep = _sample(sk.branches[b], r)
        prev = 0 if sk.parent[b] < 0 else end_point[int(sk.parent[b])]
        for a, i in itertools.pairwise(keep):
            pts.append(q[i])
            pparent.append(prev)
            seg_r.append(float(r[a]) * scale)
            seg_o.append(int(sk.order[b]))
            prev = len(pts) - 1
        end_point[b] = prev
    pts_a = np.asarray(pts)
    pp = np.asarray(pparent, np.int64)
    return pts_a, pp, np.asarray(seg_r), np.asarray(seg_o, np.int32)


#: the leaves a grown node may carry when ``ColonizeSettings.leaves`` is ``None``: the
#: count whose front view covers the picture's area best is kept
LEAF_COUNTS = (1, 2, 3, 4)


def _leaves(g, par_pos, gseg, gorder, per: int, height: float, seed: int, settings):
    """The leaves on the grown twigs' nodes, ``per`` a node, turned by the golden angle:
    their segments' ``(start, end, radius, parent, order, kind)``."""
    k = len(g.nodes)
    ll = settings.leaf_length * height
    if per <= 0 or ll <= 0 or k == 0:
        e = np.zeros(0)
        return (np.zeros((0, 3)), np.zeros((0, 3)), e, e.astype(np.int64),
                e.astype(np.int32), e.astype(np.int8))  # fmt: skip
    rng = np.random.default_rng(seed + 1)
    host = np.repeat(np.arange(k), per)
    d = g.nodes[host] - par_pos[host]
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    turn = _GOLDEN * np.arange(host.size) + rng.uniform(0, 2 * np.pi)
    tilt = np.radians(rng.uniform(30.0, 70.0, host.size))
    horiz = np.stack([np.cos(turn), np.zeros(host.size), np.sin(turn)], axis=1)
    leaf_dir = np.cos(tilt)[:, None] * horiz + np.sin(tilt)[:, None] * np.array([0.0, 1.0, 0.0])
    leaf_dir = 0.6 * leaf_dir + 0.4 * d
    leaf_dir /= np.maximum(np.linalg.norm(leaf_dir, axis=1, keepdims=True), 1e-12)
    return (g.nodes[host], g.nodes[host] + ll * leaf_dir,
            np.full(host.size, 0.5 * settings.leaf_width * ll), gseg[host],
            gorder[host] + 1, np.full(host.size, LEAF, np.int8))  # fmt: skip


def _leaf_count(leaves, mask, parts, grown, height, seed, settings, frame):
    """``(count, why)``: ``leaves`` if given, else the count of :data:`LEAF_COUNTS` whose
    Plant's front view (drawn where the picture shows it, ``frame``, :func:`placed`, at
    256 px) has the area nearest the picture's (the ratio nearest 1 in log terms): a crown
    as dense as the picture shows it."""
    if leaves is not None:
        return int(leaves), f"{int(leaves)}, given"
    target = float(frame_silhouettes(mask, None, 256, "radius").sum())
    ratios = {}
    for per in LEAF_COUNTS:
        cols = [list(x) for x in parts]
        for part, arr in zip(cols, _leaves(*grown, per, height, seed, settings)):
            part.append(arr)
        plant = Plant(*(np.concatenate(c) for c in cols))
        drawn = plant_views(plant, 256, "radius", views=1, frame=frame)
        ratios[per] = float(drawn.sum()) / max(target, 1.0)
    per = min(LEAF_COUNTS, key=lambda n: (abs(math.log(max(ratios[n], 1e-9))), n))
    return per, (
        f"{per}: of {list(LEAF_COUNTS)}, the front area nearest the picture's "
        f"(area ratios {', '.join(f'{n}: {r:.2f}' for n, r in ratios.items())})"
    )


def reconstruct(front_mask, side_mask=None, *, height_m: float | None = None,
                leafy: bool | None = None, seed: int = 0,
                settings: ColonizeSettings | None = None) -> Reconstruction:  # fmt: skip
    """The tree of ``front_mask`` (2D bool, True the tree, row 0 at the top, the base at
    the bottom; ``side_mask`` the same tree seen from its right, optional) as a growsim
    Plant: its visible skeleton kept (the front view as the picture shows it), depth from
    the side picture or the one-picture prior, and for a leafy crown (``leafy=None``:
    decided from the mask, :func:`crown_of`) twigs and leaves grown into the crown's
    envelope by space colonization (``settings``). ``height_m``: the tree's height in
    metres (else :data:`DEFAULT_HEIGHT`). The same result for the same seed.

    Examples
    --------
    >>> m = np.zeros((80, 60), bool); m[40:80, 28:33] = True
    >>> for i in range(30):
    ...     m[40 - i, 30 - i // 2 - 1: 30 - i // 2 + 2] = True
    ...     m[40 - i, 30 + i // 2 - 1: 30 + i // 2 + 2] = True
    >>> rec = reconstruct(m, height_m=8.0)
    >>> rec.plant.n_tips, int((rec.plant.parent < 0).sum()), rec.assumptions["leafy_rule"][:4]
    (2, 1, 'mask')
    """
    m = check_mask(front_mask, "front_mask")
    side = None if side_mask is None else check_mask(side_mask, "side_mask")
    settings = ColonizeSettings() if settings is None else settings
    crown, share, r_t = crown_of(m)
    decided = leafy is None
    is_leafy = bool(share >= LEAFY_SHARE) if decided else bool(leafy)
    sk = extract_skeleton(m, crown=crown if is_leafy else None,
                          crown_radius=CROWN_LIMB * r_t)  # fmt: skip
    height = float(height_m) if height_m is not None else DEFAULT_HEIGHT
    scale = height / sk.height
    world = to_world(sk, scale)
    if side is None and is_leafy:
        # a leafy crown seen from the side looks like it does from the front: each limb
        # runs in depth as another limb of its height and length runs across
        mirrored = [p * np.array([-1.0, 1.0, 1.0]) for p in world]
        lifted, why, _ = lift_two_views(sk, world, sk, mirrored, seed, same_picture=True)
        why = {
            **why,
            "depth": "one leafy view: limbs run in depth as other limbs of their height "
            "run across (the side seen as the front), the rest by the prior",
        }
        side_sk = None
        seen = sk
    elif side is None:
        lifted, why = lift_prior(sk, world, seed)
        side_sk = None
        seen = sk
    else:
        side_sk = extract_skeleton(side)
        side_world = to_world(side_sk, height / side_sk.height)
        # the tree seen: the front's branches and the side's hidden in the front picture
        lifted, why, seen = lift_two_views(sk, world, side_sk, side_world, seed)
    pts, pp, seg_r, seg_o = _visible_plant(seen, lifted, scale)
    n_vis = len(seg_r)
    grown = None
    if is_leafy and crown.any():
        sbase = None
        scrown = None
        if side is not None:
            scrown = crown_of(side)[0]
            sb = base_point(side)
            sbase = (sb[0], sb[1])
            # the side picture at the front's scale: same height in pixels
            f = sk.height / sb[2]
            if abs(f - 1.0) > 1e-6:
                from skimage.transform import rescale

                scrown = rescale(scrown.astype(float), f, order=0) > 0.5
                sbase = (sb[0] * f, sb[1] * f)
        attract = envelope_points(crown, scale, sk.base, settings.points, seed, scrown, sbase)
        # every visible point but the base may sprout; its radius: the segment ending there
        grown = colonize(pts[1:], seg_r, attract, height, settings)
    start = [pts[pp[1:]]]
    end = [pts[1:]]
    radius = [seg_r]
    parent_seg = [pp[1:] - 1]  # the segment ending at a point is point - 1
    order = [seg_o]
    kind = [np.zeros(n_vis, np.int8)]
    if grown is not None and len(grown.nodes):
        g = grown
        k = len(g.nodes)
        gseg = n_vis + np.arange(k)
        # a new node's parent segment: a visible point's segment, or a new node's
        par_seg = np.where(g.parent >= 0, n_vis + g.parent, -1 - g.parent)
        par_pos = np.where(g.parent[:, None] >= 0, g.nodes[np.maximum(g.parent, 0)],
                           pts[1:][np.maximum(-1 - g.parent, 0)])  # fmt: skip
        gorder = np.zeros(k, np.int32)
        kids = np.zeros(n_vis + k, np.int64)
        for i in range(k):
            ps = par_seg[i]
            po = seg_o[ps] if ps < n_vis else gorder[ps - n_vis]
            first_child = kids[ps] == 0 and ps >= n_vis
            gorder[i] = po if first_child else po + 1
            kids[ps] += 1
        start.append(par_pos)
        end.append(g.nodes)
        radius.append(g.radius)
        parent_seg.append(par_seg)
        order.append(gorder)
        kind.append(np.zeros(k, np.int8))
        parts = (start, end, radius, parent_seg, order, kind)
        twigs = (g, par_pos, gseg, gorder)
        frame = placed(m, sk.base, scale, 256)
        per, leaf_why = _leaf_count(settings.leaves, m, parts, twigs, height, seed, settings,
                                    frame)  # fmt: skip
        for part, arr in zip(parts, _leaves(*twigs, per, height, seed, settings)):
            part.append(arr)
    else:
        leaf_why = None
    assumptions = {
        "method": METHOD,
        "seed": int(seed),
        "height_m": height,
        "height_given": height_m is not None,
        "scale_m_per_px": scale,
        "leafy": is_leafy,
        "leafy_rule": (
            f"mask thicker than the trunk (r_t + 1 = {r_t + 1:.1f} px opening) "
            f"{share:.3f} of the area, leafy at >= {LEAFY_SHARE}"
            if decided
            else "given"
        ),
        "leafy_share": share,
        "skeleton": {
            "connect": "skeletonize; pieces bridged nearest first (BRIDGE_REACH of the height)",
            "spur_rule": f"spur < {SPUR_K} x junction radius + {SPUR_PIXELS} px",
            "radius": "distance transform - 0.5 px, median of 5, non-increasing, pipe model",
            "branches": len(sk.branches),
            "side_branches": None if side_sk is None else len(side_sk.branches),
        },
        "lift": why,
        "colonization": None
        if grown is None
        else {
            **settings.record(),
            "iterations_done": grown.iterations,
            "points_left": grown.points_left,
            "nodes_grown": len(grown.nodes),
            "envelope": "crown mask swept by revolution about each row's centre"
            + ("" if side is None else ", cut by the side view's sweep"),
            "leaves_per_node": leaf_why,
        },
    }
    plant = Plant(
        np.concatenate(start),
        np.concatenate(end),
        np.concatenate(radius),
        np.concatenate(parent_seg),
        np.concatenate(order),
        np.concatenate(kind),
        meta={"model": "reconstruction", "method": METHOD, "seed": int(seed)},
    )
    return Reconstruction(
        plant=plant,
        skeleton2d=sk.segments(),
        assumptions=assumptions,
        method=METHOD,
        leafy=is_leafy,
        skeleton=sk,
        crown=crown if is_leafy else None,
        scale=scale,
    )
