"""Shadow-map light, hard shadows (growsim.env.light, growsim.kernels.light)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from naive.light import point_light_kernel as point_oracle
from naive.light import segment_light_kernel as segment_oracle

from growsim.env.light import Light, point_light, segment_light, view_basis
from growsim.errors import UserInputError
from growsim.kernels.light import point_light_kernel, segment_light_kernel
from growsim.models import honda
from growsim.plant import LEAF, Plant


def random_tree(rng, n, root=(0.0, 0.0, 0.0)):
    """A random tree stored parents first, growing mostly upwards, thin segments."""
    parent = [-1] + [int(rng.integers(max(0, s - 8), s)) for s in range(1, n)]
    start = np.zeros((n, 3))
    end = np.zeros((n, 3))
    for s in range(n):
        start[s] = root if parent[s] < 0 else end[parent[s]]
        step = rng.normal(size=3) + np.array([0.0, 1.2, 0.0])
        end[s] = start[s] + step / np.linalg.norm(step) * rng.uniform(0.5, 2.0)
    radius = rng.uniform(0.02, 0.15, n)
    return start, end, radius


def random_direction(rng):
    d = rng.normal(size=3)
    d[1] = -abs(d[1]) - 0.3
    return d / np.linalg.norm(d)


def kernel_args(start, end, radius, offsets, d, res=256):
    u, v = view_basis(d)
    n = len(start)
    return (start, end, radius, np.asarray(offsets, np.int64), np.zeros((n, 3)),
            np.zeros(n, np.bool_), u, v, d, 1.0, res, 1.5, 1)  # fmt: skip


def population(rng, k, n):
    parts = [random_tree(rng, n, root=rng.normal(size=3) * 3) for _ in range(k)]
    start, end, radius = (np.concatenate([p[i] for p in parts]) for i in range(3))
    return start, end, radius, np.arange(k + 1, dtype=np.int64) * n


def test_segment_kernel_matches_oracle_on_random_trees():
    total = disagree = 0
    for seed in range(8):
        rng = np.random.default_rng(seed)
        start, end, radius, offsets = population(rng, 3, int(rng.integers(40, 90)))
        d = random_direction(rng)
        args = kernel_args(start, end, radius, offsets, d)
        got = segment_light_kernel(*args, np.full(len(start), np.nan))
        want = segment_oracle(*args)
        edge = segment_oracle(*args, tol_pixels=1.0)
        lit_got, lit_want = got > 0, want > 0
        # every disagreement is within a pixel of a silhouette edge (or of the depth test)
        assert not np.any((lit_got != lit_want) & ~edge), seed
        assert np.mean(lit_got == lit_want) >= 0.97, seed
        both = lit_got & lit_want
        np.testing.assert_allclose(got[both], want[both], rtol=1e-12)
        # both shade a fair share of the segments: the test is not trivial
        assert 0.05 < 1 - lit_want.mean() < 0.95
        total += len(got)
        disagree += int(np.sum(lit_got != lit_want))
    assert 1 - disagree / total >= 0.98, disagree / total


@pytest.mark.parametrize("seed", range(3))
def test_point_kernel_matches_oracle(seed):
    rng = np.random.default_rng(100 + seed)
    start, end, radius, offsets = population(rng, 2, 60)
    d = random_direction(rng)
    u, v = view_basis(d)
    m = 400
    # points near each plant's segments, so that many are in its shade
    pick = [rng.integers(offsets[k], offsets[k + 1], m) for k in range(2)]
    mids = 0.5 * (start + end)
    pts = np.concatenate([mids[i] for i in pick]) + rng.normal(scale=0.5, size=(2 * m, 3))
    nrm = rng.normal(size=(2 * m, 3))
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    poff = np.array([0, m, 2 * m])
    args = (start, end, radius, offsets, pts, nrm, poff, u, v, d, 1.0, 128, 1.5)
    got = point_light_kernel(*args, np.empty(2 * m))
    want = point_oracle(*args)
    edge = point_oracle(*args, tol_pixels=1.0)
    assert not np.any(((got > 0) != (want > 0)) & ~edge)  # only within a pixel of an edge
    assert np.mean((got > 0) == (want > 0)) >= 0.95
    both = (got > 0) & (want > 0)
    np.testing.assert_allclose(got[both], want[both], rtol=1e-12)
    assert 0.05 < np.mean(want[-nrm @ d > 0] == 0) < 0.95


def test_simple_scenes_agree_exactly():
    # a stack of crossing horizontal leaves, a slanted stem and a few in the open
    start = np.array([[0.0, 3, 0], [0.5, 2, -1], [0, 1, 0.3], [6, 0, 0], [-5, 0, 2], [1, 0, 0]])
    end = np.array([[2.0, 3, 0], [0.5, 2, 1], [2, 1, 0.3], [6, 0, 2], [-4, 2, 2], [1, 0.5, 0]])
    radius = np.array([0.4, 0.3, 0.3, 0.2, 0.1, 0.05])
    for d in ([0.0, -1, 0], [0.3, -1, 0.2], [1.0, -0.2, 0.0], [0, 0, 1]):
        d = np.array(d) / np.linalg.norm(d)
        args = kernel_args(start, end, radius, [0, 6], d, res=256)
        got = segment_light_kernel(*args, np.empty(6))
        np.testing.assert_allclose(got, segment_oracle(*args), rtol=1e-12, err_msg=str(d))


def test_one_segment_in_the_open_gets_its_cosine():
    def light(a, b, d, **kw):
        return float(segment_light(np.array([a]), np.array([b]), [0.1], direction=d, **kw)[0])

    o = [0.0, 0.0, 0.0]
    assert light(o, [1, 0, 0], (0, -1, 0)) == 1.0  # horizontal, light from above
    assert light(o, [1, 1, 0], (0, -1, 0)) == pytest.approx(math.sqrt(0.5))
    # vertical stem from straight above: the side gets no light (caps are joints)
    assert light(o, [0, 1, 0], (0, -1, 0)) == 0.0
    assert light(o, [0, 1, 0], (1, 0, 0)) == pytest.approx(1.0)
    assert light(o, [0, 1, 0], (1, -1, 0), intensity=0.5) == pytest.approx(0.5 * math.sqrt(0.5))
    # a leaf with a normal: |n . d| (two-sided)
    leaf = dict(start=[o], end=[[1, 0, 0]], radius=[0.3], kind=[LEAF], normal=[[0, 0, -2]])
    assert float(segment_light(leaf, direction=(0, -1, -1))[0]) == pytest.approx(math.sqrt(0.5))
    # the same normal on a stem is ignored (cylinder rule)
    stem = {**leaf, "kind": [0]}
    assert float(segment_light(stem, direction=(0, -1, -1))[0]) == pytest.approx(1.0)


def test_leaf_under_an_identical_leaf_is_shaded():
    leaf = Plant.from_points([[0, 0, 0], [3, 0, 0]], [-1], [-1, 0], radius=0.5)
    above = Plant.from_points([[0, 2, 0], [3, 2, 0]], [-1], [-1, 0], radius=0.5)
    both = Plant.concat([above, leaf])
    assert Light().segment_light(both).tolist() == [1.0, 0.0]
    # slanted light misses the lower leaf once the shadow has moved past it
    slanted = Light(direction=[2.0, -1.0, 0.0]).segment_light(both)
    np.testing.assert_allclose(slanted, [1 / math.sqrt(5)] * 2)  # sin of axis and light
    # half covered: with several samples along it, the share lit
    half = Plant.concat([above, leaf], offsets=[[2.0, 0, 0], [0, 0, 0]])
    assert Light().segment_light(half, samples=8).tolist() == [1.0, 0.5]


def test_plants_shade_each_other_only_within_one_group():
    rng = np.random.default_rng(7)
    small = random_tree(rng, 20)
    s = small[0] * 0.2  # a small plant, deep under a big flat canopy
    e = small[1] * 0.2
    r = small[2] * 0.2
    canopy_s = np.array([[x, 10.0, -3] for x in np.linspace(-3, 3, 13)])
    canopy_e = canopy_s + np.array([0.0, 0.0, 6.0])
    start = np.concatenate([canopy_s, s])
    end = np.concatenate([canopy_e, e])
    radius = np.concatenate([np.full(13, 0.3), r])
    one = segment_light(start, end, radius, offsets=[0, 33])
    two = segment_light(start, end, radius, offsets=[0, 13, 33])
    assert np.all(one[13:] == 0.0)  # one plant: entirely in the canopy's shadow
    assert np.all(one[:13] == 1.0) and np.all(two[:13] == 1.0)
    alone = segment_light(s, e, r)
    np.testing.assert_array_equal(two[13:], alone)  # separate plants: as if alone
    assert np.mean(two[13:] > 0) > 0.3


def test_honda_tree_side_light_differs_from_light_from_above():
    tree = honda.develop(honda.PRESETS["zelkova"])
    leaves = tree.kind == LEAF
    mid = (0.5 * (tree.start + tree.end))[leaves]
    above = Light().segment_light(tree)
    lit = {}
    for name, d in (("above", [0, -1, 0]), ("+x", [1, 0, 0]), ("-x", [-1, 0, 0])):
        lit[name] = Light(direction=d).segment_light(tree)[leaves] > 0
        assert 0.2 < lit[name].mean() < 0.8, name  # the crown shades a good part of itself
    # from above the lit leaves are the high ones; light travelling along +x lights the
    # leaves on the -x side of the crown, and the other way round
    y = mid[:, 1]
    x = mid[:, 0]
    assert y[lit["above"]].mean() > y[~lit["above"]].mean() + 2
    assert x[lit["+x"]].mean() < x[~lit["+x"]].mean() - 3
    assert x[lit["-x"]].mean() > x[~lit["-x"]].mean() + 3
    # a different set of leaves sees the light
    assert np.mean(lit["above"] != lit["+x"]) > 0.2
    # the population form: two trees side by side in one call, each its own map
    pair = Plant.concat([tree, tree], offsets=[[0, 0, 0], [10, 0, 0]])
    n = tree.n_segments
    both = Light().segment_light(pair, offsets=[0, n, 2 * n])
    np.testing.assert_allclose(both[:n], above, rtol=1e-12)
    np.testing.assert_allclose(both[n:], above, rtol=1e-12)  # only rounding moves


def test_point_light_public():
    leaf = dict(start=[[0.0, 2, 0]], end=[[2.0, 2, 0]], radius=[0.5])
    pts = [[1.0, 0, 0], [1.0, 0, 0], [1.0, 3, 0], [9.0, 0, 0]]
    nrm = [[0, 1, 0], [0, -1, 0], [0, 1, 0], [1, 1, 0]]
    got = Light(intensity=2.0).point_light(leaf, points=pts, normals=nrm)
    assert got.round(6).tolist() == [0.0, 0.0, 2.0, round(2 * math.sqrt(0.5), 6)]
    two = point_light(
        [[0.0, 2, 0], [5, 2, 0]], [[2.0, 2, 0], [7, 2, 0]], [0.5, 0.5], offsets=[0, 1, 2],
        points=[[6.0, 0, 0], [6.0, 0, 0]], normals=[[0, 1, 0]] * 2, point_offsets=[0, 1, 2],
    )  # fmt: skip
    assert two.tolist() == [1.0, 0.0]  # the point is under plant 1's leaf, not plant 0's


def test_bad_input_is_named():
    a, b, r = np.zeros((2, 3)), np.ones((2, 3)), np.full(2, 0.1)
    with pytest.raises(UserInputError, match="direction"):
        segment_light(a, b, r, direction=(0, 0, 0))
    with pytest.raises(UserInputError, match="direction"):
        point_light(a, b, r, points=a, normals=b, direction=(0, np.nan, 0))
    bad = b.copy()
    bad[1, 2] = np.nan
    with pytest.raises(UserInputError, match=r"end: segment 1 is not finite"):
        segment_light(a, bad, r)
    with pytest.raises(UserInputError, match=r"points: segment 1 is not finite"):
        point_light(a, b, r, points=bad, normals=b)
    with pytest.raises(UserInputError, match="normals: row 0 is zero"):
        point_light(a, b, r, points=a, normals=np.zeros((2, 3)))
    with pytest.raises(UserInputError, match="radius"):
        segment_light(a, b, [0.1, -1.0])
    with pytest.raises(UserInputError, match="offsets"):
        segment_light(a, b, r, offsets=[0, 3])
    with pytest.raises(UserInputError, match="resolution"):
        segment_light(a, b, r, resolution=2)
    with pytest.raises(UserInputError, match="normal"):
        segment_light(dict(start=a, end=b, radius=r, normal=[[0, 0, 1], [np.inf, 0, 0]]))
    assert segment_light(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0)).shape == (0,)


@pytest.mark.parametrize("seed", range(4))
def test_render_matches_the_shared_depth_rasteriser(seed):
    # the kernel's row-span z-buffer covers the same pixels with the same depths and ids as
    # growsim.kernels.raster.draw_segments_depth (axis-aligned view: projections are exact)
    from growsim.kernels.light import _render
    from growsim.kernels.raster import draw_segments_depth

    rng = np.random.default_rng(seed)
    start, end, radius = random_tree(rng, 80)
    radius[rng.random(80) < 0.2] = 0.0
    end[3] = start[3]  # a point
    d = np.array([0.0, -1.0, 0.0])
    u, v = view_basis(d)
    res = 64 if seed % 2 else 200
    depth = np.full((res, res), np.nan)
    ids = np.full((res, res), -7, np.int64)
    stamp = np.full((res, res), -1, np.int64)
    mask = np.zeros((res, res), np.uint8)
    ox, oy, pix = _render(start, end, radius, 0, 80, u, v, d, res, depth, ids, stamp, 5, mask)
    want = np.full((res, res), np.inf)
    want_ids = np.full((res, res), -1, np.int64)
    a = np.stack([(start @ u - ox) / pix, (start @ v - oy) / pix], 1)
    b = np.stack([(end @ u - ox) / pix, (end @ v - oy) / pix], 1)
    draw_segments_depth(a, b, start @ d, end @ d, 2 * radius / pix, want, want_ids)
    covered = stamp == 5
    np.testing.assert_array_equal(covered, np.isfinite(want))
    np.testing.assert_array_equal(depth[covered], want[covered])
    np.testing.assert_array_equal(ids[covered], want_ids[covered])
    assert not mask.any()  # the scratch mask is left clean
