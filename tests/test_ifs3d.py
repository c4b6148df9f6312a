"""The IFS tree kernels and model against their oracles (:mod:`naive.ifs3d`)."""

from __future__ import annotations

import numpy as np
import pytest
from naive import ifs3d as oracle

from growsim.errors import ResourceError, UserInputError
from growsim.kernels import ifs3d as K
from growsim.models import ifs3d
from growsim.phenotypes.plant import Plant


def random_maps(rng, n, N=5):
    m = np.empty((n, N, 4))
    m[..., 0] = rng.uniform(0.1, 0.7, (n, N))
    m[..., 1] = rng.uniform(0.2, 1.0, (n, N))
    m[..., 2] = rng.uniform(0, 90, (n, N))
    m[..., 3] = rng.uniform(0, 360, (n, N))
    return m


TABLE1 = ifs3d.maps_from_params(ifs3d.PRESETS["table1"])

# ----------------------------------------------------------------------------- kernels


def test_map_matrices_match_oracle():
    rng = np.random.default_rng(0)
    maps = random_maps(rng, 1, 7)[0]
    maps[0, 2:] = [0.0, 0.0]
    maps[1, 2:] = [90.0, 360.0]
    np.testing.assert_allclose(K.map_matrices(maps), oracle.map_matrices(maps), atol=1e-14)


@pytest.mark.parametrize(("N", "depth"), [(1, 0), (1, 4), (2, 3), (3, 3), (5, 1), (5, 3), (4, 4)])
def test_compose_matches_oracle(N, depth):
    rng = np.random.default_rng(N * 10 + depth)
    maps = random_maps(rng, 1, N)[0]
    s, e = K.compose_tree(maps, depth)
    s0, e0 = oracle.compose_tree(maps, depth)
    assert s.shape == (K.n_segments(N, depth), 3)
    np.testing.assert_allclose(s, s0, atol=1e-12)
    np.testing.assert_allclose(e, e0, atol=1e-12)


@pytest.mark.parametrize("seed", range(3))
def test_render_views_matches_oracle(seed):
    rng = np.random.default_rng(seed)
    s, e = K.compose_tree(random_maps(rng, 1, 3)[0], 3)
    base = rng.normal(0, 0.1, 3) if seed else np.zeros(3)
    np.testing.assert_array_equal(
        K.render_views(s, e, base, 48), oracle.render_views(s, e, base, 48)
    )


def test_render_views_trunk_only():
    img = K.render_views(*K.compose_tree(TABLE1[:1], 0), np.zeros(3), 16)
    # the bare trunk: the centre column, top to bottom, in both views
    assert img[:, :, 8].all() and img.sum() == 32


@pytest.mark.parametrize("views", [2, 1])
@pytest.mark.parametrize("area", [False, True])
def test_score_population_matches_oracle(area, views):
    rng = np.random.default_rng(5)
    target = K.render_views(*K.compose_tree(random_maps(rng, 1, 3)[0], 3), np.zeros(3), 32)
    target = np.ascontiguousarray(target[:views])
    pop = random_maps(rng, 12, 3)
    got = K.score_population(pop, 3, target, area)
    np.testing.assert_allclose(got, oracle.score_population(pop, 3, target, area), atol=1e-12)
    assert K.score_population(pop[:0], 3, target).shape == (0,)


def test_blurred_score_matches_oracle_and_is_smoother():
    rng = np.random.default_rng(7)
    target = K.render_views(*K.compose_tree(random_maps(rng, 1, 3)[0], 3), np.zeros(3), 32)
    pop = random_maps(rng, 6, 3)
    for area in (False, True):
        got = K.score_population(pop, 3, target, area, 1.2)
        want = oracle.score_population(pop, 3, target, area, 1.2)
        np.testing.assert_allclose(got, want, atol=1e-12)
    # a branch shifted by a fraction of a pixel: the binary score jumps, the blurred one
    # changes a little and continuously
    s, e = K.compose_tree(TABLE1, 5)
    t64 = K.render_views(s, e, np.zeros(3), 64)
    y = TABLE1[1, 1] + np.linspace(-0.03, 0.03, 13)
    pop = np.repeat(TABLE1[None], 13, axis=0)
    pop[:, 1, 1] = y
    hard = K.score_population(pop, 5, t64)
    soft = K.score_population(pop, 5, t64, False, 1.0)
    assert hard[6] == 1.0 and soft[6] > 0.99
    assert np.abs(np.diff(soft)).max() < 0.5 * np.abs(np.diff(hard)).max()
    assert soft.min() > hard.min()
    with pytest.raises(ValueError, match="blur"):
        K.score_population(pop, 5, t64, False, -1.0)


