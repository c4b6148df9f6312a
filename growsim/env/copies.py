"""The light of plants among copies of themselves (a periodic stand): each plant's
shadow map holds the plant and its copies moved by the stand's offsets, and only the
plant's own points are judged (:func:`growsim.env.light.segment_light` with ``shifts``).
"""

from __future__ import annotations

import numpy as np

from growsim.env.shadow_gl import segment_exposure_gl
from growsim.kernels import light as kernels

__all__ = ["copies_exposure", "copies_frames"]


def copies_exposure(segments, shifts, plane, samples, shadow, trans, backend, scratch):
    """``(n,)`` each segment's exposure (mean over its samples) in its plant's map, the
    plant joined by its copies moved by ``shifts`` ``(k, 3)``: plant ``p``'s block of the
    map's segments is the plant, then each copy in turn (the copies' segments in the
    plant's order), and only the plant's own samples are judged (each owned by its
    segment, as :func:`segment_light` judges them). ``shadow`` ``(res, bias, soft)``;
    ``trans`` the plant's per-segment transmissions when soft; ``scratch`` a
    :func:`growsim.kernels.light.shadow_scratch` of ``res``.

    The map is framed over the plant and all its copies (:func:`copies_frames`: the frame
    :func:`growsim.kernels.light.plant_frames` gives them all), then a copy whose shadow's
    bounding box (its axes' widened by its largest radius and a pixel) misses the plant's
    samples is left out: its capsules cover no pixel holding a sample (a capsule covers a
    pixel only when it holds the pixel's centre), so the answers are those of the whole
    stand of copies, bit for bit, at the cost of the copies that can shade the plant.

    Examples
    --------
    >>> from growsim.kernels.light import shadow_scratch
    >>> seg = (np.array([[0.0, 0, 0]]), np.array([[0.0, 1, 0]]), np.array([0.1]),
    ...        np.array([0, 1]))
    >>> plane = (np.array([1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([0, -1.0, 0]))
    >>> above = np.array([[0.0, 2.0, 0.0]])  # a copy 2 m above shades it
    >>> copies_exposure(seg, above, plane, 1, (64, 0.5, False), None, "numba",
    ...                 shadow_scratch(64)).tolist()
    [0.0]
    """

    s, e, r, off = segments
    u, v, d = plane
    res, bias, soft = shadow
    n, k = s.shape[0], shifts.shape[0]
    moves = np.concatenate([np.zeros((1, 3)), shifts])  # (k + 1, 3): the plant, its copies
    blocks = [(int(off[p]), int(off[p + 1])) for p in range(len(off) - 1)]
    frames = copies_frames(s, e, r, blocks, moves, u, v, res)
    t = (np.arange(samples) + 0.5) / samples  # as segment_exposure_into places them
    query = (s[:, None, :] + t[None, :, None] * (e - s)[:, None, :]).reshape(-1, 3)
    parts, kept_off, own = [], [0], []
    for p, (a, b) in enumerate(blocks):
        hit = np.zeros(k + 1, bool)
        if b > a and backend == "moderngl" and not soft:
            hit[:] = True  # the whole stand (the GPU draws every copy)
        elif b > a:
            q = query[a * samples : b * samples]
            ends = np.concatenate([s[a:b], e[a:b]])
            rim = float(r[a:b].max()) + frames[p, 2]
            hit[:] = True
            for axis in (u, v):
                pa, qa, moved = ends @ axis, q @ axis, moves @ axis
                hit &= (pa.min() - rim + moved <= qa.max()) & (pa.max() + rim + moved >= qa.min())
            hit[0] = True
        for j in np.flatnonzero(hit):
            parts.append((a, b, j))
        own.append(kept_off[-1] + np.arange(b - a))
        kept_off.append(kept_off[-1] + int(hit.sum()) * (b - a))
    all_s, all_e = (
        np.ascontiguousarray(np.concatenate([x[a:b] + moves[j] for a, b, j in parts] or [s[:0]]))
        for x in (s, e)
    )
    all_r = np.ascontiguousarray(np.concatenate([r[a:b] for a, b, _ in parts] or [r[:0]]))
    all_off = np.asarray(kept_off, np.int64)
    own = np.concatenate(own).astype(np.int64) if own else np.empty(0, np.int64)
    if backend == "moderngl" and not soft:
        every = segment_exposure_gl(all_s, all_e, all_r, all_off, frames, u, v, d, res, bias,
                                    samples)  # fmt: skip
        return np.ascontiguousarray(every[own])
    all_t = np.concatenate([trans[a:b] for a, b, _ in parts]) if soft else np.empty(0)
    none = np.empty(0, np.int64)
    expo = kernels.judge_queries(
        (all_s, all_e, all_r, all_off), frames, (u, v, d), (res, bias, soft, all_t),
        (0, np.ascontiguousarray(query), np.ascontiguousarray(samples * off, dtype=np.int64),
         np.repeat(own, samples)),
        np.empty(n * samples), (np.empty(0), none), scratch,
    )  # fmt: skip
    return np.ascontiguousarray(expo.reshape(n, samples).sum(axis=1) / samples)


def copies_frames(s, e, r, blocks, moves, u, v, res) -> np.ndarray:
    """``(P, 3)`` each plant's frame over itself and its copies (``moves`` ``(k + 1, 3)``):
    what :func:`growsim.kernels.light.plant_frames` gives over every copy's segments, from
    the few points that can hold the extremes (the plant's end points and the copies
    within a rounding error of the extreme along each axis, the points moved as the
    copies' segments are: ``point + move``) and the largest radius.

    Examples
    --------
    >>> s, e, r = np.array([[0.0, 0, 0]]), np.array([[0.0, 1, 0]]), np.array([0.1])
    >>> moves = np.array([[0.0, 0, 0], [3.0, 0, 0]])  # the plant, a copy 3 m along x
    >>> u, v = np.array([1.0, 0, 0]), np.array([0, 0, 1.0])
    >>> copies_frames(s, e, r, [(0, 1)], moves, u, v, 64).shape
    (1, 3)
    """

    cand, radii, offsets = [], [], [0]
    for a, b in blocks:
        if b <= a:
            offsets.append(offsets[-1])
            continue
        pts = np.concatenate([s[a:b], e[a:b]])
        found = []
        for axis in (u, v):
            pa, ma = pts @ axis, moves @ axis
            tol = 1e-9 * (np.abs(pa).max() + np.abs(ma).max() + 1.0)
            for sign in (1.0, -1.0):
                at_p = pts[sign * pa >= (sign * pa).max() - tol]
                at_m = moves[sign * ma >= (sign * ma).max() - tol]
                found.append((at_p[None, :, :] + at_m[:, None, :]).reshape(-1, 3))
        c = np.concatenate(found)
        cand.append(c)
        radii.append(np.full(len(c), r[a:b].max()))
        offsets.append(offsets[-1] + len(c))
    c = np.ascontiguousarray(np.concatenate(cand)) if cand else np.empty((0, 3))
    rr = np.concatenate(radii) if radii else np.empty(0)
    return kernels.plant_frames(c, c, rr, np.asarray(offsets, np.int64), u, v, res)
