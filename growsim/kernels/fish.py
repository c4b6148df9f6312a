"""Numba kernels of the fish in a tank (seed 001, Okusa, "GA-tuned path control of a fish
agent", 2003): one fish's path, or a whole population's collision counts, frame by frame.

Every fish is one row of a ``(n, len(FISH_FIELDS))`` float64 table (:data:`FISH_FIELDS`:
start position in pixels, scale, view distance, avoidance angle in radians, maximum speed,
heading and pitch in radians, preferred turn 0/1, the body's half length, width and height
at scale 1). The tank is its size ``(3,)`` and two ``(k, 4)`` tables of spheres
``[cx, cy, cz, radius]`` and cubes ``[cx, cy, cz, half edge]``, passed to the kernels as
one tuple ``tank = (size, spheres, cubes)``.

One frame (the behaviour of ``docs/models/fish.md``):

1. when not avoiding, look: side walls seen by the 45-degree horizontal view sector within
   the view distance; obstacles whose centre lies within 45 degrees left/right and up/down
   of the heading and whose surface (a cube counts as a sphere of radius half edge x
   sqrt(2)) is closer than the view distance; the top or bottom wall when pitched toward
   it and closer than the view distance. Two or more side walls start pattern b (turn the
   avoidance angle + 30 degrees), one side wall or an obstacle pattern a (the avoidance
   angle), only the top/bottom wall pattern c (pitch away 5 degrees a frame for 9
   frames). Turns go the preferred way with probability 3/4;
2. steer: a turn frame turns the heading 10 degrees (the rest on the last frame) and slows
   by 0.01 (not below 5); a straight frame recovers 0.1 of speed up to the maximum and,
   every 50 straight frames, tilts the pitch 3 degrees (up when frame // 50 is even,
   down when odd);
3. move ``0.25 x speed`` along the heading;
4. count collisions: each of the 7 body points (centre, nose/tail, left/right, top/bottom)
   scores 1 when on or outside the tank's walls and 1 per obstacle it is inside.

Randomness: one SplitMix64 stream per fish from its seed, one draw per turn, so a fish
swims the same alone or in a population.
"""

from __future__ import annotations

import math

import numpy as np

from growsim.kernels.config import njit

__all__ = [
    "FISH_FIELDS",
    "count_collisions",
    "population_collisions",
    "swim_path",
    "uniform",
]

#: columns of a fish table (lengths in pixels, angles in radians)
FISH_FIELDS = (
    "x",
    "y",
    "z",
    "scale",
    "view",
    "angle",
    "speed",
    "heading",
    "pitch",
    "turn",
    "half_length",
    "half_width",
    "half_height",
)

TURN_STEP = math.radians(10.0)
EXTRA_TWO_WALLS = math.radians(30.0)
PITCH_STEP = math.radians(5.0)
PITCH_FRAMES = 9
PITCH_LIMIT = math.radians(80.0)
SLOW = 0.01
MIN_SPEED = 5.0
RECOVER = 0.1
WOBBLE_EVERY = 50
WOBBLE = math.radians(3.0)
STEP = 0.25
PREFERRED = 0.75
COS45 = math.sqrt(0.5)
SQRT2 = math.sqrt(2.0)
COS_TURN, SIN_TURN = math.cos(TURN_STEP), math.sin(TURN_STEP)
COS_PITCH, SIN_PITCH = math.cos(PITCH_STEP), math.sin(PITCH_STEP)
COS_WOBBLE, SIN_WOBBLE = math.cos(WOBBLE), math.sin(WOBBLE)
#: the manoeuvre codes recorded per frame
STRAIGHT, TURNING, PITCHING = 0, 1, 2


@njit(inline="always")
def _splitmix(state):
    state = state + np.uint64(0x9E3779B97F4A7C15)
    z = state
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    z = z ^ (z >> np.uint64(31))
    return state, float(z >> np.uint64(11)) * (1.0 / 9007199254740992.0)


def uniform(seed: int, k: int) -> np.ndarray:
    """The first ``k`` uniforms of a fish's random stream (SplitMix64 from ``seed``).

    Examples
    --------
    >>> u = uniform(1, 3)
    >>> u.shape, bool(((u >= 0) & (u < 1)).all())
    ((3,), True)
    """
    out = np.empty(int(k))
    _uniforms(np.uint64(seed), out)
    return out