def test_score_is_one_on_its_own_target_and_lower_elsewhere():
    s, e = K.compose_tree(TABLE1, 5)
    target = K.render_views(s, e, np.zeros(3), 64)
    pert = TABLE1.copy()
    pert[2, 3] += 20.0
    sc = K.score_population(np.stack([TABLE1, pert]), 5, target)
    assert sc[0] == 1.0 and sc[1] < 0.99


def test_kernel_input_checks():
    with pytest.raises(ValueError, match="shape"):
        K.compose_tree(np.zeros((2, 3)), 2)
    with pytest.raises(ValueError, match="depth"):
        K.compose_tree(TABLE1, -1)
    with pytest.raises(ValueError, match="params"):
        K.score_population(np.zeros((2, 4)), 2, np.zeros((2, 8, 8), np.uint8))
    with pytest.raises(ValueError, match="target"):
        K.score_population(TABLE1[None], 2, np.zeros((8, 8), np.uint8))


# ----------------------------------------------------------------------------- model


def test_develop_table1_plant():
    tree = ifs3d.develop(ifs3d.PRESETS["table1"], seed=3)
    assert isinstance(tree, Plant)
    assert tree.n_segments == 3906
    s0, e0 = oracle.compose_tree(TABLE1, 5)
    np.testing.assert_allclose(tree.start, s0, atol=1e-12)
    np.testing.assert_allclose(tree.end, e0, atol=1e-12)
    # every child starts on its parent segment, one level deeper
    i = np.arange(1, tree.n_segments)
    p = tree.parent[i]
    assert (tree.parent[0] == -1) and (p < i).all()
    d = tree.end[p] - tree.start[p]
    v = tree.start[i] - tree.start[p]
    assert np.abs(np.cross(d, v)).max() < 1e-12
    t = (v * d).sum(1) / (d * d).sum(1)
    assert t.min() >= 0.4 - 1e-9 and t.max() <= 0.4 + 1e-9
    np.testing.assert_array_equal(tree.order[i], tree.order[p] + 1)
    # radius proportional to length; symmetric crown
    length = np.linalg.norm(tree.end - tree.start, axis=1)
    np.testing.assert_allclose(tree.radius, ifs3d.RADIUS_RATIO * length)
    assert tree.height() == pytest.approx(1.0)
    assert tree.crown_width() == pytest.approx(tree.crown_depth())
    assert tree.meta["model"] == "ifs3d" and tree.meta["seed"] == 3


def test_param_spec_and_defaults():
    names = [p.name for p in ifs3d.PARAMS]
    assert names[:2] == ["n_maps", "depth"] and len(names) == 22 + len(ifs3d.LEAF_PARAMS)
    by = {p.name: p for p in ifs3d.PARAMS}
    # the seed's ranges
    assert (by["y_1"].low, by["y_1"].high) == (0.3, 0.6)
    assert (by["theta_y_3"].low, by["theta_y_3"].high) == (90.0, 180.0)
    assert (by["theta_y_1"].low, by["theta_y_1"].high) == (0.0, 360.0)
    spec3 = ifs3d.param_spec({"n_maps": 3})
    assert len(spec3) == 2 + 12 + len(ifs3d.LEAF_PARAMS)
    assert {p.name: p for p in spec3}["theta_y_3"].low == 180.0
    tree = ifs3d.develop({"n_maps": 3, "depth": 2})
    assert tree.n_segments == 13
    for name, preset in ifs3d.PRESETS.items():
        assert ifs3d.develop(preset).n_segments == 3906, name


