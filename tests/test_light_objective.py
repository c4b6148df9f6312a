"""The light objective: leaf light from the shadow map, light response, the old projection."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from growsim.env import Environment, Light
from growsim.errors import ConfigError
from growsim.experiment import load_config
from growsim.models.honda import PRESETS, develop
from growsim.objectives.light import LightObjective, saturating_response
from growsim.phenotypes.plant import LEAF, STEM, Plant, leaf_light

BLADE = 0.5  # a leaf of length 1 and radius 0.25: a blade 1 x 0.5


def segments(rows, kinds, radius=0.25) -> Plant:
    """A plant of separate segments ``rows = [(start, end), ...]`` (each its own root)."""
    n = len(rows)
    return Plant(
        np.array([r[0] for r in rows], float),
        np.array([r[1] for r in rows], float),
        np.broadcast_to(np.asarray(radius, float), (n,)).copy(),
        np.full(n, -1),
        np.zeros(n, np.int32),
        np.array(kinds, np.int8),
    )


def env_with(**light) -> Environment:
    return Environment.model_validate({"light": light})


@pytest.fixture(scope="module")
def tree() -> Plant:
    return develop(PRESETS["zelkova"])


# ------------------------------------------------------------------ the response R


@pytest.mark.parametrize("k", [0.05, 0.25, 0.5, 1.0, 4.0])
def test_saturating_response_is_a_normalised_rectangular_hyperbola(k):
    L = np.linspace(0.0, 3.0, 301)
    R = saturating_response(L, k)
    assert saturating_response(1.0, k) == pytest.approx(1.0, rel=1e-15)
    assert R[0] == 0.0
    assert saturating_response(k, k) == pytest.approx((1 + k) / 2)  # K: half of the way
    assert np.all(np.diff(R) > 0)  # rises
    assert np.all(np.diff(R, 2) < 1e-12)  # concave
    low, high = L <= 1.0, L >= 1.0
    assert np.all(R[low] >= L[low] - 1e-12) and np.all(R[high] <= L[high] + 1e-12)
    # P = Pmax L / (L + K) with Pmax = 1 + K
    np.testing.assert_allclose(R, (1 + k) * L / (L + k), rtol=1e-14)


def test_linear_and_saturating_on_a_tree(tree):
    lin = LightObjective(wood_cost=0.0)
    sat = LightObjective(wood_cost=0.0, response="saturating", half_saturation=0.3)
    tl, ts = lin.terms(tree), sat.terms(tree)
    assert tl["leaf_area"] == ts["leaf_area"] and tl["wood_volume"] == ts["wood_volume"]
    # the formula, term by term: blade areas x R(segment light) over the leaves
    leaf = tree.kind == LEAF
    L = Light().segment_light(tree)[leaf]
    A = 2.0 * tree.radius[leaf] * tree.lengths()[leaf]
    assert tl["leaf_area"] == pytest.approx(A.sum(), rel=1e-12)
    assert tl["light"] == pytest.approx(np.sum(A * L), rel=1e-12)
    assert ts["light"] == pytest.approx(np.sum(A * 1.3 * L / (L + 0.3)), rel=1e-12)
    # some leaves are shaded, some lit; none gets more than full light
    assert 0.0 < tl["light"] < tl["leaf_area"] and L.max() <= 1.0 + 1e-12
    # so the saturating response counts each leaf at least as much (R(L) >= L for L <= 1)
    assert ts["light"] > tl["light"]
    # a very large K is the linear response again
    flat = LightObjective(wood_cost=0.0, response="saturating", half_saturation=1e6)
    assert flat(tree) == pytest.approx(lin(tree), rel=1e-5)
    # and the score is light - wood_cost * wood volume
    costly = LightObjective(wood_cost=0.7)
    assert costly(tree) == pytest.approx(tl["light"] - 0.7 * tl["wood_volume"], rel=1e-12)


def test_saturation_penalises_stacked_leaves_less_at_low_light():
    # two leaves side by side (a monolayer) against the same two stacked, the lower one in
    # the upper one's partial shade (soft shadows let half the light through), dim light
    side_by_side = segments([([0, 2, 0], [1, 2, 0]), ([3, 2, 0], [4, 2, 0])], [LEAF, LEAF])
    stacked = segments([([0, 2, 0], [1, 2, 0]), ([0, 0, 0], [1, 0, 0])], [LEAF, LEAF])
    env = env_with(intensity=0.3, shadows="soft", transmission=0.5)
    lower = env.light.segment_light(stacked)[1]
    assert 0.0 < lower < 0.3
    for k in (0.1, 0.5, 2.0):
        ratio = {}
        for response in ("linear", "saturating"):
            obj = LightObjective(response=response, half_saturation=k, wood_cost=0.0, env=env)
            ratio[response] = obj(stacked) / obj(side_by_side)
        assert ratio["linear"] == pytest.approx((0.3 + lower) / 0.6, rel=1e-9)
        assert 0.5 < ratio["linear"] < ratio["saturating"] < 1.0


# ------------------------------------------------------------------ shading


def test_a_leaf_under_a_leaf_receives_nothing_and_its_area_does_not_count():
    top = ([0, 2, 0], [1, 2, 0])
    pair = segments([top, ([0, 0, 0], [1, 0, 0])], [LEAF, LEAF])
    alone = segments([top], [LEAF])
    light = Light().segment_light(pair)
    assert light[0] == pytest.approx(1.0) and light[1] == pytest.approx(0.0, abs=1e-12)
    obj = LightObjective(wood_cost=0.0)
    t = obj.terms(pair)
    assert t["leaf_area"] == pytest.approx(2 * BLADE)  # both blades
    assert t["light"] == pytest.approx(BLADE) == obj(alone)  # only the top one is lit
    # moved aside, the lower leaf counts again
    apart = segments([top, ([3, 0, 0], [4, 0, 0])], [LEAF, LEAF])
    assert obj(apart) == pytest.approx(2 * BLADE)


def test_a_stem_above_a_leaf_shades_it():
    leaf = ([0, 0, 0], [1, 0, 0])
    over = segments([([-0.5, 2, 0], [1.5, 2, 0]), leaf], [STEM, LEAF], radius=[0.4, 0.25])
    aside = segments([([-0.5, 2, 5], [1.5, 2, 5]), leaf], [STEM, LEAF], radius=[0.4, 0.25])
    obj = LightObjective(wood_cost=0.0)
    assert obj.terms(over)["light"] == pytest.approx(0.0, abs=1e-12)
    assert obj.terms(aside)["light"] == pytest.approx(BLADE)
    # stems never count as light, only as shade
    assert obj.terms(over)["leaf_area"] == pytest.approx(BLADE)


def test_overrides_are_the_environment_light_with_those_values(tree):
    env = env_with(intensity=0.5, direction=[1.0, -1.0, 0.0])
    mine = LightObjective(direction=[1.0, -1.0, 0.0], intensity=0.5, wood_cost=0.0)
    bound = LightObjective(wood_cost=0.0, env=env)
    assert mine(tree) == bound(tree) > 0
    assert bound.light is env.light  # no override: the environment's own light
    assert LightObjective(resolution=64).light.resolution == 64
    assert LightObjective().resolution == Light().resolution
    sat = LightObjective(response="saturating", half_saturation=0.5, env=env)
    assert pickle.loads(pickle.dumps(sat))(tree) == sat(tree)


def test_measures_light_captured_is_the_linear_light_term(tree):
    env = env_with(intensity=0.7, direction=[0.0, -1.0, 1.0])
    m = tree.measures(env)
    assert m["light_captured"] == LightObjective(env=env).terms(tree)["light"]
    assert m["light_captured"] == leaf_light(tree, env.light).light
    stems = segments([([0, 0, 0], [0, 1, 0])], [STEM])
    assert stems.measures(env)["light_captured"] == 0.0


# ------------------------------------------------------------------ the old measure


def test_projection_is_exactly_the_old_formula(tree):
    env = env_with(intensity=0.8, direction=[1.0, -1.0, 0.0])
    for opts in (
        {"wood_cost": 0.5, "resolution": 64},
        {"wood_cost": 1.0, "resolution": 128, "direction": [0, -1, 0], "intensity": 2.0},
        {"wood_cost": 0.02},
    ):
        obj = LightObjective(shading="projection", env=env, **opts)
        d = opts.get("direction", env.light.direction)
        intensity = opts.get("intensity", env.light.intensity)
        res = opts.get("resolution", env.light.resolution)
        area = tree.leaf_area(tuple(float(x) for x in d), resolution=res)
        old = intensity * area - opts["wood_cost"] * tree.wood_volume()
        assert obj(tree) == old
        t = obj.terms(tree)
        assert t["leaf_area"] == area and t["light"] == intensity * area


# ------------------------------------------------------------------ options


@pytest.mark.parametrize(
    ("option", "needle"),
    [
        ({"half_saturation": 0}, "objective[0].half_saturation: Input should be greater than 0"),
        ({"half_saturation": -1.0}, "objective[0].half_saturation"),
        ({"half_saturation": "x"}, "objective[0].half_saturation"),
        ({"response": "sigmoid"}, "objective[0].response"),
        ({"shading": "zbuffer"}, "objective[0].shading"),
        ({"resolution": 8}, "objective[0].resolution"),
        ({"resolution": 1.5}, "objective[0].resolution"),
        ({"direction": [0, 0, 0]}, "objective[0].direction"),
        ({"wood_cost": -1}, "objective[0].wood_cost"),
        ({"saturation": 0.5}, "objective[0].saturation: unknown key; allowed: kind, weight"),
        (
            {"shading": "projection", "response": "saturating"},
            "objective[0]: response = 'saturating' needs shading = 'shadow-map'",
        ),
    ],
)
def test_bad_options_are_refused_with_their_key_path(option, needle):
    cfg = {
        "model": {"kind": "honda", "evolve": {"f": True}},
        "objective": [{"kind": "light", **option}],
        "ga": {"population": 10, "generations": 3},
    }
    with pytest.raises(ConfigError) as info:
        load_config(cfg)
    assert needle in str(info.value), str(info.value)
    with pytest.raises(ConfigError):
        LightObjective(**option)


def test_resolved_config_round_trips_the_new_options():
    import tomllib

    cfg = load_config(
        {
            "model": {"kind": "honda", "evolve": {"f": True}},
            "objective": [{"kind": "light", "response": "saturating", "half_saturation": 0.2}],
            "ga": {"population": 10, "generations": 3},
        }
    )
    o = cfg.objective[0]
    assert (o.shading, o.response, o.half_saturation, o.resolution) == (
        "shadow-map",
        "saturating",
        0.2,
        None,
    )
    assert load_config(tomllib.loads(cfg.to_toml())).objective[0] == o
