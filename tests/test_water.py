"""Water from a fixed supply shared by path conductance: kernels vs oracles, the supply
never exceeded, more demand bringing no more water, edge cases, a Honda tree."""

from __future__ import annotations

import math

import numpy as np
import pytest
from naive.water import conductance_kernel as conductance_oracle
from naive.water import fill_kernel as fill_oracle
from naive.water import transport_kernel as transport_oracle

from growsim.env import Environment, Water
from growsim.env.water import segment_demand, transport
from growsim.errors import ConfigError, UserInputError
from growsim.kernels.water import (
    REFERENCE_AREA,
    conductance_kernel,
    fill_kernel,
    transport_into_kernel,
    transport_kernel,
)
from growsim.models import honda
from growsim.phenotypes.plant import LEAF, Plant

#: the radius of a stem of 1 cm^2 cross-section
CM2 = math.sqrt(REFERENCE_AREA / math.pi)


def _random_skeleton(rng, n, roots=1):
    parent = np.array([-1] + [int(rng.integers(0, i)) for i in range(1, n)], np.int64)
    parent[rng.choice(np.arange(1, n), size=roots - 1, replace=False)] = -1
    start = rng.normal(size=(n, 3))
    end = start + rng.normal(size=(n, 3))
    radius = rng.uniform(0.001, 0.02, n)
    radius[rng.random(n) < 0.05] = 0.0
    demand = rng.uniform(0, 2, n) * (rng.random(n) < 0.7)
    return start, end, radius, parent, demand


def _arrays(points, point_parent, parent, radius=CM2, kind=None):
    p = Plant.from_points(points, parent, point_parent, radius=radius, kind=kind)
    return {"start": p.start, "end": p.end, "radius": p.radius, "parent": p.parent}


@pytest.mark.parametrize("seed", range(12))
def test_kernels_match_oracles(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 60))
    start, end, radius, parent, demand = _random_skeleton(
        rng, n, roots=1 + (seed % 3 > 0) * (n > 3)
    )
    resistance, lift = rng.uniform(0, 0.5, 2) * (seed % 5 > 0)
    k = conductance_kernel(start, end, radius, parent, resistance, lift, np.empty(n))
    np.testing.assert_allclose(k, conductance_oracle(start, end, radius, parent, resistance, lift),
                               rtol=1e-12)  # fmt: skip
    for supply in (0.0, 0.3, 1.0, 4.0, 100.0):
        met = fill_kernel(parent, demand, k, supply, np.empty(n))
        np.testing.assert_allclose(met, fill_oracle(parent, demand, k, supply), rtol=1e-10,
                                   atol=1e-13)  # fmt: skip
        rec, met = transport_kernel(start, end, radius, parent, demand, supply, resistance, lift)
        want = transport_oracle(start, end, radius, parent, demand, supply, resistance, lift)
        np.testing.assert_allclose(rec, want[0], rtol=1e-10, atol=1e-13)
        np.testing.assert_allclose(met, want[1], rtol=1e-10, atol=1e-13)


def test_conductance_worked_by_hand():
    # a metre up, then a metre across, each of 1 cm^2: x = 0.5 + 0.25 (the climb), then
    # + 0.5; k = 1 / (1 + x)
    s = np.array([[0.0, 0, 0], [0, 1, 0]])
    e = np.array([[0.0, 1, 0], [1, 1, 0]])
    k = conductance_kernel(s, e, np.full(2, CM2), np.array([-1, 0]), 0.5, 0.25, np.empty(2))
    np.testing.assert_allclose(k, [1 / 1.75, 1 / 2.25])
    # a quarter of the cross-section: four times the resistance
    k = conductance_kernel(s, e, np.full(2, CM2 / 2), np.array([-1, 0]), 0.5, 0.0, np.empty(2))
    np.testing.assert_allclose(k, [1 / 3, 1 / 5])


def test_one_segment():
    seg = {"start": [[0, 0, 0]], "end": [[0, 1, 0]], "radius": [CM2], "parent": [-1]}
    w = transport(seg, [2.0], 0.25, soil=1.0, resistance=0, lift=0)
    assert w.received.tolist() == [0.25] and w.met.tolist() == [0.125] and w.total == 0.25
    w = transport(seg, [2.0], 4.0, soil=1.0, lift=0.1)  # enough: all of the demand
    assert w.met.tolist() == [1.0] and w.total == 2.0


