"""Numba kernels of the Honda nutrient-split tree (seed 003, "C G による枝ぶり生成法").

Vertex numbering follows the seed: vertex 0 is the root on the ground, vertex 1 the top of
the first trunk segment; a branching of vertex ``i`` creates vertices ``k+1`` (the
continuation, which keeps the parent's ration) and ``k+2`` (the lateral, ``f`` times the
ration) where ``k`` is the highest vertex so far. Segment ``v - 1`` joins vertex
``vparent[v]`` to vertex ``v``.

Random numbers are drawn outside (a ``numpy.random.Generator``) and passed in as ``U``
``(n_branchings, N_DRAWS)`` uniforms in ``[0, 1)``: branching ``b`` (in birth order) uses
row ``b`` with a fixed slot per draw, so a switch that uses an extra draw never shifts the
others.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit
from growsim.kernels.mesh import perpendicular_frame

__all__ = [
    "GEO_FIELDS",
    "N_DRAWS",
    "grow_kernel",
    "leaves_kernel",
    "sag_kernel",
    "subtree_tips_kernel",
]

#: draws per branching: theta (2), fold (2), which side (1), phi (2), length (2), spare
#: for avoidance retries (the remaining slots).
N_DRAWS = 9
#: layout of the ``geo`` float64 vector passed to :func:`grow_kernel` (angles in radians).
GEO_FIELDS = ("theta0", "theta_max", "phi0", "phi_max", "thq", "thr", "bd", "b0", "b_max", "avoid")


@njit
def _place(pos, i, v, t, ph, b):
    pos[v, 0] = pos[i, 0] + b * math.sin(t) * math.cos(ph)
    pos[v, 1] = pos[i, 1] + b * math.cos(t)
    pos[v, 2] = pos[i, 2] + b * math.sin(t) * math.sin(ph)


@njit
def _min_dist2(pos, nv, skip, x, y, z):
    """Squared distance from ``(x, y, z)`` to the nearest of vertices ``0..nv-1`` other
    than ``skip``."""
    best = np.inf
    for j in range(nv):
        if j == skip:
            continue
        dx = pos[j, 0] - x
        dy = pos[j, 1] - y
        dz = pos[j, 2] - z
        d = dx * dx + dy * dy + dz * dz
        if d < best:
            best = d
    return best


@njit
def grow_kernel(f, generations, geo, U, n_vertices):
    """Grow the Honda tree: topology by nutrient accumulation, geometry by the seed's draws.

    Parameters
    ----------
    f : float, lateral ration factor in ``[0, 1]``.
    generations : int, number of nutrient steps (``class_cnt``).
    geo : ``(10,)`` float64, see :data:`GEO_FIELDS` (angles in radians, lengths in units).
    U : ``(n_branchings, N_DRAWS)`` float64 uniforms in ``[0, 1)``.
    n_vertices : int, ``2 + 2 * n_branchings`` (see
        :func:`growsim.models.honda.count_topology`).

    Returns
    -------
    pos ``(n_vertices, 3)`` float64, vparent ``(n,)`` int64 (-1 for vertex 0), depth
    ``(n,)`` int64 (hops from vertex 0), order ``(n,)`` int32, generation ``(n,)`` int32
    (the step a vertex was born in), main ``(n,)`` bool (main trunk), theta ``(n,)``
    float64 (angle from vertical), phi ``(n,)`` float64 (azimuth).
    """
    th0 = geo[0]
    th_max = geo[1]
    ph0 = geo[2]
    ph_max = geo[3]
    thq = geo[4]
    thr = geo[5]
    bd = geo[6]
    b0 = geo[7]
    b_max = geo[8]
    avoid = geo[9]
    n = n_vertices
    half_pi = 0.5 * math.pi
    pos = np.zeros((n, 3))
    vparent = np.full(n, -1, np.int64)
    depth = np.zeros(n, np.int64)
    order = np.zeros(n, np.int32)
    gen = np.zeros(n, np.int32)
    main = np.zeros(n, np.bool_)
    theta = np.zeros(n)
    phi = np.zeros(n)
    droop = np.zeros(n)  # the seed's th[]: -1 marks the main trunk
    # Nutrients in float32 like the seed's C floats: the topology (which tip reaches 1 in
    # which step) then matches its vertex counts exactly (Table 3).
    acc = np.zeros(n, np.float32)
    ration = np.zeros(n, np.float32)
    f32 = np.float32(f)
    one = np.float32(1.0)
    tips = np.empty(n, np.int64)
    new_tips = np.empty(n, np.int64)
    pos[1, 1] = bd
    vparent[1] = 0
    depth[1] = 1
    main[1] = True
    ration[1] = one
    tips[0] = 1
    n_tips = 1
    k = 1  # highest vertex number so far
    nb = 0  # branchings so far (row of U)
    for step in range(1, generations + 1):
        n_new = 0
        born = 0
        kids_from = k + 1
        for ti in range(n_tips):
            i = tips[ti]
            if not main[i]:
                acc[i] = acc[i] + ration[i]
                if acc[i] < one:
                    new_tips[n_new] = i
                    n_new += 1
                    continue
            # ---- branch vertex i into k+1 (continuation) and k+2 (lateral)
            c1 = k + 1
            c2 = k + 2
            u = U[nb]
            if i == 1 or i == 2:
                droop[c1] = -1.0
                droop[c2] = thq
            elif droop[i] > 0.0:
                droop[c1] = droop[i]
                droop[c2] = droop[i] + thq
            else:
                droop[c1] = droop[i]
                droop[c2] = 0.0
            if droop[c1] == -1.0:
                t1 = thr * (th0 + u[0] * th_max)
            else:
                t1 = (1.0 + droop[c1]) * (th0 + u[0] * th_max)
            t2 = (1.0 + droop[c2]) * (th0 + u[1] * th_max)
            # Beyond the vertical +/-90 degrees the seed puts the angle back inside the
            # limit by a random amount up to theta_max.
            if t1 > half_pi:
                t1 = half_pi - u[2] * th_max
            elif t1 < -half_pi:
                t1 = -half_pi + u[2] * th_max
            if t2 > half_pi:
                t2 = half_pi - u[3] * th_max
            elif t2 < -half_pi:
                t2 = -half_pi + u[3] * th_max
            if i != 1:
                da = ph0 + u[5] * ph_max
                db = ph0 + u[6] * ph_max
                if u[4] < 0.5:  # which child turns +: the seed's r = 1 + random() % 2
                    p1 = phi[i] + da
                    p2 = phi[i] - db
                else:
                    p2 = phi[i] + da
                    p1 = phi[i] - db
            else:
                # the first node's two branches about 180 degrees apart
                p1 = ph0 + u[5] * ph_max
                p2 = p1 + math.pi + u[6] * ph_max
            l1 = b0 + u[7] * b_max
            l2 = b0 + u[8] * b_max
            _place(pos, i, c1, t1, p1, l1)
            _place(pos, i, c2, t2, p2, l2)
            if avoid > 0.0:
                # Beyond the seed: turn a lateral whose tip lands within avoid * length
                # of an existing vertex around its parent's axis (up to 7 tries of
                # 45 degrees), keeping the azimuth with the most room.
                lim = (avoid * l2) ** 2
                best = _min_dist2(pos, c2, i, pos[c2, 0], pos[c2, 1], pos[c2, 2])
                if best < lim:
                    best_p = p2
                    for a in range(1, 8):
                        pa = p2 + a * 0.25 * math.pi
                        _place(pos, i, c2, t2, pa, l2)
                        d = _min_dist2(pos, c2, i, pos[c2, 0], pos[c2, 1], pos[c2, 2])
                        if d > best:
                            best = d
                            best_p = pa
                        if d >= lim:
                            break
                    p2 = best_p
                    _place(pos, i, c2, t2, p2, l2)
            theta[c1] = t1
            theta[c2] = t2
            phi[c1] = p1
            phi[c2] = p2
            vparent[c1] = i
            vparent[c2] = i
            depth[c1] = depth[i] + 1
            depth[c2] = depth[i] + 1
            gen[c1] = step
            gen[c2] = step
            if main[i]:
                main[c1] = True
                order[c1] = 0
                ration[c2] = f32
            else:
                order[c1] = order[i]
                ration[c2] = ration[i] * f32
            order[c2] = order[i] + 1
            ration[c1] = ration[i]
            acc[c1] = 0.0
            acc[c2] = 0.0
            acc[i] = -1.0
            k += 2
            nb += 1
            born += 2
        # children are numbered after every older vertex, so appending them keeps the
        # tip list in vertex order, as the seed's scan over vertex numbers
        for c in range(kids_from, kids_from + born):
            new_tips[n_new] = c
            n_new += 1
        tmp = tips
        tips = new_tips
        new_tips = tmp
        n_tips = n_new
    return pos, vparent, depth, order, gen, main, theta, phi


@njit
def _child_counts(parent):
    """``(n,)`` int64: how many segments have each segment as ``parent`` (``-1``: none)."""
    nchild = np.zeros(parent.shape[0], np.int64)
    for s in range(parent.shape[0]):
        if parent[s] >= 0:
            nchild[parent[s]] += 1
    return nchild


@njit
def subtree_tips_kernel(parent):
    """Number of tips (segments without children) in each segment's sub-tree.

    ``parent`` ``(n,)`` int64 with ``parent[s] < s`` (parents before children). Returns
    ``(n,)`` int64.
    """
    n = parent.shape[0]
    nchild = _child_counts(parent)
    tips = np.zeros(n, np.int64)
    for s in range(n - 1, -1, -1):
        if nchild[s] == 0:
            tips[s] += 1
        if parent[s] >= 0:
            tips[parent[s]] += tips[s]
    return tips


@njit
def sag_kernel(start, end, radius, parent, sag, max_bend):
    """Bend branches down under the weight of their sub-trees (beyond the seed).

    ``start``, ``end`` ``(n, 3)``, ``radius`` ``(n,)``, ``parent`` ``(n,)`` int64 with
    parents before children and each segment starting at its parent's end. The mass of a
    segment is ``length * radius**2``; the torque at a segment's base is its sub-tree's
    mass times the horizontal distance to the sub-tree's centre of mass; the stiffness is
    ``radius**4``. Each segment bends down (about the horizontal axis across it) by
    ``sag * max_bend * q / max(q)`` with ``q = torque / stiffness``, and carries its
    sub-tree with it (bends add up along a path; a direction never passes straight down).
    Returns new ``(start, end)``.
    """
    n = start.shape[0]
    mass = np.zeros(n)
    mx = np.zeros(n)
    mz = np.zeros(n)
    for s in range(n):
        dx = end[s, 0] - start[s, 0]
        dy = end[s, 1] - start[s, 1]
        dz = end[s, 2] - start[s, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        m = L * radius[s] * radius[s]
        mass[s] = m
        mx[s] = m * 0.5 * (start[s, 0] + end[s, 0])
        mz[s] = m * 0.5 * (start[s, 2] + end[s, 2])
    for s in range(n - 1, 0, -1):
        p = parent[s]
        if p >= 0:
            mass[p] += mass[s]
            mx[p] += mx[s]
            mz[p] += mz[s]
    q = np.zeros(n)
    qmax = 0.0
    for s in range(n):
        if mass[s] <= 0.0 or radius[s] <= 0.0:
            continue
        cx = mx[s] / mass[s] - start[s, 0]
        cz = mz[s] / mass[s] - start[s, 2]
        r2 = radius[s] * radius[s]
        q[s] = mass[s] * math.sqrt(cx * cx + cz * cz) / (r2 * r2)
        if q[s] > qmax:
            qmax = q[s]
    bend = np.zeros(n)
    new_start = start.copy()
    new_end = end.copy()
    for s in range(n):
        p = parent[s]
        b = 0.0
        if qmax > 0.0:
            b = sag * max_bend * q[s] / qmax
        if p >= 0:
            b += bend[p]
            new_start[s, 0] = new_end[p, 0]
            new_start[s, 1] = new_end[p, 1]
            new_start[s, 2] = new_end[p, 2]
        bend[s] = b
        dx = end[s, 0] - start[s, 0]
        dy = end[s, 1] - start[s, 1]
        dz = end[s, 2] - start[s, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        h = math.sqrt(dx * dx + dz * dz)
        t = math.atan2(h, dy) + b  # angle from vertical, grown by the bend
        if t > math.pi - 1e-3:
            t = math.pi - 1e-3
        if h > 0.0:
            ux = dx / h
            uz = dz / h
        else:
            ux = 0.0
            uz = 0.0
            t = math.atan2(h, dy)  # a vertical segment has no horizontal lever to bend
        new_end[s, 0] = new_start[s, 0] + L * math.sin(t) * ux
        new_end[s, 1] = new_start[s, 1] + L * math.cos(t)
        new_end[s, 2] = new_start[s, 2] + L * math.sin(t) * uz
    return new_start, new_end


@njit
def leaves_kernel(start, end, parent, per_branch, e, cut):
    """Leaf segments on the branches the seed gives leaves: every tip and every segment
    whose children are all tips (``parent`` ``(n,)`` int64 of the stems, parents first).

    Each such branch gets ``per_branch`` leaves at its division points ``(j + 1) / k``,
    turned 50 degrees off the branch and spread round it by the golden angle (no random
    draws, so leaves never change the tree). A leaf is the cut face of a hexagonal prism of
    radius ``e`` cut at ``cut`` radians: length ``2 e / cos(cut)``, half-width
    ``e sqrt(3) / 2``.

    Returns ``lstart`` ``(m, 3)``, ``lend`` ``(m, 3)``, ``lradius`` ``(m,)``, ``lparent``
    ``(m,)`` int64 (the stem each leaf is on).
    """
    n = parent.shape[0]
    nchild = _child_counts(parent)
    nontip = np.zeros(n, np.int64)
    for s in range(n):
        if parent[s] >= 0 and nchild[s] > 0:
            nontip[parent[s]] += 1
    nb = 0
    for s in range(n):
        if nchild[s] == 0 or nontip[s] == 0:
            nb += 1
    if e <= 0.0:
        per_branch = 0
    m = nb * per_branch
    ls = np.empty((m, 3))
    le = np.empty((m, 3))
    lr = np.full(m, e * math.sqrt(3.0) / 2.0)
    lp = np.empty(m, np.int64)
    length = 2.0 * e / math.cos(cut)
    golden = 137.508 * math.pi / 180.0
    ct = math.cos(50.0 * math.pi / 180.0)
    st = math.sin(50.0 * math.pi / 180.0)
    q = 0
    for s in range(n):
        if per_branch == 0:
            break
        if not (nchild[s] == 0 or nontip[s] == 0):
            continue
        dx = end[s, 0] - start[s, 0]
        dy = end[s, 1] - start[s, 1]
        dz = end[s, 2] - start[s, 2]
        L = math.sqrt(dx * dx + dy * dy + dz * dz)
        if L < 1e-12:
            L = 1e-12
        ax, ay, az = dx / L, dy / L, dz / L
        ux, uy, uz, vx, vy, vz = perpendicular_frame(ax, ay, az)
        for j in range(per_branch):
            t = (j + 1) / per_branch
            psi = (j + s) * golden
            cp = math.cos(psi)
            sp = math.sin(psi)
            wx = ct * ax + st * (cp * ux + sp * vx)
            wy = ct * ay + st * (cp * uy + sp * vy)
            wz = ct * az + st * (cp * uz + sp * vz)
            ls[q, 0] = start[s, 0] + t * dx
            ls[q, 1] = start[s, 1] + t * dy
            ls[q, 2] = start[s, 2] + t * dz
            le[q, 0] = ls[q, 0] + length * wx
            le[q, 1] = ls[q, 1] + length * wy
            le[q, 2] = ls[q, 2] + length * wz
            lp[q] = s
            q += 1
    return ls, le, lr, lp
