"""Oracle of the fish kernels (:mod:`growsim.kernels.fish`): one fish, plain Python.

Written from the behaviour as described (``docs/models/fish.md``), with vectors and
trigonometry of the angles every frame, no shortcuts: every body point is tested against
every wall and obstacle.
"""

from __future__ import annotations

import math

import numpy as np

MASK = (1 << 64) - 1


class SplitMix:
    """SplitMix64, the fish's random stream."""

    def __init__(self, seed):
        self.state = int(seed) & MASK

    def uniform(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        z = z ^ (z >> 31)
        return (z >> 11) / 2.0**53


def axes(heading, pitch):
    """Forward, side and up unit vectors of a fish."""
    f = np.array(
        [math.cos(pitch) * math.cos(heading), math.sin(pitch), math.cos(pitch) * math.sin(heading)]
    )
    s = np.array([-math.sin(heading), 0.0, math.cos(heading)])
    u = np.cross(s, f)
    return f, s, u


def body_points(p, heading, pitch, hl, hw, hh):
    """The 7 collision points."""
    f, s, u = axes(heading, pitch)
    return [p, p + hl * f, p - hl * f, p + hw * s, p - hw * s, p + hh * u, p - hh * u]


def hits(points, size, spheres, cubes):
    """Collisions of the points: 1 per point on/outside the walls, 1 per obstacle it is in."""
    n = 0
    for q in points:
        if any(q[k] <= 0 or q[k] >= size[k] for k in range(3)):
            n += 1
        for c in spheres:
            if np.linalg.norm(q - c[:3]) < c[3]:
                n += 1
        for c in cubes:
            if all(abs(q[k] - c[k]) < c[3] for k in range(3)):
                n += 1
    return n


def side_walls_seen(p, heading, size, view):
    """How many side walls the 45-degree horizontal sector reaches within ``view``."""
    walls = [
        (p[0], math.pi),
        (size[0] - p[0], 0.0),
        (p[2], -math.pi / 2),
        (size[2] - p[2], math.pi / 2),
    ]
    n = 0
    for d, direction in walls:
        delta = abs((heading - direction + math.pi) % (2 * math.pi) - math.pi)
        if delta >= math.radians(135):
            continue
        # the nearest ray of the sector: along the wall's normal, or the sector's edge
        off = max(0.0, delta - math.pi / 4)
        if d / math.cos(off) < view if d >= 0 else d < view:
            n += 1
    return n


def obstacle_seen(p, heading, pitch, view, spheres, cubes):
    """Is an obstacle's centre within 45 degrees of the heading (left/right and up/down)
    and its surface closer than ``view``?"""
    f, s, u = axes(heading, pitch)
    obs = [(c[:3], c[3]) for c in spheres] + [(c[:3], c[3] * math.sqrt(2)) for c in cubes]
    for centre, radius in obs:
        r = centre - p
        if np.linalg.norm(r) - radius >= view:
            continue
        a, b, c = r @ f, r @ s, r @ u
        if a > 0 and abs(b) <= a and abs(c) <= a:
            return True
    return False


def swim_path(g, seed, size, spheres, cubes, frames):
    """Positions, [heading, pitch, speed], hits and manoeuvre per frame, and the total."""
    g = [float(x) for x in g]
    size = [float(x) for x in size]
    spheres = np.asarray(spheres, float).reshape(-1, 4)
    cubes = np.asarray(cubes, float).reshape(-1, 4)
    p = np.array(g[:3])
    scale, view, angle, vmax, heading, pitch = g[3:9]
    pref = 1.0 if g[9] >= 0.5 else -1.0
    hl, hw, hh = (x * scale for x in g[10:13])
    rng = SplitMix(seed)
    v = vmax
    mode, remaining, tdir, left, pdir, straight = 0, 0.0, 1.0, 0, 0.0, 0
    limit = math.radians(80)
    pos, ang, hit, modes = [p.copy()], [[heading, pitch, v]], [0], [0]
    for frame in range(frames):
        if mode == 0:
            nside = side_walls_seen(p, heading, size, view)
            if nside or obstacle_seen(p, heading, pitch, view, spheres, cubes):
                mode = 1
                remaining = angle + (math.radians(30) if nside >= 2 else 0.0)
                tdir = pref if rng.uniform() < 0.75 else -pref
            elif (pitch > 0 and size[1] - p[1] < view) or (pitch < 0 and p[1] < view):
                mode, left, pdir = 2, 9, (-1.0 if pitch > 0 else 1.0)
        code = mode
        if mode == 1:
            step = min(math.radians(10), remaining)
            heading += tdir * step
            remaining -= step
            v = max(5.0, v - 0.01)
            if remaining <= 1e-12:
                mode = 0
        elif mode == 2:
            pitch = min(limit, max(-limit, pitch + pdir * math.radians(5)))
            left -= 1
            if left == 0:
                mode = 0
        else:
            v = min(vmax, v + 0.1) if v < vmax else v
            straight += 1
            if straight == 50:
                straight = 0
                w = math.radians(3) if (frame // 50) % 2 == 0 else -math.radians(3)
                pitch = min(limit, max(-limit, pitch + w))
        f, _, _ = axes(heading, pitch)
        p = p + 0.25 * v * f
        n = hits(body_points(p, heading, pitch, hl, hw, hh), size, spheres, cubes)
        pos.append(p.copy())
        ang.append([heading, pitch, v])
        hit.append(n)
        modes.append(code)
    return np.array(pos), np.array(ang), np.array(hit), np.array(modes), int(sum(hit))
