"""Water transport by negative pressure: kernels vs oracles, edge cases, a Honda tree."""

from __future__ import annotations

import numpy as np
import pytest
from naive.water import distribute_kernel as distribute_oracle
from naive.water import subtree_demand_kernel as subtree_oracle

from growsim.env import Environment, Water
from growsim.env.water import segment_demand, transport
from growsim.errors import ConfigError, UserInputError
from growsim.kernels.water import (
    distribute_kernel,
    subtree_demand_kernel,
    transport_into_kernel,
    transport_kernel,
)
from growsim.models import honda
from growsim.phenotypes.plant import LEAF, Plant


def _random_skeleton(rng, n, roots=1):
    parent = np.array([-1] + [int(rng.integers(0, i)) for i in range(1, n)], np.int64)
    parent[rng.choice(np.arange(1, n), size=roots - 1, replace=False)] = -1
    start = rng.normal(size=(n, 3))
    end = start + rng.normal(size=(n, 3))
    radius = rng.uniform(0.05, 1.0, n)
    radius[rng.random(n) < 0.05] = 0.0
    demand = rng.uniform(0, 2, n) * (rng.random(n) < 0.7)
    return start, end, radius, parent, demand


def _arrays(points, point_parent, parent, radius=0.1, kind=None):
    p = Plant.from_points(points, parent, point_parent, radius=radius, kind=kind)
    return {"start": p.start, "end": p.end, "radius": p.radius, "parent": p.parent}


@pytest.mark.parametrize("seed", range(12))
def test_kernels_match_oracles(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 60))
    start, end, radius, parent, demand = _random_skeleton(
        rng, n, roots=1 + (seed % 3 > 0) * (n > 3)
    )
    D = subtree_demand_kernel(parent, demand)
    np.testing.assert_allclose(D, subtree_oracle(parent, demand), rtol=1e-12)
    supply = [0.0, 0.3, 1.0, 4.0][seed % 4]
    resistance, lift = rng.uniform(0, 0.5, 2) * (seed % 5 > 0)
    got = distribute_kernel(start, end, radius, parent, demand, D, supply, resistance, lift)
    want = distribute_oracle(start, end, radius, parent, demand, D, supply, resistance, lift)
    for g, w in zip(got, want):
        np.testing.assert_allclose(g, w, rtol=1e-10, atol=1e-14)
    rec, met = transport_kernel(start, end, radius, parent, demand, supply, resistance, lift)
    np.testing.assert_allclose(rec, want[0], rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(met, want[1], rtol=1e-10, atol=1e-14)


def test_one_segment():
    seg = {"start": [[0, 0, 0]], "end": [[0, 1, 0]], "radius": [0.1], "parent": [-1]}
    w = transport(seg, [2.0], 0.25, resistance=0, lift=0)
    assert w.received.tolist() == [0.5] and w.met.tolist() == [0.25] and w.total == 0.5
    w = transport(seg, [2.0], 1.0, lift=0.1)  # climbing 1 costs exp(-0.1), plus a bit of path
    assert 0 < w.met[0] < np.exp(-0.1)


def test_chain():
    pts = [[0, y, 0] for y in range(6)]
    seg = _arrays(pts, [-1, 0, 1, 2, 3, 4], [-1, 0, 1, 2, 3])
    w = transport(seg, np.ones(5), 1.0, resistance=0, lift=0)
    assert w.met.tolist() == [1.0] * 5
    w = transport(seg, np.ones(5), 1.0, resistance=0, lift=0.2)
    assert np.all(np.diff(w.met) < 0)  # higher up, less water
    np.testing.assert_allclose(w.met[0], np.exp(-0.2))


def test_two_equal_branches_share_equally():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [1, 2, 0], [-1, 2, 0]], [-1, 0, 1, 1], [-1, 0, 0])
    for supply in (0.3, 1.0, 2.0):
        w = transport(seg, [0.0, 1.0, 1.0], supply)
        assert w.received[1] == w.received[2] and w.met[0] == 1.0


