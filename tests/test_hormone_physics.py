"""The hormone model's two physics (issue 43): ``growsim`` (leaves as organs that pay for
their area, water from a fixed supply shared by conductance, thickening by load, breaks
that shed) and ``paper`` (the paper's model as its text gives it): leaves drawn, weighed
and photosynthesising with one area; water never above the supply; fork cross-sections;
a break that sheds and a plant that goes on; sizes the plants decide; the new kernels
against their oracles."""

from __future__ import annotations

import numpy as np
import pytest
from naive import hormone_light as naive_light
from naive import hormone_mechanics as naive_mechanics
from naive import hormone_modules as naive_modules
from test_hormone import modules as module_tuple
from test_hormone import random_state

from growsim.env import Environment
from growsim.env.light import projected_area
from growsim.errors import ConfigError, UserInputError
from growsim.kernels import hormone as K
from growsim.models import hormone
from growsim.phenotypes.plant import Plant

SKY = Environment.model_validate(hormone.PRESET_ENVIRONMENTS["demo_3d"])
DEMOS = ("demo_2d", "demo_3d", "paper_2d", "paper_3d")


def _grown(name="demo_3d", steps=18, env=SKY, **extra):
    """``(n, state)`` of a plant of preset ``name`` grown ``steps`` steps (its
    :func:`growsim.models.hormone.seedling` state, updated in place)."""
    p = hormone.resolve_params(hormone.PARAMS, {**hormone.PRESETS[name], **extra})
    n, s = hormone.seedling(p, env)
    for _ in range(steps):
        n, code = K.grow_step(n, *s.values())
        assert code not in hormone.STOPPING
    return n, s


def _copy(s):
    return {**s, "modules": K.Modules(*(a.copy() for a in s["modules"]))}


def _forks(plant):
    """Parent cross-section over the sum of its children's, at every fork."""
    r2 = plant.radius**2
    kids: dict[int, list[int]] = {}
    for i, q in enumerate(plant.parent):
        if q >= 0:
            kids.setdefault(int(q), []).append(i)
    return np.array([r2[q] / r2[c].sum() for q, c in kids.items() if len(c) >= 2])


# -- leaves: one area photosynthesises, is drawn in the shadow map and carries mass
def test_photosynthesising_area_is_the_drawn_leaf_area_that_carries_leaf_mass():
    n, s = _grown()
    m = s["modules"]
    leaf, L = m.leaf[:n], m.length[:n]
    assert leaf.sum() > 0.5 and (leaf > 0).all()
    # drawn: each module is its stem and a coaxial foliage cylinder whose side view, 2 r L,
    # is its leaf area
    foliage = leaf / (2 * L)
    np.testing.assert_array_equal(m.drawn[:n], np.maximum(m.radius[:n], foliage))
    plant = hormone.develop({**hormone.PRESETS["demo_3d"], "steps": 18}, env=SKY)
    assert plant.n_segments == n  # the same plant, through the model
    blades = hormone.leaves(plant)
    np.testing.assert_allclose(2 * blades.radius * blades.lengths(), leaf[blades.data["module"]])
    np.testing.assert_allclose(plant.data["leaf_area"], leaf)
    # the leaves weigh leaf_mass_per_area each m^2 of that area (the stems and their
    # blades through the environment's gravity pass, each blade the child of its module)
    both = Plant.concat([plant, blades])
    parent = both.parent.copy()
    parent[n:] = blades.data["module"]
    loads = SKY.gravity.loads({"start": both.start, "end": both.end, "radius": both.radius,
                               "parent": parent, "kind": both.kind})  # fmt: skip
    np.testing.assert_allclose(loads.mass[n:], SKY.gravity.leaf_mass_per_area * leaf, rtol=1e-12)
    # photosynthesis is that area's: in proportion to it, blind to the stem's walls
    gained = []
    for scale, radius in ((1.0, 1.0), (2.0, 1.0), (1.0, 3.0), (0.0, 1.0)):
        x = _copy(s)
        x["modules"].leaf[:n] *= scale
        x["modules"].radius[:n] *= radius
        gained.append(K.step_kernel(n, 3, x["modules"], x["genes"], x["c"])[1])
    assert gained[0] > 0 and gained[3] == 0.0
    assert gained[1] == pytest.approx(2 * gained[0], rel=1e-12) and gained[2] == gained[0]


