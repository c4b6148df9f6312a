"""Gravity loads at joints and breaking (growsim.env.gravity, growsim.kernels.gravity)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from naive.gravity import first_break_kernel as first_break_oracle
from naive.gravity import loads_kernel as loads_oracle
from naive.gravity import radius_end_kernel as radius_end_oracle

from growsim.env import Environment
from growsim.env.gravity import Gravity
from growsim.errors import UserInputError
from growsim.kernels.gravity import first_break_kernel, loads_kernel, radius_end_kernel
from growsim.models import honda
from growsim.phenotypes.plant import LEAF, STEM, Plant


def random_skeleton(rng, n, n_roots=1):
    """A random forest stored parents first: each segment starts at its parent's end."""
    parent = np.array([-1] * n_roots + [int(rng.integers(0, s)) for s in range(n_roots, n)])
    start = np.zeros((n, 3))
    end = np.zeros((n, 3))
    for s in range(n):
        start[s] = rng.normal(size=3) if parent[s] < 0 else end[parent[s]]
        end[s] = start[s] + rng.normal(size=3) * rng.uniform(0.1, 2.0)
    radius = rng.uniform(0.0, 0.2, n)
    radius[rng.random(n) < 0.05] = 0.0
    radius_end = radius * rng.uniform(0.0, 1.2, n)
    kind = (rng.random(n) < 0.3).astype(np.int8)
    kind[:n_roots] = STEM
    return start, end, radius, radius_end, parent, kind