def test_the_supply_is_never_exceeded_and_more_demand_brings_no_more_water():
    rng = np.random.default_rng(7)
    for trial in range(20):
        start, end, radius, parent, demand = _random_skeleton(rng, 40, roots=1 + trial % 3)
        seg = {"start": start, "end": end, "radius": radius, "parent": parent}
        roots = np.flatnonzero(parent < 0)
        for supply in (0.1, 1.0, 5.0):
            w = transport(seg, demand, supply, soil=1.0, resistance=0.2, lift=0.1)
            # each plant (root) receives at most its supply, and all of it when short
            own = np.array([_root(parent, i) for i in range(40)])
            for r in roots:
                got = w.received[own == r].sum()
                assert got <= supply * (1 + 1e-12)
                wanted = demand[(own == r) & (w.met > 0)].sum()
                assert got == pytest.approx(min(supply, wanted), rel=1e-10, abs=1e-12)
            twice = transport(seg, 2 * demand, supply, soil=1.0, resistance=0.2, lift=0.1)
            for r in roots:  # twice the demand (twice the leaves): no more water once short
                if demand[own == r].sum() >= supply:
                    assert twice.received[own == r].sum() == pytest.approx(
                        w.received[own == r].sum(), rel=1e-10
                    )


def _root(parent, i):
    while parent[i] >= 0:
        i = parent[i]
    return i


def test_chain():
    pts = [[0, y, 0] for y in range(6)]
    seg = _arrays(pts, [-1, 0, 1, 2, 3, 4], [-1, 0, 1, 2, 3])
    w = transport(seg, np.ones(5), 5.0, soil=1.0, resistance=0, lift=0)
    assert w.met.tolist() == [1.0] * 5  # enough for all
    w = transport(seg, np.ones(5), 2.5, soil=1.0, resistance=0, lift=0.2)
    assert np.all(np.diff(w.met) < 0)  # higher up, less water
    assert w.total == pytest.approx(2.5)


def test_two_equal_branches_share_equally():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [1, 2, 0], [-1, 2, 0]], [-1, 0, 1, 1], [-1, 0, 0])
    for supply in (0.3, 1.0, 2.0):
        w = transport(seg, [0.0, 1.0, 1.0], supply, soil=1.0)
        assert w.received[1] == w.received[2] and w.met[0] == 1.0
        assert w.total == pytest.approx(min(supply, 2.0))


def test_thin_long_branch_gets_less_than_thick_short():
    # a horizontal fork: one thick short branch, one thin long one, equal demand
    pts = [[0, 0, 0], [0, 1, 0], [1, 1, 0], [-3, 1, 0]]
    seg = _arrays(pts, [-1, 0, 1, 1], [-1, 0, 0], radius=[CM2, CM2, CM2 / 4])
    w = transport(seg, [0.0, 1.0, 1.0], 1.0, soil=1.0, resistance=0.05, lift=0)
    assert w.met[2] < w.met[1] <= 1.0 and w.total == pytest.approx(1.0)
    # the same fork, both thick and short: equal again
    seg = _arrays([[0, 0, 0], [0, 1, 0], [1, 1, 0], [-1, 1, 0]], [-1, 0, 1, 1], [-1, 0, 0])
    w = transport(seg, [0.0, 1.0, 1.0], 1.0, soil=1.0, resistance=0.05, lift=0)
    assert w.met[2] == w.met[1]


def test_zero_radius_passes_nothing():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0, 1], [-1, 0], radius=[CM2, 0.0])
    w = transport(seg, [1.0, 1.0], 5.0, soil=1.0, resistance=0.01, lift=0)
    assert w.met[0] == 1.0 and w.met[1] == 0.0


def test_ample_supply_meets_every_demand():
    rng = np.random.default_rng(1)
    start, end, radius, parent, demand = _random_skeleton(rng, 40)
    radius[radius == 0] = 0.01
    seg = {"start": start, "end": end, "radius": radius, "parent": parent}
    w = transport(seg, demand, demand.sum(), soil=1.0)
    np.testing.assert_allclose(w.met, 1.0)
    np.testing.assert_allclose(w.total, demand.sum())


def test_zero_water():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0, 1], [-1, 0])
    w = Water(supply=0.0).transport(seg, [0.0, 1.0])
    assert w.received.tolist() == [0.0, 0.0] and w.met.tolist() == [1.0, 0.0] and w.total == 0.0


def test_forest_is_its_plants():
    rng = np.random.default_rng(5)
    plants = []
    for _ in range(3):
        s, e, r, par, _d = _random_skeleton(rng, 20)
        plants.append(Plant(s, e, r, par, np.zeros(20), np.ones(20)))
    demand = [rng.uniform(0, 1, 20) for _ in plants]
    forest = transport(Plant.concat(plants), np.concatenate(demand), 0.6, soil=3.0, lift=0.1)
    alone = [transport(p, q, 0.6, soil=3.0, lift=0.1) for p, q in zip(plants, demand)]
    np.testing.assert_allclose(forest.received, np.concatenate([a.received for a in alone]))
    np.testing.assert_allclose(forest.total, sum(a.total for a in alone))