def test_leaves_cast_shade_in_the_shadow_map():
    # two level modules, one 1 m above the other and 5 cm aside, the sun straight from
    # above: the lower module's leaves are lit until the upper module grows leaves over
    # them
    env = hormone.environment_args(Environment.model_validate({"light": {"diffuse": 0.0}}))
    m = K.new_module_arrays(2, 6)
    m.parent[:] = -1
    m.R[:] = np.column_stack([(0.0, 1, 0), (0.0, 0, 1), (1.0, 0, 0)])  # growing along +x
    m.origin[:] = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.05]]
    m.length[:], m.radius[:] = 0.5, 0.002
    scratch = hormone.shadow_scratch(int(env.resolution))
    for upper_leaf, lit in ((0.0, 1.0), (0.2, 0.0)):
        m.leaf[:] = (0.05, upper_leaf)
        K.drawn_kernel(2, m)
        got = K.lights_kernel(2, 3, m, env, np.zeros((0, 3)), scratch, K.LEAVES)
        assert got.tolist() == [lit, 1.0]
    # the drawn foliage's shadow from above is its leaf area (and the capsule's round ends)
    r = m.drawn[1]
    shadow = projected_area(m.origin[1:], m.origin[1:] + 0.5 * m.R[1, :, 2], [r], resolution=512)
    assert shadow == pytest.approx(0.2 + np.pi * r**2, rel=0.02)


def test_one_upkeep_rule_in_2d_and_3d():
    # the same module, the same leaf light and water: the same carbon in 2D and 3D (genes
    # blind to the walls, so that the hormones agree)
    c = np.array([[*(d for _, d, _ in hormone.CONSTANTS), K.GROWSIM]])
    genes = hormone.genes(hormone.resolve_params(hormone.PARAMS, hormone.PRESETS["demo_3d"]))
    genes[:, 3:] = 0.0
    out = {}
    for dims, walls in ((2, 2), (3, 6)):
        m = K.new_module_arrays(2, walls)
        K.new_plant(m, c[0])
        m.length[0], m.radius[0], m.leaf[0], m.nutrient[0] = 0.4, 0.006, 0.1, 3.0
        m.leaf_light[0], m.met[0], m.hormone[0] = 0.7, 0.8, 0.3
        gained = K.step_kernel(1, dims, m, genes[None], c)[1]
        out[dims] = (gained, m.nutrient[0], m.leaf[0], m.length[0])
    assert out[2] == pytest.approx(out[3], rel=1e-12) and out[2][0] > 0


# -- water: a fixed supply shared by conductance
@pytest.mark.parametrize("dims", [2, 3])
def test_water_received_never_exceeds_the_supply(dims):
    for supply, soil in ((1.0, 20.0), (0.5, 2.0), (0.1, 1.0)):
        env = Environment.model_validate({**hormone.PRESET_ENVIRONMENTS[f"demo_{dims}d"],
                                          "water": {"supply": supply, "soil": soil}})  # fmt: skip
        binding = 0
        for plant in hormone.grow(hormone.PRESETS[f"demo_{dims}d"], env=env):
            got = plant.data["water"].sum()
            assert plant.meta["water_supply"] == supply * soil
            assert got <= supply * soil * (1 + 1e-12)
            assert (plant.data["water_met"] >= 0).all() and (plant.data["water_met"] <= 1).all()
            binding += got > 0.999 * supply * soil
        if soil <= 2.0:
            assert binding > 5  # the supply bound the plant, step after step


def test_doubling_leaf_area_brings_no_extra_water():
    env = Environment.model_validate({**hormone.PRESET_ENVIRONMENTS["demo_3d"],
                                      "water": {"soil": 2.0}})  # fmt: skip
    n, s = _grown(env=env)
    got = {}
    for scale in (1.0, 2.0):
        x = _copy(s)
        x["modules"].leaf[:n] *= scale
        K.grow_step(n, *x.values())
        got[scale] = x["modules"].water[:n].sum()
    assert got[1.0] == pytest.approx(2.0, rel=1e-12) and got[2.0] == pytest.approx(2.0, rel=1e-12)
    # the paper's water is a share of every pull: twice the pull, twice the water
    x = _copy(s)
    x["c"][:, K.C_PHYSICS] = K.PAPER
    K.grow_step(n, *x.values())
    assert x["modules"].met[:n].max() == 1.0  # supply 1: every pull met


# -- mechanics: forks, breaks
def test_fork_cross_sections_follow_the_loads():
    ratios = []
    for name in ("demo_2d", "demo_3d"):
        plant = hormone.develop(hormone.PRESETS[name], env=SKY)
        ratios.append(_forks(plant))
        assert len(ratios[-1]) >= 10
    ratios = np.concatenate(ratios)
    assert 0.8 <= np.median(ratios) <= 1.25  # the pipe model's 1, within a quarter