@njit
def _uniforms(state, out):
    for i in range(out.shape[0]):
        state, out[i] = _splitmix(state)


@njit(inline="always")
def _point_hits(q, box, obstacles, walls, near):
    """Collisions of the point ``q`` ``(x, y, z)``: 1 when ``walls`` and on or outside the
    tank ``box`` ``(X, Y, Z)``, 1 per sphere and cube of ``obstacles`` ``(spheres, cubes)``
    it lies inside, among those flagged in ``near`` ``(near_s, near_c)``."""
    qx, qy, qz = q
    X, Y, Z = box
    spheres, cubes = obstacles
    near_s, near_c = near
    n = 0
    if walls and (qx <= 0.0 or qx >= X or qy <= 0.0 or qy >= Y or qz <= 0.0 or qz >= Z):
        n += 1
    for k in range(spheres.shape[0]):
        if near_s[k]:
            dx = qx - spheres[k, 0]
            dy = qy - spheres[k, 1]
            dz = qz - spheres[k, 2]
            if dx * dx + dy * dy + dz * dz < spheres[k, 3] * spheres[k, 3]:
                n += 1
    for k in range(cubes.shape[0]):
        if near_c[k]:
            a = cubes[k, 3]
            if (
                abs(qx - cubes[k, 0]) < a
                and abs(qy - cubes[k, 1]) < a
                and abs(qz - cubes[k, 2]) < a
            ):
                n += 1
    return n


@njit(inline="always")
def _body_hits(p, pose, body, box, obstacles, near):
    """Collisions of the 7 body points at centre ``p`` ``(x, y, z)`` with ``pose`` the
    heading's and pitch's cosines and sines ``(ch, sh, cp, sp)``, ``body`` its half
    length, width and height and bounding radius ``(hl, hw, hh, br)``; ``box``,
    ``obstacles`` and the scratch flags ``near`` as :func:`_point_hits`."""
    px, py, pz = p
    ch, sh, cp, sp = pose
    hl, hw, hh, br = body
    X, Y, Z = box
    spheres, cubes = obstacles
    near_s, near_c = near
    walls = not (
        px - br > 0.0 and px + br < X and py - br > 0.0 and py + br < Y
        and pz - br > 0.0 and pz + br < Z
    )  # fmt: skip
    anyobs = False
    for k in range(spheres.shape[0]):
        dx = px - spheres[k, 0]
        dy = py - spheres[k, 1]
        dz = pz - spheres[k, 2]
        r = spheres[k, 3] + br
        near_s[k] = dx * dx + dy * dy + dz * dz < r * r
        anyobs = anyobs or near_s[k]
    for k in range(cubes.shape[0]):
        a = cubes[k, 3] + br
        near_c[k] = (
            abs(px - cubes[k, 0]) < a and abs(py - cubes[k, 1]) < a and abs(pz - cubes[k, 2]) < a
        )
        anyobs = anyobs or near_c[k]
    if not anyobs:
        if not walls:
            return 0
        if (
            px + br <= 0.0 or px - br >= X or py + br <= 0.0 or py - br >= Y
            or pz + br <= 0.0 or pz - br >= Z
        ):  # fmt: skip
            return 7  # the whole body is beyond one wall
    fx, fy, fz = cp * ch, sp, cp * sh
    sx, sz = -sh, ch
    ux, uy, uz = -ch * sp, cp, -sh * sp
    n = _point_hits((px, py, pz), box, obstacles, walls, near)
    for sign in (1.0, -1.0):
        a = sign * hl
        n += _point_hits((px + a * fx, py + a * fy, pz + a * fz), box, obstacles, walls, near)
        a = sign * hw
        n += _point_hits((px + a * sx, py, pz + a * sz), box, obstacles, walls, near)
        a = sign * hh
        n += _point_hits((px + a * ux, py + a * uy, pz + a * uz), box, obstacles, walls, near)
    return n