def test_stem_demand():
    p = Plant.from_points([[0, 0, 0], [0, 2, 0], [0, 3, 0]], [-1, 0], [-1, 0, 1], kind=[0, 1])
    assert segment_demand(p.kind, [9.0, 1.0], p.lengths(), 0.5).tolist() == [1.0, 1.0]
    w = transport(p, [9.0, 1.0], 1.0, soil=1.0, stem_demand=0.5, resistance=0, lift=0)
    assert w.received.tolist() == [0.5, 0.5]
    w = transport(p, [9.0, 1.0], 1.0, soil=1.0, resistance=0, lift=0)  # stems: nothing
    assert w.received.tolist() == [0.0, 1.0] and w.met[0] == 1.0


def test_gravity_scales_the_height_term():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [1, 1, 0]], [-1, 0, 1], [-1, 0])
    flat = transport(seg, [1.0, 1.0], 1.0, soil=1.0, resistance=0, lift=0.1, g=0.0)
    earth = transport(seg, [1.0, 1.0], 1.0, soil=1.0, resistance=0, lift=0.1, g=9.81)
    assert flat.met[0] == flat.met[1] == 0.5 and earth.met[0] == earth.met[1]  # both climb 1
    assert earth.total == pytest.approx(1.0)


def test_honda_tree_met_falls_with_path_and_height():
    plant = honda.develop(honda.PRESETS["zelkova"])
    leaf = plant.kind == LEAF
    env = Environment()
    w = env.water.transport(plant, leaf.astype(float), g=env.gravity.g)  # demand 1 a leaf
    assert np.all(w.met[~leaf] == 1.0)  # stems demand nothing
    assert np.all((w.met[leaf] > 0) & (w.met[leaf] < 1))  # 282 leaves, a soil of 20
    assert w.total == pytest.approx(env.water.soil)
    path = np.zeros(plant.n_segments)
    L = plant.lengths()
    for i in range(plant.n_segments):
        path[i] = L[i] + (path[plant.parent[i]] if plant.parent[i] >= 0 else 0.0)
    height = plant.end[:, 1]
    for x in (path[leaf], height[leaf]):
        rank = np.corrcoef(np.argsort(np.argsort(x)), np.argsort(np.argsort(w.met[leaf])))[0, 1]
        assert rank < -0.5
    order = np.argsort(height[leaf])
    assert w.met[leaf][order[-20:]].mean() < w.met[leaf][order[:20]].mean()


def test_input_errors():
    seg = _arrays([[0, 0, 0], [0, 1, 0], [0, 2, 0]], [-1, 0, 1], [-1, 0])
    with pytest.raises(UserInputError, match="supply"):
        transport(seg, [1.0, 1.0], -0.5)
    with pytest.raises(UserInputError, match="soil"):
        transport(seg, [1.0, 1.0], soil=-1.0)
    with pytest.raises(ConfigError, match=r"water\.supply"):
        Water.parse({"supply": -1}, where="water.")
    with pytest.raises(UserInputError, match="demand: segment 1 is negative"):
        transport(seg, [1.0, -1.0])
    with pytest.raises(UserInputError, match="demand: segment 0 is not finite"):
        transport(seg, [np.nan, 1.0])
    with pytest.raises(UserInputError, match=r"demand: (expected shape|has 1 rows)"):
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
    tree = honda.develop(honda.PRESETS["zelkova"])
    demand = (tree.kind == 1).astype(float)
    env = Environment.model_validate(
        {
            "water": {
                "supply": 0.8,
                "soil": 30.0,
                "resistance": 0.0,
                "lift": 0.02,
                "stem_demand": 0.001,
            }
        }
    )
    got = env.water.transport(tree, demand, g=env.gravity.g)
    want = transport(tree, demand, 0.8, soil=30.0, resistance=0.0, lift=0.02, stem_demand=0.001)
    np.testing.assert_array_equal(got.met, want.met)
    default = Environment().water.transport(tree, demand)
    assert not np.array_equal(got.met, default.met)
    with pytest.raises(Exception, match="resistance"):
        Environment.model_validate({"water": {"resistance": -1.0}})
    with pytest.raises(Exception, match="soil"):
        Environment.model_validate({"water": {"soil": -1.0}})
