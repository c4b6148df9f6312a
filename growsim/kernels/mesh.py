"""Numba kernel: plant skeleton -> triangle mesh (n-gon tubes for stems, hexagon leaves).

Stems become open tubes: ``segments + 1`` rings of ``sides`` vertices, the radius going
linearly from the segment's base radius to its end radius (the seed's n-gon prisms split
into d pieces, "C G による枝ぶり生成法" section 4.3). Leaves become the seed's cut face of a
hexagonal prism: a flat hexagon along the leaf segment (tip and base on its axis, width
twice the leaf radius) plus its centre, 7 vertices and 6 triangles, facing up as far as
the leaf's direction allows.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = ["LEAF_TRIS", "LEAF_VERTS", "mesh_counts", "mesh_kernel", "weld_targets"]

#: vertices and triangles of one leaf
LEAF_VERTS = 7
LEAF_TRIS = 6


def mesh_counts(n_stems: int, n_leaves: int, sides: int, segments: int) -> tuple[int, int]:
    """``(n_vertices, n_triangles)`` of the mesh of ``n_stems`` tubes and ``n_leaves``
    leaves.

    Examples
    --------
    >>> mesh_counts(1, 1, 6, 2)
    (25, 30)
    """
    nv = n_stems * sides * (segments + 1) + n_leaves * LEAF_VERTS
    nt = n_stems * 2 * sides * segments + n_leaves * LEAF_TRIS
    return nv, nt


@njit
def perpendicular_frame(ax, ay, az):
    """Two unit vectors perpendicular to the unit axis ``a`` (and to each other)."""
    # the helper axis is the world axis least aligned with ``a``, so the cross product
    # never degenerates
    if abs(ax) <= abs(ay) and abs(ax) <= abs(az):
        hx, hy, hz = 1.0, 0.0, 0.0
    elif abs(ay) <= abs(az):
        hx, hy, hz = 0.0, 1.0, 0.0
    else:
        hx, hy, hz = 0.0, 0.0, 1.0
    ux = ay * hz - az * hy
    uy = az * hx - ax * hz
    uz = ax * hy - ay * hx
    n = math.sqrt(ux * ux + uy * uy + uz * uz)
    ux /= n
    uy /= n
    uz /= n
    vx = ay * uz - az * uy
    vy = az * ux - ax * uz
    vz = ax * uy - ay * ux
    return ux, uy, uz, vx, vy, vz


@njit
def _axis(dx, dy, dz, fx, fy, fz):
    """``(L, ax, ay, az)``: the length of ``(dx, dy, dz)`` and its unit direction, or the
    fallback axis ``(fx, fy, fz)`` for a zero-length vector."""
    L = math.sqrt(dx * dx + dy * dy + dz * dz)
    if L > 0.0:
        return L, dx / L, dy / L, dz / L
    return L, fx, fy, fz


@njit
def weld_targets(parent, kind, radius):
    """For each stem, the parent stem whose end ring its tube may share (``-1``: none).

    A segment continues its parent's tube when it is the parent's thickest stem child
    (the first one on ties): the continuation of a branch axis. ``parent`` ``(n,)`` int64,
    ``kind`` ``(n,)`` int8, ``radius`` ``(n,)`` float64; returns ``(n,)`` int64.
    """
    n = parent.shape[0]
    best = np.full(n, -1, np.int64)
    for s in range(n):
        p = parent[s]
        if kind[s] != 0 or p < 0 or kind[p] != 0:
            continue
        b = best[p]
        if b < 0 or radius[s] > radius[b]:
            best[p] = s
    out = np.full(n, -1, np.int64)
    for p in range(n):
        if best[p] >= 0:
            out[best[p]] = p
    return out


@njit
def mesh_kernel(start, end, r0, r1, kind, sides, segments, weld_to):
    """Build the mesh arrays.

    Parameters
    ----------
    start, end : ``(n, 3)`` float64 segment end points.
    r0, r1 : ``(n,)`` float64 radius at the base and at the end (leaves: half width, r0).
    kind : ``(n,)`` int8, 0 stem (tube), 1 leaf (hexagon).
    sides : int >= 3, tube polygon sides. segments : int >= 1, tube pieces per segment.
    weld_to : ``(n,)`` int64, for a stem the stem whose end ring its tube starts from
        (segment merging: consecutive segments of one axis share the joint ring), or
        ``-1`` for a tube with its own base ring. See :func:`weld_targets`.

    Returns
    -------
    points ``(N, 3)`` float32, tris ``(M, 3)`` int64, vkind ``(N,)`` uint8 (0 bark, 1 leaf).
    Stems come first in segment order (a welded stem without its base ring), then leaves
    in segment order.
    """
    n = start.shape[0]
    n_leaf = 0
    for s in range(n):
        if kind[s] == 1:
            n_leaf += 1
    n_stem = n - n_leaf
    # pass 1: where each stem's vertex block starts (a welded stem has one ring less)
    vstart = np.full(n, -1, np.int64)
    own = np.zeros(n, np.int64)
    nv = 0
    for s in range(n):
        if kind[s] == 1:
            continue
        own[s] = segments + 1
        if weld_to[s] >= 0:
            own[s] = segments
        vstart[s] = nv
        nv += own[s] * sides
    nv += n_leaf * 7
    nt = n_stem * 2 * sides * segments + n_leaf * 6
    pts = np.empty((nv, 3), np.float32)
    tris = np.empty((nt, 3), np.int64)
    vkind = np.zeros(nv, np.uint8)
    cosa = np.empty(sides)
    sina = np.empty(sides)
    for k in range(sides):
        a = 2.0 * math.pi * k / sides
        cosa[k] = math.cos(a)
        sina[k] = math.sin(a)
    v = 0
    t = 0
    for s in range(n):
        if kind[s] == 1:
            continue
        dx = end[s, 0] - start[s, 0]
        dy = end[s, 1] - start[s, 1]
        dz = end[s, 2] - start[s, 2]
        L, ax, ay, az = _axis(dx, dy, dz, 0.0, 1.0, 0.0)
        ux, uy, uz, wx, wy, wz = perpendicular_frame(ax, ay, az)
        w = weld_to[s]
        first = 1 if w >= 0 else 0
        for j in range(first, segments + 1):
            f = j / segments
            cx = start[s, 0] + f * dx
            cy = start[s, 1] + f * dy
            cz = start[s, 2] + f * dz
            r = r0[s] + f * (r1[s] - r0[s])
            for k in range(sides):
                pts[v, 0] = cx + r * (cosa[k] * ux + sina[k] * wx)
                pts[v, 1] = cy + r * (cosa[k] * uy + sina[k] * wy)
                pts[v, 2] = cz + r * (cosa[k] * uz + sina[k] * wz)
                v += 1
        for j in range(segments):
            if j == 0 and w >= 0:
                a0 = vstart[w] + (own[w] - 1) * sides  # the parent's end ring
            else:
                a0 = vstart[s] + (j - first) * sides
            b0 = vstart[s] + (j + 1 - first) * sides
            for k in range(sides):
                k1 = (k + 1) % sides
                tris[t, 0] = a0 + k
                tris[t, 1] = a0 + k1
                tris[t, 2] = b0 + k
                tris[t + 1, 0] = b0 + k
                tris[t + 1, 1] = a0 + k1
                tris[t + 1, 2] = b0 + k1
                t += 2
    for s in range(n):
        if kind[s] != 1:
            continue
        dx = end[s, 0] - start[s, 0]
        dy = end[s, 1] - start[s, 1]
        dz = end[s, 2] - start[s, 2]
        L, ax, ay, az = _axis(dx, dy, dz, 1.0, 0.0, 0.0)
        # across the blade: horizontal and perpendicular to the leaf axis, so the blade
        # faces up (a vertical leaf falls back to the frame's first axis)
        sx = -az
        sz = ax
        sn = math.sqrt(sx * sx + sz * sz)
        if sn > 1e-9:
            sx /= sn
            sy = 0.0
            sz /= sn
        else:
            sx, sy, sz, _wx, _wy, _wz = perpendicular_frame(ax, ay, az)
        h = 0.5 * L
        w = r0[s]
        cx = start[s, 0] + 0.5 * dx
        cy = start[s, 1] + 0.5 * dy
        cz = start[s, 2] + 0.5 * dz
        v0 = v
        pts[v, 0] = cx
        pts[v, 1] = cy
        pts[v, 2] = cz
        vkind[v] = 1
        v += 1
        # hexagon corners at 0, 60, ..., 300 degrees: (cos * h) along, (sin / sin60 * w) across
        for k in range(6):
            ang = k * math.pi / 3.0
            along = math.cos(ang) * h
            across = math.sin(ang) / math.sin(math.pi / 3.0) * w
            pts[v, 0] = cx + along * ax + across * sx
            pts[v, 1] = cy + along * ay + across * sy
            pts[v, 2] = cz + along * az + across * sz
            vkind[v] = 1
            v += 1
        for k in range(6):
            tris[t, 0] = v0
            tris[t, 1] = v0 + 1 + k
            tris[t, 2] = v0 + 1 + (k + 1) % 6
            t += 1
    return pts, tris, vkind