@njit(inline="always")
def _tilt(ph, cp, sp, d, cd, sd):
    """Pitch ``ph`` (cosine ``cp``, sine ``sp``) turned by ``d`` (cosine ``cd``, sine
    ``sd``), kept within +-PITCH_LIMIT."""
    ph += d
    if ph > PITCH_LIMIT or ph < -PITCH_LIMIT:
        ph = PITCH_LIMIT if ph > 0.0 else -PITCH_LIMIT
        return ph, math.cos(ph), math.sin(ph)
    return ph, cp * cd - sp * sd, sp * cd + cp * sd


@njit(inline="always")
def _side_wall_seen(d, nx, nz, ch, sh, view):
    """Is a side wall at distance ``d`` in direction ``(nx, nz)`` inside the 45-degree
    horizontal view sector, within ``view``?"""
    if d >= view:
        return False
    c = ch * nx + sh * nz  # cosine of the angle between heading and the wall's direction
    if c >= COS45:
        return True
    k = (c + abs(ch * nz - sh * nx)) / SQRT2  # cosine of (that angle - 45 degrees)
    return k > 0.0 and d < view * k


@njit
def _swim(g, seed, tank, frames, track, record):
    """One fish ``g`` (a row of a fish table) from its random stream's state ``seed`` in
    ``tank`` ``(size, spheres, cubes)`` for ``frames`` frames: its total collisions; with
    ``record``, each frame's position, angles, hits and manoeuvre go into ``track``
    ``(pos, ang, hits, modes)`` (see :func:`swim_path`)."""
    size, spheres, cubes = tank
    pos, ang, hits, mode_out = track
    X, Y, Z = size[0], size[1], size[2]
    px, py, pz = g[0], g[1], g[2]
    scale, view, angle, vmax = g[3], g[4], g[5], g[6]
    h, ph = g[7], g[8]
    pref = 1.0 if g[9] >= 0.5 else -1.0
    hl, hw, hh = g[10] * scale, g[11] * scale, g[12] * scale
    br = max(hl, max(hw, hh))
    near_s = np.zeros(spheres.shape[0], dtype=np.bool_)
    near_c = np.zeros(cubes.shape[0], dtype=np.bool_)
    v = vmax
    mode = STRAIGHT
    remaining = 0.0
    tdir = 1.0
    left = 0
    pdir = 0.0
    straight = 0
    state = seed
    ch, sh, cp, sp = math.cos(h), math.sin(h), math.cos(ph), math.sin(ph)
    if record:
        pos[0, 0], pos[0, 1], pos[0, 2] = px, py, pz
        ang[0, 0], ang[0, 1], ang[0, 2] = h, ph, v
        ang[0, 3], ang[0, 4], ang[0, 5], ang[0, 6] = ch, sh, cp, sp
        hits[0] = 0
        mode_out[0] = STRAIGHT
    total = 0
    for f in range(frames):
        if mode == STRAIGHT:
            nside = 0
            if _side_wall_seen(px, -1.0, 0.0, ch, sh, view):
                nside += 1
            if _side_wall_seen(X - px, 1.0, 0.0, ch, sh, view):
                nside += 1
            if _side_wall_seen(pz, 0.0, -1.0, ch, sh, view):
                nside += 1
            if _side_wall_seen(Z - pz, 0.0, 1.0, ch, sh, view):
                nside += 1
            seen = nside > 0
            if not seen:
                fx, fy, fz = cp * ch, sp, cp * sh
                ux, uy, uz = -ch * sp, cp, -sh * sp
                for k in range(spheres.shape[0] + cubes.shape[0]):
                    if k < spheres.shape[0]:
                        rx = spheres[k, 0] - px
                        ry = spheres[k, 1] - py
                        rz = spheres[k, 2] - pz
                        rad = spheres[k, 3]
                    else:
                        j = k - spheres.shape[0]
                        rx = cubes[j, 0] - px
                        ry = cubes[j, 1] - py
                        rz = cubes[j, 2] - pz
                        rad = cubes[j, 3] * SQRT2
                    reach = view + rad
                    if rx * rx + ry * ry + rz * rz < reach * reach:
                        fwd = rx * fx + ry * fy + rz * fz
                        if fwd > 0.0:
                            side = -rx * sh + rz * ch
                            up = rx * ux + ry * uy + rz * uz
                            if abs(side) <= fwd and abs(up) <= fwd:
                                seen = True
                                break
            if seen:
                mode = TURNING
                remaining = angle + EXTRA_TWO_WALLS if nside >= 2 else angle
                state, u = _splitmix(state)
                tdir = pref if u < PREFERRED else -pref
            elif (sp > 0.0 and Y - py < view) or (sp < 0.0 and py < view):
                mode = PITCHING
                left = PITCH_FRAMES
                pdir = -1.0 if sp > 0.0 else 1.0
        if mode == TURNING:
            if remaining > TURN_STEP:
                step, cs, sn = TURN_STEP, COS_TURN, SIN_TURN
            else:
                step, cs, sn = remaining, math.cos(remaining), math.sin(remaining)
            h += tdir * step
            sn *= tdir
            ch, sh = ch * cs - sh * sn, sh * cs + ch * sn
            remaining -= step
            v -= SLOW
            if v < MIN_SPEED:
                v = MIN_SPEED
            if remaining <= 1e-12:
                mode = STRAIGHT
            code = TURNING
        elif mode == PITCHING:
            ph, cp, sp = _tilt(ph, cp, sp, pdir * PITCH_STEP, COS_PITCH, pdir * SIN_PITCH)
            left -= 1
            if left == 0:
                mode = STRAIGHT
            code = PITCHING
        else:
            if v < vmax:
                v += RECOVER
                if v > vmax:
                    v = vmax
            straight += 1
            if straight == WOBBLE_EVERY:
                straight = 0
                w = 1.0 if (f // WOBBLE_EVERY) % 2 == 0 else -1.0
                ph, cp, sp = _tilt(ph, cp, sp, w * WOBBLE, COS_WOBBLE, w * SIN_WOBBLE)
            code = STRAIGHT
        d = STEP * v
        px += d * cp * ch
        py += d * sp
        pz += d * cp * sh
        n = _body_hits((px, py, pz), (ch, sh, cp, sp), (hl, hw, hh, br), (X, Y, Z),
                       (spheres, cubes), (near_s, near_c))  # fmt: skip
        total += n
        if record:
            pos[f + 1, 0], pos[f + 1, 1], pos[f + 1, 2] = px, py, pz
            ang[f + 1, 0], ang[f + 1, 1], ang[f + 1, 2] = h, ph, v
            ang[f + 1, 3], ang[f + 1, 4], ang[f + 1, 5], ang[f + 1, 6] = ch, sh, cp, sp
            hits[f + 1] = n
            mode_out[f + 1] = code
    return total


@njit
def _population(fish, seeds, tank, frames, out):
    track = (np.zeros((0, 3)), np.zeros((0, 7)), np.zeros(0, dtype=np.int32),
             np.zeros(0, dtype=np.int8))  # fmt: skip
    for i in range(fish.shape[0]):
        out[i] = _swim(fish[i], seeds[i], tank, frames, track, False)


@njit
def _path(g, seed, tank, frames, track):
    return _swim(g, seed, tank, frames, track, True)


@njit
def _recount(pos, ang, g, tank, out):
    size, spheres, cubes = tank
    scale = g[3]
    hl, hw, hh = g[10] * scale, g[11] * scale, g[12] * scale
    br = max(hl, max(hw, hh))
    near_s = np.zeros(spheres.shape[0], dtype=np.bool_)
    near_c = np.zeros(cubes.shape[0], dtype=np.bool_)
    total = 0
    for f in range(1, pos.shape[0]):
        n = _body_hits(
            (pos[f, 0], pos[f, 1], pos[f, 2]), (ang[f, 3], ang[f, 4], ang[f, 5], ang[f, 6]),
            (hl, hw, hh, br), (size[0], size[1], size[2]), (spheres, cubes), (near_s, near_c),
        )  # fmt: skip
        out[f] = n
        total += n
    return total


def _geometry(size, spheres, cubes):
    size = np.ascontiguousarray(size, dtype=np.float64).reshape(3)
    spheres = np.ascontiguousarray(spheres, dtype=np.float64).reshape(-1, 4)
    cubes = np.ascontiguousarray(cubes, dtype=np.float64).reshape(-1, 4)
    return size, spheres, cubes


def _fish_table(fish) -> np.ndarray:
    fish = np.ascontiguousarray(fish, dtype=np.float64)
    if fish.ndim != 2 or fish.shape[1] != len(FISH_FIELDS):
        raise ValueError(f"fish table must be (n, {len(FISH_FIELDS)}), got {fish.shape}")
    if not np.isfinite(fish).all():
        raise ValueError("fish table holds NaN or inf")
    return fish


def population_collisions(fish, seeds, size, spheres, cubes, frames: int) -> np.ndarray:
    """Total collisions of each fish of a ``(n, 13)`` table over ``frames`` frames.

    ``seeds`` ``(n,)`` uint64: each fish's random stream. Returns ``(n,)`` int64.

    Examples
    --------
    >>> fish = np.array([[150, 200, 150, 4, 60, np.radians(150), 15, 0, 0, 1, 2, .75, 1]])
    >>> out = population_collisions(fish, [1], [300, 400, 300], np.zeros((0, 4)),
    ...                             np.zeros((0, 4)), 2000)
    >>> out.shape, out.dtype
    ((1,), dtype('int64'))
    """
    fish = _fish_table(fish)
    seeds = np.ascontiguousarray(seeds, dtype=np.uint64).reshape(len(fish))
    size, spheres, cubes = _geometry(size, spheres, cubes)
    out = np.zeros(len(fish), dtype=np.int64)
    _population(fish, seeds, (size, spheres, cubes), int(frames), out)
    return out


def swim_path(g, seed: int, size, spheres, cubes, frames: int):
    """One fish's path: ``(positions (frames+1, 3), angles (frames+1, 7), hits (frames+1,)
    int32, modes (frames+1,) int8, total collisions)``; ``angles`` holds heading, pitch,
    speed and the cosines and sines of heading and pitch; row 0 is the start (no
    collision counted there).

    Examples
    --------
    >>> g = np.array([150, 200, 150, 4, 60, np.radians(150), 15, 0, 0, 1, 2, .75, 1])
    >>> pos, ang, hits, modes, total = swim_path(g, 1, [300, 400, 300], np.zeros((0, 4)),
    ...                                          np.zeros((0, 4)), 100)
    >>> pos.shape, float(pos[1, 0] - pos[0, 0]), total
    ((101, 3), 3.75, 0)
    """
    g = _fish_table(np.asarray(g, dtype=np.float64).reshape(1, -1))[0]
    size, spheres, cubes = _geometry(size, spheres, cubes)
    frames = int(frames)
    pos = np.zeros((frames + 1, 3))
    ang = np.zeros((frames + 1, 7))
    hits = np.zeros(frames + 1, dtype=np.int32)
    modes = np.zeros(frames + 1, dtype=np.int8)
    total = _path(g, np.uint64(seed), (size, spheres, cubes), frames, (pos, ang, hits, modes))
    return pos, ang, hits, modes, int(total)


def count_collisions(pos, ang, g, size, spheres, cubes):
    """Collisions along a recorded path (``pos``, ``ang`` as :func:`swim_path` returns:
    the body's orientation is read from the cosines and sines of ``ang``, exactly as the
    fish swam) of the fish ``g`` in a tank: ``(per-frame hits (frames+1,) int32, total)``.

    Examples
    --------
    >>> g = np.array([150, 200, 150, 4, 60, np.radians(150), 15, 0, 0, 1, 2, .75, 1])
    >>> pos, ang, *_ = swim_path(g, 1, [300, 400, 300], np.zeros((0, 4)), np.zeros((0, 4)), 10)
    >>> int(count_collisions(pos, ang, g, [100, 400, 300], np.zeros((0, 4)),
    ...                      np.zeros((0, 4)))[1]) > 0
    True
    """
    g = _fish_table(np.asarray(g, dtype=np.float64).reshape(1, -1))[0]
    size, spheres, cubes = _geometry(size, spheres, cubes)
    pos = np.ascontiguousarray(pos, dtype=np.float64)
    ang = np.ascontiguousarray(ang, dtype=np.float64)
    out = np.zeros(len(pos), dtype=np.int32)
    total = _recount(pos, ang, g, (size, spheres, cubes), out)
    return out, int(total)