def test_map_groups():
    names = [p.name for p in ifs3d.PARAMS]
    rng = np.random.default_rng(2)
    rows = np.array([[rng.uniform(p.low, p.high) for p in ifs3d.PARAMS] for _ in range(5)])
    rows[:, names.index("leaves")] = 0  # bare trees (leafy rows are not grouped)
    rows[:, 0] = 5
    rows[:, 1] = [4, 5, 4.2, 3, 5]  # depths rounded: groups 3, 4, 5
    groups = list(ifs3d.map_groups(rows, names))
    assert [(r.tolist(), d) for r, _, d in groups] == [([3], 3), ([0, 2], 4), ([1, 4], 5)]
    for r, maps, _ in groups:
        for i, m in zip(r, maps):
            want = ifs3d.maps_from_params(dict(zip(names, rows[i])))
            np.testing.assert_array_equal(m, want)
    # columns in any order; n_maps and depth default when absent; one row as a vector
    perm = rng.permutation(len(names))[::-1]
    again = list(ifs3d.map_groups(rows[:, perm], [names[i] for i in perm]))
    for (r0, m0, d0), (r1, m1, d1) in zip(groups, again):
        assert r0.tolist() == r1.tolist() and d0 == d1 and np.array_equal(m0, m1)
    ((r, maps, d),) = ifs3d.map_groups(rows[0, 2:], names[2:])
    assert r.tolist() == [0] and maps.shape == (1, 5, 4) and d == ifs3d.DEFAULT_DEPTH
    # fewer maps
    spec3 = ifs3d.param_spec({"n_maps": 3})
    row3 = [3] + [p.default for p in spec3[1:]]
    ((_, maps3, _),) = ifs3d.map_groups([row3], [p.name for p in spec3])
    assert maps3.shape == (1, 3, 4)
    with pytest.raises(UserInputError, match="theta_y_5"):
        i = names.index("theta_y_5")
        list(ifs3d.map_groups(np.delete(rows, i, axis=1), names[:i] + names[i + 1 :]))
    big = rows[:1].copy()
    big[0, :2] = [5, 10]
    with pytest.raises(ResourceError, match="segments"):
        list(ifs3d.map_groups(big, names))


def test_develop_errors():
    with pytest.raises(UserInputError, match="s_1"):
        ifs3d.develop({"s_1": 0.9})
    with pytest.raises(UserInputError, match="theta_z_9"):
        ifs3d.develop({"theta_z_9": 1.0})
    with pytest.raises(UserInputError, match="n_maps"):
        ifs3d.develop({"n_maps": 2.5})
    with pytest.raises(ResourceError, match="segments"):
        ifs3d.develop({"n_maps": 12, "depth": 10})


def test_compare_maps_symmetries():
    ref = TABLE1
    assert ifs3d.compare_maps(ref, ref, azimuth_period=90)["within"]
    # map order does not matter; the leader's azimuth counts modulo 90 for table1
    fit = ref[[0, 3, 1, 4, 2]].copy()
    fit[0, 3] = 180.0
    r = ifs3d.compare_maps(fit, ref, azimuth_period=90)
    assert r["within"] and r["order"].tolist() == [0, 2, 4, 1, 3]
    # without the period, the leader turned by 180 degrees makes another tree
    assert not ifs3d.compare_maps(fit, ref)["within"]
    far = ref.copy()
    far[1, 2] = 52.0
    r = ifs3d.compare_maps(far, ref, azimuth_period=90)
    assert not r["within"] and r["max_error"][2] == pytest.approx(7.0)
    # azimuths wrap around the circle
    wrap = ref.copy()
    wrap[4, 3] = 268.0
    wrap[1, 3] = 358.0
    assert ifs3d.compare_maps(wrap, ref)["max_error"][3] == pytest.approx(2.0)
    with pytest.raises(UserInputError):
        ifs3d.compare_maps(ref[:3], ref)