def test_a_break_sheds_the_branch_and_the_plant_goes_on():
    n, s = _grown(steps=20)
    m = s["modules"]
    parent = m.parent[:n]
    subtree = lambda k: {q for q in range(n) if _above(parent, q, k)}  # noqa: E731
    # a lateral branch of several modules, its base made a thread that cannot thicken
    k = max((q for q in range(1, n)), key=lambda q: (len(subtree(q)) < n // 2, len(subtree(q))))
    lost = subtree(k)
    assert 2 <= len(lost) < n // 2
    m.radius[k], m.target[k] = 1e-5, 0.0
    s["c"][:, K.C_THICK] = 0.0  # no thickening this step: it breaks
    kept_leaf = m.leaf[[q for q in range(n) if q not in lost]].sum()
    events = m.events.copy()
    n2, code = K.grow_step(n, *s.values())
    assert code != K.STOP_BROKEN and m.events[0] >= events[0] + 1
    assert m.events[1] - events[1] >= len(lost)
    assert m.leaf[:n2].sum() <= kept_leaf * 1.5
    # and the plant goes on growing
    s["c"][:, K.C_THICK] = hormone.resolve_params(hormone.PARAMS, {})["thickening"]
    area = m.leaf[:n2].sum()
    for _ in range(8):
        n2, code = K.grow_step(n2, *s.values())
        assert code not in hormone.STOPPING
    assert m.leaf[:n2].sum() > area and n2 > n - len(lost)


def _above(parent, q, k):
    """Whether module ``q`` is ``k`` or one of its descendants."""
    while q >= 0:
        if q == k:
            return True
        q = parent[q]
    return False


def test_a_fallen_growsim_plant_is_dead_a_paper_plant_keeps_its_nutrient():
    for name, total in (("demo_3d", 0.0), ("paper_3d", None)):
        plant = hormone.develop({**hormone.PRESETS[name], "strength_young": 1e3,
                                 "steps": 30}, env=SKY)  # fmt: skip
        assert plant.meta["stopped"] == "broken" and plant.meta["steps"] < 30
        if total is not None:
            assert plant.meta["total_nutrient"] == total
        else:
            assert plant.meta["total_nutrient"] > 0


def test_a_plant_that_cannot_pay_its_upkeep_starves():
    plant = hormone.develop({**hormone.PRESETS["demo_3d"], "leaf_upkeep": 1e3}, env=SKY)
    assert plant.meta["stopped"] == "starved" and plant.meta["total_nutrient"] < 0
    rows = [hormone.resolve_params(hormone.PARAMS, {**hormone.PRESETS["demo_3d"],
                                                    "leaf_upkeep": 1e3})]  # fmt: skip
    table = hormone.population(np.array([list(r.values()) for r in rows]), list(rows[0]), SKY)
    assert table.stopped.tolist() == ["starved"]
    assert table.total_nutrient[0] == plant.meta["total_nutrient"]


# -- sizes the model decides
@pytest.mark.parametrize("name", DEMOS)
def test_each_physics_grows_from_its_demo_preset_and_far_below_the_cap(name):
    env = Environment.model_validate(hormone.PRESET_ENVIRONMENTS[name])
    plants = list(hormone.grow(hormone.PRESETS[name], env=env))
    last = plants[-1]
    assert len(plants) == 30 and last.meta["stopped"] == ""
    assert last.meta["physics"] == ("paper" if name.startswith("paper") else "growsim")
    assert last.n_segments >= 4 and last.height() > 1.0
    for key in ("nutrient", "radius_like", "leaf_area", "water", "water_met"):
        values = last.radius if key == "radius_like" else last.data[key]
        assert np.isfinite(values).all(), key
    cap = hormone.resolve_params(hormone.PARAMS, hormone.PRESETS[name])["max_modules"]
    assert max(p.n_segments for p in plants) <= cap / 5
    assert all(p.meta["stopped"] != "cap" for p in plants)
    if name.startswith("demo"):
        assert last.data["leaf_area"].sum() > 0.5
    else:  # the paper's modules have no leaves: their walls photosynthesise
        assert (last.data["leaf_area"] == 0).all()


def test_the_physics_is_a_named_parameter():
    from growsim.experiment import load_config
    from growsim.experiment.plan import plan_model

    model = {"kind": "hormone", "params": {"physics": "paper"}, "evolve": {"h0_bias": True}}
    config = {"model": model, "objective": [{"kind": "nutrient"}]}
    assert plan_model(load_config(config)).fixed["physics"] == K.PAPER
    with pytest.raises(ConfigError, match=r"model\.params\.physics: 'papr' is not one of"):
        plan_model(load_config({**config, "model": {**model, "params": {"physics": "papr"}}}))
    with pytest.raises(UserInputError, match="physics"):
        hormone.develop({"physics": "nope"})
    assert hormone.develop({"physics": "paper", "steps": 2}).meta["physics"] == "paper"
    assert hormone.develop({"steps": 2}).meta["physics"] == "growsim"  # the default
    with pytest.raises(UserInputError, match="physics"):  # a stand grows with one physics
        next(hormone.grow_stand([{"steps": 2}, {"steps": 2, "physics": "paper"}], env=SKY,
                                xz=np.array([[0.0, 0.0], [1.0, 0.0]])))  # fmt: skip


# -- the new kernels against their oracles
@pytest.mark.parametrize("seed", range(6))
def test_mechanics_kernels_match_their_oracles(seed):
    rng = np.random.default_rng(60 + seed)
    dims = 2 if seed % 2 else 3
    n, plants = int(rng.integers(2, 40)), 1 + (seed >= 4) * 2
    state, inputs = random_state(rng, n, n + 5, 2 if dims == 2 else 5, dims, plants)
    state["hormone"][:, :, 1] = rng.uniform(0, 1.5, state["hormone"].shape[:2])
    young = rng.uniform(1e6, 3e7, plants)
    material = (800.0, 0.1, 9.81, 4e7)
    a = module_tuple({k: v.copy() for k, v in state.items()}, inputs)
    b = module_tuple({k: v.copy() for k, v in state.items()}, inputs)
    for m in (a, b):
        m.origin[:] = K.place_kernel(n, m.parent, m.R, m.length, m.origin)
    want = naive_mechanics.design_kernel(n, b, inputs["c"], young, material)[:n]
    np.testing.assert_allclose(K.design_kernel(n, a, inputs["c"], young, material)[:n], want,
                               rtol=1e-10)  # fmt: skip
    a.nutrient[:] = b.nutrient[:] = rng.uniform(-1, 3, len(a.nutrient))
    want = naive_mechanics.thicken_kernel(n, b, inputs["c"])[:n]
    np.testing.assert_allclose(K.thicken_kernel(n, a, inputs["c"])[:n], want, rtol=1e-10)
    np.testing.assert_allclose(a.nutrient[:n], b.nutrient[:n], rtol=1e-9, atol=1e-12)
    assert (a.radius[:n] >= state["radius"][:n]).all()
    np.testing.assert_array_equal(K.drawn_kernel(n, a)[:n], naive_modules.drawn_kernel(n, b)[:n])
    for field in K.Modules._fields:  # the same state for the shedding
        getattr(b, field)[...] = getattr(a, field)
    broken = rng.random(n) < 0.15
    broken[0] = False
    kept = K.shed_kernel(n, a, broken)
    assert kept == naive_mechanics.shed_kernel(n, b, broken)
    for field in K.Modules._fields:
        got, want = getattr(a, field), getattr(b, field)
        if field != "events":
            got, want = got[:kept], want[:kept]
        np.testing.assert_array_equal(got, want, err_msg=field)


def test_light_helpers_match_their_oracles():
    # each module's far end, and the modules lying on the soil unlit, as NumPy does them
    from growsim.kernels import hormone_light as KL

    rng = np.random.default_rng(5)
    n = 40
    origin, length = rng.normal(size=(n, 3)), rng.uniform(0.1, 0.5, n)
    R = np.linalg.qr(rng.normal(size=(n, 3, 3)))[0]
    end = KL.module_ends(n, origin, length, R, np.empty((n, 3)))
    np.testing.assert_allclose(end, naive_light.module_ends(n, origin, length, R, np.empty((n, 3))),
                               rtol=1e-15, atol=1e-15)  # fmt: skip
    end[:, 1] = np.abs(end[:, 1]) + 0.1
    end[::3, 1] = 0.0  # a third of them lie on the soil at 0
    arrays = [
        rng.uniform(size=(n, 6)),
        rng.uniform(size=n),
        rng.uniform(size=n),
        rng.uniform(size=n),
    ]
    copies = [a.copy() for a in arrays]
    KL.soil_unlit(n, end, length, 0.0, *arrays)
    naive_light.soil_unlit(n, end, length, 0.0, *copies)
    for a, b in zip(arrays, copies):
        np.testing.assert_array_equal(a, b)
    assert (arrays[1][::3] == 0).all() and (arrays[1][1::3] > 0).all()