def test_thin_long_branch_gets_less_than_thick_short():
    # a horizontal fork: one thick short branch, one thin long one, equal demand
    pts = [[0, 0, 0], [0, 1, 0], [1, 1, 0], [-3, 1, 0]]
    seg = _arrays(pts, [-1, 0, 1, 1], [-1, 0, 0], radius=[0.5, 0.5, 0.1])
    w = transport(seg, [0.0, 1.0, 1.0], 1.0, resistance=0.05, lift=0)
    assert w.met[2] < w.met[1] < 1.0
    # the same fork, both thick and short: equal again
    seg = _arrays([[0, 0, 0], [0, 1, 0], [1, 1, 0], [-1, 1, 0]], [-1, 0, 1, 1], [-1, 0, 0])
    w = transport(seg, [0.0, 1.0, 1.0], 1.0, resistance=0.05, lift=0)
    assert w.met[2] == w.met[1]


def test_zero_radius_passes_nothing():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0, 1], [-1, 0], radius=[0.1, 0.0])
    w = transport(seg, [1.0, 1.0], 1.0, resistance=0.01, lift=0)
    assert w.met[0] > 0.9 and w.met[1] == 0.0


def test_ample_supply_meets_every_demand():
    rng = np.random.default_rng(1)
    start, end, radius, parent, demand = _random_skeleton(rng, 40)
    radius[radius == 0] = 0.1
    seg = {"start": start, "end": end, "radius": radius, "parent": parent}
    w = transport(seg, demand, 1.0, resistance=0, lift=0)
    np.testing.assert_allclose(w.met, 1.0)
    np.testing.assert_allclose(w.total, demand.sum())
    w = transport(seg, demand, 1e6)  # losses overcome by plenty of water
    np.testing.assert_allclose(w.met, 1.0)


def test_zero_water():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0, 1], [-1, 0])
    w = Water(supply=0.0).transport(seg, [0.0, 1.0])
    assert w.received.tolist() == [0.0, 0.0] and w.met.tolist() == [1.0, 0.0] and w.total == 0.0


@pytest.mark.parametrize("seed", range(6))
def test_conservation(seed):
    rng = np.random.default_rng(100 + seed)
    start, end, radius, parent, demand = _random_skeleton(rng, 50, roots=2)
    seg = {"start": start, "end": end, "radius": radius, "parent": parent}
    total = demand.sum()
    for supply in (0.0, 0.2, 0.7, 1.0, 3.0):
        lossless = transport(seg, demand, supply, resistance=0, lift=0)
        np.testing.assert_allclose(lossless.total, min(1.0, supply) * total, rtol=1e-12)
        np.testing.assert_allclose(lossless.met[demand > 0], min(1.0, supply))
        lossy = transport(seg, demand, supply, resistance=0.1, lift=0.1)
        assert lossy.total <= min(1.0, supply) * total * (1 + 1e-12)
        assert np.all(lossy.met <= lossless.met + 1e-12)
        assert np.all((lossy.met >= 0) & (lossy.met <= 1))


def test_forest_is_its_plants():
    rng = np.random.default_rng(5)
    plants = []
    for _ in range(3):
        s, e, r, par, _d = _random_skeleton(rng, 20)
        plants.append(Plant(s, e, r, par, np.zeros(20), np.ones(20)))
    light = [rng.uniform(0, 1, 20) for _ in plants]
    forest = transport(Plant.concat(plants), np.concatenate(light), 0.6, lift=0.1)
    alone = [transport(p, q, 0.6, lift=0.1) for p, q in zip(plants, light)]
    np.testing.assert_allclose(forest.received, np.concatenate([a.received for a in alone]))
    np.testing.assert_allclose(forest.total, sum(a.total for a in alone))


def test_stem_demand():
    p = Plant.from_points([[0, 0, 0], [0, 2, 0], [0, 3, 0]], [-1, 0], [-1, 0, 1], kind=[0, 1])
    assert segment_demand(p.kind, [9.0, 1.0], p.lengths(), 0.5).tolist() == [1.0, 1.0]
    w = transport(p, [9.0, 1.0], 0.5, stem_demand=0.5, resistance=0, lift=0)
    assert w.received.tolist() == [0.5, 0.5]
    w = transport(p, [9.0, 1.0], 0.5, resistance=0, lift=0)  # stems demand nothing by default
    assert w.received.tolist() == [0.0, 0.5] and w.met[0] == 1.0


def test_gravity_scales_the_height_term():
    seg = _arrays([[0, 0, 0], [0, 1, 0]], [-1, 0], [-1])
    flat = transport(seg, [1.0], 1.0, resistance=0, lift=0.1, g=0.0)
    earth = transport(seg, [1.0], 1.0, resistance=0, lift=0.1, g=9.81)
    assert flat.met[0] == 1.0 and earth.met[0] == pytest.approx(np.exp(-0.1))


