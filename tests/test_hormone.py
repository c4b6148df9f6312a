"""The hormone-module model (growsim.models.hormone, growsim.kernels.hormone; oracle in
tests/naive/hormone.py)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT
from naive import hormone as naive
from naive import hormone_mechanics as naive_mechanics
from naive import walls as naive_walls

from growsim.env import Environment
from growsim.errors import UserInputError
from growsim.kernels import hormone as K
from growsim.kernels import walls as KW
from growsim.models import get_model, hormone
from growsim.objectives.nutrient import NutrientObjective

SKY = Environment.model_validate({"light": {"diffuse": 0.5, "direction": [0.3, -1.0, 0.2]}})


def random_state(rng, n, cap, walls, dims, plants=1, physics=K.GROWSIM):
    """A random population of modules, parents first, and random inputs of a step:
    ``plants`` plants (some modules are roots; a module belongs to its parent's plant), each
    its own genes and constants (``inputs["genes"]`` ``(plants, H, 3 + J)``, ``c``
    ``(plants, C)``, the ``physics`` last)."""
    H, J = len(K.HORMONES), len(K.STIMULI)
    parent = np.array([-1] + [int(rng.integers(0, m)) for m in range(1, n)] + [-1] * (cap - n))
    plant = np.zeros(cap, np.int64)
    for m in range(1, n):
        if plants > 1 and rng.random() < 0.15:  # a root of a random plant
            parent[m], plant[m] = -1, rng.integers(0, plants)
        else:
            plant[m] = plant[parent[m]]
    R = np.zeros((cap, 3, 3))
    for m in range(cap):
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        if dims == 2:  # axes in the x-y plane, the second across the plane
            a = rng.uniform(0, 2 * np.pi)
            q = np.column_stack([[np.cos(a), np.sin(a), 0], [0, 0, -1], [-np.sin(a), np.cos(a), 0]])
        R[m] = q * np.sign(np.linalg.det(q))
    c = np.array([d for _, d, _ in hormone.CONSTANTS] + [physics])
    state = dict(
        parent=parent, R=R, length=rng.uniform(0.1, 0.6, cap), radius=rng.uniform(0.002, 0.02, cap),
        nutrient=rng.uniform(-1.0, 60.0, cap), chlorophyll=rng.uniform(0, 1, cap),
        lignin=rng.uniform(0, 1, cap), apex=rng.random(cap) < 0.5,
        laterals=rng.integers(0, 2, cap).astype(np.int64),
        hormone=rng.uniform(0, 1, (cap, walls, H)), plant=plant,
        leaf=rng.uniform(0, 0.2, cap), target=rng.uniform(0, 0.03, cap),
    )  # fmt: skip

    def random_genes():
        return np.column_stack([rng.uniform(-2, 2, H), rng.uniform(0, 1, H),
                                rng.uniform(0, 1, H), rng.uniform(-3, 3, (H, J))])  # fmt: skip

    inputs = dict(wall_light=rng.uniform(0, 1, (cap, walls)), met=rng.uniform(0, 1, cap),
                  leaf_light=rng.uniform(0, 1, cap))  # fmt: skip
    genes = [random_genes() for _ in range(plants)]
    inputs["genes"] = np.stack(genes)
    # the other plants' constants: the defaults scaled by up to 20 % (the same physics)
    scale = [np.r_[rng.uniform(0.8, 1.2, len(c) - 1), 1.0] for _ in range(plants - 1)]
    inputs["c"] = np.stack([c] + [c * f for f in scale])
    return state, inputs


def modules(state, inputs):
    """The :class:`growsim.kernels.hormone.Modules` of a :func:`random_state` (the arrays
    themselves, not copies)."""
    cap = len(state["parent"])
    return K.Modules(
        state["parent"], state["R"], np.zeros((cap, 3)), state["length"], state["radius"],
        state["nutrient"], state["chlorophyll"], state["lignin"], state["apex"],
        state["laterals"], state["hormone"], inputs["wall_light"], inputs["met"], np.zeros(cap),
        state["plant"], state["leaf"], state["target"], np.zeros(cap), np.zeros(cap),
        inputs["leaf_light"], np.zeros(2, np.int64),
    )  # fmt: skip


@pytest.mark.parametrize("physics", [K.GROWSIM, K.PAPER])
@pytest.mark.parametrize("seed", range(8))
def test_step_kernel_matches_oracle(seed, physics):
    # seeds 6 and 7: three plants, each its own genes and constants (a mixed stand)
    rng = np.random.default_rng(seed)
    dims = 2 if seed % 2 else 3
    walls = 2 if dims == 2 else int(rng.integers(3, 8))
    n, cap = int(rng.integers(1, 30)), 60
    plants = 3 if seed >= 6 else 1
    state, inputs = random_state(rng, n if plants == 1 else 30, cap, walls, dims, plants,
                                 physics)  # fmt: skip
    n = n if plants == 1 else 30
    if plants > 1:
        assert len(set(state["plant"][:n].tolist())) > 1
    a = {k: v.copy() for k, v in state.items()}
    b = {k: v.copy() for k, v in state.items()}
    got = K.step_kernel(n, dims, modules(a, inputs), inputs["genes"], inputs["c"])
    want = naive.step_kernel(n, dims, modules(b, inputs), inputs["genes"], inputs["c"])
    assert got[0] == want[0]
    assert got[1] == pytest.approx(want[1], rel=1e-12)
    for k in a:
        np.testing.assert_allclose(a[k][: got[0]], b[k][: got[0]], rtol=1e-9, atol=1e-12, err_msg=k)


def test_place_kernel_matches_oracle():
    rng = np.random.default_rng(1)
    state, _ = random_state(rng, 40, 40, 6, 3)
    origin = np.zeros((40, 3))
    got = K.place_kernel(40, state["parent"], state["R"], state["length"], origin.copy())
    np.testing.assert_allclose(got, naive.place_kernel(40, state["parent"], state["R"],
                                                       state["length"], origin))  # fmt: skip


def test_walls_match_oracle():
    rng = np.random.default_rng(2)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    for dims, walls in ((2, 2), (3, 3), (3, 6)):
        got = KW.wall_frame(q, walls, dims, np.empty((walls, 3)))
        np.testing.assert_allclose(got, naive_walls.wall_frame(q, walls, dims), atol=1e-12)


def test_one_module_step_worked_by_hand_from_the_doc():
    # one 2D module of the growsim physics, lit more on its +x wall, one step; every
    # number below follows the equations of docs/models/hormone.md ("One step"), not the
    # kernel's loops
    sig = lambda a: 1.0 / (1.0 + np.exp(-a))  # noqa: E731
    C = {name: d for name, d, _ in hormone.CONSTANTS}
    c = np.array([*C.values(), K.GROWSIM])
    eps, maxlen, turn = C["elongation"], C["max_length"], C["turning"]
    p_, K_, b_, u_ = C["photosynthesis"], C["half_saturation"], C["build_cost"], C["upkeep"]
    uL, tau, gL, rhoL, cL = (C[k] for k in ("leaf_upkeep", "leaf_turnover", "leaf_growth",
                                             "leaf_density", "leaf_cost"))  # fmt: skip
    lam, rho, kappa, q_ = C["lignify"], C["greening"], C["chlorophyll_loss"], C["drought"]
    assert (eps, maxlen, turn, p_, b_) == (0.15, 0.5, 0.3, 50.0, 3e5)  # the documented units
    beta = np.array([0.0, 1.0, -5.0, 0.0, -5.0, 0.0, 0.0, 0.0, 2.0, -1.0])
    gamma = np.array([1.0, 0.5, 0.1, 0.3, 0.1, 1.0, 0.4, 0.6, 1.0, 1.0])
    genes = np.zeros((10, 9))
    genes[:, 0], genes[:, 1], genes[:, 2] = beta, gamma, 0.5
    genes[0, 3] = 2.0  # elongation: weight 2 on the wall's light
    walls, cap = 2, 3
    m = K.new_module_arrays(cap, walls)
    K.new_plant(m, c)  # one module growing up (+y), its walls facing +x and -x
    L, r, n0, chl, lig, A0 = 0.3, 0.004, 5.0, 0.8, 0.1, 0.05
    m.length[0], m.radius[0], m.nutrient[0], m.leaf[0] = L, r, n0, A0
    m.chlorophyll[0], m.lignin[0] = chl, lig
    m.hormone[0] = 0.2
    light, up, w = np.array([0.6, 0.2]), 0.8, 0.9
    m.wall_light[0], m.leaf_light[0], m.met[0] = light, up, w
    n_new, gained = K.step_kernel(1, 2, m, genes[None], c[None])
    # hormones: h = (1 - decay) h + gain sigma(bias + a . x); only h0 reads the light
    h = 0.5 * 0.2 + gamma[None, :] * sig(beta[None, :] + np.outer(light, genes[:, 3]))
    H = h.mean(axis=0)
    np.testing.assert_allclose(m.hormone[0], h, rtol=1e-14)
    # photosynthesis of the leaves (facing up), saturating: P = p A l (1 + K) / (l + K) c w s
    s = 1 - q_ * min(1.0, H[7])
    P = p_ * A0 * up * (1 + K_) / (up + K_) * chl * w * s
    assert gained == pytest.approx(P, rel=1e-13)
    # upkeep of the leaves and the wood; the leaves' turnover
    n1 = n0 + P - uL * A0 - u_ * np.pi * r**2 * L
    A1 = A0 * (1 - tau)
    # elongation: e_i = eps h_i0 w s (1 - g), the module by the mean, paying b pi r^2 e
    e = eps * h[:, 0] * w * s * (1 - lig)
    grow = min(e.mean(), maxlen - L)
    n2 = n1 - b_ * np.pi * r**2 * grow
    assert m.length[0] == pytest.approx(L + grow, rel=1e-14)
    # turning: the +x wall grew more, so the tip leans to -x by t min(1, H8) (e0 - e1) / L
    alpha = turn * min(1.0, H[8]) * (e[0] - e[1]) / L
    assert alpha > 0
    np.testing.assert_allclose(m.R[0, :, 2], [-np.sin(alpha), np.cos(alpha), 0.0], atol=1e-14)
    # leaves grow: dA = min(g_L min(1, H9) (1 - g) L', rho_L L' - A), paying c_L dA
    L1 = L + grow
    dA = min(gL * min(1.0, H[9]) * (1 - lig) * L1, rhoL * L1 - A1)
    assert m.leaf[0] == pytest.approx(A1 + dA, rel=1e-13)
    assert m.nutrient[0] == pytest.approx(n2 - cL * dA, rel=1e-12)
    assert m.radius[0] == r  # growsim thickens before the step (thicken_kernel), not here
    # lignin and chlorophyll
    dg = lam * min(1.0, H[5])
    assert m.lignin[0] == pytest.approx(lig + dg, rel=1e-14)
    assert m.chlorophyll[0] == pytest.approx(chl - kappa * dg + rho * min(1.0, H[6]), rel=1e-14)
    # no new module: not grown to max_length, branching hormone under the threshold
    assert n_new == 1 and H[2] < 0.5
    # the oracle agrees with the hand (it is compared with the kernel above)
    o = K.new_module_arrays(cap, walls)
    K.new_plant(o, c)
    o.length[0], o.radius[0], o.nutrient[0], o.leaf[0] = L, r, n0, A0
    o.chlorophyll[0], o.lignin[0] = chl, lig
    o.hormone[0], o.wall_light[0], o.leaf_light[0], o.met[0] = 0.2, light, up, w
    assert naive.step_kernel(1, 2, o, genes[None], c[None])[1] == pytest.approx(P, rel=1e-13)
    assert o.nutrient[0] == pytest.approx(n2 - cL * dA, rel=1e-12)


def test_the_ground_worked_by_hand():
    # a module starting 0.1 above the soil, leaning 60 degrees below the horizontal, 0.4
    # long: its end would be at 0.1 - 0.4 sin 60 = -0.246; it is turned up (about the
    # horizontal axis across it) until its end touches the soil: sin(elevation) = -0.1 / 0.4
    a = np.radians(-60.0)
    z = np.array([np.cos(a) * 0.6, np.sin(a), np.cos(a) * 0.8])  # across the horizontal: x
    x = np.array([0.8, 0.0, -0.6])  # across, horizontal
    R = np.column_stack([x, np.cross(z, x), z])[None]
    origin = np.array([[0.0, 0.1, 0.0]])
    for ground in (0.0, -0.5):
        Rk = R.copy()
        K.ground_kernel(1, np.array([-1]), Rk, np.array([0.4]), origin.copy(), ground)
        want = min(0.0, ground) if ground > 0.1 - 0.4 * np.sin(np.radians(60)) else None
        if want is None:  # the soil is lower than the end: nothing moves
            np.testing.assert_array_equal(Rk, R)
            continue
        rise = (ground - 0.1) / 0.4
        turned = np.array([np.sqrt(1 - rise**2) * 0.6, rise, np.sqrt(1 - rise**2) * 0.8])
        np.testing.assert_allclose(Rk[0, :, 2], turned, atol=1e-14)
        np.testing.assert_allclose(Rk[0, :, 0], x, atol=1e-14)  # the axis it turned about
        np.testing.assert_allclose(Rk[0] @ Rk[0].T, np.eye(3), atol=1e-14)


@pytest.mark.parametrize("seed", range(4))
def test_ground_kernel_matches_oracle(seed):
    rng = np.random.default_rng(10 + seed)
    n = 40
    state, _ = random_state(rng, n, n, 6, 3 if seed % 2 else 2)
    height = -float(rng.uniform(0.0, 0.4))
    R1, R2 = state["R"].copy(), state["R"].copy()
    o1 = K.ground_kernel(n, state["parent"], R1, state["length"], np.zeros((n, 3)), height)
    o2 = naive.ground_kernel(n, state["parent"], R2, state["length"], np.zeros((n, 3)), height)
    np.testing.assert_allclose(o1, o2, atol=1e-12)
    np.testing.assert_allclose(R1, R2, atol=1e-12)
    ends = o1 + state["length"][:, None] * R1[:, :, 2]
    assert ends[:, 1].min() >= height - 1e-12
    assert (np.abs(ends[:, 1] - height) < 1e-9).sum() >= 3  # several were turned up
    assert not np.array_equal(R1, state["R"])


@pytest.mark.parametrize("seed", range(4))
def test_several_steps_match_the_oracle(seed):
    # eight steps in a row, new light and water each step, the ground placing the modules
    # after each: the kernels and the oracle carry the same plant from step to step
    rng = np.random.default_rng(20 + seed)
    dims = 2 if seed % 2 else 3
    walls = 2 if dims == 2 else 5
    n, cap = 3, 80
    state, inputs = random_state(rng, n, cap, walls, dims)
    inputs["c"][:, K.C_MAXLEN] = 0.3  # modules finish growing: apical children come
    if seed >= 2:  # the demo genome (it branches), else random genes
        inputs["genes"][0] = hormone.genes(
            hormone.resolve_params(hormone.PARAMS, hormone.PRESETS["demo_3d"])
        )
    else:  # random genes with elongation and a meristem always on
        inputs["genes"][0, [0, 4], :3] = (4.0, 1.0, 0.5)
        inputs["genes"][0, 4, 3:] = 0.0
    state["nutrient"][:] = 20.0
    state["apex"][:] = True
    a = {k: v.copy() for k, v in state.items()}
    b = {k: v.copy() for k, v in state.items()}
    na = nb = n
    grew = []
    for _ in range(8):
        inputs["wall_light"] = rng.uniform(0, 1, (cap, walls))
        inputs["met"] = rng.uniform(0.5, 1, cap)
        inputs["leaf_light"] = rng.uniform(0, 1, cap)
        ma, mb = modules(a, inputs), modules(b, inputs)
        na, ga = K.step_kernel(na, dims, ma, inputs["genes"], inputs["c"])
        nb, gb = naive.step_kernel(nb, dims, mb, inputs["genes"], inputs["c"])
        K.ground_kernel(na, a["parent"], a["R"], a["length"], ma.origin, -0.2)
        ob = naive.ground_kernel(nb, b["parent"], b["R"], b["length"], mb.origin, -0.2)
        assert na == nb
        # the radius each module's loads ask for, which the next step thickens toward
        material = (800.0, 0.1, 9.81, 4e7)
        young = np.full(len(inputs["c"]), 5e6)
        mb.origin[:] = ob
        K.design_kernel(na, ma, inputs["c"], young, material)
        naive_mechanics.design_kernel(nb, mb, inputs["c"], young, material)
        assert ga == pytest.approx(gb, rel=1e-10)
        np.testing.assert_allclose(ma.origin[:na], ob[:na], rtol=1e-9, atol=1e-10)
        for k in a:
            np.testing.assert_allclose(a[k][:na], b[k][:na], rtol=1e-9, atol=1e-10, err_msg=k)
        grew.append(na)
    assert grew[-1] > n + 2  # the plant grew new modules on the way


def test_grows_step_by_step_deterministically_and_2d_stays_in_its_plane():
    params = {**hormone.PRESETS["demo_2d"], "steps": 20}
    plants = list(get_model("hormone").grow(params, env=SKY))
    assert len(plants) == 20
    sizes = [p.n_segments for p in plants]
    assert sizes == sorted(sizes) and sizes[-1] > 10
    last = plants[-1]
    assert np.all(last.start[:, 2] == 0) and np.all(last.end[:, 2] == 0)  # the x-y plane
    again = hormone.develop(params, env=SKY)
    np.testing.assert_array_equal(again.end, last.end)
    np.testing.assert_array_equal(again.data["nutrient"], last.data["nutrient"])
    assert last.meta["total_nutrient"] == pytest.approx(last.data["nutrient"].sum())


def test_environment_changes_the_plant():
    params = {**hormone.PRESETS["demo_2d"], "steps": 25}
    full = hormone.develop(params, env=SKY)
    dark = hormone.develop(params, env=SKY.model_copy(
        update={"light": SKY.light.model_copy(update={"intensity": 0.5})}))  # fmt: skip
    dry = hormone.develop(params, env=Environment.model_validate(
        {"light": SKY.light.model_dump(), "water": {"supply": 0.5}}))  # fmt: skip
    obj = NutrientObjective(env=SKY)
    assert obj(dark) < obj(full) and obj(dry) < obj(full)
    # light from the side: the shaded walls elongate (the demo's genes), so it leans to it
    side = Environment.model_validate({"light": {"diffuse": 0.3, "direction": [1.0, -0.3, 0.0]}})
    leaning = hormone.develop(params, env=side)
    tips = leaning.end[leaning.n_segments // 2 :]
    assert tips[:, 0].mean() < -0.2  # light travels +x: it comes from -x


def test_module_cap_break_and_nan_stop_the_plant():
    capped = hormone.develop({**hormone.PRESETS["demo_3d"], "max_modules": 20}, env=SKY)
    assert capped.n_segments == 20 and capped.meta["stopped"] == "cap"
    weak = hormone.develop({**hormone.PRESETS["demo_3d"], "strength_young": 1e3}, env=SKY)
    assert weak.meta["stopped"] == "broken" and weak.meta["steps"] < 30
    # parent and child even out a million times their difference: the nutrient swings
    # grow without bound until they overflow (inf - inf = NaN), which stops the plant (in
    # the paper's physics: a growsim plant starves first, its costs paid by the swings)
    blown_params = {**hormone.PRESETS["paper_2d"], "share": 1e6}
    blown = hormone.develop(blown_params, env=SKY)
    assert blown.meta["stopped"] == "nan" and blown.meta["steps"] < 30
    assert np.isnan(blown.meta["total_nutrient"])
    obj = NutrientObjective(env=SKY)
    assert np.isnan(obj(blown)) and np.isfinite(obj(capped))
    rows, names = _rows([blown_params, hormone.PRESETS["demo_2d"]])
    table = hormone.population(rows, names, SKY)
    assert table.stopped.tolist() == ["nan", ""]
    assert np.isnan(table.total_nutrient[0]) and np.isfinite(table.total_nutrient[1])


def _rows(params_list):
    rows = [hormone.resolve_params(hormone.PARAMS, p) for p in params_list]
    return np.array([list(r.values()) for r in rows]), list(rows[0])


@pytest.mark.parametrize("dims", [2, 3])
def test_population_kernel_matches_its_oracle(dims):
    from naive import hormone_population as naive_population

    from growsim.kernels.hormone_population import grow_population

    rng = np.random.default_rng(40 + dims)
    base = hormone.resolve_params(hormone.PARAMS, hormone.PRESETS[f"demo_{dims}d"])
    rows = [base, *({**base, **{p.name: float(rng.uniform(p.low, p.high))
                                for p in hormone.GENES}} for _ in range(3))]  # fmt: skip
    g = np.stack([hormone.genes(p) for p in rows])
    c = np.array([[p[name] for name, _, _ in hormone.CONSTANTS] for p in rows])
    young = np.array([p["strength_young"] for p in rows])
    walls = 2 if dims == 2 else int(base["walls"])
    args = (g, c, young, dims, walls, 10, 40, hormone.environment_args(SKY))
    got, want = grow_population(*args), naive_population.grow_population(*args)
    np.testing.assert_allclose(got[0], want[0], rtol=1e-12)
    for a, b in zip(got[1:], want[1:]):
        np.testing.assert_array_equal(a, b)
    assert got[1].max() > 5  # the demo grew


@pytest.mark.parametrize("dims", [2, 3])
def test_population_path_grows_the_same_plants(dims):
    # random genomes, a capped one, a weak one that breaks: the one-call population path
    # gives each plant's total, module count, stop and module-steps as grow() does
    rng = np.random.default_rng(dims)
    base = {**hormone.PRESETS[f"demo_{dims}d"], "steps": 14, "max_modules": 5}
    params = [base, {**base, "strength_young": 3e3}]
    for _ in range(5):
        params.append({**base, **{p.name: float(rng.uniform(p.low, p.high))
                                  for p in hormone.GENES}})  # fmt: skip
    rows, names = _rows(params)
    for env in (SKY, SKY.model_copy(update={"light": SKY.light.model_copy(
            update={"shadows": "soft"})})):  # fmt: skip
        table = hormone.population(rows, names, env)
        for i, p in enumerate(params):
            plants = list(hormone.grow(p, env=env))
            last = plants[-1]
            want = last.meta["total_nutrient"]
            got = table.total_nutrient[i]
            assert got == want or (np.isnan(got) and np.isnan(want)), i
            assert table.modules[i] == last.n_segments, i
            assert table.stopped[i] == last.meta["stopped"], i
            assert table.module_steps[i] == sum(q.n_segments for q in plants), i
        assert {"cap", "broken"} <= set(table.stopped)
    # the objective's population path scores as the plant by plant path
    obj = NutrientObjective(env=SKY)
    fast = obj.batch(hormone.MODEL, rows, names)
    slow = [obj(hormone.develop(p, env=SKY)) for p in params]
    np.testing.assert_array_equal(fast, slow)
    # settings that differ between rows: no population path
    mixed, _ = _rows([base, {**base, "steps": 5}])
    assert hormone.population(mixed, names, SKY) is None
    with pytest.raises(UserInputError, match=r"hormone\.h0_gain.*row 1"):
        bad = rows[:2].copy()
        bad[1, names.index("h0_gain")] = 2.0
        hormone.population(bad, names, SKY)


def test_bad_parameters_are_named():
    with pytest.raises(UserInputError, match=r"hormone\.h3_gain"):
        hormone.develop({"h3_gain": 2.0})
    with pytest.raises(UserInputError, match="unknown parameter"):
        hormone.develop({"h99_bias": 0.0})


def test_configs_evolve_every_gene_by_a_pattern():
    from growsim.errors import ConfigError
    from growsim.experiment import load_config
    from growsim.experiment.plan import plan_model

    for dims in (2, 3):
        plan = plan_model(load_config(ROOT / f"experiments/hormone_{dims}d.toml"))
        assert len(plan.evolved) == 90 and plan.fixed["dims"] == dims
        assert all(p.name.startswith("h") for p in plan.evolved)
    with pytest.raises(ConfigError, match=r"model.evolve.zz\*: the pattern matches no parameter"):
        config = ROOT / "experiments/hormone_2d.toml"
        plan_model(load_config(config, overrides=["model.evolve.zz*=true"]))


def test_sweep_variants_and_the_common_garden(tmp_path):
    # the config's three environments as a sweep, then compare --garden: every best genome
    # grown in every environment, tests between origins and between gardens
    from growsim.experiment import sweep
    from growsim.report import compare

    tiny = ["ga.population=6", "ga.islands=1", "ga.generations=2", "model.params.steps=6",
            "model.params.max_modules=20"]  # fmt: skip
    df = sweep(ROOT / "experiments/hormone_2d.toml", repeats=2, out=tmp_path / "sw",
               overrides=tiny, progress=False)  # fmt: skip
    assert sorted(df["sweep_variant"].unique()) == ["ample", "half_light", "half_water"]
    assert {Path(p).parent.name for p in df["out"]} == {"ample", "half_light", "half_water"}
    # the summary counts why the final population stopped growing (cap, broken, nan)
    summary = json.loads((Path(df["out"][0]) / "summary.json").read_text())
    assert summary["stops"]["population"] == 6 and sum(summary["stops"].values()) == 12
    history = pd.read_parquet(Path(df["out"][0]) / "history.parquet")
    assert summary["failures"] == int(history["failures"].sum())
    # no module of any run's best plant below the ground (environment.ground.height = 0)
    from growsim.phenotypes.plant import Plant

    for out in df["out"]:
        best_plant = Plant.load(Path(out) / "best_plant.npz")
        assert best_plant.meta["ground"] == 0.0
        assert best_plant.start[:, 1].min() >= -1e-9 and best_plant.end[:, 1].min() >= -1e-9
    c = compare([tmp_path / "sw"], tmp_path / "cmp", renders=False, garden=True)
    grown = pd.read_csv(c.files["garden"])
    assert len(grown) == 6 * 3  # 6 runs x 3 gardens
    # grown in its own garden, a genome scores what its run found
    own = grown[grown.origin == grown.garden]
    for row in own.itertuples():
        best = json.loads((Path(row.path) / "best.json").read_text())
        assert row.fitness == pytest.approx(best["fitness"], rel=1e-12)
    # half the light grows less in every garden than the full light, for the same genomes
    name = {o: Path(p).parent.name for o, p in zip(grown.origin, grown.path)}  # label: variant
    lit = grown.assign(garden=grown.garden.map(name)).pivot_table(
        index=["origin", "seed"], columns="garden", values="fitness"
    )
    assert (lit["half_light"] <= lit["ample"]).all()
    stats = pd.read_csv(c.files["garden_stats"])
    assert set(stats.contrast) == {"genetic", "plastic"}
    assert (stats.welch_t_p_holm >= stats.welch_t_p - 1e-15).all()
    shares = pd.read_csv(c.files["garden_variance"])
    parts = shares[["origin", "garden", "interaction", "residual"]]
    # every run grown in every garden, two runs per origin: a balanced design, where the
    # four shares split the whole variance
    assert len(shares) > 0 and (parts >= 0).all().all()
    np.testing.assert_allclose(parts.sum(axis=1), 1.0, atol=1e-9)
    assert "Common garden" in c.files["html"].read_text()
    # why each cell's plants stopped: every run of each origin counted once in each garden
    stops = pd.read_csv(c.files["garden_stops"])
    assert len(stops) == 9 and (stops["n"] == 2).all()
    assert (stops.drop(columns=["family", "origin", "garden", "n"]).sum(axis=1) == 2).all()
    # a primary test within one garden: the two origins grown side by side there (the
    # garden grown for it without --garden), the same Welch p as the garden's own test
    from growsim.experiment.schema import CompareConfig

    spec = CompareConfig(primary=[
        {"measure": "fitness", "expect": "half_light > ample", "garden": "half_light"},
        {"measure": "height", "expect": "ample > half_light"},
    ])  # fmt: skip
    c2 = compare([tmp_path / "sw"], tmp_path / "cmp2", renders=False, primary=spec)
    prim = pd.read_csv(c2.files["primary"], keep_default_na=False)
    row = prim[prim.garden == "half_light"].iloc[0]
    same = stats[(stats.contrast == "genetic") & (stats.within == "half_light")
                 & (stats.measure == "fitness") & (stats.group_a == "ample")
                 & (stats.group_b == "half_light")].iloc[0]  # fmt: skip
    assert float(row.p) == pytest.approx(same.welch_t_p, rel=1e-12)
    assert float(row.difference) == pytest.approx(-same.difference, rel=1e-12)
    assert set(prim.garden) == {"half_light", ""} and "garden" in c2.files
    assert "grown in half_light" in c2.files["html"].read_text()


def test_sweep_variants_are_checked():
    from growsim.errors import ConfigError
    from growsim.experiment import load_config

    base = {"model": {"kind": "hormone", "evolve": {"h0_bias": True}},
            "objective": [{"kind": "nutrient"}]}  # fmt: skip
    with pytest.raises(ConfigError, match="given twice"):
        load_config({**base, "sweep": {"variants": [{"name": "a"}, {"name": "a"}]}})
    with pytest.raises(ConfigError, match=r"sweep\.variants\[0\]\.name: required"):
        load_config({**base, "sweep": {"variants": [{"nme": "a"}]}})


@pytest.mark.parametrize(
    ("override", "key"),
    [
        ("environment.water.supply=-0.5", r"environment\.water\.supply"),
        ("environment.light.direction=[0, 0, 0]", r"environment\.light\.direction"),
        ("environment.light.intensity=-1", r"environment\.light\.intensity"),
        ('environment.light.backend="moderngl"', r"environment\.light\.backend"),
        ("environment.ground.height=0.5", r"environment\.ground\.height"),
    ],
)
def test_an_impossible_environment_is_refused_before_evolution(tmp_path, override, key):
    from growsim.errors import GrowsimError
    from growsim.experiment import run

    out = tmp_path / "run"
    with pytest.raises(GrowsimError, match=key):
        run(ROOT / "experiments/hormone_2d.toml", out, overrides=[override, "ga.generations=1"],
            progress=False)  # fmt: skip
    assert not (out / "history.parquet").exists()


def test_same_plants_serially_in_a_pool_and_on_dask(process_pool, dask_client):
    # the population path in worker processes: same fitness, bit for bit
    from growsim.experiment import load_plan

    plan = load_plan(ROOT / "experiments/hormone_3d.toml", ["model.params.steps=8"])
    f = plan.fitness()
    rng = np.random.default_rng(3)
    x = np.array([[rng.uniform(p.low, p.high) for p in plan.evolved] for _ in range(12)])
    serial = f(x)
    pooled = np.concatenate(list(process_pool.map(f, np.array_split(x, 4))))
    np.testing.assert_array_equal(pooled, serial)
    parts = dask_client.gather(dask_client.map(f, np.array_split(x, 3), pure=False))
    np.testing.assert_array_equal(np.concatenate(parts), serial)
    one = [f(x[i : i + 1])[0] for i in range(3)]  # one plant at a time: the same numbers
    np.testing.assert_array_equal(one, serial[:3])


def test_census_counts_the_same_on_a_pool():
    # why the final population stopped: counted in tasks on the run's executor, summed
    from types import SimpleNamespace

    from growsim.experiment import load_plan
    from growsim.experiment.runner import _census

    sets = ["model.params.max_modules=20", 'model.evolve={"strength_young"=true}']
    plan = load_plan(ROOT / "experiments/hormone_3d.toml", sets)
    f = plan.fitness()
    result = SimpleNamespace(population=np.geomspace(1e6, 1e9, 10)[:, None])
    serial = _census(f, result, [])
    assert serial == {"population": 10, "cap": 6, "broken": 4}  # weak plants fall
    warnings: list[str] = []
    pooled = _census(f, result, warnings, executor=2)
    assert list(pooled.items()) == list(serial.items()) and not warnings


def test_a_sweep_of_unbranched_plants_keeps_their_branch_angle_as_nan(tmp_path):
    """Plants of a few modules have no branch point, so no branch angle (NaN, written
    ``"nan"`` in each summary): the sweep's table reads it back as a float column and
    writes its parquet."""
    from growsim.experiment.sweep import sweep

    tiny = ["ga.population=4", "ga.generations=1", "model.params.steps=2",
            "model.params.max_modules=4", "sweep.variants=[]"]  # fmt: skip
    df = sweep(ROOT / "experiments/hormone_2d.toml", repeats=2, out=tmp_path / "sw",
               overrides=tiny, progress=False)  # fmt: skip
    assert df["best_branch_angle"].dtype == float and df["best_branch_angle"].isna().all()
    back = pd.read_parquet(tmp_path / "sw" / "sweep.parquet")
    assert back["best_branch_angle"].isna().all()