@pytest.mark.parametrize("seed", range(8))
def test_loads_kernel_matches_oracle(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 60))
    args = random_skeleton(rng, n, n_roots=int(rng.integers(1, 4)) if n > 3 else 1)
    strength = rng.uniform(1e3, 1e5, n) if seed % 2 else np.array([2e4])
    consts = (float(rng.uniform(100, 1000)), float(rng.uniform(0, 1)), float(rng.uniform(0, 20)))
    got = loads_kernel(*args, strength, consts, np.full((4, n), np.nan))
    want = loads_oracle(*args, strength, consts)
    for name, a, b in zip(("mass", "mass_above", "moment", "ratio"), got, want):
        np.testing.assert_allclose(a, b, rtol=1e-7, atol=1e-9, err_msg=name)
    # a reused buffer gives the same result
    again = loads_kernel(*args, strength, consts, got.copy())
    np.testing.assert_array_equal(again, got)
    offsets = np.array([0, n // 3, n], np.int64)
    ratio = got[3] * 50  # some joints over 1
    assert (
        first_break_kernel(ratio, offsets).tolist() == first_break_oracle(ratio, offsets).tolist()
    )


@pytest.mark.parametrize("seed", range(4))
def test_radius_end_kernel_matches_oracle(seed):
    rng = np.random.default_rng(seed)
    n = 60
    parent = np.array([-1] + [int(rng.integers(0, i)) for i in range(1, n)], np.int64)
    kind = rng.integers(0, 2, n).astype(np.int8)
    radius = rng.uniform(0.0, 1.0, n)
    got = radius_end_kernel(parent, kind, radius, np.empty(n))
    np.testing.assert_array_equal(got, radius_end_oracle(parent, kind, radius))
    assert np.any(got < radius)  # some segments narrow to a child


def test_first_break_kernel_ties_and_empty_plants():
    ratio = np.array([1.0, 3.0, 3.0, 0.2, 1.0, 1.0])
    offsets = np.array([0, 3, 3, 4, 6], np.int64)
    assert first_break_kernel(ratio, offsets).tolist() == [1, -1, -1, 4]


def horizontal(length, radius, **kw):
    return Plant.from_points([[0, 0, 0], [length, 0, 0]], [-1], [-1, 0], radius=radius, **kw)


def test_one_segment_horizontal_branch_analytic():
    # a cylinder lying along x: moment at its base = weight x half its length
    gr = Gravity(g=9.81, density=700.0)
    L, r = 3.0, 0.04
    out = gr.loads(horizontal(L, r))
    m = 700.0 * math.pi * r * r * L
    assert out.mass[0] == pytest.approx(m)
    assert out.mass_above[0] == pytest.approx(m)
    assert out.moment[0] == pytest.approx(m * 9.81 * L / 2)
    assert out.stress[0] == pytest.approx(m * 9.81 * L / 2 / (math.pi * r**3 / 4))
    assert out.stress_ratio[0] == pytest.approx(out.stress[0] / gr.strength)
    # a branch along z and one at 45 degrees up in x-z carry the same kind of moment
    along_z = Plant.from_points([[0, 0, 0], [0, 0, L]], [-1], [-1, 0], radius=r)
    assert gr.loads(along_z).moment[0] == pytest.approx(out.moment[0])
    tilted = Plant.from_points([[0, 0, 0], [L, L, 0]], [-1], [-1, 0], radius=r)
    t = gr.loads(tilted)
    assert t.moment[0] == pytest.approx(t.mass[0] * 9.81 * L / 2)  # horizontal arm L / 2


def test_horizontal_branch_of_two_segments_and_a_cone():
    gr = Gravity(g=10.0, density=1000.0)
    p = Plant.from_points([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [-1, 0], [-1, 0, 1], radius=0.1)
    out = gr.loads(p)
    m = 1000.0 * math.pi * 0.01
    assert out.mass_above.tolist() == pytest.approx([2 * m, m])
    assert out.moment[0] == pytest.approx(10.0 * (m * 0.5 + m * 1.5))
    assert out.moment[1] == pytest.approx(10.0 * m * 0.5)
    # a full cone (tip radius 0): centroid at a quarter of its length from the base
    cone = horizontal(4.0, 0.1, data={"radius_end": [0.0]})
    c = gr.loads(cone)
    assert c.mass[0] == pytest.approx(1000.0 * math.pi * 0.01 * 4.0 / 3.0)
    assert c.moment[0] == pytest.approx(c.mass[0] * 10.0 * 1.0)


def test_vertical_pole_has_no_moment():
    pole = Plant.from_points(
        [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 5, 0]], [-1, 0, 1], [-1, 0, 1, 2], radius=0.01
    )
    out = Gravity().loads(pole)
    assert np.all(out.moment == 0.0) and np.all(out.stress_ratio == 0.0)
    assert out.first_break == -1
    assert out.mass_above[0] == pytest.approx(out.mass.sum())
    assert np.all(np.diff(out.mass_above) < 0)


def test_leaves_add_mass_by_area_and_are_not_judged():
    gr = Gravity(g=9.81, leaf_mass_per_area=0.2)
    # a vertical stem with one horizontal leaf (length 0.5, half-width 0.05) at its top
    p = Plant(
        start=[[0, 0, 0], [0, 1, 0]],
        end=[[0, 1, 0], [0.5, 1, 0]],
        radius=[0.01, 0.05],
        parent=[-1, 0],
        order=[0, 0],
        kind=[STEM, LEAF],
    )
    out = gr.loads(p)
    leaf = 0.2 * 0.5 * 2 * 0.05
    assert out.mass[1] == pytest.approx(leaf)
    assert out.mass_above[0] == pytest.approx(out.mass[0] + leaf)
    assert out.moment[0] == pytest.approx(leaf * 9.81 * 0.25)
    assert out.moment[1] == pytest.approx(leaf * 9.81 * 0.25)
    assert out.stress_ratio[1] == 0.0 and out.stress[1] == 0.0  # a leaf's joint never breaks
    assert out.stress_ratio[0] > 0.0
    # leaves without mass leave only the stem
    light = Gravity(leaf_mass_per_area=0.0).loads(p)
    assert light.moment[0] == 0.0 and light.mass_above[0] == pytest.approx(out.mass[0])


def test_zero_gravity_no_stress():
    rng = np.random.default_rng(3)
    start, end, radius, radius_end, parent, kind = random_skeleton(rng, 40)
    skel = {"start": start, "end": end, "radius": radius, "parent": parent, "kind": kind}
    out = Gravity(g=0.0).loads({**skel, "radius_end": radius_end})
    assert np.all(out.moment == 0) and np.all(out.stress_ratio == 0)
    assert out.first_break == -1 and out.mass_above[0] > 0 and np.all(out.mass_above >= 0)


def test_break_rule_thin_long_branch_breaks_thick_does_not():
    # sigma / MOR = 2 rho g L^2 / (r MOR) for a horizontal cylinder: 1.41 and 0.28 here
    gr = Gravity()
    thin, thick = horizontal(6.0, 0.01), horizontal(6.0, 0.05)
    ratio = 2 * gr.density * gr.g * 36.0 / gr.strength
    assert gr.loads(thin).stress_ratio[0] == pytest.approx(ratio / 0.01)
    assert gr.loads(thin).first_break == 0 and gr.breaks(thin)
    assert gr.loads(thick).first_break == -1 and not gr.breaks(thick)
    # a trunk holding the thin branch: the branch's joint is the one that breaks
    tree = Plant.from_points(
        [[0, 0, 0], [0, 2, 0], [6, 2, 0]], [-1, 0], [-1, 0, 1], radius=[0.3, 0.01]
    )
    assert gr.loads(tree).first_break == 1
    # a stronger wood, per segment from the model or as the argument, holds it
    strong = horizontal(6.0, 0.01, data={"strength": [1e9]})
    assert not gr.breaks(strong)
    assert not gr.breaks(thin, strength=[1e9])
    assert gr.breaks(strong, strength=[1e6])
    assert gr.first_breaks([thin, thick, tree, strong]).tolist() == [0, -1, 1, -1]
    assert gr.first_breaks([]).tolist() == []


def test_environment_table_and_mapping_input():
    env = Environment.model_validate({"gravity": {"g": 1.62, "density": 600.0}})
    assert env.gravity.g == 1.62 and env.gravity.strength == 40e6
    p = horizontal(2.0, 0.02)
    a = env.gravity.loads(p)
    b = env.gravity.loads({"start": p.start, "end": p.end, "radius": p.radius, "parent": [-1]})
    np.testing.assert_array_equal(a.moment, b.moment)
    # a concatenated forest: each plant loaded on its own
    both = Plant.concat([p, horizontal(3.0, 0.05)], offsets=[[0, 0, 0], [10, 0, 0]])
    f = env.gravity.loads(both)
    assert f.moment[0] == pytest.approx(a.moment[0])


def test_bad_input_errors():
    gr = Gravity()
    p = Plant.from_points([[0, 0, 0], [0, 1, 0], [1, 1, 0]], [-1, 0], [-1, 0, 1])
    arrays = {"start": p.start.copy(), "end": p.end.copy(), "radius": p.radius, "parent": p.parent}
    arrays["end"][1, 2] = np.nan
    with pytest.raises(UserInputError, match="end: segment 1 is not finite"):
        gr.loads(arrays)
    with pytest.raises(UserInputError, match="parents first"):
        gr.loads({**arrays, "end": p.end, "parent": [1, -1]})
    with pytest.raises(UserInputError, match="strength: segment 1 is not positive"):
        gr.loads(p, strength=[1e6, 0.0])
    with pytest.raises(UserInputError, match="strength"):
        gr.loads(p, strength=[1e6])
    with pytest.raises(UserInputError, match="expected a Plant"):
        gr.loads(42)
    with pytest.raises(UserInputError, match="missing"):
        gr.loads({"start": p.start})
    with pytest.raises(UserInputError, match="kind"):
        gr.loads({**arrays, "end": p.end, "kind": [0, 2]})
    with pytest.raises(ValueError, match="density"):
        Gravity(density=0.0)


@pytest.mark.parametrize("name", sorted(honda.PRESETS))
def test_honda_trees_stress_is_highest_near_lateral_bases(name):
    """Honda's presets read in metres (20 m trunk segments of radius 1 m, taper 0.85 per
    level): the worst joint sits low in the tree, at the base of a first lateral of the
    trunk or on the trunk between them (depth <= 6), the tips carry little, and a
    lateral's base is the worst joint of its own branch in most cases (77 of 83 laterals
    of the main trunk over the 8 presets; where not, the joint one level up is at most
    ~20 % higher: taper narrows the wood faster than the lever shrinks)."""
    t = honda.develop(honda.PRESETS[name])
    out = Gravity().loads(t)
    r = out.stress_ratio
    assert np.all(np.isfinite(r)) and np.all(r >= 0)
    assert out.mass_above[0] == pytest.approx(out.mass.sum())
    stem = t.kind == STEM
    worst = int(np.argmax(r))
    assert stem[worst] and t.data["depth"][worst] <= 6
    assert out.first_break == (worst if r[worst] >= 1 else -1)
    tips = stem & (t.stem_children_count() == 0)
    assert r[tips].max() < 0.5 * r[worst]
    main, par = t.data["main"], t.parent
    laterals = np.flatnonzero(stem & ~main & (par >= 0) & main[np.maximum(par, 0)])
    own_best = 0
    for b in laterals:
        inside = np.zeros(t.n_segments, bool)
        inside[b] = True
        for s in range(b + 1, t.n_segments):
            inside[s] = par[s] >= 0 and inside[par[s]]
        rest = r[inside & stem]
        own_best += r[b] >= rest.max()
        assert r[b] >= 0.75 * rest.max()
    assert own_best >= 0.6 * len(laterals)


def test_first_break_step_of_a_growing_branch_and_of_a_one_shot_model():
    from growsim.models import get_model
    from growsim.phenotypes.plant import Plant

    def lengthening(radius):
        for k in range(1, 12):
            yield Plant.from_points([[0, 0, 0], [0.5 * k, 0, 0]], [-1], [-1, 0], radius=radius)

    g = Gravity()
    step, seg = g.first_break_step(lengthening(0.01))
    # the first step whose branch breaks, and no earlier one does
    plants = list(lengthening(0.01))
    assert seg == 0 and g.breaks(plants[step]) and not any(g.breaks(p) for p in plants[:step])
    assert g.first_break_step(lengthening(0.5)) == (-1, -1)
    honda = get_model("honda")
    dome = honda.preset("f_dome")  # breaks at its defaults (see the docs)
    assert g.first_break_step(honda.grow(dome)) == (0, g.loads(honda.develop(dome)).first_break)
