"""Oracles of the Honda tree's kernels (:mod:`growsim.kernels.honda`): plain Python loops.

The growth oracle follows the seed's first program literally: every step scans all vertex
numbers 1..l, feeds the non-main tips, and branches those whose total reached 1.
"""

from __future__ import annotations

import math

import numpy as np


def grow_kernel(f, generations, geo, U):
    """Vertex positions, vertex parents, orders and generations of the grown tree."""
    th0, th_max, ph0, ph_max, thq, thr, bd, b0, b_max, avoid = (float(x) for x in geo)
    pts = {0: np.zeros(3), 1: np.array([0.0, bd, 0.0])}
    par = {1: 0}
    x1 = {1: np.float32(2.0)}  # 2 = main trunk, -1 = done branching
    x2 = {1: np.float32(1.0)}
    th = {1: 0.0}
    phi = {1: 0.0}
    order = {0: 0, 1: 0}
    gen = {0: 0, 1: 0}
    l = k = 1
    nb = 0

    def place(i, t, p, b):
        return pts[i] + b * np.array(
            [math.sin(t) * math.cos(p), math.cos(t), math.sin(t) * math.sin(p)]
        )

    for step in range(1, generations + 1):
        for i in range(1, l + 1):
            if 0 <= x1[i] < 1:
                x1[i] = np.float32(x1[i] + x2[i])
            if x1[i] < 1:
                continue
            u = U[nb]
            nb += 1
            if i in (1, 2):
                th[k + 1], th[k + 2] = -1.0, thq
            elif th[i] > 0:
                th[k + 1], th[k + 2] = th[i], th[i] + thq
            else:
                th[k + 1], th[k + 2] = th[i], 0.0
            base1 = th0 + u[0] * th_max
            t1 = thr * base1 if th[k + 1] == -1.0 else (1 + th[k + 1]) * base1
            t2 = (1 + th[k + 2]) * (th0 + u[1] * th_max)
            t = [t1, t2]
            for g in range(2):
                if t[g] > math.pi / 2:
                    t[g] = math.pi / 2 - u[2 + g] * th_max
                elif t[g] < -math.pi / 2:
                    t[g] = -math.pi / 2 + u[2 + g] * th_max
            if i != 1:
                plus = phi[i] + ph0 + u[5] * ph_max
                minus = phi[i] - (ph0 + u[6] * ph_max)
                p = [plus, minus] if u[4] < 0.5 else [minus, plus]
            else:
                a = ph0 + u[5] * ph_max
                p = [a, a + math.pi + u[6] * ph_max]
            b = [b0 + u[7] * b_max, b0 + u[8] * b_max]
            pts[k + 1] = place(i, t[0], p[0], b[0])
            pts[k + 2] = place(i, t[1], p[1], b[1])
            if avoid > 0:
                lim = (avoid * b[1]) ** 2

                def room(q, i=i, k=k):
                    return min(
                        (float(np.sum((pts[j] - q) ** 2)) for j in range(k + 2) if j != i),
                        default=np.inf,
                    )

                best = room(pts[k + 2])
                if best < lim:
                    best_p = p[1]
                    for a in range(1, 8):
                        pa = p[1] + a * 0.25 * math.pi
                        d = room(place(i, t[1], pa, b[1]))
                        if d > best:
                            best, best_p = d, pa
                        if d >= lim:
                            break
                    p[1] = best_p
                    pts[k + 2] = place(i, t[1], p[1], b[1])
            for c, pc in ((k + 1, p[0]), (k + 2, p[1])):
                par[c] = i
                phi[c] = pc
                gen[c] = step
            order[k + 1] = order[i]
            order[k + 2] = order[i] + 1
            if x1[i] == 2:
                x1[k + 1], x2[k + 1] = np.float32(2), np.float32(1)
                x1[k + 2], x2[k + 2] = np.float32(0), np.float32(f)
            else:
                x1[k + 1], x2[k + 1] = np.float32(0), x2[i]
                x1[k + 2], x2[k + 2] = np.float32(0), np.float32(x2[i] * np.float32(f))
            x1[i] = np.float32(-1)
            k += 2
        l = k
    n = l + 1
    pos = np.array([pts[v] for v in range(n)])
    vparent = np.array([-1] + [par[v] for v in range(1, n)])
    return (
        pos,
        vparent,
        np.array([order[v] for v in range(n)]),
        np.array([gen[v] for v in range(n)]),
    )


def sag_kernel(start, end, radius, parent, sag, max_bend):
    """New segment end points after bending each branch by its sub-tree's load."""
    n = len(start)
    L = np.linalg.norm(end - start, axis=1)
    m = L * radius**2
    mid = (start + end) / 2
    children = [[] for _ in range(n)]
    for s in range(n):
        if parent[s] >= 0:
            children[parent[s]].append(s)

    def subtree(s):
        out = [s]
        for c in children[s]:
            out += subtree(c)
        return out

    q = np.zeros(n)
    for s in range(n):
        sub = subtree(s)
        M = m[sub].sum()
        if M <= 0 or radius[s] <= 0:
            continue
        com = (m[sub, None] * mid[sub]).sum(0) / M
        lever = math.hypot(com[0] - start[s, 0], com[2] - start[s, 2])
        q[s] = M * lever / radius[s] ** 4
    bend = sag * max_bend * q / q.max() if q.max() > 0 else np.zeros(n)
    total = bend.copy()
    for s in range(n):
        if parent[s] >= 0:
            total[s] += total[parent[s]]
    ns, ne = start.copy(), end.copy()
    for s in range(n):
        if parent[s] >= 0:
            ns[s] = ne[parent[s]]
        d = end[s] - start[s]
        h = math.hypot(d[0], d[2])
        t = math.atan2(h, d[1])
        if h > 0:
            t = min(t + total[s], math.pi - 1e-3)
            ux, uz = d[0] / h, d[2] / h
        else:
            ux = uz = 0.0
        ne[s] = ns[s] + L[s] * np.array([math.sin(t) * ux, math.cos(t), math.sin(t) * uz])
    return ns, ne


def leaves_kernel(start, end, seg_ids, per_branch, e, cut_deg):
    """Leaf segments along the stem segments ``seg_ids``: ``per_branch`` leaves at the
    branch's division points, turned 50 degrees off the branch, round the branch by the
    golden angle (deterministic: the leaves do not consume random draws)."""
    m = seg_ids.size * per_branch
    if m == 0 or e <= 0.0:
        return None
    sid = np.repeat(seg_ids, per_branch)
    j = np.tile(np.arange(per_branch), seg_ids.size)
    a = start[sid]
    d = end[sid] - a
    t = ((j + 1) / per_branch)[:, None]
    att = a + t * d
    ax = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    helper = np.eye(3)[np.argmin(np.abs(ax), axis=1)]  # least aligned axis, as the kernel
    e1 = np.cross(ax, helper)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(ax, e1)
    psi = (j + sid) * (137.508 * math.pi / 180.0)
    tilt = 50.0 * math.pi / 180.0
    w = math.cos(tilt) * ax + math.sin(tilt) * (
        np.cos(psi)[:, None] * e1 + np.sin(psi)[:, None] * e2
    )
    # the cut face of a hexagonal prism of radius e cut at angle g: a hexagon stretched
    # to length 2e / cos(g) along the leaf, sqrt(3) e wide
    length = 2.0 * e / math.cos(math.radians(cut_deg))
    return att, att + length * w, np.full(m, e * math.sqrt(3.0) / 2.0), sid