def test_honda_tree_met_falls_with_path_and_height():
    plant = honda.develop(honda.PRESETS["zelkova"])
    light = (plant.kind == LEAF).astype(float)  # demand 1 per leaf
    env = Environment()
    w = env.water.transport(plant, light, g=env.gravity.g)
    leaf = plant.kind == LEAF
    assert np.all(w.met[~leaf] == 1.0)  # stems demand nothing
    assert np.all((w.met[leaf] > 0) & (w.met[leaf] < 1))
    assert w.total <= leaf.sum()
    # path length from the ground to each leaf's tip; leaf heights
    path = np.zeros(plant.n_segments)
    L = plant.lengths()
    for i in range(plant.n_segments):
        path[i] = L[i] + (path[plant.parent[i]] if plant.parent[i] >= 0 else 0.0)
    height = plant.end[:, 1]
    for x in (path[leaf], height[leaf]):
        rank = np.corrcoef(np.argsort(np.argsort(x)), np.argsort(np.argsort(w.met[leaf])))[0, 1]
        assert rank < -0.5
    # the highest leaves get less than the lowest
    order = np.argsort(height[leaf])
    assert w.met[leaf][order[-20:]].mean() < w.met[leaf][order[:20]].mean()


def test_input_errors():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0, 1], [-1, 0])
    with pytest.raises(UserInputError, match="supply"):
        transport(seg, [1.0, 1.0], -0.5)
    with pytest.raises(ConfigError, match=r"water\.supply"):
        Water.parse({"supply": -1}, where="water.")
    with pytest.raises(UserInputError, match="light: segment 1 is negative"):
        transport(seg, [1.0, -1.0])
    with pytest.raises(UserInputError, match="light: segment 0 is not finite"):
        transport(seg, [np.nan, 1.0])
    with pytest.raises(UserInputError, match=r"light: (expected shape|has 1 rows)"):
        transport(seg, [1.0])
    bad = dict(seg, end=seg["end"].copy())
    bad["end"][1, 2] = np.nan
    with pytest.raises(UserInputError, match="end: segment 1 is not finite"):
        transport(bad, [1.0, 1.0])
    with pytest.raises(UserInputError, match="segment 0 has parent 1: parents must come"):
        transport(dict(seg, parent=[1, -1]), [1.0, 1.0])
    with pytest.raises(UserInputError, match="radius: segment 1 is negative"):
        transport(dict(seg, radius=[0.1, -0.1]), [1.0, 1.0])
    with pytest.raises(UserInputError, match="miss"):
        transport({"start": seg["start"]}, [1.0, 1.0])
    with pytest.raises(UserInputError, match="resistance"):
        transport(seg, [1.0, 1.0], resistance=-1)


def test_empty_plant():
    w = transport(Plant.empty(), np.zeros(0))
    assert w.received.shape == (0,) and w.total == 0.0


def test_into_kernel_reuses_buffers():
    rng = np.random.default_rng(9)
    start, end, radius, parent, demand = _random_skeleton(rng, 30)
    rec, met = np.full(30, np.nan), np.full(30, np.nan)
    transport_into_kernel(start, end, radius, parent, demand, 0.7, 0.1, 0.1, rec, met)
    want = transport_kernel(start, end, radius, parent, demand, 0.7, 0.1, 0.1)
    np.testing.assert_array_equal(rec, want[0])
    np.testing.assert_array_equal(met, want[1])


def test_environment_water_keys_set_the_losses():
    from growsim.env import Environment
    from growsim.models import honda

    tree = honda.develop(honda.PRESETS["zelkova"])
    light = (tree.kind == 1).astype(float)
    env = Environment.model_validate(
        {"water": {"supply": 0.8, "resistance": 0.0, "lift": 0.02, "stem_demand": 0.001}}
    )
    got = env.water.transport(tree, light, g=env.gravity.g)
    want = transport(tree, light, 0.8, resistance=0.0, lift=0.02, stem_demand=0.001)
    np.testing.assert_array_equal(got.met, want.met)
    default = Environment().water.transport(tree, light)
    assert not np.array_equal(got.met, default.met)
    with pytest.raises(Exception, match="resistance"):
        Environment.model_validate({"water": {"resistance": -1.0}})
