"""Numba kernels of the shadow-map light (:mod:`growsim.env.light`).

Framing
-------
Each plant (segments ``offsets[k]:offsets[k + 1]``) gets its own square raster across the
light's direction ``d`` (unit), on the image plane ``(u, v)``: :func:`plant_frames` gives
``(ox, oy, pix)`` per plant, and a point ``p`` falls at pixel coordinates
``x = (p . u - ox) / pix``, ``y = (p . v - oy) / pix`` (pixel ``(i, j) = (floor(y),
floor(x))``), at depth ``z = p . d`` (nearer to the light = smaller). The frame is the
plant's projected bounding box grown by its largest radius, ``resolution`` pixels across
with one pixel of margin each side, as :func:`growsim.env.light.projected_area` frames a
shadow. Every backend (this one, :mod:`growsim.env.shadow_gl`) uses these frames.

Coverage and depth
------------------
Every segment is a capsule of its radius (in pixels ``r = radius / pix``): it covers the
pixels whose centre lies within ``r`` of its projected axis, and the depth it gives a
pixel is the depth of its axis at the point nearest the pixel centre. Sampling pixel
centres at the true radius estimates each shadow's area without bias (a segment thinner
than a pixel covers some pixels or none, in proportion to its width); a minimum width of
a pixel, as silhouettes use, would darken plants of thin twigs (measured in
``docs/environment.md``).

The map is read only where it is queried: each plant's query points (segment samples or
given points) are listed per pixel first, and a bit is set for each such pixel in
occupancy words by rows and by columns (:func:`shadow_scratch`). A capsule then visits
only the pixels that hold queries (:func:`growsim.kernels.capsule.walk_capsule`): a
small one (its bounding box at most 64 pixels or 3 times its area) tests the occupied pixels of
its bounding box against its radius (by rows, or by columns when the box is taller than
wide); a larger one is walked line by line along its
shorter extent (rows, or columns for a segment taller than wide) over exactly the
pixels of each line's chord of the capsule, computed in closed form, masked by the
line's occupancy. A capsule is not walked at all (:func:`_culled`) when its bounding box,
widened by its radius and a pixel, misses the box of the pixels holding queries, or when
its axis lies wholly behind the deepest query less the bias (it can shade none; not for
:func:`map_depth_kernel`, whose depths are read): a plant among its copies in a periodic
stand walks only the copies' capsules that can reach its queries, with the same answers
bit for bit. So a plant costs its segments' walks and its queries, not a whole
map's writes. The answers are those of the whole map at the pixels read (tested against
a pixel-by-pixel z-buffer, ``tests/naive/light.py``'s ``render_depth``,
:func:`map_depth_kernel` read at every pixel centre).

Three entries, all what production calls: :func:`segment_exposure_into` (each segment's
samples, :func:`growsim.env.light.segment_light`), :func:`point_light_into` (given
points with normals under several lights: :meth:`growsim.env.Light.point_light` and the
hormone model's step) and :func:`module_light_into` (the walls of cylinders, one point
per cylinder and light shared by its walls: the hormone model's step with
``light.walls = "module"``). State is passed as tuples: ``segments`` ``(start, end, radius,
offsets)``, ``plane`` ``(u, v, d)``, ``shadow`` ``(res, bias_pixels, soft, trans)``,
``lights`` ``(dirs, us, vs, weights)``, ``targets`` ``(points, point_offsets, normals)``.

Hard shadows (``soft`` False): the map keeps each queried pixel's nearest depth and
segment (the first drawn on a tie, as a z-buffer). A point at depth ``z`` in pixel ``(i,
j)`` is lit (exposure 1) when the pixel is empty, when its nearest segment is the point's
own segment, or when ``z - depth[i, j] <= bias`` (``bias = bias_pixels * pix``); else 0.
Points outside the frame are lit.

Soft shadows (``soft`` True, per-segment transmissions ``trans``): the deep map (every
segment covering a pixel, at its depth there). A point's exposure is the product of the
transmissions ``trans[s]`` of the other segments ``s`` lying in front of it at its pixel
by more than the bias: ``exp(-sum k_s)``, ``k_s = -ln trans[s]``. With
every ``trans -> 0`` it is 0 when anything else lies in front: the binary map, except
that a steep segment whose own nearest depth at the pixel is in front of an occluder does
not shield its point here.

Among copies (a periodic stand, :func:`point_light_into` with ``shifts``): the plant's own
map is read at each point and at the point moved back by each copy's shift
(:mod:`growsim.kernels.copies`).

Plants never shade each other: each has its own map (one scratch of list heads,
occupancy and nearest depths, a pixel's cells set up by its first query and its
occupancy bits cleared after each plant).
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.capsule import project_segment, walk_capsule
from growsim.kernels.config import njit
from growsim.kernels.copies import among_copies, copies_hard

__all__ = [
    "apply_cosines",
    "judge_queries",
    "map_depth_kernel",
    "module_light_into",
    "plant_frames",
    "point_light_into",
    "segment_exposure_into",
    "shadow_scratch",
]


@njit
def plant_frames(start, end, radius, offsets, u, v, res):
    """``(k, 3)`` float64: each plant's raster frame ``(ox, oy, pix)`` (see the module).

    A plant with no segments gets ``(0, 0, 1)``; one whose shadow is a single point (no
    width, seen end on) gets pixel size 1.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((1, 3)); e = np.array([[4.0, 0, 0]])
    >>> u, v = np.array([1.0, 0, 0]), np.array([0.0, 0, -1])
    >>> plant_frames(s, e, np.array([0.5]), np.array([0, 1]), u, v, 12).tolist()
    [[-1.0, -1.0, 0.5]]
    """
    k = offsets.shape[0] - 1
    out = np.empty((k, 3))
    for p in range(k):
        s0 = offsets[p]
        s1 = offsets[p + 1]
        if s1 <= s0:
            out[p, 0] = 0.0
            out[p, 1] = 0.0
            out[p, 2] = 1.0
            continue
        lox = np.inf
        loy = np.inf
        hix = -np.inf
        hiy = -np.inf
        rmax = 0.0
        for s in range(s0, s1):
            for q in range(2):
                pt = start if q == 0 else end
                x = pt[s, 0] * u[0] + pt[s, 1] * u[1] + pt[s, 2] * u[2]
                y = pt[s, 0] * v[0] + pt[s, 1] * v[1] + pt[s, 2] * v[2]
                lox = min(lox, x)
                hix = max(hix, x)
                loy = min(loy, y)
                hiy = max(hiy, y)
            rmax = max(rmax, radius[s])
        size = max(hix - lox, hiy - loy) + 2.0 * rmax
        pix = size / (res - 2) if size > 0.0 else 1.0
        out[p, 0] = lox - rmax - pix
        out[p, 1] = loy - rmax - pix
        out[p, 2] = pix
    return out


@njit
def judge_queries(segments, frames, plane, shadow, queries, expo, hits, scratch):
    """Exposure of every query point into ``expo`` ``(m,)``: each plant's shadow map read
    at its queries' pixels only (a pixel holding no query is never written: the same
    answers as a whole z-buffer or deep map, for the pixels read).

    ``segments`` ``(start, end, radius, offsets)``, ``frames`` from :func:`plant_frames`,
    ``plane`` ``(u, v, d)``, ``shadow`` ``(res, bias_pixels, soft, trans)`` as
    :func:`segment_exposure_into`. ``queries`` ``(samples, query, query_offsets, own)``:
    with ``samples > 0``, each segment's ``samples`` points at ``t = (i + 0.5) / samples``
    of its axis (query ``s * samples + i``, its own segment ``s``; ``query``,
    ``query_offsets``, ``own`` unused); with ``samples == 0``, the points ``query`` ``(m,
    3)``, plant ``p`` owning ``query_offsets[p]:query_offsets[p + 1]``, ``own[q]`` the
    segment a query belongs to or -1. ``scratch`` a :func:`shadow_scratch` of ``res``,
    left as given. For hard shadows, the map's depth and segment at each query's pixel
    (``inf`` and -1 where empty) go into ``hits`` ``(depth, seg)`` ``(m,)`` unless they
    are empty. Returns ``expo``. The one pass every exposure here runs through
    (:func:`segment_exposure_into`, :func:`point_light_into`, :func:`module_light_into`,
    :func:`map_depth_kernel`) and :func:`growsim.env.light.segment_light`'s plants among
    their copies.

    Examples
    --------
    >>> import numpy as np
    >>> start, end = np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, 2.0, 0.0]])
    >>> radius, offsets = np.array([0.2]), np.array([0, 1])
    >>> d, u, v = np.array([0.0, -1.0, 0.0]), np.array([1.0, 0, 0]), np.array([0, 0, 1.0])
    >>> frames = plant_frames(start, end, radius, offsets, u, v, 32)
    >>> points = np.array([[0.0, 0.0, 0.0], [0.8, 0.5, 0.0]])  # under the stem, beside it
    >>> none = np.empty(0, np.int64)
    >>> judge_queries((start, end, radius, offsets), frames, (u, v, d),
    ...               (32, 0.5, False, np.empty(0)), (0, points, np.array([0, 2]),
    ...               np.array([-1, -1])), np.empty(2), (np.empty(0), none),
    ...               shadow_scratch(32)).tolist()
    [0.0, 1.0]
    """
    start, end, radius, offsets = segments
    u, v, d = plane
    res, bias_pixels, soft, trans = shadow
    samples, query, query_offsets, own = queries
    depth, seg = hits
    head, occ, near_z, near_id = scratch
    W = (res + 63) // 64
    keep = depth.shape[0] > 0
    # a plant's queries, numbered from 0: their depth, pixel, next query in the pixel and
    # segment
    most = 0
    for p in range(offsets.shape[0] - 1):
        if samples > 0:
            most = max(most, (offsets[p + 1] - offsets[p]) * samples)
        else:
            most = max(most, query_offsets[p + 1] - query_offsets[p])
    qz = np.empty(most)
    work = np.empty((5, most), np.int64)
    pix, nxt, mine = work[0], work[1], work[2]
    rows, cols = work[3], work[4]  # the query's occupancy words: its row's, its column's
    for p in range(offsets.shape[0] - 1):
        if samples > 0:
            q0 = offsets[p] * samples
            q1 = offsets[p + 1] * samples
        else:
            q0 = query_offsets[p]
            q1 = query_offsets[p + 1]
        if q1 <= q0:
            continue
        ox, oy, inv = frames[p, 0], frames[p, 1], 1.0 / frames[p, 2]
        bias = bias_pixels * frames[p, 2]
        # the queries' pixels, as lists per pixel, and their bits by rows and by columns;
        # the box of the pixels holding queries and the deepest query in them (_culled)
        lo_x = lo_y = res
        hi_x = hi_y = -1
        deep = -np.inf
        for i in range(q1 - q0):
            if samples > 0:
                k = offsets[p] + i // samples
                t = (i % samples + 0.5) / samples
                px = start[k, 0] + t * (end[k, 0] - start[k, 0])
                py = start[k, 1] + t * (end[k, 1] - start[k, 1])
                pz = start[k, 2] + t * (end[k, 2] - start[k, 2])
                mine[i] = k
            else:
                px, py, pz = query[q0 + i, 0], query[q0 + i, 1], query[q0 + i, 2]
                mine[i] = own[q0 + i]
            x = (px * u[0] + py * u[1] + pz * u[2] - ox) * inv
            y = (px * v[0] + py * v[1] + pz * v[2] - oy) * inv
            qz[i] = px * d[0] + py * d[1] + pz * d[2]
            if soft:
                expo[q0 + i] = 1.0
            if x >= 0.0 and y >= 0.0 and x < res and y < res:
                xi = int(x)
                yi = int(y)
                pix[i] = yi * res + xi
                rows[i] = yi * W + (xi >> 6)
                cols[i] = (res + xi) * W + (yi >> 6)
                bit = np.uint64(1) << np.uint64(xi & 63)
                if occ[rows[i]] & bit == 0:  # the pixel's first query: its cells begin here
                    occ[rows[i]] |= bit
                    occ[cols[i]] |= np.uint64(1) << np.uint64(yi & 63)
                    head[pix[i]] = -1
                    near_z[pix[i]] = np.inf
                    near_id[pix[i]] = -1
                nxt[i] = head[pix[i]]
                head[pix[i]] = i
                lo_x = min(lo_x, xi)
                hi_x = max(hi_x, xi)
                lo_y = min(lo_y, yi)
                hi_y = max(hi_y, yi)
                deep = max(deep, qz[i])
            else:
                pix[i] = -1  # outside the frame: in the open
        plant_queries = (nxt, qz, mine, expo[q0:q1])
        for k in range(offsets[p], offsets[p + 1]) if hi_x >= 0 else range(0):
            ends = project_segment(start, end, k, u, v, d, ox, oy, inv)
            if _culled(ends, radius[k] * inv, (lo_x, hi_x, lo_y, hi_y), deep - bias, keep):
                continue
            walk_capsule(k, ends, radius[k] * inv, res, scratch, plant_queries, bias, soft,
                         trans[k] if soft else 1.0)  # fmt: skip
        if not soft:
            for i in range(q1 - q0):
                z, k = (near_z[pix[i]], near_id[pix[i]]) if pix[i] >= 0 else (np.inf, -1)
                lit = k < 0 or k == mine[i] or qz[i] - z <= bias
                expo[q0 + i] = 1.0 if lit else 0.0
                if keep:
                    depth[q0 + i] = z
                    seg[q0 + i] = k
        for i in range(q1 - q0):
            if pix[i] >= 0:
                occ[rows[i]] = 0
                occ[cols[i]] = 0
    return expo


@njit(inline="always")
def _culled(ends, rr, box, behind, keep):
    """Whether a capsule (``ends`` as :func:`project_segment` gives them, radius ``rr``
    pixels) can be left out of a map read only at the pixels of ``box`` ``(lo_x, hi_x,
    lo_y, hi_y)`` (the columns and rows holding queries) without changing an answer: its
    bounding box, widened by its radius and a pixel, misses them (it covers a pixel only
    when it holds the pixel's centre), or, unless the map's depths are kept (``keep``),
    its axis lies wholly behind ``behind`` (the deepest query less the bias, with a
    rounding margin): it shades no query, and where it would be a pixel's nearest
    segment every capsule left there lies behind the queries too."""
    ax, ay, bx, by, za, zb = ends
    lo_x, hi_x, lo_y, hi_y = box
    if max(ax, bx) + rr < lo_x - 1.0 or min(ax, bx) - rr > hi_x + 2.0:
        return True
    if max(ay, by) + rr < lo_y - 1.0 or min(ay, by) - rr > hi_y + 2.0:
        return True
    if keep:
        return False
    z = min(za, zb)
    return z - 1e-9 * (1.0 + abs(za) + abs(zb) + abs(behind)) > behind


@njit
def segment_exposure_into(segments, frames, plane, samples, shadow, scratch, out):
    """Each segment's exposure: the mean over its ``samples`` points (at ``t = (q + 0.5) /
    samples`` of its axis) of their exposure in their plant's shadow map (hard: 1 when lit,
    else 0; soft: the product of the transmissions of the other segments in front), into
    ``out`` ``(n,)`` (overwritten and returned). The production entry of
    :func:`growsim.env.light.segment_light`.

    ``segments`` ``(start, end, radius, offsets)``: ``start, end`` ``(n, 3)``, ``radius``
    ``(n,)`` float64, ``offsets`` ``(k + 1,)`` int64 (plant ``p`` the segments
    ``offsets[p]:offsets[p + 1]``); ``frames`` ``(k, 3)`` from :func:`plant_frames`;
    ``plane`` ``(u, v, d)`` ``(3,)`` each: the image plane and the unit direction the light
    travels; ``shadow`` ``(res, bias_pixels, soft, trans)``: pixels across, the depth bias
    in pixels, soft shadows (else hard) and, when soft, the per-segment transmissions
    ``(n,)`` (else an empty array); ``scratch`` a :func:`shadow_scratch` of ``res``, left
    as it was given: a caller that lights many plants at one resolution keeps one, whose
    pages stay mapped.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0, 0, 0]]); e = np.array([[1.0, 1, 0], [1, 0, 0]])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> r, off = np.full(2, 0.2), np.array([0, 2])
    >>> f = plant_frames(s, e, r, off, u, v, 64)
    >>> hard = (64, 1.5, False, np.empty(0))
    >>> segment_exposure_into((s, e, r, off), f, (u, v, d), 1, hard, shadow_scratch(64),
    ...                       np.empty(2)).tolist()
    [1.0, 0.0]
    >>> soft = (64, 1.5, True, np.full(2, 0.5))
    >>> segment_exposure_into((s, e, r, off), f, (u, v, d), 1, soft, shadow_scratch(64),
    ...                       np.empty(2)).tolist()
    [1.0, 0.5]
    """
    none = np.empty(0, np.int64)
    expo = judge_queries(segments, frames, plane, shadow, (samples, np.empty((0, 3)), none, none),
                  np.empty(segments[0].shape[0] * samples), (np.empty(0), none),
                  scratch)  # fmt: skip
    for s in range(segments[0].shape[0]):
        acc = 0.0
        for i in range(samples):
            acc += expo[s * samples + i]
        out[s] = acc / samples
    return out


@njit
def point_light_into(segments, targets, lights, shadow, scratch, out, shifts):
    """Light at points from several parallel lights: ``out[m] = sum_k weights[k] x
    exposure_k[m] x max(0, -normals[m] . dirs[k])``, each direction ``k`` (unit
    ``dirs[k]``, image plane ``us[k], vs[k]``) with its own shadow maps; a direction of
    weight 0 is skipped, and so is a point facing away from a light (its shadow is not
    judged). The production entry of :meth:`growsim.env.Light.point_light` and of the
    hormone model's step (:func:`growsim.kernels.hormone.grow_step`).

    ``segments`` and ``shadow`` ``(res, bias_pixels, soft, trans)`` as
    :func:`segment_exposure_into`; ``targets`` ``(points, point_offsets, normals)``: the
    points ``(m, 3)``, plant ``p`` owning ``point_offsets[p]:point_offsets[p + 1]``, their
    unit normals ``(m, 3)``; ``lights`` ``(dirs, us, vs, weights)``: ``(j, 3)`` each and
    ``(j,)``. ``scratch`` a :func:`shadow_scratch` of ``res``, left as it was given.
    ``out`` ``(m,)`` is overwritten and returned. A point outside its plant's map, or on
    an empty pixel, is in the open.

    ``shifts`` ``(k, 3)`` puts each plant among copies of itself moved by each row (a
    periodic stand, :func:`growsim.kernels.stand.periodic_shifts`; ``(0, 3)``: alone):
    copy ``j`` shades point ``q`` as the plant shades ``q - shifts[j]``, so each point is
    judged at itself and at ``q - shifts[j]`` in its plant's own map (the plant's frame
    and pixel size, as alone), and its exposure along a light is the product of those
    answers (hard: lit when lit in all; soft: the transmissions of every copy in front),
    read by :mod:`growsim.kernels.copies`. A moved point outside the plant's frame is in
    the open and not judged: a plant among ``k`` copies costs its own raster and its
    points' moved queries, not ``k`` rasters.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0]]); e = np.array([[1.0, 1, 0]]); r = np.array([0.2])
    >>> d = np.array([[0.0, -1, 0], [-1.0, 0, 0]])  # from above, from the right
    >>> u = np.array([[1.0, 0, 0], [0.0, 0, -1]]); v = np.array([[0.0, 0, -1], [0.0, 1, 0]])
    >>> pts = (np.array([[0.5, 0, 0]]), np.array([0, 1]), np.array([[0.6, 0.8, 0]]))
    >>> scratch = shadow_scratch(64)
    >>> alone = np.zeros((0, 3))
    >>> point_light_into((s, e, r, np.array([0, 1])), pts, (d, u, v, np.array([1.0, 0.5])),
    ...     (64, 0.1, False, np.empty(0)), scratch, np.empty(1), alone).round(3).tolist()
    [0.3]
    >>> bool((scratch[1] == 0).all())  # left as given
    True
    >>> far = (np.array([[5.5, 0, 0]]), np.array([0, 1]), np.array([[0.0, 1, 0]]))
    >>> copy = np.array([[5.0, 0.0, 0.0]])  # a copy 5 m along x shades the far point
    >>> [point_light_into((s, e, r, np.array([0, 1])), far, (d[:1], u[:1], v[:1], np.ones(1)),
    ...      (64, 0.1, False, np.empty(0)), scratch, np.empty(1), sh).tolist()
    ...  for sh in (alone, copy)]
    [[1.0], [0.0]]
    """
    start, end, radius, offsets = segments
    points, point_offsets, normals = targets
    dirs, us, vs, weights = lights
    res = shadow[0]
    m = points.shape[0]
    P = point_offsets.shape[0] - 1
    out[:] = 0.0
    # the points facing a light (the others get none of it: their shadow is not judged)
    real = np.empty(5 * m)
    facing = real[: 3 * m].reshape((m, 3))
    expo, cosine = real[3 * m : 4 * m], real[4 * m :]
    ints = np.empty(2 * m + P + 1, np.int64)
    own, which, facing_offsets = ints[:m], ints[m : 2 * m], ints[2 * m :]
    own[:] = -1
    for k in range(dirs.shape[0]):
        w = weights[k]
        if w == 0.0:
            continue
        d, u, v = dirs[k], us[k], vs[k]
        c = 0
        for p in range(P):
            facing_offsets[p] = c
            for q in range(point_offsets[p], point_offsets[p + 1]):
                cos = -(normals[q, 0] * d[0] + normals[q, 1] * d[1] + normals[q, 2] * d[2])
                if cos > 0.0:
                    facing[c, 0], facing[c, 1], facing[c, 2] = (
                        points[q, 0],
                        points[q, 1],
                        points[q, 2],
                    )
                    which[c] = q
                    cosine[c] = cos
                    c += 1
        facing_offsets[P] = c
        frames = plant_frames(start, end, radius, offsets, u, v, res)
        if shifts.shape[0] == 0:
            judge_queries(segments, frames, (u, v, d), shadow,
                          (0, facing[:c], facing_offsets, own[:c]), expo[:c],
                          (np.empty(0), own[:0]), scratch)  # fmt: skip
        elif not shadow[2]:
            copies_hard(segments, frames, (u, v, d), shadow, (facing[:c], facing_offsets),
                        shifts, scratch, expo[:c])  # fmt: skip
        else:
            moved = among_copies(facing[:c], facing_offsets, frames, (u, v, res), shifts)
            q, q_offsets, src = moved
            nobody = np.full(src.shape[0], -1, np.int64)
            got = judge_queries(segments, frames, (u, v, d), shadow, (0, q, q_offsets, nobody),
                                np.empty(src.shape[0]), (np.empty(0), nobody[:0]),
                                scratch)  # fmt: skip
            expo[:c] = 1.0
            for i in range(src.shape[0]):
                expo[src[i]] *= got[i]
        for i in range(c):
            out[which[i]] += expo[i] * cosine[i] * w
    return out


@njit
def module_light_into(segments, walls, lights, shadow, scratch, out):
    """Light on the walls of modules (cylinders with ``walls`` sides): each module's
    exposure to each light judged once, at one point, and shared by its walls, each wall
    its own cosine: ``out[s, i] = sum_k weights[k] x E_k[s] x max(0, cos_ik)``, ``cos_ik =
    -n_si . dirs[k]``. The faster, shared alternative to one :func:`point_light_into`
    point per wall (``environment.light.walls = "module"`` of the hormone model,
    :func:`growsim.kernels.hormone.grow_step`).

    Segment ``s``'s walls face ``n_si = cs[i, 0] x_s + cs[i, 1] y_s`` (``x_s, y_s`` the
    first two columns of its pose ``R[s]``, the axes across it); ``walls`` is ``(R, cs)``,
    ``R`` ``(n, 3, 3)`` (or longer) and ``cs`` ``(walls, 2)``. Along light ``k`` the point
    judged is on the surface halfway along the segment, facing the lit walls: ``mid +
    radius n*``, ``n*`` the unit sum of the walls' normals weighted by their clipped
    cosines (in 2D, two walls ``+-x``, this is the lit wall's own point: the per-wall
    light to rounding). A segment none of whose walls faces a light gets none of it and
    is not judged. ``E_k`` is that point's exposure in its plant's shadow map along the
    light (hard or soft, as :func:`point_light_into`). ``segments``, ``lights`` and
    ``shadow`` as :func:`point_light_into`; ``scratch`` a :func:`shadow_scratch` of
    ``res``, left as it was given; ``out`` ``(n, walls)`` is overwritten and returned.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 1, 0], [0.0, 0, 0]]); e = s + np.array([0.0, 0, 1])  # two rods
    >>> R = np.zeros((2, 3, 3)); R[:, 0, 0] = 1; R[:, 1, 1] = 1; R[:, 2, 2] = 1
    >>> cs = np.array([[0.0, 1], [0.0, -1]])  # walls facing up and down
    >>> d = np.array([[0.0, -1, 0]]); u = np.array([[1.0, 0, 0]]); v = np.array([[0.0, 0, -1]])
    >>> module_light_into((s, e, np.full(2, 0.1), np.array([0, 2])), (R, cs),
    ...     (d, u, v, np.ones(1)), (64, 0.1, False, np.empty(0)), shadow_scratch(64),
    ...     np.empty((2, 2))).tolist()  # the upper rod shades the lower
    [[1.0, 0.0], [0.0, 0.0]]
    """
    start, end, radius, offsets = segments
    R, cs = walls
    dirs, us, vs, weights = lights
    res = shadow[0]
    n = start.shape[0]
    W = cs.shape[0]
    P = offsets.shape[0] - 1
    out[:] = 0.0
    real = np.empty(4 * n + n * W)
    points = real[: 3 * n].reshape((n, 3))
    expo = real[3 * n : 4 * n]
    cosine = real[4 * n :].reshape((n, W))
    ints = np.empty(2 * n + P + 1, np.int64)
    own, which, point_offsets = ints[:n], ints[n : 2 * n], ints[2 * n :]
    own[:] = -1
    for k in range(dirs.shape[0]):
        w = weights[k]
        if w == 0.0:
            continue
        d, u, v = dirs[k], us[k], vs[k]
        c = 0
        for p in range(P):
            point_offsets[p] = c
            for s in range(offsets[p], offsets[p + 1]):
                a = -(R[s, 0, 0] * d[0] + R[s, 1, 0] * d[1] + R[s, 2, 0] * d[2])
                b = -(R[s, 0, 1] * d[0] + R[s, 1, 1] * d[1] + R[s, 2, 1] * d[2])
                sa = 0.0
                sb = 0.0
                for i in range(W):
                    cos = cs[i, 0] * a + cs[i, 1] * b
                    cos = cos if cos > 0.0 else 0.0
                    cosine[c, i] = cos
                    sa += cs[i, 0] * cos
                    sb += cs[i, 1] * cos
                norm = math.sqrt(sa * sa + sb * sb)
                if norm == 0.0:  # no wall faces the light
                    continue
                f = radius[s] / norm
                for j in range(3):
                    mid = start[s, j] + 0.5 * (end[s, j] - start[s, j])
                    points[c, j] = mid + f * (sa * R[s, j, 0] + sb * R[s, j, 1])
                which[c] = s
                c += 1
        point_offsets[P] = c
        frames = plant_frames(start, end, radius, offsets, u, v, res)
        judge_queries(segments, frames, (u, v, d), shadow, (0, points[:c], point_offsets, own[:c]),
               expo[:c], (np.empty(0), own[:0]), scratch)  # fmt: skip
        for q in range(c):
            e = expo[q] * w
            if e != 0.0:
                s = which[q]
                for i in range(W):
                    out[s, i] += e * cosine[q, i]
    return out


@njit
def shadow_scratch(res):
    """The scratch a shadow map of ``res`` pixels across reads its queries through:
    ``(head, occ, near_z, near_id)``. ``occ`` ``(2 * res * W,)`` uint64 (``W = (res + 63)
    // 64`` words per row, then per column) holds a bit per pixel that holds queries, all
    0 between calls; the pixel's cells, read only where its bit is set (and set when it
    is), are ``head`` its first query (int64), ``near_z`` and ``near_id`` its nearest
    depth (float64) and segment (int64, hard shadows), ``(res * res,)`` each and never
    filled: a map costs the pages its queries touch, not ``res ** 2`` writes. The kernels
    leave ``occ`` all 0; a caller that lights a plant at every step
    (:func:`growsim.kernels.hormone.grow_step`) makes the scratch once.

    Examples
    --------
    >>> head, occ, near_z, near_id = shadow_scratch(64)
    >>> head.shape, occ.shape, near_z.shape, int(occ.max())
    ((4096,), (128,), (4096,), 0)
    """
    W = (res + 63) // 64
    n = res * res
    return (
        np.empty(n, np.int64),
        np.zeros(2 * res * W, np.uint64),
        np.empty(n),
        np.empty(n, np.int64),
    )


@njit
def map_depth_kernel(segments, frames, points, point_offsets, plane, res):
    """The hard shadow map the production entries build, read at points: ``(depth,
    segment)`` ``(m,)`` of the nearest capsule at each point's pixel of its plant's map
    (``inf`` and -1 where the pixel is empty or the point lies outside the frame). A probe
    of the rasteriser (the same :func:`judge_queries` as :func:`segment_exposure_into` and
    :func:`point_light_into`), tested against a pixel-by-pixel z-buffer.

    Examples
    --------
    >>> import numpy as np
    >>> s = np.array([[0.0, 2, 0], [0, 1, 0]]); e = s + np.array([1.0, 0, 0])
    >>> u, v, d = np.array([1.0, 0, 0]), np.array([0.0, 0, -1]), np.array([0.0, -1, 0])
    >>> r, off = np.full(2, 0.2), np.array([0, 2]); f = plant_frames(s, e, r, off, u, v, 64)
    >>> z, k = map_depth_kernel((s, e, r, off), f, np.array([[0.5, 0, 0], [3, 0, 0]]),
    ...                         np.array([0, 2]), (u, v, d), 64)
    >>> z.tolist(), k.tolist()
    ([-2.0, inf], [0, -1])
    """
    m = points.shape[0]
    scratch = shadow_scratch(res)
    depth, seg = np.empty(m), np.empty(m, np.int64)
    judge_queries(segments, frames, plane, (res, 0.0, False, np.empty(0)),
           (0, points, point_offsets, np.full(m, -1, np.int64)), np.empty(m), (depth, seg),
           scratch)  # fmt: skip
    return depth, seg


@njit
def apply_cosines(start, end, normal, use_normal, d, intensity, out):
    """``out[s] = (out[s] x cos_s) x intensity`` in place, ``cos_s`` segment ``s``'s
    Lambert cosine for the light travelling along unit ``d``: ``|normal . d|`` where
    ``use_normal`` (a blade with a unit ``normal``, two-sided), else the side of a
    cylinder, ``sqrt(1 - (axis . d)^2)`` (1 for a segment of no length); ``use_normal`` and
    ``normal`` may both have length 0 (no blades). Exposures into light, as
    :func:`growsim.env.light.segment_light` returns it. (A pass of its own: folded into
    :func:`segment_exposure_into`'s last loop it slowed the whole kernel by 15 %.)

    Examples
    --------
    >>> import numpy as np
    >>> s = np.zeros((2, 3)); e = np.array([[1.0, 0, 0], [0, 1, 0]])
    >>> apply_cosines(s, e, np.empty((0, 3)), np.empty(0, np.bool_), np.array([0.0, -1, 0]),
    ...               2.0, np.array([0.5, 1.0])).tolist()
    [1.0, 0.0]
    """
    blades = use_normal.shape[0] > 0
    for s in range(start.shape[0]):
        out[s] = out[s] * _cosine(start, end, normal, blades and use_normal[s], d, s) * intensity
    return out


@njit(inline="always")
def _cosine(start, end, normal, blade, d, s):
    """Segment ``s``'s Lambert cosine (:func:`apply_cosines`; ``blade``: use its
    ``normal``)."""
    if blade:
        return abs(normal[s, 0] * d[0] + normal[s, 1] * d[1] + normal[s, 2] * d[2])
    ex = end[s, 0] - start[s, 0]
    ey = end[s, 1] - start[s, 1]
    ez = end[s, 2] - start[s, 2]
    L = math.sqrt(ex * ex + ey * ey + ez * ez)
    if L > 0.0:
        ad = (ex * d[0] + ey * d[1] + ez * d[2]) / L
        return math.sqrt(max(0.0, 1.0 - ad * ad))
    return 1.0
