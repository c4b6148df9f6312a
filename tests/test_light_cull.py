"""Capsules left out of a shadow map that cannot change its answers
(growsim.kernels.light._culled): a plant among its copies (a periodic stand) judged at its
own points gives the answers of the whole map, pixel by pixel (tests/naive/light.py)."""

from __future__ import annotations

import numpy as np
import pytest
from naive import light as naive
from test_light import random_direction, random_tree

from growsim.env.light import view_basis
from growsim.kernels import light as kernels
from growsim.kernels.stand import periodic_shifts


def stand(rng, n, spacing, rings):
    """A random plant and its copies moved by :func:`periodic_shifts` (the plant first),
    as :func:`growsim.kernels.hormone.walls_light` joins them, and points on the plant's
    segments (the walls' points: on the surface, halfway along)."""
    start, end, radius = random_tree(rng, n)
    moves = np.concatenate([np.zeros((1, 3)), periodic_shifts(spacing, rings, 3)])
    all_s = np.concatenate([start + m for m in moves])
    all_e = np.concatenate([end + m for m in moves])
    all_r = np.tile(radius, len(moves))
    side = rng.normal(size=(n, 3))
    side /= np.linalg.norm(side, axis=1)[:, None]
    points = start + 0.5 * (end - start) + radius[:, None] * side
    return (all_s, all_e, all_r), points


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("soft", [False, True])
def test_a_plant_among_copies_gets_the_whole_maps_answers(seed, soft):
    rng = np.random.default_rng(seed)
    # spacings from far apart (most copies out of the plant's box) to crowded
    spacing = (2.0, 5.0, 12.0, 40.0)[seed % 4]
    (s, e, r), points = stand(rng, 40, spacing, 1 + seed % 2)
    d = random_direction(rng) if seed % 3 else np.array([0.0, -1.0, 0.0])
    u, v = view_basis(d)
    res = (64, 100, 256)[seed % 3]
    trans = rng.uniform(0.05, 0.95, len(s)) if soft else None
    normals = np.tile(-d, (len(points), 1))  # every point faces the light: cosine 1
    got = kernels.point_light_into(
        (s, e, r, np.array([0, len(s)])), (points, np.array([0, len(points)]), normals),
        (d[None], u[None], v[None], np.ones(1)),
        (res, 0.5, soft, trans if soft else np.empty(0)), kernels.shadow_scratch(res),
        np.empty(len(points)), np.zeros((0, 3)),
    )  # fmt: skip
    framing = kernels.plant_frames(s, e, r, np.array([0, len(s)]), u, v, res)[0]
    want = naive.map_exposure((s, e, r), points, (u, v, d), res, 0.5, trans, framing)
    cos = -(normals[:, 0] * d[0] + normals[:, 1] * d[1] + normals[:, 2] * d[2])  # 1 to rounding
    np.testing.assert_allclose(got, want * cos, rtol=1e-12, atol=0)
    if spacing < 12.0:  # crowded: some points shaded, some lit
        assert (got < 0.5).any() and (got > 0.5).any()


def test_culled_leaves_out_only_capsules_that_miss_or_lie_behind():
    box = (10, 20, 30, 40, 5.0)  # columns 10..20, rows 30..40 hold queries, deepest at 5
    beside = (0.0, 35.0, 8.0, 35.0, 0.0, 0.0)  # ends 2 pixels left of the box
    assert kernels._culled(beside, 0.5, box[:4], box[4] - 0.0, False)
    assert not kernels._culled(beside, 1.5, box[:4], box[4], False)  # its radius reaches
    over = (12.0, 35.0, 18.0, 35.0, 1.0, 2.0)  # in the box, in front of the deepest query
    assert not kernels._culled(over, 0.5, box[:4], box[4], False)
    under = (12.0, 35.0, 18.0, 35.0, 6.0, 7.0)  # behind every query
    assert kernels._culled(under, 0.5, box[:4], box[4], False)
    assert not kernels._culled(under, 0.5, box[:4], box[4], True)  # depths kept: drawn
    assert not kernels._culled(under, 0.5, box[:4], box[4] + 2.0, False)  # within the bias


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("soft", [False, True])
def test_capsules_behind_the_points_are_left_out_without_changing_an_answer(seed, soft):
    # a plant over copies sunk below it, some wholly behind its points along the light,
    # some just in front of the deepest (within and beyond the bias)
    rng = np.random.default_rng(100 + seed)
    start, end, radius = random_tree(rng, 30)
    d = np.array([0.0, -1.0, 0.0]) if seed % 2 else random_direction(rng)
    parts_s, parts_e = [start], [end]
    for _ in range(6):
        drop = rng.normal(size=3) * 0.5 - d * rng.uniform(-1.0, 25.0)
        parts_s.append(start + drop)
        parts_e.append(end + drop)
    s, e = np.concatenate(parts_s), np.concatenate(parts_e)
    r = np.tile(radius, 7)
    side = rng.normal(size=(30, 3))
    side /= np.linalg.norm(side, axis=1)[:, None]
    points = start + rng.uniform(0, 1, (30, 1)) * (end - start) + radius[:, None] * side
    u, v = view_basis(d)
    res, bias = (64, 128, 256)[seed % 3], (0.0, 0.5, 3.0)[seed % 3]
    trans = rng.uniform(0.05, 0.95, len(s)) if soft else None
    normals = np.tile(-d, (30, 1))
    got = kernels.point_light_into(
        (s, e, r, np.array([0, len(s)])), (points, np.array([0, 30]), normals),
        (d[None], u[None], v[None], np.ones(1)),
        (res, bias, soft, trans if soft else np.empty(0)), kernels.shadow_scratch(res),
        np.empty(30), np.zeros((0, 3)),
    )  # fmt: skip
    framing = kernels.plant_frames(s, e, r, np.array([0, len(s)]), u, v, res)[0]
    want = naive.map_exposure((s, e, r), points, (u, v, d), res, bias, trans, framing)
    cos = -(normals[:, 0] * d[0] + normals[:, 1] * d[1] + normals[:, 2] * d[2])
    np.testing.assert_allclose(got, want * cos, rtol=1e-12, atol=0)
